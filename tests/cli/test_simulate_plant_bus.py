"""`regmap simulate PLANT --bus NAME`: every device of a plant's bus on one port, each at its slave id with its
own map's rules; other ids stay silent, a broadcast write reaches every device of the bus, and the options that
set up one device are refused with a plant."""

from __future__ import annotations

import socket
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

from regmap.frontend import load_map
from regmap_runtime.rtu import with_crc

from conftest import ROOT, free_port, wait_for

MAPS = ROOT / "maps"
PEAK = load_map(MAPS / "idm_rs.yaml").register("peak_current")  # iDM-RS Pr5.00
PEAK_CURRENT = PEAK.address
DEFAULT = int(PEAK.default or 0)  # its raw default, what a fresh simulator holds


def _plant(tmp_path: Path, port: int, extra_bus: bool = False) -> Path:
    text = f"""format: regmap-plant/1
plant: {{id: cell1, title: Assembly cell 1}}
buses:
  - name: line1
    tcp: {{host: 127.0.0.1, port: {port}}}
    devices:
      - {{name: axis_x, map: {MAPS}/idm_rs.yaml, slave: 1}}
      - {{name: axis_y, map: {MAPS}/idm_rs.yaml, slave: 2}}
      - {{name: spindle, map: {MAPS}/c630s.yaml, slave: 3}}
"""
    if extra_bus:
        text += f"""  - name: line2
    tcp: {{host: 127.0.0.1, port: {port + 1}}}
    devices:
      - {{name: stepper, map: {MAPS}/id243pro.yaml, slave: 1}}
"""
    path = tmp_path / "plant.yaml"
    path.write_text(text, encoding="utf-8")
    return path


def _port_open(port: int) -> bool:
    try:
        socket.create_connection(("127.0.0.1", port), timeout=0.5).close()
    except OSError:
        return False
    return True


@pytest.fixture
def served(tmp_path: Path, request: pytest.FixtureRequest) -> Iterator[tuple[int, Path]]:
    port = free_port()
    plant = _plant(tmp_path, port)
    extra: list[str] = list(getattr(request, "param", []))
    log = tmp_path / "bus.log"
    cmd = [
        sys.executable,
        "-m",
        "regmap",
        "simulate",
        str(plant),
        "--bus",
        "line1",
        "--tcp",
        f"127.0.0.1:{port}",
        "--log",
        str(log),
        *extra,
    ]
    process = subprocess.Popen(cmd, cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    try:
        wait_for(lambda: _port_open(port) or process.poll() is not None, 20, "the bus simulator to listen")
        assert process.poll() is None, process.communicate()[0]
        yield port, log
    finally:
        process.terminate()
        process.wait(timeout=10)


def _mbap(sock: socket.socket, unit: int, pdu: bytes, transaction: int = 1) -> bytes | None:
    sock.sendall(transaction.to_bytes(2, "big") + b"\0\0" + (len(pdu) + 1).to_bytes(2, "big") + bytes([unit]) + pdu)
    try:
        header = sock.recv(7)
    except TimeoutError:
        return None
    return header + sock.recv(int.from_bytes(header[4:6], "big") - 1)


def test_each_slave_answers_with_its_own_map_and_other_ids_stay_silent(served: tuple[int, Path]) -> None:
    port, log = served
    with socket.create_connection(("127.0.0.1", port), timeout=1.5) as sock:
        read_peak = bytes([0x03]) + PEAK_CURRENT.to_bytes(2, "big") + (1).to_bytes(2, "big")
        for unit in (1, 2):
            assert _mbap(sock, unit, read_peak) == b"\x00\x01\x00\x00\x00\x05" + bytes([unit, 0x03, 0x02]) + DEFAULT.to_bytes(2, "big")
        # The C630S at slave 3 documents no 0x0191: its own map's exception, not an iDM-RS value.
        assert _mbap(sock, 3, read_peak) == b"\x00\x01\x00\x00\x00\x03\x03\x83\x02"
        assert _mbap(sock, 9, read_peak) is None  # nobody at slave 9
        assert _mbap(sock, 0xFF, read_peak) is None  # several devices: 0xFF addresses none of them directly
    text = log.read_text(encoding="utf-8")
    assert "unit 1" in text and "unit 3" in text


@pytest.mark.parametrize("served", [["--rtu-over-tcp"]], indirect=True)
def test_a_broadcast_write_reaches_every_device_and_gets_no_reply(served: tuple[int, Path]) -> None:
    port, _ = served
    with socket.create_connection(("127.0.0.1", port), timeout=1.0) as sock:
        sock.sendall(with_crc(bytes([0x00, 0x06]) + PEAK_CURRENT.to_bytes(2, "big") + (30).to_bytes(2, "big")))
        with pytest.raises(TimeoutError):
            sock.recv(64)
        time.sleep(0.1)
        for unit in (1, 2):
            sock.sendall(with_crc(bytes([unit, 0x03]) + PEAK_CURRENT.to_bytes(2, "big") + (1).to_bytes(2, "big")))
            time.sleep(0.2)
            assert sock.recv(64) == with_crc(bytes([unit, 0x03, 0x02, 0x00, 30]))


def _simulate(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "regmap", "simulate", *args], cwd=ROOT, capture_output=True, text=True, timeout=60)


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (["--bus", "line1", "--slave", "2"], "--slave: one device's setting"),
        (["--bus", "line1", "--firmware", "1.0"], "--firmware: one device's setting"),
        (
            ["--bus", "line1", "--variant", "three_phase"],
            "--variant: one device's setting; a plant's bus takes its devices, slave ids and variants",
        ),
        (["--bus", "line9"], "--bus line9: "),
        ([], "has 2 buses: name one with --bus (line1, line2)"),
        (["--bus", "line1", "--state-dir", "/nonexistent/dir"], "--state-dir /nonexistent/dir: not a directory"),
    ],
)
def test_one_device_options_and_unknown_buses_are_refused(tmp_path: Path, extra: list[str], message: str) -> None:
    plant = _plant(tmp_path, free_port(), extra_bus=True)
    result = _simulate(str(plant), "--tcp", f"127.0.0.1:{free_port()}", *extra)
    assert result.returncode == 2 and message in result.stderr and "Traceback" not in result.stderr, result.stderr


def test_bus_options_are_refused_with_a_map() -> None:
    result = _simulate(str(MAPS / "idm_rs.yaml"), "--bus", "line1")
    assert result.returncode == 2 and "--bus and --state-dir serve a plant's bus" in result.stderr


def _regmap(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "regmap", *args], cwd=ROOT, capture_output=True, text=True, timeout=60)


def test_read_and_write_talk_to_one_device_of_the_plant(served: tuple[int, Path], tmp_path: Path) -> None:
    port, _ = served
    plant = str(tmp_path / "plant.yaml")
    written = _regmap("write", plant, "--bus", "line1", "--device", "axis_y", "peak_current=3.0")
    assert written.returncode == 0 and "peak_current = 3 A (raw 30)  (verified)" in written.stdout, written.stderr
    with socket.create_connection(("127.0.0.1", port), timeout=1.5) as sock:
        read_peak = bytes([0x03]) + PEAK_CURRENT.to_bytes(2, "big") + (1).to_bytes(2, "big")
        assert _mbap(sock, 2, read_peak) == b"\x00\x01\x00\x00\x00\x05\x02\x03\x02\x00\x1e"  # axis_y written
        assert _mbap(sock, 1, read_peak) == b"\x00\x01\x00\x00\x00\x05\x01\x03\x02" + DEFAULT.to_bytes(2, "big")  # axis_x untouched
    spindle = _regmap("read", plant, "--bus", "line1", "--device", "spindle", "P02-00")
    assert spindle.returncode == 0 and "P02-00 control_mode" in spindle.stdout, spindle.stderr
    refused = _regmap("write", plant, "--bus", "line1", "--device", "axis_x", "peak_current=99")
    assert refused.returncode == 2 and refused.stderr.count("\n") == 1 and "outside 0..8 A" in refused.stderr


def test_a_plant_file_where_a_map_is_wanted_is_one_line(tmp_path: Path) -> None:
    plant = str(_plant(tmp_path, free_port()))
    shown = _regmap("show", plant, "peak_current")
    assert shown.returncode == 2 and shown.stderr.count("\n") == 1 and "is a plant file, not a map" in shown.stderr
    read = _regmap("read", plant, "peak_current")
    assert (
        read.returncode == 2
        and read.stderr == f"regmap read: error: {plant} is a plant file: name the device with --bus NAME --device NAME\n"
    )
