"""Issue #34's float meter answers a read only when it starts on an even address and covers an even count
(tests/maps/fixtures/float_meter.yaml, `transport.read_alignment`; the CT ratio may be read alone). Every
read plan of every target is checked against that rule, read back from what each target prints or runs."""

from __future__ import annotations

import re
from itertools import combinations
from typing import Any

import pytest

from regmap.backends.c import render_device as c_files
from regmap.frontend import load_map
from regmap.homeauto.entities import planned
from regmap.model import Device, PollClass
from regmap.runtime_bridge import read_plan, runtime_device, runtime_specs
from regmap.tools.live import plan as live_plan
from regmap_runtime.align import Alignment
from regmap_runtime.plan import ReadBlock, plan_reads
from regmap_runtime.spec import RegisterSpec

from conftest import ROOT
from support.fixture_clients import flavour

FLOAT_METER = ROOT / "tests" / "maps" / "fixtures" / "float_meter.yaml"
DEVICE = load_map(FLOAT_METER)
EXEMPT = {("holding", 0x0104, 1)}  # ct_ratio alone, as the fixture's read_alignment.exempt says


def _device_answers(space: str, address: int, count: int) -> bool:
    """The rule as the fixture states it, written out here apart from the runtime."""
    return (address % 2 == 0 and count % 2 == 0) or (space, address, count) in EXEMPT


def _check(blocks: list[ReadBlock], what: str) -> None:
    assert blocks, what
    for b in blocks:
        assert _device_answers(b.space, b.address, b.count), (what, b.space, hex(b.address), b.count)
        for spec in b.registers:  # the block still holds its registers' words
            assert b.address <= spec.address and spec.address + spec.words <= b.address + b.count, (what, spec.name)


def _selections(device: Device) -> list[tuple[str, list[Any]]]:
    readable = [r for r in device.registers if r.access.readable]
    chosen: list[tuple[str, list[Any]]] = [("all", readable)]
    chosen += [(r.name, [r]) for r in readable]
    chosen += [(f"{a.name}+{b.name}", [a, b]) for a, b in combinations(readable, 2)]
    return chosen


def test_every_python_plan_keeps_the_rule() -> None:
    """read_plan (the C and ST tables, the docs, frame/read/dump) and the clients' own planner (both flavours)."""
    for name, regs in _selections(DEVICE):
        _check(read_plan(DEVICE, regs), f"read_plan {name}")
        _check(live_plan(DEVICE, regs, None, None), f"live.plan {name}")
    for poll in (PollClass.FAST, PollClass.NORMAL, PollClass.SLOW):
        _check(read_plan(DEVICE, poll=poll), f"poll {poll.value}")
    for name in ("runtime", "generated"):
        f = flavour(name, DEVICE.id)
        for variant in (None, "single_phase", "three_phase"):
            client = f.sync_class(object(), 1, variant=variant)
            _check(client.plan_reads(client.readable()), f"{name} client read_all {variant}")
            for reg in client.readable():
                _check(client.plan_reads([reg]), f"{name} client {reg.name}")


def test_home_automation_plans_keep_the_rule() -> None:
    """The ESPHome ranges and HA polls start from `planned` (per poll class and firmware gate)."""
    for name, regs in _selections(DEVICE):
        for bits in (None, 16):
            _check([block for block, _, _ in planned(DEVICE, regs, bits)], f"planned {name}")


def _c_tables(text: str) -> list[tuple[int, int]]:
    return [(int(a, 16), int(n)) for a, n in re.findall(r"\{ 0x([0-9A-F]{4})u, (\d+)u \}", text)]


def test_the_c_read_plan_tables_keep_the_rule() -> None:
    files = c_files(DEVICE)
    source = next(text for path, text in files.items() if path.endswith(".h"))
    rows = _c_tables(source)
    assert len(rows) >= 4
    spaces = {(b.address, b.count): b.space for b in read_plan(DEVICE)}
    for address, count in rows:
        space = spaces.get((address, count), "input" if address < 0x0100 else "holding")
        assert _device_answers(space, address, count), (hex(address), count)


def test_the_planner_pads_over_readable_words_and_splits_at_gaps() -> None:
    """Alone, humidity (0x0007) reads 0x0006-0x0007 (temperature, readable); the CT ratio (0x0104, beside an
    undocumented 0x0105) is read alone as exempted; a read limit of 3 is 2 for pairs."""
    spec = runtime_device(DEVICE)
    specs = {s.name: s for s in runtime_specs(DEVICE)}
    assert spec.alignment == Alignment(2, ("holding", "input"), (("holding", 0x0104, 1),), 0x02)
    (block,) = plan_reads([specs["humidity"]], 60, spec.documented, alignment=spec.alignment)
    assert (block.address, block.count, [r.name for r in block.registers]) == (6, 2, ["humidity"])
    blocks = plan_reads([specs["ct_ratio"], specs["voltage_alarm"], specs["baud_code"]], 60, spec.documented, alignment=spec.alignment)
    assert [(b.address, b.count) for b in blocks] == [(0x0100, 2), (0x0104, 1), (0x0106, 2)]
    pair = [specs["humidity"], specs["pulse_count"]]
    assert [(b.address, b.count) for b in plan_reads(pair, 3, spec.documented)] == [(7, 3)]  # without the rule: one misaligned read
    assert [(b.address, b.count) for b in plan_reads(pair, 3, spec.documented, alignment=spec.alignment)] == [(6, 2), (8, 2)]
    assert [(b.address, b.count) for b in plan_reads(pair, 4, spec.documented, alignment=spec.alignment)] == [(6, 4)]
    # Padded at both ends: four words at 0x0001-0x0004 fit a limit of 4, their aligned read (0x0000-0x0005) does not.
    odd: list[RegisterSpec[int]] = [RegisterSpec(f"r{a}", a, "u16", "r", space="input") for a in (1, 2, 3, 4)]
    blocks = plan_reads(odd, 4, None, alignment=Alignment(2, ("input",)))
    assert [(b.address, b.count, len(b.registers)) for b in blocks] == [(0, 4, 3), (4, 2, 1)]
    # A device that tolerates gaps: the CT ratio is padded over 0x0105 instead of read alone.
    (padded,) = plan_reads([specs["ct_ratio"]], 60, None, alignment=Alignment(2, ("holding",)))
    assert (padded.address, padded.count) == (0x0104, 2)


def test_the_client_refuses_a_misaligned_raw_read_before_sending() -> None:
    class Nothing:
        def __getattr__(self, name: str) -> Any:
            raise AssertionError(f"{name} was called: something was sent")

    for name in ("runtime", "generated"):
        f = flavour(name, DEVICE.id)
        client = f.sync_class(Nothing(), 1)
        for address, count, space in ((0x0001, 2, "input"), (0x0000, 3, "input"), (0x0106, 1, "holding"), (0x0105, 1, "holding")):
            with pytest.raises(f.errors.AccessError, match=r"read alignment.*exception 0x02.*nothing was sent"):
                client.read_raw(address, count, space=space)
        assert client.requests_sent == 0
