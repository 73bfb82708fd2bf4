"""The generated Python plant client: one connection per bus, every device's typed client on it, read_all()
interleaved in the shared schedule's order, the serial line's timing kept (measured where the bytes cross a pty).

The bus is tests/support/plant_bus.py (the simulator's own store and dispatcher per slave id behind one pty or
one TCP socket, time-stamping every byte), and `regmap simulate PLANT --bus` itself for the TCP plant."""

from __future__ import annotations

import importlib
import itertools
import json
import re
import socket
import subprocess
import sys
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest

from regmap.frontend.plant import load_plant
from regmap.runtime_bridge import plant_schedule
from regmap_runtime.rtu import build_read

from conftest import GENERATED, ROOT, free_port, mypy_strict, require_tool, wait_for
from support.fake_clock import FakeClock
from support.plant_bus import PtyBus, TcpBus
from support.plants import generate_python_plant, write_plant

CELL1_PY = GENERATED / "plants" / "cell1" / "python"
# examples/plants/cell1.yaml's devices on a line without parity: a Linux pty refuses parity settings (EINVAL).
CELL = [("axis_x", "idm_rs.yaml", 1), ("axis_y", "idm_rs.yaml", 2), ("spindle", "c630s.yaml", 3)]


@pytest.fixture
def socat() -> str:
    return require_tool("socat")


@dataclass
class PlantOnPty:
    bus: PtyBus
    module: Any
    plant_file: Path


@pytest.fixture
def cell_on_pty(socat: str, tmp_path: Path) -> Iterator[PlantOnPty]:
    plant_file = write_plant(tmp_path, "cellpty", "serial: {port: /dev/null, baud: 38400, parity: none}", CELL)
    module = generate_python_plant(plant_file, tmp_path / "out")
    bus = PtyBus({dev.slave: dev.device for dev in load_plant(plant_file).devices}, socat, tmp_path)
    yield PlantOnPty(bus, module, plant_file)
    bus.close()


def _set(bus: PtyBus | TcpBus, slave: int, register: str, raw: int) -> None:
    store = bus.stores[slave]
    store.store_raw(store.device.register(register), raw)


def test_read_all_reads_every_device_through_one_line_in_the_schedule_order(cell_on_pty: PlantOnPty) -> None:
    bus = cell_on_pty.bus
    _set(bus, 1, "peak_current", 42)  # 4.2 A
    _set(bus, 2, "peak_current", 17)
    with cell_on_pty.module.Cellpty(line1_port=bus.path, timeout=2.0) as plant:
        values = plant.read_all()
        assert values["axis_x"]["peak_current"] == pytest.approx(4.2)
        assert values["axis_y"]["peak_current"] == pytest.approx(1.7)
        assert set(values) == {"axis_x", "axis_y", "spindle"}
        for name in ("axis_x", "axis_y", "spindle"):
            client = getattr(plant, name)
            assert set(values[name]) == {spec.name for spec in client.readable()}, name
        assert plant.axis_x.modbus is plant.axis_y.modbus is plant.spindle.modbus  # one connection for the bus
    seen = [(e.slave, e.function, e.start, e.count) for e in bus.exchanges]
    (schedule,) = plant_schedule(load_plant(cell_on_pty.plant_file))
    assert seen == [(e.slave, e.function, e.start, e.count) for e in schedule.entries]
    assert [slave for slave, *_ in seen[:6]] == [1, 2, 3, 1, 2, 3]  # round robin, block by block


def test_two_instances_of_one_map_are_two_slaves_on_the_line(cell_on_pty: PlantOnPty) -> None:
    bus = cell_on_pty.bus
    _set(bus, 1, "peak_current", 30)
    _set(bus, 2, "peak_current", 60)
    with cell_on_pty.module.Cellpty(line1_port=bus.path, timeout=2.0) as plant:
        assert plant.axis_x.read_peak_current() == pytest.approx(3.0)
        assert plant.axis_y.read_peak_current() == pytest.approx(6.0)
        plant.axis_y.write_peak_current(5.5)
        assert plant.axis_y.read_peak_current() == pytest.approx(5.5)
        assert plant.axis_x.read_peak_current() == pytest.approx(3.0)
    store_x, store_y = bus.stores[1], bus.stores[2]
    assert store_x.raw_of(store_x.device.register("peak_current")) == 30
    assert store_y.raw_of(store_y.device.register("peak_current")) == 55


def test_the_serial_schedule_keeps_the_silence_and_each_devices_turnaround(socat: str, tmp_path: Path) -> None:
    # 9600 baud: a 3.6 ms silence (3.5 characters of 10 bits) and the iDM-RS's 24.9 ms turnaround, both well above
    # the jitter of a loaded machine; the C630S's turnaround is its 1 ms response delay.
    plant_file = write_plant(
        tmp_path,
        "slowline",
        "serial: {port: /dev/null, baud: 9600, parity: none}",
        [("near", "idm_rs.yaml", 1), ("far", "idm_rs.yaml", 2), ("spindle", "c630s.yaml", 3)],
    )
    module = generate_python_plant(plant_file, tmp_path / "out")
    plant_model = load_plant(plant_file)
    line = plant_model.buses[0].serial
    assert line is not None
    turnaround = {dev.slave: dev.turnaround_s(line.baud) for dev in plant_model.devices}
    bus = PtyBus({dev.slave: dev.device for dev in plant_model.devices}, socat, tmp_path)
    try:
        with module.Slowline(line1_port=bus.path, timeout=2.0) as plant:
            for client in (plant.near, plant.far, plant.spindle):
                client.read_raw(0x0000 if client is not plant.spindle else 0x0100, 1)
            plant.near.read_peak_current()
            plant.far.read_peak_current()
    finally:
        bus.close()
    exchanges = bus.exchanges
    assert len(exchanges) == 5
    for before, after in itertools.pairwise(exchanges):
        assert before.answered is not None
        # The answer was stamped before it was written: this gap can only be longer than the master waited. (pymodbus's
        # own receive loop already waits 8 characters after an answer; the plant's pacing is shown on a fake clock too.)
        assert after.request_first - before.answered >= line.silence_s
        # From the end of the request to the next one: the turnaround of the device just addressed (the pty
        # hands bytes on at once; 3 ms for the test thread's scheduling).
        assert after.request_first - before.request_last >= turnaround[before.slave] - 0.003, (before, after)
    assert line.silence_s == pytest.approx(3.5 * 10 / 9600)
    assert turnaround[1] == pytest.approx(0.0249)


def test_a_tcp_bus_reads_every_device_through_one_connection(tmp_path: Path) -> None:
    devices = [("near", "idm_rs.yaml", 1), ("far", "idm_rs.yaml", 2), ("drive", "id243pro.yaml", 7)]
    plant_file = write_plant(tmp_path, "gateway", "tcp: {host: 127.0.0.1, port: 502}", devices)
    module = generate_python_plant(plant_file, tmp_path / "out")
    bus = TcpBus({dev.slave: dev.device for dev in load_plant(plant_file).devices})
    try:
        _set(bus, 2, "peak_current", 25)
        with module.Gateway(line1_port=bus.port) as plant:
            values = plant.read_all()
        assert values["far"]["peak_current"] == pytest.approx(2.5)
        assert set(values) == {"near", "far", "drive"}
        assert bus.connections == 1
        assert {e.slave for e in bus.exchanges} == {1, 2, 7}
    finally:
        bus.close()


def test_the_plant_client_reads_every_device_from_the_multi_unit_simulator(tmp_path: Path) -> None:
    """The real `regmap simulate PLANT --bus line1` (one port, one store per slave id), not the test bus."""
    port = free_port()
    devices = [("axis_x", "idm_rs.yaml", 1), ("axis_y", "idm_rs.yaml", 2), ("spindle", "c630s.yaml", 3)]
    plant_file = write_plant(tmp_path, "simcell", f"tcp: {{host: 127.0.0.1, port: {port}}}", devices)
    module = generate_python_plant(plant_file, tmp_path / "out")
    states = tmp_path / "states"
    states.mkdir()
    plant = load_plant(plant_file)
    for dev, raw in zip(plant.devices[:2], (31, 17), strict=True):
        body = {"device": dev.device.id, "map_version": dev.device.info.map_version, "registers": {"peak_current": raw}}
        (states / f"{dev.name}.json").write_text(json.dumps(body), encoding="utf-8")
    log = tmp_path / "bus.log"
    cmd = [sys.executable, "-m", "regmap", "simulate", str(plant_file), "--tcp", f"127.0.0.1:{port}", "--state-dir", str(states)]
    process = subprocess.Popen([*cmd, "--log", str(log)], cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    try:
        wait_for(lambda: _listening(port) or process.poll() is not None, 20, "the bus simulator to listen")
        with module.Simcell(line1_port=port) as cell:
            values = cell.read_all()
    finally:
        process.terminate()
        process.wait(timeout=10)
    assert values["axis_x"]["peak_current"] == pytest.approx(3.1) and values["axis_y"]["peak_current"] == pytest.approx(1.7)
    assert set(values) == {"axis_x", "axis_y", "spindle"} and len(values["spindle"]) > 100
    peers = set(re.findall(r"^\S+ (\S+) > MBAP", log.read_text(encoding="utf-8"), re.MULTILINE))
    assert len(peers) == 1, peers  # every request of the cycle came through one connection
    (schedule,) = plant_schedule(plant)
    units = [int(u) for u in re.findall(r"> MBAP transaction \d+, unit (\d+)", log.read_text(encoding="utf-8"))]
    assert units == [e.slave for e in schedule.entries]  # in the schedule's order, nothing else


def _listening(port: int) -> bool:
    try:
        socket.create_connection(("127.0.0.1", port), timeout=0.5).close()
    except OSError:
        return False
    return True


def _cell1_module() -> Any:
    sys.path.insert(0, str(CELL1_PY))
    try:
        return importlib.import_module("cell1_plant")
    finally:
        sys.path.remove(str(CELL1_PY))


def test_the_generated_plant_paces_its_line_as_the_plant_file_says() -> None:
    """examples/plants/cell1.yaml at 38400 baud: a 1.75 ms silence; the iDM-RS turns around in 7.12 ms (its timing row
    for 38400), the C630S in 1 ms (its response delay). On a fake clock, without a bus: pymodbus's own receive loop
    waits 8 characters after an answer, so on a pty the silence cannot be told from it."""
    fake = FakeClock()
    plant = _cell1_module().Cell1(clock=fake.clock, sleep=fake.sleep)  # not connected: the hook alone
    line = plant.line1.line
    line(True, build_read(3, 0x0100, 1))  # the spindle
    fake.now += 0.010  # its answer, 10 ms later
    line(False, bytes.fromhex("0303020000B844"))
    answered = fake.now
    line(True, build_read(1, 0x0000, 12))  # axis_x: after the silence (the spindle turned around long ago)
    assert fake.now == pytest.approx(answered + 0.00175)
    sent = fake.now
    fake.now += 0.003  # a quick answer
    line(False, bytes.fromhex("0103020000B844"))
    line(True, build_read(2, 0x0000, 12))  # axis_y: after axis_x's turnaround, counted from the end of its request
    assert fake.now == pytest.approx(sent + 8 * 11 / 38400 + 0.00712)
    assert plant.axis_x.slave == 1 and plant.axis_y.slave == 2 and plant.spindle.slave == 3


def test_the_generated_plant_passes_mypy_strict() -> None:
    result = mypy_strict("cell1_plant.py", cwd=CELL1_PY)
    assert result.returncode == 0, result.stdout + result.stderr


def test_a_name_the_python_plant_would_use_twice_is_refused_at_its_line(tmp_path: Path) -> None:
    from regmap.backends.python.plant import render_plant
    from regmap.diagnostics import MapError

    plant_file = write_plant(tmp_path, "clash", "tcp: {host: 127.0.0.1}", [("line1", "idm_rs.yaml", 1), ("read_all", "idm_rs.yaml", 2)])
    with pytest.raises(MapError) as refused:
        render_plant(load_plant(plant_file))
    text = str(refused.value)
    assert f"{plant_file}:7:" in text and "'line1' already as bus line1" in text
    assert f"{plant_file}:8:" in text and "would shadow its own read_all()" in text
