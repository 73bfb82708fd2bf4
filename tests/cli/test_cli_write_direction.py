"""The command line never builds or sends a state the drive only reports: `frame`, `write`, `--raw`;
`--words` (words at any address, the map's checks left out on purpose) stays the one override. Error
messages and `show` list the values that may be written."""

from __future__ import annotations

import subprocess
import sys

from regmap.diagnostics import ExitCode

from conftest import ROOT, SimulatorFactory

IDM = "maps/idm_rs.yaml"


def regmap(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "regmap", *args], cwd=ROOT, capture_output=True, text=True, check=False, timeout=60)


def refused(result: subprocess.CompletedProcess[str], *needles: str) -> None:
    assert result.returncode == ExitCode.USAGE, (result.returncode, result.stdout, result.stderr)
    assert result.stdout == ""  # no frame
    assert len(result.stderr.strip().splitlines()) == 1 and "Traceback" not in result.stderr, result.stderr
    for needle in needles:
        assert needle in result.stderr, result.stderr


def test_the_issue_reproduction_builds_no_frame() -> None:
    # It printed 01 06 60 02 00 05 F6 09: a request that writes "path 5 done" into the motion trigger.
    result = regmap("frame", IDM, "write", "pr_trigger=done_path_5")
    refused(result, "pr_trigger (Pr8.02)", "done_path_5", "a state the device only reports")


def test_by_number_and_raw_the_state_is_refused_too() -> None:
    refused(regmap("frame", IDM, "write", "pr_trigger=5"), "done_path_5 (5)")
    refused(regmap("frame", IDM, "write", "--raw", "Pr8.02=0x0105"), "running_path_5 (261)", "only reports")
    refused(regmap("frame", IDM, "write", "--raw", "0x6002=0x0200"), "command_done_waiting (512)")


def test_a_command_value_still_builds_its_frame() -> None:
    result = regmap("frame", IDM, "write", "--raw", "pr_trigger=0x0015")
    assert result.returncode == 0 and result.stdout.split("\n")[0] == "01 06 60 02 00 15 F7 C5", result.stderr


def test_words_stay_the_explicit_override() -> None:
    # --words writes words at any address with none of the map's checks (documented as such): not a new bypass.
    result = regmap("frame", IDM, "write", "--words", "0x6002=5")
    assert result.returncode == 0 and result.stdout.strip() == "01 06 60 02 00 05 F6 09", result.stderr


def test_an_unknown_value_lists_only_writable_members() -> None:
    result = regmap("frame", IDM, "write", "pr_trigger=go")
    refused(result, "start_path_15=31", "home=32", "emergency_stop=64")
    assert "done" not in result.stderr and "running_path" not in result.stderr


def test_write_refuses_before_opening_the_port(simulator: SimulatorFactory) -> None:
    sim = simulator(ROOT / IDM)
    tcp = ["--tcp", f"127.0.0.1:{sim.port}"]
    refused(regmap("write", IDM, "pr_trigger=running_path_3", *tcp), "running_path_3 (259)", "only reports")
    refused(regmap("write", IDM, "--raw", "pr_trigger=0x0103", *tcp), "running_path_3 (259)")
    read = regmap("read", IDM, "pr_trigger", *tcp)
    assert read.returncode == 0 and "done" in read.stdout and "running_path_3" not in read.stdout, read.stdout + read.stderr
    ok = regmap("write", IDM, "pr_trigger=start_path_3", "--no-verify", *tcp)
    assert ok.returncode == 0, ok.stderr


def test_show_marks_each_members_direction() -> None:
    result = regmap("show", IDM, "pr_trigger")
    lines = {line.split()[1]: line for line in result.stdout.splitlines() if line.strip()[:1].isdigit()}
    assert lines["done_path_5"].endswith("[read only: never written]")
    assert lines["start_path_0"].endswith("[write only]")
    assert "[" not in regmap("show", IDM, "loop_mode").stdout  # an enum without directions is shown as before
