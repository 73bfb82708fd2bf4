"""`regmap probe` against the simulator (issue 23): a clean drive agrees; a drive started on a changed
map, or playing quirks (gap reads, a smaller read limit, the other word order), is reported exactly;
the profile it learns is what `dump --profile` and the client read with."""

from __future__ import annotations

import contextlib
import io
import json
import re
import signal
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest
import yaml

from regmap.cli import main
from regmap.diagnostics import ExitCode
from regmap.frontend import load_map
from regmap.model import Device
from regmap.runtime_bridge import documented_addresses, read_plan
from regmap.tools.probe.bus import ProbeBus, Stop
from regmap.tools.probe.registers import probe_plan
from regmap_runtime.errors import DeviceTimeout
from regmap_runtime.profile import DeviceProfile, ProfileError, load_profile

from conftest import MAPS, ROOT, SimulatorFactory
from support.clients import client_module

IDS = [p.stem for p in MAPS]
# A plain register per map (16-bit, read-write, ranged, with a default, named by no command, example or erratum).
PLAIN = {"idm_rs": "homing_accel", "id243pro": "acceleration", "c630s": "servo_on_filter_time"}
OTHER_ORDER = {"high_first": "low_first", "low_first": "high_first"}
Map = dict[str, Any]


def probe(port: int, map_path: Path | str, *extra: str) -> tuple[int, dict[str, Any]]:
    """`regmap probe ... --json` in this process (the simulator is a process of its own)."""
    out = io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(io.StringIO()):
        code = main(["probe", str(map_path), "--tcp", f"127.0.0.1:{port}", "--json", "--timeout", "0.5", "--retries", "0", *extra])
    return code, json.loads(out.getvalue()) if out.getvalue().strip() else {}


def disagreements(report: dict[str, Any]) -> set[tuple[str, str, str]]:
    return {(n["stage"], n["kind"], n["subject"]) for n in report["disagreements"]}


def map_path(device_id: str) -> Path:
    return ROOT / "maps" / f"{device_id}.yaml"


def changed(tmp_path: Path, device_id: str, edit: Callable[[dict[str, Any]], object]) -> Path:
    data: Map = yaml.safe_load(map_path(device_id).read_text(encoding="utf-8"))
    for group in data["groups"]:
        for reg in group.get("registers") or []:
            if reg.get("name") == PLAIN[device_id]:
                edit(reg)
                if reg.get("remove"):
                    group["registers"].remove(reg)
                break
    out = tmp_path / f"{device_id}-changed.yaml"
    out.write_text(yaml.safe_dump(data, allow_unicode=True, sort_keys=False), encoding="utf-8")
    return out


def free_address(device: Device) -> int:
    used = {a for r in device.registers for a in range(r.first_address, r.last_address + 1)}
    return next(a for a in range(max(used) + 2, 0xFFFF) if a not in used and a - 1 not in used)


@pytest.mark.parametrize("device_id", IDS)
def test_a_clean_drive_agrees(device_id: str, simulator: SimulatorFactory, tmp_path: Path) -> None:
    sim = simulator(map_path(device_id), "--firmware", "2.10")
    profile = tmp_path / "drive.json"
    code, report = probe(sim.port or 0, map_path(device_id), "--profile", str(profile))
    assert code == ExitCode.OK, report["disagreements"]
    assert report["verdict"] == "agrees" and report["disagreements"] == []
    assert all(r["status"] == "answered" and r["in_range"] and r["enum_member"] for r in report["registers"])
    assert report["limits"]["largest_taken"] == load_map(map_path(device_id)).transport.max_read_registers
    assert report["gaps"]["answered"] == 0
    assert any("names no firmware register" in n["text"] for n in report["information"])
    learned = load_profile(profile)
    assert (learned.max_read_registers, learned.readable_gaps) == (None, ())


REG = "registers"


@pytest.mark.parametrize("device_id", IDS)
@pytest.mark.parametrize("change", ["moved", "removed", "range"])
def test_a_drive_on_a_changed_map_is_reported_exactly(device_id: str, change: str, simulator: SimulatorFactory, tmp_path: Path) -> None:
    device = load_map(map_path(device_id))
    reg = device.register(PLAIN[device_id])
    extra: list[str] = []
    if change == "moved":
        served = changed(tmp_path, device_id, lambda r: (r.pop("param", None), r.update(address=free_address(device))))
        expected = {(REG, "not_answered", reg.label)}
    elif change == "removed":
        served = changed(tmp_path, device_id, lambda r: r.update(remove=True))
        expected = {(REG, "not_answered", reg.label)}
    else:  # the map's range is narrower than the drive's: the drive holds, and takes, a value the map does not admit
        assert reg.max is not None
        high = reg.max
        served = changed(tmp_path, device_id, lambda r: r.update(max=high + 5, default=high + 1))
        extra = ["--write-test", reg.name]
        expected = {(REG, "out_of_range", reg.label), ("write_test", "out_of_range_write", reg.label)}
    sim = simulator(served)
    code, report = probe(sim.port or 0, map_path(device_id), *extra)
    assert code == ExitCode.PROBE_DISAGREES
    assert disagreements(report) == expected
    if change != "range":
        (row,) = [r for r in report["registers"] if r["register"] == reg.name]
        assert (row["status"], row["exception"]) == ("exception", 0x02)
    else:
        (test,) = report["write_test"]
        assert test["write_back"] == "answered" and test["out_of_range_answer"] == "answered"


@pytest.mark.parametrize("device_id", IDS)
@pytest.mark.parametrize("quirk", ["gaps", "max_read", "word_order"])
def test_a_drive_with_quirks_is_reported_exactly(device_id: str, quirk: str, simulator: SimulatorFactory, tmp_path: Path) -> None:
    device = load_map(map_path(device_id))
    map_order = device.transport.word_order.value
    args = {"gaps": ["--answer-gaps"], "max_read": ["--max-read", "10"], "word_order": ["--word-order", OTHER_ORDER[map_order]]}[quirk]
    sim = simulator(map_path(device_id), *args)
    profile = tmp_path / "drive.json"
    code, report = probe(sim.port or 0, map_path(device_id), "--profile", str(profile))
    learned = load_profile(profile)
    if quirk == "gaps":
        assert disagreements(report) == {("gaps", "gap_reads", "transport")}
        assert report["gaps"]["answered"] == report["gaps"]["tried"] > 0
        assert learned.readable_gaps and learned.max_read_registers is None
    elif quirk == "max_read":
        assert disagreements(report) == {("limits", "read_limit", "transport")}
        assert (report["limits"]["largest_taken"], report["limits"]["smallest_refused"]) == (10, 11)
        assert learned.max_read_registers == 10
    elif device.transport.word_order_register is None:
        assert disagreements(report) == {("word_order", "word_order", "transport")}
        assert report["word_order"]["inferred"] == learned.word_order == OTHER_ORDER[map_order]
    else:  # C630S: the drive was set to the other order with P0C-26; the values agree with it
        assert disagreements(report) == set()
        assert report["word_order"]["register_says"] == report["word_order"]["inferred"] == OTHER_ORDER[map_order]
    assert code == (ExitCode.OK if not report["disagreements"] else ExitCode.PROBE_DISAGREES)


def test_the_learned_profile_gives_the_gap_spanning_plan(simulator: SimulatorFactory, tmp_path: Path) -> None:
    device = load_map(map_path("idm_rs"))
    sim = simulator(map_path("idm_rs"), "--answer-gaps")
    profile_path = tmp_path / "idm.json"
    probe(sim.port or 0, map_path("idm_rs"), "--profile", str(profile_path))
    profile = load_profile(profile_path)
    strict, learned = read_plan(device), read_plan(device, profile=profile)
    assert len(learned) < len(strict) and len(learned) == 18
    allowed = {a for _, a in documented_addresses(device)} | profile.gap_addresses
    assert all(a in allowed for b in learned for a in range(b.address, b.address + b.count))  # never spans what was not seen answering
    idm = client_module("idm_rs")
    with idm.IdmRs.tcp("127.0.0.1", sim.port or 0, timeout=5, profile=profile) as client:
        values = client.read_all()
        assert client.requests_sent == 18 and len(values) == 255
    dumped = subprocess.run(
        [
            sys.executable,
            "-m",
            "regmap",
            "dump",
            "maps/idm_rs.yaml",
            "--tcp",
            f"127.0.0.1:{sim.port}",
            "--json",
            "--profile",
            str(profile_path),
        ],
        cwd=ROOT,
        capture_output=True,
        text=True,
        check=False,
        timeout=60,
    )
    assert dumped.returncode == 0 and len(json.loads(dumped.stdout)) == 255, dumped.stderr


def test_a_profile_for_another_map_is_refused(tmp_path: Path) -> None:
    device = load_map(map_path("idm_rs"))
    other = DeviceProfile("idm_rs", "0123456789abcdef", max_read_registers=20)
    path = tmp_path / "old.json"
    path.write_text(json.dumps(other.to_json()), encoding="utf-8")
    with pytest.raises(ProfileError, match="another version of the idm_rs map"):
        read_plan(device, profile=other)
    result = subprocess.run(
        [sys.executable, "-m", "regmap", "dump", "maps/idm_rs.yaml", "--tcp", "127.0.0.1:1", "--profile", str(path)],
        cwd=ROOT,
        capture_output=True,
        text=True,
        check=False,
        timeout=60,
    )
    assert result.returncode == ExitCode.USAGE and "another version of the idm_rs map" in result.stderr
    idm = client_module("idm_rs")
    with pytest.raises(ProfileError):
        idm.IdmRs.tcp("127.0.0.1", 1, profile=other)
    path.write_text('{"format": "something else"}', encoding="utf-8")
    with pytest.raises(ProfileError, match="not regmap-device-profile/1"):
        load_profile(path)


def test_the_scan_finds_undocumented_addresses_that_answer(simulator: SimulatorFactory) -> None:
    sim = simulator(map_path("id243pro"))
    code, report = probe(sim.port or 0, map_path("id243pro"), "--scan-undocumented")
    assert code == ExitCode.OK and report["scan"]["scanned"] > 0 and report["scan"]["answering"] == []
    lenient = simulator(map_path("id243pro"), "--answer-gaps")
    code, report = probe(lenient.port or 0, map_path("id243pro"), "--scan-undocumented")
    assert disagreements(report) == {("gaps", "gap_reads", "transport"), ("scan", "undocumented_answers", "transport")}
    assert report["scan"]["answering"]


def test_a_silent_or_absent_drive_could_not_be_probed(simulator: SimulatorFactory) -> None:
    sim = simulator(map_path("id243pro"), "--fault", "no_answer")
    started = time.monotonic()
    code, report = probe(sim.port or 0, map_path("id243pro"), "--timeout", "0.2")
    assert code == ExitCode.BUS and report["verdict"] == "could not probe"
    assert "confused" in (report["stopped"] or "") and report["requests"] == 3 and time.monotonic() - started < 20
    code, _ = probe(1, map_path("id243pro"))
    assert code == ExitCode.BUS


def test_ctrl_c_prints_what_was_learned(simulator: SimulatorFactory) -> None:
    sim = simulator(map_path("c630s"))
    cmd = [sys.executable, "-m", "regmap", "probe", "maps/c630s.yaml", "--tcp", f"127.0.0.1:{sim.port}", "--rate", "20"]
    process = subprocess.Popen(cmd, cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    time.sleep(2.5)
    process.send_signal(signal.SIGINT)
    out, err = process.communicate(timeout=30)
    assert process.returncode == ExitCode.INTERRUPTED, (out, err)
    assert "stopped by Ctrl-C" in out and "documented readable registers answered" in out


def test_the_budget_and_the_rate_bound_the_bus() -> None:
    now = [0.0]

    class Silent:
        def read_raw(self, address: int, count: int, space: str = "holding") -> list[int]:
            now[0] += 0.5
            raise DeviceTimeout("no answer")

    class Answers:
        def read_raw(self, address: int, count: int, space: str = "holding") -> list[int]:
            return [0] * count

    def sleep(seconds: float) -> None:
        now[0] += seconds

    bus = ProbeBus(Answers(), budget_s=1.0, rate=4, clock=lambda: now[0], sleep=sleep)  # type: ignore[arg-type]
    with pytest.raises(Stop, match="budget"):
        for _ in range(100):
            bus.read(0, 1)
    assert bus.requests == 5 and now[0] == 1.0  # four a second, stopped at the budget
    silent = ProbeBus(Silent(), budget_s=100, clock=lambda: now[0], sleep=sleep)  # type: ignore[arg-type]
    with pytest.raises(Stop, match="confused"):
        for _ in range(100):
            silent.read(0, 1)
    assert silent.requests == 3


FIXTURE_DIR = ROOT / "tests" / "maps" / "fixtures"


@pytest.mark.parametrize("fixture", ["power_meter", "remote_io", "swapped_gated"])
def test_a_clean_fixture_device_agrees_in_every_space(fixture: str, simulator: SimulatorFactory) -> None:
    """Input registers, coils, discrete inputs, floats, text and byte-swapped words are read and judged like holding registers."""
    path = FIXTURE_DIR / f"{fixture}.yaml"
    sim = simulator(path)
    code, report = probe(sim.port or 0, path)
    assert code == ExitCode.OK, report["disagreements"]
    device = load_map(path)
    readable = {r.name for r in device.registers if r.access.readable}
    answered = {r["register"] for r in report["registers"] if r["status"] == "answered"}
    gated_out = {r["register"] for r in report["registers"] if r["status"] == "exception"}
    assert answered | gated_out == readable
    assert all(device.register(name).firmware is not None for name in gated_out)


def _without_gate(tmp_path: Path, register: str) -> Path:
    data: Map = yaml.safe_load((FIXTURE_DIR / "swapped_gated.yaml").read_text(encoding="utf-8"))
    for group in data["groups"]:
        for reg in group["registers"]:
            if reg.get("name") == register:
                reg.pop("firmware")
    out = tmp_path / "ungated.yaml"
    out.write_text(yaml.safe_dump(data, allow_unicode=True, sort_keys=False), encoding="utf-8")
    return out


def test_the_firmware_stage_checks_the_gates_against_the_version_read(simulator: SimulatorFactory, tmp_path: Path) -> None:
    path = FIXTURE_DIR / "swapped_gated.yaml"
    old = simulator(path, "--firmware", "1.9")  # torque_limit (from 2.0) and the 2.5 diagnostics are absent
    code, report = probe(old.port or 0, path)
    assert code == ExitCode.OK, report["disagreements"]
    (note,) = [n for n in report["information"] if n["stage"] == "firmware"]
    assert note["text"].startswith("firmware 1.9 (firmware): 1 of 4 gated registers exist in it")
    # A drive that has torque_limit although its firmware is 1.9: the map's gate is wrong for it.
    served = _without_gate(tmp_path, "torque_limit")
    odd = simulator(served, "--firmware", "1.9")
    code, report = probe(odd.port or 0, path)
    assert code == ExitCode.PROBE_DISAGREES
    assert disagreements(report) == {("firmware", "firmware", "transport")}
    (note,) = [n for n in report["disagreements"] if n["stage"] == "firmware"]
    assert "torque_limit (firmware >= 2.0) answered" in note["text"]
    # A map without the gate probing a 1.9 drive: the refusal is a register the drive lacks.
    code, report = probe(old.port or 0, served)
    assert code == ExitCode.PROBE_DISAGREES
    assert disagreements(report) == {(REG, "not_answered", "torque_limit")}


def test_the_probe_compares_identification_and_server_id_with_the_map(simulator: SimulatorFactory, tmp_path: Path) -> None:
    path = FIXTURE_DIR / "power_meter.yaml"
    sim = simulator(path)
    code, report = probe(sim.port or 0, path)
    assert code == ExitCode.OK, report["disagreements"]
    identity = {n["kind"]: n["text"] for n in report["information"] if n["stage"] == "identity"}
    assert identity == {
        "identification": "identification agrees (4 objects)",
        "server_id": "server id agrees (50 4D FF 50 4D 2D 33 30 30 30)",
    }
    assert report["identity"]["identification"]["0x02"] == "1.25"
    # The device a map edit describes differently: another revision, other additional data.
    text = (
        path.read_text(encoding="utf-8")
        .replace('revision: "1.25"', 'revision: "1.30"')
        .replace("additional_data: PM-3000", "additional_data: PM-9")
    )
    other = tmp_path / "other_meter.yaml"
    other.write_text(text, encoding="utf-8")
    code, report = probe(sim.port or 0, other)
    assert code == ExitCode.PROBE_DISAGREES
    texts = sorted(n["text"] for n in report["disagreements"] if n["stage"] == "identity")
    assert texts == ["additional data b'PM-3000', the map 'PM-9'", "object 0x02 (revision): the device says '1.25', the map '1.30'"]


# -- variants (issue #34's float meter): each register only some variants have is read by itself, and the
# report names the variant whose registers answered as the device's did, or says that none does.

FLOAT_METER = FIXTURE_DIR / "float_meter.yaml"
GATED = "voltage_l2"  # on the three-phase model only


def _variants_note(report: dict[str, Any]) -> dict[str, Any]:
    (note,) = [n for kind in ("disagreements", "information") for n in report[kind] if n["stage"] == "variants"]
    assert isinstance(note, dict)
    return note


@pytest.mark.parametrize("variant", ["single_phase", "three_phase"])
def test_the_probe_names_the_variant_the_device_is(variant: str, simulator: SimulatorFactory) -> None:
    sim = simulator(FLOAT_METER, "--variant", variant)
    code, report = probe(sim.port or 0, FLOAT_METER)
    assert code == ExitCode.OK, report["disagreements"]
    device = load_map(FLOAT_METER)
    has = device.register(GATED).on_variant(variant)
    assert report["variants"] == {
        "present": [GATED] if has else [],
        "absent": [] if has else [GATED],
        "unclear": [],
        "matches": [variant],
    }
    note = _variants_note(report)
    assert note["disagrees"] is False
    assert str(note["text"]).startswith(f"the device is {variant} (of single_phase, three_phase): ")
    # Every other register answered: the refused voltage_l2 took none of them down.
    status = {r["register"]: r["status"] for r in report["registers"]}
    assert status == {r.name: "answered" if r.on_variant(variant) else "exception" for r in device.registers if r.access.readable}
    assert "variants" in report["stages"]


def test_the_probes_reads_neither_mix_nor_bridge_variant_sets() -> None:
    """A block holds registers of one set of variants, and every variant that has them answers each word it
    reads: on a single-phase meter only the reads of what it lacks fail (before, the whole input block did)."""
    device = load_map(FLOAT_METER)
    declared = [v.name for v in device.info.variants]
    blocks = probe_plan(device)
    assert {s.name for b in blocks for s in b.registers} == {r.name for r in device.registers if r.access.readable}
    for block in blocks:
        sets = {tuple(sorted(device.register(s.name).variants)) for s in block.registers}
        assert len(sets) == 1, block
        for variant in declared:
            if all(device.register(s.name).on_variant(variant) for s in block.registers):
                answered = documented_addresses(device, (variant,))
                assert all((block.space, a) in answered for a in range(block.address, block.address + block.count)), (variant, block)


def test_a_variant_lacking_a_register_costs_the_probe_no_extra_request(simulator: SimulatorFactory) -> None:
    """Its plan keeps voltage_l2 apart, so a single-phase meter refuses that read alone and nothing is read again."""
    requests = {}
    for variant in ("single_phase", "three_phase"):
        code, report = probe(simulator(FLOAT_METER, "--variant", variant).port or 0, FLOAT_METER)
        assert code == ExitCode.OK, report["disagreements"]
        requests[variant] = report["requests"]
    assert requests["single_phase"] == requests["three_phase"], requests


def test_a_failed_block_is_read_again_as_the_plan_reads_each_register_alone(simulator: SimulatorFactory) -> None:
    """The fourth request (the input registers' block) is answered once with exception 0x04: its registers are
    then read one by one, each widened to the meter's 2-word units (a lone humidity read at 0x0007 x 1 would be
    refused 0x02), and all of them answer."""
    _, plain = probe(simulator(FLOAT_METER, "--variant", "three_phase").port or 0, FLOAT_METER)
    sim = simulator(FLOAT_METER, "--variant", "three_phase", "--fault", "exception", "--fault-count", "1", "--fault-after", "3")
    code, report = probe(sim.port or 0, FLOAT_METER)
    assert code == ExitCode.OK, report["disagreements"]
    assert {r["status"] for r in report["registers"]} == {"answered"}
    block = next(b for b in probe_plan(load_map(FLOAT_METER)) if b.space == "input" and b.address == 0)
    assert report["requests"] == plain["requests"] + len(block.registers)  # the failed block, then each of its registers


def _also_single_phase_only(tmp_path: Path, register: str) -> Path:
    """The fixture with `register` on the single-phase model only: a three-phase meter has it anyway."""
    text = FLOAT_METER.read_text(encoding="utf-8")
    line = re.search(rf"^.*\{{name: {register},.*$", text, re.MULTILINE)
    assert line is not None and "variants" not in line[0]
    path = tmp_path / "float_meter_two_gates.yaml"
    path.write_text(text.replace(line[0], line[0].replace(", title:", ", variants: [single_phase], title:", 1)), encoding="utf-8")
    return path


def test_a_device_no_declared_variant_describes_disagrees(simulator: SimulatorFactory, tmp_path: Path) -> None:
    sim = simulator(FLOAT_METER, "--variant", "three_phase")
    probed = _also_single_phase_only(tmp_path, "pulse_count")  # answers on the three-phase meter, as voltage_l2 does
    code, report = probe(sim.port or 0, probed)
    assert code == ExitCode.PROBE_DISAGREES
    assert disagreements(report) == {("variants", "variants", "transport")}
    assert report["variants"]["matches"] == []
    assert sorted(report["variants"]["present"]) == sorted([GATED, "pulse_count"])
    assert str(_variants_note(report)["text"]).startswith("no declared variant (single_phase, three_phase) has these registers: ")
