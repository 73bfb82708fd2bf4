"""Option values and messages (issue #28, items 6-8): every value the command line takes is checked
where it is parsed and refused in one line naming the option, the value and what is allowed; the
messages say what happened in regmap's words (never pymodbus's); `simulate` takes the line settings."""

from __future__ import annotations

import socket
import subprocess
import sys
import threading
from collections.abc import Iterator
from pathlib import Path

import pytest

from regmap.diagnostics import ExitCode

from conftest import ROOT, SimulatorFactory

IDM = "maps/idm_rs.yaml"
POWER_METER = "tests/maps/fixtures/power_meter.yaml"  # its line: 9600 baud, even parity
CLOSED_PORT = ("--tcp", "127.0.0.1:1")  # refuses connections: a value that passed the checks fails with 4, not 2


def regmap(*args: str, cwd: Path = ROOT, timeout: float = 30) -> subprocess.CompletedProcess[str]:
    """`regmap ARGS` as a process; one that is still running after `timeout` accepted what it should have refused."""
    try:
        return subprocess.run(
            [sys.executable, "-m", "regmap", *args], cwd=cwd, capture_output=True, text=True, check=False, timeout=timeout
        )
    except subprocess.TimeoutExpired:
        pytest.fail(f"regmap {' '.join(args)} was still running after {timeout} s: it accepted the value")


def one_line_error(result: subprocess.CompletedProcess[str], code: int, *needles: str) -> str:
    assert result.returncode == code, (result.returncode, result.stdout, result.stderr)
    lines = result.stderr.strip().splitlines()
    assert lines and "Traceback" not in result.stderr and "internal error" not in result.stderr, result.stderr
    for needle in needles:
        assert needle in lines[-1], lines[-1]
    return lines[-1]


def test_a_range_error_shows_the_value_as_given() -> None:
    line = one_line_error(regmap("write", POWER_METER, "demand_period=3600.0001", *CLOSED_PORT), ExitCode.USAGE)
    assert line == "regmap write: error: demand_period: 3600.0001 s is outside 1..3600 s"


def test_an_answer_from_another_slave_over_tcp_is_wrong_slave_as_on_rtu(simulator: SimulatorFactory) -> None:
    sim = simulator(ROOT / IDM, "--fault", "wrong_slave")
    result = regmap("read", IDM, "Pr5.00", "--tcp", f"127.0.0.1:{sim.port}", "--timeout", "0.5", "--retries", "0")
    line = one_line_error(result, ExitCode.BUS, "WrongSlave: asked slave 1, the answer came from slave 2: 00 01 00 00 00 05 02 03")
    assert "ProtocolError" not in line


@pytest.fixture
def closes_mid_answer() -> Iterator[int]:
    """A Modbus TCP server that sends the first bytes of an answer, then closes the connection."""
    server = socket.create_server(("127.0.0.1", 0))
    server.settimeout(10)

    def serve() -> None:
        for _ in range(3):  # the first try and the retries
            try:
                connection, _ = server.accept()
            except OSError:
                return
            with connection:
                request = connection.recv(260)
                connection.sendall(request[:4] + b"\x00\x05")  # MBAP: transaction, protocol, length 5 ... and no more

    thread = threading.Thread(target=serve, daemon=True)
    thread.start()
    yield int(server.getsockname()[1])
    server.close()
    thread.join(timeout=10)


def test_a_connection_closed_mid_answer_is_said_in_regmaps_words(closes_mid_answer: int) -> None:
    result = regmap("read", IDM, "Pr5.00", "--tcp", f"127.0.0.1:{closes_mid_answer}", "--timeout", "0.5", "--retries", "0")
    line = one_line_error(result, ExitCode.BUS, "ConnectionLost: the connection closed before the answer was complete")
    for pymodbus_text in ("Modbus Error", "ModbusTcpClient", "unbounded", "unexpectedly"):
        assert pymodbus_text not in line


# -- 8. simulate's line settings -----------------------------------------------------------------
