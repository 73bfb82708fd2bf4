"""`make bench`'s code paths on tiny inputs, so the benchmarks cannot rot unnoticed. Nothing here
asserts a timing: benchmarks are measurements, not tests."""

from __future__ import annotations

import random
import sys
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Any

import pytest
from pymodbus.client import ModbusTcpClient

from regmap.frontend import load_map, load_map_text
from regmap.runtime_bridge import read_plan
from regmap_runtime.plan import plan_reads
from regmap_runtime.spec import RegisterSpec

from conftest import MAPS, ROOT

if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))  # bench/ sits at the top of the repository

from bench import bus, chelpers, floor, genspeed, optimal, overhead, plant, simload, synth
from bench.common import client_class, client_module, machine
from bench.plot import Series, loglog
from bench.report import Results, render, targets

DEVICES = {path.stem: load_map(path, str(path.relative_to(ROOT))) for path in MAPS}


def test_line_timing_uses_the_manuals_turnaround() -> None:
    line = bus.line_of(DEVICES["idm_rs"])
    assert (line.baud, line.bits_per_char) == (38400, 10)  # 8N1
    assert line.turnaround_s == pytest.approx(1.16e-3)  # 5.1 table, T2 at 38400
    assert line.idle_s == pytest.approx(3.5 * 10 / 38400)  # T3 0.46 ms is shorter than the 3.5-character gap
    c630s = bus.line_of(DEVICES["c630s"])
    assert c630s.bits_per_char == 11  # 8N2
    assert c630s.turnaround_s == pytest.approx(1e-3)  # P0C-25 default response delay


@pytest.fixture(scope="module")
def bus_result() -> bus.BusResult:
    return bus.measure(DEVICES["id243pro"])


def test_bus_counts_the_frames_the_simulator_received(bus_result: bus.BusResult) -> None:
    device = DEVICES["id243pro"]
    readable = [r for r in device.registers if r.access.readable]
    assert bus_result.plan_matches_frames
    assert bus_result.plan.requests == len(read_plan(device))
    assert bus_result.per_register.requests == len(readable)
    assert bus_result.bound.wire_s <= bus_result.plan.wire_s <= bus_result.per_register.wire_s


def _random_specs(rng: random.Random) -> list[RegisterSpec[Any]]:
    specs: list[RegisterSpec[Any]] = []
    address = rng.randint(0, 50)
    for i in range(rng.randint(1, 30)):
        address += rng.randint(0, 3)
        data_type = rng.choice(["u16", "s16", "u32", "s32"])
        paired = data_type in ("u16", "s16") and rng.random() < 0.5
        address += paired
        specs.append(RegisterSpec(name=f"r{i}", address=address, data_type=data_type, access="rw", paired=paired))
        address += 2 if data_type in ("u32", "s32") else 1
    return specs


def test_dynamic_programme_agrees_with_the_planner() -> None:
    rng = random.Random(13)
    for _ in range(200):
        specs = _random_specs(rng)
        limit = rng.randint(2, 20)
        documented = (
            None if rng.random() < 0.3 else frozenset((r.space, a) for r in specs for a in range(r.first_address, r.address + r.words))
        )
        assert optimal.fewest_requests(specs, limit, documented).requests == len(plan_reads(specs, limit, documented))
    for device in DEVICES.values():
        assert optimal.check(device, sweep=(2, 125)).optimal


@pytest.mark.parametrize("registers", [37, 150])
def test_synthetic_maps_are_valid_maps_of_that_size(registers: int) -> None:
    device = load_map_text(synth.synthetic_map(registers), f"synthetic_{registers}.yaml")
    assert len(device.registers) == registers
    assert device.arrays and any(r.array is None for r in device.registers)


def test_generation_runner_and_stage_breakdown(tmp_path: Path) -> None:
    runner = genspeed.Runner(tmp_path)
    path = synth.write_synthetic_map(tmp_path, 60)
    run = runner.runs("synthetic 60", 60, [path], 1)
    assert len(run.wall_s) == 1 and run.files > 0
    spent = runner.phases([path])
    assert {"YAML parsing", "back end python", "back end c", "back end markdown", "total in process"} <= set(spent)
    assert runner.profile([path])


def test_overhead_paths_compare_equal_values() -> None:
    module = client_module("idm_rs")
    cls = client_class(module)
    specs = [s for s in module.DEVICE.registers if s.readable]
    window = overhead.window(specs, 0x6200, 100)
    offline = cls(ModbusTcpClient("127.0.0.1", port=1))
    comparison = overhead.decode_case(offline, [window], random.Random(1), 1, "decode", "smoke")
    assert comparison.generated_s > 0 and comparison.raw_s > 0
    cost = overhead.client_cost(cls, list(window.registers), "window", 1)
    assert cost.read_many_s > 0


def test_c_helpers_build_and_measure() -> None:
    result = chelpers.measure(iterations=1000, repeats=1)
    assert result.python_ns
    if result.blocked is None:
        assert result.m0_text is not None and result.m0_text > 0
        assert set(result.host_ns) == set(chelpers.CASES)


def test_report_renders_every_section(bus_result: bus.BusResult) -> None:
    plans = [optimal.check(DEVICES["id243pro"], sweep=(125,))]
    run = genspeed.GenRun("the three maps", 766, 3, (1.0,), (1.0,), 47)
    gen = genspeed.GenSpeed(
        run,
        [genspeed.GenRun("synthetic 1000", 1000, 1, (0.5,), (0.5,), 18), genspeed.GenRun("synthetic 10000", 10000, 1, (4.0,), (4.0,), 45)],
    )
    text = render(Results(machine(), [bus_result], plans, gen, [], [], None, quick=True))
    for heading in ("## Targets", "## 1. Bus time", "## 2. Read-plan", "## 3. Generation", "## 4. Runtime", "## 5. C frame"):
        assert heading in text
    assert "<svg" in text and targets(Results(machine(), [bus_result], plans, gen, [], [], None))
    svg = loglog("t", "x", "y", [Series("a", ((1.0, 0.1), (10.0, 1.0)), "#000")])
    assert ET.fromstring(svg).tag.endswith("svg")


def test_simulator_load_beside_libmodbus() -> None:
    result = simload.measure(requests=200, rss_requests=200, warmup=50)
    if result.blocked is not None:
        pytest.skip(result.blocked)
    assert {(r.server, r.clients) for r in result.runs} == {(s, n) for s in simload.SERVERS for n in simload.LEVELS}
    assert all(r.errors == 0 and r.requests >= 200 - r.clients for r in result.runs)
    assert set(result.rss_kb) == set(simload.SERVERS)
    text = render(Results(machine(), [], [], None, [], [], None, quick=True, sim=result))
    assert "## 6. Simulator under load" in text and "req/s ratio" in text


def test_generation_floor_and_big_import_measure_and_render(tmp_path: Path) -> None:
    small = ROOT / "tests" / "maps" / "small" / "idm_rs_small.yaml"
    gen = floor.measure_generate(repeats=1, maps=[small])
    assert gen.cold.ratio > 0 and gen.warm.ratio > 0
    # The warm run may use the output cache, the cold runs may not (CPU of one run each is too close to compare on a
    # small map: speed is make bench's to judge, not a test's).
    assert "REGMAP_NO_CACHE" not in floor._environment(tmp_path, cache=True)
    assert floor._environment(tmp_path, cache=False)["REGMAP_NO_CACHE"] == "1"
    run = floor.measure_import(rows=60)
    assert run.status == 0 and run.peak_mib > 0 and run.draft_sha256 and "valid" in run.verdict
    text = render(Results(machine(), [], [], None, [], [], None, quick=True, floor=gen, big_import=run))
    assert "## 7. Generation against its import floor" in text and "warm" in text and "draft = before's bytes" in text
    if floor.base_source(tmp_path) is not None:  # a clone with the round's base: it ran in the same pairs
        assert len(gen.cold.base_s) == len(gen.cold.floor_s) == 1 and f"{floor.BEFORE_BRANCH_COMMIT} in the same runs" in text
    assert any(
        "import floor" not in t and "import" in t for t, _, _ in targets(Results(machine(), [], [], None, [], [], None, big_import=run))
    )


def test_the_base_ratio_is_over_the_same_floor_runs() -> None:
    same_runs = floor.Ratio(generate_s=(3.0, 5.0, 4.0), floor_s=(1.0, 2.0, 1.0), base_s=(4.0, 6.0, 6.0))
    assert (same_runs.ratio, same_runs.base_ratio, same_runs.base) == (3.0, 4.0, 6.0)
    alone = floor.Ratio(generate_s=(3.0,), floor_s=(1.0,))
    assert alone.base_ratio is None and alone.base is None


def test_the_plant_bench_polls_the_cycle_beside_the_devices_own_plans() -> None:
    """cell1's read_all() through the multi-unit simulator: the requests of the three single-device plans, in the
    schedule's order, and the same wire time as their sum and as the schedule's budget."""
    run = plant.measure()
    leftover = [n for n, m in sys.modules.items() if "regmap-bench-plant-" in (getattr(m, "__file__", None) or "")]
    assert not leftover, f"modules of the deleted temporary plant are still imported: {leftover}"
    assert run.devices == 3 and run.order_matches
    assert run.plant_requests == run.single_requests > 100
    assert run.plant_wire_s == pytest.approx(run.single_wire_s) and run.budget_s == pytest.approx(run.plant_wire_s)
    assert any("plant `read_all()`" in t for t, _, _ in targets(Results(machine(), [], [], None, [], [], None, plant=run)))
