"""`regmap read/dump/frame` on issue #34's float meter (tests/maps/fixtures/float_meter.yaml), which answers a
read only when it starts on an even address and covers an even count: a raw word read that breaks the rule is
refused in one line (exit 2) before anything is sent; reads by name follow the aligned read plan."""

from __future__ import annotations

import subprocess
import sys

from conftest import ROOT, SimulatorFactory, free_port

FLOAT_METER = "tests/maps/fixtures/float_meter.yaml"


def regmap(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "regmap", *args], cwd=ROOT, capture_output=True, text=True, check=False, timeout=60)


def _refused(result: subprocess.CompletedProcess[str], address: str, count: int) -> None:
    assert result.returncode == 2, (result.returncode, result.stdout, result.stderr)
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in result.stderr, result.stderr
    assert f"a read of {count} word(s) at {address} breaks the device's read alignment" in lines[0], lines[0]
    assert "exception 0x02" in lines[0] and result.stdout == ""


def test_frame_refuses_a_misaligned_word_read() -> None:
    _refused(regmap("frame", FLOAT_METER, "read", "--words", "0x0001", "2", "-t", "input"), "0x0001", 2)
    _refused(regmap("frame", FLOAT_METER, "read", "--words", "0x0000", "3", "-t", "input"), "0x0000", 3)
    ok = regmap("frame", FLOAT_METER, "read", "--words", "0x0104", "1")  # the CT ratio alone: exempted
    assert ok.returncode == 0 and ok.stdout.strip() == "01 03 01 04 00 01 C4 37", ok.stderr
    ok = regmap("frame", FLOAT_METER, "read", "humidity")  # by name: the aligned plan, with the temperature beside it
    assert ok.returncode == 0 and ok.stdout.strip() == "01 04 00 06 00 02 91 CA", ok.stderr


def test_read_refuses_a_misaligned_word_read_before_connecting() -> None:
    """No server listens on the port: a refusal after trying to connect would be a bus error (exit 4)."""
    port = free_port()
    result = regmap("read", FLOAT_METER, "--words", "0x0007", "-t", "input", "--tcp", f"127.0.0.1:{port}")
    _refused(result, "0x0007", 1)


def test_read_and_dump_by_name_follow_the_aligned_plan(simulator: SimulatorFactory) -> None:
    sim = simulator(FLOAT_METER)
    assert sim.port is not None
    where = f"127.0.0.1:{sim.port}"
    result = regmap("read", FLOAT_METER, "humidity", "ct_ratio", "--tcp", where, "--json")
    assert result.returncode == 0, result.stderr
    result = regmap("dump", FLOAT_METER, "--tcp", where, "--json")
    assert result.returncode == 0 and "voltage_alarm" in result.stdout, result.stderr
    result = regmap("read", FLOAT_METER, "--words", "0x0006", "2", "-t", "input", "--tcp", where)
    assert result.returncode == 0, result.stderr
