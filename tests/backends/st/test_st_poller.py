"""The generated poller (FB_<DEV>_POLL), run: matiec compiles it, in its matiec spelling, with the device's
plain-standard ST and a stub library of the runtime's interface (tests/support/st_stubs/, the vendors'
block, argument and type names), gcc builds it with a driver that plays the bus (tests/support/st_poll.py),
and the run is held to the Python client:

- every read-plan block is requested as planned (function, address, count) and nothing else; a static
  block once, a firmware-gated block not while the firmware is unknown;
- after two passes the values struct holds what the Python client decodes from the same words (the
  manuals' read responses, and each register's minimum or maximum elsewhere);
- the injected reply timeout and exception are counted in aTimeouts / aErrors of their block;
- a value the encoder refuses queues nothing and sends nothing; an accepted write is sent once with the
  Python client's words, and when its reply times out it is `bOutcomeUnknown` and never sent again.

The vendor spelling itself (CODESYS / TwinCAT text: namespaces, actions, pointers) is parsed with blark;
a poller with a wrong argument name or type is refused by matiec, so the stubs check the calls.
Without matiec or gcc the test skips (CI=true: fails).
"""

from __future__ import annotations

import json
import re
import subprocess
from pathlib import Path
from typing import Any

import pytest

from regmap.backends.st.encoders import encoder_targets
from regmap.backends.st.names import StIdentifier
from regmap.backends.st.views import configurable
from regmap.backends.st.writes import write_function_code
from regmap.core.decoding import decode_words
from regmap.frontend import load_map
from regmap.generate import render
from regmap.model import Device, Register
from regmap_runtime.codec import raw_to_value, raw_to_words
from regmap_runtime.spec import HIGH_FIRST, LOW_FIRST

from conftest import FIXTURE_MAPS, MAPS, ROOT, built_tool
from support.st_matiec import matiec_and_gcc
from support.st_poll import PollBench, Run, WriteStep
from support.st_values import block_words, compare_value, edge_words, example_data, order_flag, register_spec

RUNTIMES = ("codesys", "twincat")
SCALED_FROM = ROOT / "tests" / "maps" / "scaled_from" / "inverter.yaml"  # scale factors (scale_from)
PARSE = ROOT / "tests" / "st" / "parse_st.py"
FAULTS = {2: "timeout", 3: "exception"}  # the second request gets no reply, the third an exception
SCALE_FACTOR = -1  # a scale factor's word in the image and a scaled write's nSf (the s16 edges are no real device's)


@pytest.fixture(scope="session")
def matiec() -> Path:
    return matiec_and_gcc()


def _image(bench: PollBench) -> tuple[dict[str, dict[int, int]], list[list[int]]]:
    """A register image per space: each block's registers at their minimum (even blocks) or maximum (odd), then
    the words of every read response the manuals print (the golden frames) where they fall."""
    device = bench.device
    image: dict[str, dict[int, int]] = {"coil": {}, "discrete_input": {}, "holding": {}, "input": {}}
    for index, block in enumerate(bench.plan):
        specs = {r.name: register_spec(device, r) for r in block.registers}
        words = block_words(block, edge_words(specs, "max" if index % 2 else "min"))
        for k, word in enumerate(words):
            image[block.space][block.address + k] = word
        for reg in block.registers:
            if any(r.scale_from == reg.name for r in device.registers):
                image[block.space][reg.address] = SCALE_FACTOR & 0xFFFF
    for _, kind, space, address, words in example_data(device):  # the manuals' read responses, over the edges
        if kind == "read":
            for k, word in enumerate(words):
                image[space][address + k] = word
    per_block = [[image[b.space][b.address + k] for k in range(b.count)] for b in bench.plan]
    return image, per_block


def _candidate(device: Device) -> Register | None:
    """A plain writable holding register whose range the encoder checks (raw_max + 1 is refused)."""
    for label, regs in encoder_targets(device):
        reg = regs[0]
        if (
            label == reg.name
            and reg.space == "holding"
            and reg.type.numeric
            and not reg.type.is_float
            and reg.enum is None
            and not reg.bitfields
            and not reg.paired
            and not configurable(device, reg)
            and reg.raw_max < reg.type.raw_max
        ):
            return reg
    return None


def _accepted_raw(device: Device, reg: Register) -> int:
    taken = [command.raw_values for command in device.destructive_commands(reg)]
    # not 0, so that a write of a constant 0 shows; never a destructive command's value (the encoder refuses those)
    return next(int(r) for r in (reg.raw_min + 1, reg.raw_max, reg.raw_min) if r != 0 and not any(lo <= r <= hi for lo, hi in taken))


def _c_value(device: Device, reg: Register, raw: int) -> tuple[str, ...]:
    """The WRITE function's arguments for the raw value (a scaled point's: its value at SCALE_FACTOR, nSf, bSfAvailable)."""
    if reg.scale_from is not None:
        return (f"(LREAL){raw / 10**-SCALE_FACTOR!r}", f"(INT){SCALE_FACTOR}", "1")
    return (_c_number(device, reg, raw),)


def _c_number(device: Device, reg: Register, raw: int) -> str:
    if reg.scaled or reg.offset_set:
        return f"(LREAL){float(raw_to_value(register_spec(device, reg), raw))!r}"
    return f"({'UINT' if reg.type.value == 'u16' else 'INT' if reg.type.value == 's16' else 'UDINT' if reg.type.value == 'u32' else 'DINT'}){raw}LL"


def _writes(bench: PollBench, run: Run, reg: Register) -> list[str]:
    device = bench.device
    problems = []
    accepted = _accepted_raw(device, reg)
    refused, sent, after = run.writes["refused"], run.writes["timeout"], run.writes["timeout_after"]
    # returned, bRefused, bPending, bSent, bDone, bFailed, bOutcomeUnknown
    if refused[:3] != (False, True, False):
        problems.append(f"a refused value: returned {refused[0]}, bRefused {refused[1]}, bPending {refused[2]}")
    if sent[:3] != (True, False, True):
        problems.append(f"an accepted value: returned {sent[0]}, bRefused {sent[1]}, bPending {sent[2]}")
    if after[2:] != (False, True, False, False, True):
        problems.append(f"after the write's reply timed out: bPending/bSent/bDone/bFailed/bOutcomeUnknown = {after[2:]}")
    writes = [r for r in run.requests if r.function in (5, 6, 16)]
    expected = (write_function_code(reg), reg.first_address, reg.span, tuple(raw_to_words(register_spec(device, reg), accepted)))
    got = [(r.function, r.address, r.count, r.words) for r in writes]
    if got != [expected]:
        problems.append(f"writes sent {got}, expected exactly one {expected} (the refused value none, the timed-out one once)")
    return problems


def _reads(bench: PollBench, run: Run, per_block: list[list[int]], high_word_first: bool) -> list[str]:
    device = bench.device
    problems = []
    planned = {(b.function, b.address, b.count): i for i, b in enumerate(bench.plan)}
    reads = [r for r in run.requests[: run.first_pass_end] if r.function in (1, 2, 3, 4)]
    for r in reads:
        if (r.function, r.address, r.count) not in planned:
            problems.append(f"a read outside the plan: function {r.function} at {r.address}, {r.count}")
    faults = {number: outcome for number, outcome in FAULTS.items() if number <= len(run.requests)}
    if sorted(r.outcome for r in run.requests if r.number in faults) != sorted(faults.values()):
        problems.append("the injected faults did not hit requests")
    from regmap.backends.st.functions import plan_blocks

    classes = plan_blocks(device)
    for i, block in enumerate(bench.plan):
        mine = [r for r in reads if planned.get((r.function, r.address, r.count)) == i]
        ok = [r for r in mine if r.outcome == "ok"]
        _, poll, gate, _ = classes[i]
        decoded, errors, timeouts = run.blocks[i]
        if errors != sum(r.outcome == "exception" for r in mine) or timeouts != sum(r.outcome == "timeout" for r in mine):
            problems.append(f"block {i}: counted {errors} errors and {timeouts} timeouts, the bus gave {[r.outcome for r in mine]}")
        if gate is not None:
            if mine:
                problems.append(f"block {i} is firmware-gated and the firmware unknown, yet it was read")
            continue
        if poll.value == "static" and len(ok) != 1:
            problems.append(f"static block {i} read {len(ok)} times")
        if not ok:
            problems.append(f"block {i} was never read")
            continue
        order = (HIGH_FIRST if high_word_first else LOW_FIRST) if any(configurable(device, r) for r in block.registers) else None
        values = [v for v in decode_words(device, block.address, per_block[i], space=block.space, word_order=order) if v.raw is not None]
        all_valid = True
        for value in values:
            reg = device.register(str(value.register))
            if reg not in block.registers:
                continue
            valid, wrong = compare_value(reg, value, run.values, bench.program.value_types[StIdentifier(reg.name)])
            all_valid &= valid
            problems += [f"block {i} {reg.name}: {w}" for w in wrong]
        if decoded != all_valid:
            problems.append(f"block {i}: aDecoded {decoded}, the Python client reads every value: {all_valid}")
    if run.passes < 2:
        problems.append(f"{run.passes} passes")
    return problems


@pytest.mark.parametrize("runtime", RUNTIMES)
@pytest.mark.parametrize("map_path", [*MAPS, *FIXTURE_MAPS, SCALED_FROM], ids=lambda p: p.stem)
def test_poller_reads_the_plan_and_writes_once(map_path: Path, runtime: str, matiec: Path, tmp_path: Path) -> None:
    device = load_map(map_path, display_name=map_path.relative_to(ROOT).as_posix())
    bench = PollBench(device, runtime)
    image, per_block = _image(bench)
    reg = _candidate(device)
    steps: list[WriteStep] = []
    if reg is not None:
        function = StIdentifier("F", device.id, "WRITE", reg.name)
        accepted = _accepted_raw(device, reg)
        cycles = 8 * len(bench.plan) + 20  # more than a pass: a re-sent write would show
        steps = [
            WriteStep("refused", function, _c_value(device, reg, int(reg.raw_max) + 1), cycles),
            WriteStep("timeout", function, _c_value(device, reg, accepted), cycles, fault="timeout"),
        ]
    high_word_first = order_flag(device, None)
    run = bench.run(matiec, tmp_path, image, FAULTS, steps, high_word_first=high_word_first)
    problems = _reads(bench, run, per_block, high_word_first)
    if reg is not None:
        problems += _writes(bench, run, reg)
    print(f"{device.id} {runtime}: {len(run.requests)} requests, {run.passes} passes, write through {reg.name if reg else None}")
    assert not problems, f"{len(problems)} problems:\n" + "\n".join(problems[:30])
    assert reg is not None or map_path not in MAPS, "a seed map without a plain writable register: the write path was not run"


@pytest.mark.parametrize(
    ("runtime", "old", "new"),
    [
        ("codesys", "uiStartItem := nAddr", "uiStartAddress := nAddr"),  # a name the library does not have
        ("codesys", "uiValue := aWords[0]", "uiValue := bExecute"),  # a BOOL where the library takes a UINT
        ("twincat", "MBAddr := UINT_TO_WORD(nAddr)", "MbAddress := UINT_TO_WORD(nAddr)"),
        ("twincat", "Timeout := tReplyTimeout", "Timeout := nUnitId"),  # a UINT where the library takes a TIME
    ],
)
def test_matiec_refuses_a_call_the_library_does_not_have(runtime: str, old: str, new: str, matiec: Path, tmp_path: Path) -> None:
    device = load_map(ROOT / "maps" / "id243pro.yaml", display_name="maps/id243pro.yaml")
    bench = PollBench(device, runtime)
    text = bench.poll_text()
    assert old in text
    good = bench.compile(matiec, tmp_path, text, "good")
    assert good.returncode == 0 and not good.errors, good.output[-2000:]
    bad = bench.compile(matiec, tmp_path, text.replace(old, new), "bad")
    assert bad.returncode != 0 and bad.errors, f"matiec took a call with {new!r}"


@pytest.fixture(scope="session")
def st_python() -> Path:
    return built_tool("st")


def test_vendor_pollers_parse_with_blark(st_python: Path, tmp_path: Path) -> None:
    """The CODESYS and TwinCAT text as generated (namespaces, actions, ADR, SIZEOF): blark, TwinCAT's grammar,
    reads the pollers of the fixture maps, whose logic is every map's."""
    devices = [load_map(p, display_name=p.relative_to(ROOT).as_posix()) for p in [*FIXTURE_MAPS, SCALED_FROM]]
    files = []
    for rel, text in render(devices, ["st"])["st"].items():
        if rel.endswith("_poll.st"):
            path = tmp_path / rel
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(text, encoding="utf-8")
            files.append(path)
    assert {p.parent.name for p in files} == set(RUNTIMES)
    result = subprocess.run(
        [str(st_python), str(PARSE), "blark", *map(str, files)], capture_output=True, text=True, timeout=900, check=False
    )
    assert result.returncode == 0, result.stderr
    problems: list[Any] = json.loads(result.stdout)
    assert problems == []


README_PATH = re.compile(r"`((?:codesys|twincat|iec|plcopen)/[A-Za-z0-9_.]+)`")


@pytest.mark.parametrize("map_path", MAPS, ids=lambda p: p.stem)
def test_readme_steps_name_files_that_exist(map_path: Path) -> None:
    """Every file the README's import steps name is in the device's folder of generated/st/, and each runtime's steps are there."""
    device = load_map(map_path, display_name=map_path.relative_to(ROOT).as_posix())
    folder = ROOT / "generated" / "st" / device.id
    text = (folder / "README.md").read_text(encoding="utf-8")
    named = set(README_PATH.findall(text))
    assert {f"twincat/{device.id}_poll.st", f"codesys/{device.id}_poll.st", f"plcopen/{device.id}.xml"} <= named
    missing = sorted(path for path in named if not (folder / path).is_file())
    assert not missing, f"the README names files that are not generated: {missing}"
    bare = set(re.findall(rf"`({device.id}_[a-z]+\.st)`", text))
    assert bare and all((folder / "codesys" / name).is_file() for name in bare), bare
    for heading in ("## TwinCAT 3 (Tc2_ModbusRTU)", "## CODESYS (ModbusFB)", "## OpenPLC"):
        assert heading in text
    assert "Tc2_ModbusRTU" in text and "ModbusFB.ClientSerial" in text
