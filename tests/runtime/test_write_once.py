"""A command or a trigger write goes out once: a lost answer is "outcome unknown", never a second motion.
Reads and settings still retry. Against the simulator dropping the first answer, counting what it receives."""

from __future__ import annotations

import asyncio
import re
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest

from conftest import ROOT, SimulatorFactory
from support.clients import client_module

ID243 = ROOT / "maps" / "id243pro.yaml"
IDM = ROOT / "maps" / "idm_rs.yaml"
OUTCOME_UNKNOWN_EXIT = 9  # regmap.diagnostics.ExitCode.OUTCOME_UNKNOWN


def _requests(log: Path, function: str) -> int:
    """How many requests of `function` ("0x06", "0x03") the simulator received."""
    return len(re.findall(rf"function {function} .*\(request\)", log.read_text(encoding="utf-8")))


def _dropping_first_answer(simulator: SimulatorFactory, map_path: Path, tmp_path: Path) -> tuple[int, Path]:
    log = tmp_path / "requests.log"
    sim = simulator(map_path, "--fault", "no_answer", "--fault-count", "1", "--log", str(log))
    assert sim.port is not None
    return sim.port, log


def _regmap(*args: object) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "regmap", *map(str, args)], cwd=ROOT, capture_output=True, text=True, check=False, timeout=120
    )


def test_a_command_whose_answer_is_lost_is_sent_once_and_exits_outcome_unknown(simulator: SimulatorFactory, tmp_path: Path) -> None:
    port, log = _dropping_first_answer(simulator, ID243, tmp_path)
    result = _regmap("command", ID243, "relative_move", "--tcp", f"127.0.0.1:{port}", "--timeout", "0.4", "--retries", "2")
    assert _requests(log, "0x06") == 1, log.read_text(encoding="utf-8")
    assert result.returncode == OUTCOME_UNKNOWN_EXIT, result
    assert "Traceback" not in result.stderr
    (line,) = result.stderr.splitlines()
    assert line.startswith("regmap command: outcome unknown: relative_move: ")
    assert "may or may not have carried it out" in line and "not sent again" in line
    assert "read control_command (0323) back" in line  # what to check before sending it again
    assert "sent relative_move" not in result.stdout


def test_a_read_against_the_same_server_still_retries(simulator: SimulatorFactory, tmp_path: Path) -> None:
    port, log = _dropping_first_answer(simulator, ID243, tmp_path)
    result = _regmap("read", ID243, "control_command", "--tcp", f"127.0.0.1:{port}", "--timeout", "0.4", "--retries", "2")
    assert result.returncode == 0, result
    assert "control_command = none" in result.stdout
    assert _requests(log, "0x03") == 2


def test_a_write_to_a_trigger_register_is_sent_once(simulator: SimulatorFactory, tmp_path: Path) -> None:
    # Pr8.02 is a trigger (a write starts a path): `regmap write` must not start it twice either.
    port, log = _dropping_first_answer(simulator, IDM, tmp_path)
    result = _regmap("write", IDM, "pr_trigger=start_path_3", "--tcp", f"127.0.0.1:{port}", "--timeout", "0.4", "--retries", "2")
    assert _requests(log, "0x06") == 1, log.read_text(encoding="utf-8")
    assert result.returncode == OUTCOME_UNKNOWN_EXIT, result
    assert result.stderr.startswith("regmap write: outcome unknown: the write of 0x0013 to pr_trigger (Pr8.02) (0x6002)")
    assert "Traceback" not in result.stderr


def test_a_setting_whose_answer_is_lost_is_written_again(simulator: SimulatorFactory, tmp_path: Path) -> None:
    # A setting is idempotent (and verified by its read-back): retrying it is what recovers a lost answer.
    port, log = _dropping_first_answer(simulator, IDM, tmp_path)
    result = _regmap("write", IDM, "Pr5.00=1.5", "--tcp", f"127.0.0.1:{port}", "--timeout", "0.4", "--retries", "2")
    assert result.returncode == 0, result
    assert "(verified)" in result.stdout
    assert _requests(log, "0x06") == 2


def test_the_generated_client_raises_outcome_unknown_and_sends_once(simulator: SimulatorFactory, tmp_path: Path) -> None:
    id243pro = client_module("id243pro")
    port, log = _dropping_first_answer(simulator, ID243, tmp_path)
    with id243pro.Id243pro.tcp("127.0.0.1", port, timeout=0.4, retries=2) as drive:
        with pytest.raises(id243pro.OutcomeUnknown) as info:
            drive.relative_move()
        assert isinstance(info.value, id243pro.RegmapError)
        assert isinstance(info.value.cause, id243pro.DeviceTimeout)
        assert info.value.registers == ("control_command",)
        assert drive.read_control_command() is id243pro.ControlCommand.RELATIVE_MOVE  # it did arrive: the answer was lost
    assert _requests(log, "0x06") == 1


def test_the_async_client_sends_a_trigger_write_once(simulator: SimulatorFactory, tmp_path: Path) -> None:
    idm_rs = client_module("idm_rs")
    port, log = _dropping_first_answer(simulator, IDM, tmp_path)

    async def run() -> Any:
        async with idm_rs.AsyncIdmRs.tcp("127.0.0.1", port, timeout=0.4, retries=2) as drive:
            with pytest.raises(idm_rs.OutcomeUnknown):
                await drive.write_pr_trigger(idm_rs.PrTrigger.START_PATH_3)
            return await drive.read_peak_current()

    assert asyncio.run(run()) == pytest.approx(2.2)  # and a read right after it is fine
    assert _requests(log, "0x06") == 1


def test_a_word_write_at_an_address_the_map_does_not_describe_is_sent_once(simulator: SimulatorFactory, tmp_path: Path) -> None:
    # Nothing says what 0x7FF0 does: it is not known to be a setting, so it is not repeated.
    port, log = _dropping_first_answer(simulator, IDM, tmp_path)
    result = _regmap("write", IDM, "--words", "0x7FF0=1", "--tcp", f"127.0.0.1:{port}", "--timeout", "0.4", "--retries", "2")
    assert _requests(log, "0x06") == 1, log.read_text(encoding="utf-8")
    assert result.returncode == OUTCOME_UNKNOWN_EXIT, result
    assert "an address the map does not describe" in result.stderr
