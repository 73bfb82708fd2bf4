"""Faults on the bus: the client raises the right typed error or retries, and never returns a wrong value."""

from __future__ import annotations

import subprocess
import sys
from typing import Any

import pytest

from conftest import ROOT, SimulatorFactory, generated_runtime
from support.clients import client_module

_errors = generated_runtime("errors")
CrcError = _errors.CrcError
DeviceException = _errors.DeviceException
DeviceTimeout = _errors.DeviceTimeout
ProtocolError = _errors.ProtocolError
RegmapError = _errors.RegmapError

IDM = ROOT / "maps" / "idm_rs.yaml"


def _drive(port: int, retries: int = 0, timeout: float = 0.5) -> Any:
    idm = client_module("idm_rs")
    return idm.IdmRs.tcp("127.0.0.1", port, slave=1, timeout=timeout, retries=retries, rtu_over_tcp=True)


@pytest.mark.parametrize(
    ("fault", "error"),
    [
        ("no_answer", DeviceTimeout),
        ("bad_crc", CrcError),  # an answer came, but damaged: told apart from silence
        ("truncated", ProtocolError),
        ("wrong_slave", RegmapError),
        ("wrong_function", RegmapError),
        ("delay", DeviceTimeout),
    ],
)
def test_every_fault_raises_and_never_returns_a_value(simulator: SimulatorFactory, fault: str, error: type[Exception]) -> None:
    sim = simulator(IDM, "--rtu-over-tcp", "--fault", fault, "--fault-delay", "1.5")
    assert sim.port is not None
    drive: Any = _drive(sim.port)
    with drive, pytest.raises(error):
        value = drive.read_peak_current()
        pytest.fail(f"{fault}: the client returned {value!r}")


def test_exception_fault_is_a_typed_device_exception(simulator: SimulatorFactory) -> None:
    sim = simulator(IDM, "--rtu-over-tcp", "--fault", "exception", "--fault-exception", "0x08")
    assert sim.port is not None
    with _drive(sim.port) as drive:
        with pytest.raises(DeviceException) as info:
            drive.read_peak_current()
        assert info.value.code == 0x08
        assert info.value.name == "crc_error" or "CRC" in info.value.meaning


@pytest.mark.parametrize("fault", ["no_answer", "bad_crc", "truncated"])
def test_retries_recover_from_one_lost_answer(simulator: SimulatorFactory, fault: str) -> None:
    sim = simulator(IDM, "--rtu-over-tcp", "--fault", fault, "--fault-count", "1")
    assert sim.port is not None
    with _drive(sim.port, retries=2) as drive:
        assert drive.read_peak_current() == pytest.approx(2.2)


def test_dump_interrupted_by_a_fault_reports_what_was_read(simulator: SimulatorFactory) -> None:
    # The first three answers are fine, then the drive stops answering.
    sim = simulator(IDM, "--rtu-over-tcp", "--fault", "no_answer", "--fault-after", "3")
    assert sim.port is not None
    result = subprocess.run(
        [
            sys.executable,
            "-m",
            "regmap",
            "dump",
            str(IDM),
            "--tcp",
            f"127.0.0.1:{sim.port}",
            "--rtu-over-tcp",
            "--timeout",
            "0.3",
            "--retries",
            "0",
        ],
        cwd=ROOT,
        capture_output=True,
        text=True,
        check=False,
        timeout=60,
    )
    assert result.returncode == 4
    assert "request 4 of" in result.stderr
    read_names = {line.split(" = ")[0].split()[-1] for line in result.stdout.splitlines()}
    assert "pulses_per_revolution" in read_names  # from the first requests
    assert "not read: " in result.stderr
    unread = result.stderr.split("not read: ")[1]
    assert not any(name in unread.split(", ") for name in read_names)


def test_protocol_error_names_the_mismatch() -> None:
    idm = client_module("idm_rs")
    drive = idm.IdmRs.tcp("127.0.0.1", 1)
    ReadBlock = generated_runtime("plan").ReadBlock

    class Short:
        registers = (1,)

    with pytest.raises(ProtocolError, match="asked for 2 registers at 0x0190, got 1"):
        drive.read_words(Short(), ReadBlock(0x0190, 2, ()))
