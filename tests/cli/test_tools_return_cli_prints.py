"""The field tools return what they read, wrote and found; `cli/` alone prints it and picks the exit status."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

from regmap.cli.live_output import read_status, write_status
from regmap.cli.probe import probe_status
from regmap.core.decoding import decode_words
from regmap.diagnostics import ExitCode
from regmap.frontend import load_map
from regmap.tools import live
from regmap.tools.link import Link
from regmap.tools.probe.report import Findings, Note
from regmap.tools.selectors import parse_items

from conftest import ROOT, SimulatorFactory

IDM = ROOT / "maps" / "idm_rs.yaml"
TOOLS = ROOT / "generator" / "regmap" / "tools"
RESULT_TOOLS = [
    TOOLS / "live.py",
    TOOLS / "link.py",
    TOOLS / "selectors.py",
    TOOLS / "simulator" / "run.py",
    *sorted((TOOLS / "probe").glob("*.py")),
]


def _printing(path: Path) -> list[str]:
    """Where a module prints, writes to a standard stream or names an exit status."""
    found = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == "print":
            found.append(f"{path.name}:{node.lineno}: print()")
        elif isinstance(node, ast.Attribute) and node.attr in ("stdout", "stderr") and isinstance(node.value, ast.Name):
            found.append(f"{path.name}:{node.lineno}: {node.value.id}.{node.attr}")
        elif isinstance(node, ast.Name) and node.id == "ExitCode":
            found.append(f"{path.name}:{node.lineno}: ExitCode")
    return found


def test_the_field_tools_print_nothing_and_pick_no_exit_status() -> None:
    assert [line for path in RESULT_TOOLS for line in _printing(path)] == []


def test_a_read_returns_its_values_in_the_order_asked_and_prints_nothing(
    simulator: SimulatorFactory, capsys: pytest.CaptureFixture[str]
) -> None:
    sim = simulator(IDM)
    device = load_map(IDM)
    result = live.read(device, Link(tcp=f"127.0.0.1:{sim.port}"), parse_items(["peak_current", "run_status"]))
    assert [v.register for v in result.values] == ["peak_current", "run_status"]
    assert result.error is None and result.unread == [] and not result.interrupted
    assert capsys.readouterr() == ("", "")
    assert read_status(result, "read") == ExitCode.OK


def test_a_dump_cut_short_by_the_bus_returns_what_was_read_and_the_cli_exits_4(
    simulator: SimulatorFactory, capsys: pytest.CaptureFixture[str]
) -> None:
    sim = simulator(IDM, "--fault", "no_answer", "--fault-after", "3")
    device = load_map(IDM)
    steps: list[tuple[int, int]] = []
    result = live.dump(
        device, Link(tcp=f"127.0.0.1:{sim.port}", timeout=0.2, retries=0), progress=lambda done, total: steps.append((done, total))
    )
    assert result.values and result.unread and result.error is not None and "DeviceTimeout" in result.error
    assert [done for done, _ in steps] == list(range(1, len(steps) + 1)) and len(steps) < steps[0][1]
    assert capsys.readouterr() == ("", "")
    assert read_status(result, "dump") == ExitCode.BUS
    err = capsys.readouterr().err
    assert err.startswith(f"regmap dump: the bus failed after {len(result.values)} register(s) were read: ") and "not read: " in err
    result.interrupted = True
    assert read_status(result, "dump") == ExitCode.INTERRUPTED
    assert capsys.readouterr().err.startswith("regmap dump: stopped after ")


def test_a_verified_write_returns_the_read_back_and_prints_nothing(simulator: SimulatorFactory, capsys: pytest.CaptureFixture[str]) -> None:
    sim = simulator(IDM)
    device = load_map(IDM)
    plan = live.plan_write(device, ["Pr5.00=1.5"], raw=False, replace=False, words=False)
    written = live.write(device, Link(tcp=f"127.0.0.1:{sim.port}"), plan, verify=True)
    assert (written.count, written.unit, written.requests, written.mismatches) == (1, "value", 1, 0)
    assert written.checked is not None and [(c.value.register, c.outcome) for c in written.checked] == [("peak_current", "verified")]
    assert capsys.readouterr() == ("", "")


def test_a_read_back_that_differs_is_shown_as_a_mismatch_and_exits_5(capsys: pytest.CaptureFixture[str]) -> None:
    device = load_map(IDM)
    held = next(v for v in decode_words(device, 0x0191, [15]) if v.register == "peak_current")
    written = live.Written(1, "value", 1, [live.Checked(held, "mismatch", 16)], mismatches=1)
    assert write_status(written) == ExitCode.VERIFY_MISMATCH
    out, err = capsys.readouterr()
    assert out == "Pr5.00 peak_current = 1.5 A (raw 15)  (MISMATCH: wrote raw 16)\n"
    assert err == "regmap write: 1 register(s) read back different values\n"


def test_the_probe_status_is_chosen_by_the_cli_from_the_findings() -> None:
    found = Findings(load_map(IDM), "127.0.0.1:5020")
    assert probe_status(found) == ExitCode.BUS  # nothing answered
    found.stages_done.append("registers")
    found.answered_registers = 1
    assert probe_status(found) == ExitCode.OK
    found.notes.append(Note("registers", "peak_current", "range", "holds 99", disagrees=True))
    assert probe_status(found) == ExitCode.PROBE_DISAGREES
    found.interrupted = True
    assert probe_status(found) == ExitCode.INTERRUPTED
