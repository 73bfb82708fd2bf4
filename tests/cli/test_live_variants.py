"""Live commands know the device's variant: from the plant file (`--bus --device`) or `--variant`. A register the
variant lacks is refused before the port opens (read, write, command), left out of `dump`, and no read reaches
across its words; `regmap simulate PLANT --bus` listens where the plant's bus is when that is this machine."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from regmap.frontend.plant import load_plant

from conftest import FIXTURE_MAPS, ROOT, free_port
from support.plant_tcp_bus import serve_bus
from support.plants import write_meter_plant

METER = next(p for p in FIXTURE_MAPS if p.stem == "float_meter")
REGMAP = str(Path(sys.executable).with_name("regmap"))


def _regmap(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([REGMAP, *args], capture_output=True, text=True, check=False, cwd=ROOT, timeout=60)


@pytest.fixture
def meters(tmp_path: Path) -> Path:
    return write_meter_plant(tmp_path, "meters", f"tcp: {{host: 127.0.0.1, port: {free_port()}}}")


def test_a_register_the_plant_devices_variant_lacks_is_refused_and_nothing_reaches_the_bus(meters: Path, tmp_path: Path) -> None:
    plant = load_plant(meters)
    (bus,) = plant.buses
    with serve_bus(plant, bus, tmp_path) as served:
        refused = _regmap("read", str(meters), "--bus", "line1", "--device", "m1", "voltage_l2")
        assert refused.returncode == 2, refused.stderr
        assert "voltage_l2 exists only on variant three_phase; the device is single_phase: nothing was read" in refused.stderr
        read = _regmap("read", str(meters), "--bus", "line1", "--device", "m3", "voltage_l2")
        assert read.returncode == 0 and read.stdout.startswith("voltage_l2 = "), read.stderr
        dumped = _regmap("dump", str(meters), "--bus", "line1", "--device", "m1", "--json")
        assert dumped.returncode == 0, dumped.stderr
        device = bus.device("m1").device
        names = {r.name for r in device.registers if r.access.readable and r.on_variant("single_phase")}
        assert {line.split('"register": "')[1].split('"')[0] for line in dumped.stdout.split("{") if '"register": "' in line} == names
    log = served.log.read_text(encoding="utf-8")
    assert " 84 " not in log, log  # no request of the refused read, none answered with an exception


def test_variant_given_on_the_command_line(tmp_path: Path, meters: Path) -> None:
    wrong = _regmap("read", str(METER), "--tcp", "127.0.0.1:9", "--variant", "two_phase", "voltage_l1")
    assert wrong.returncode == 2 and "--variant two_phase: fixture_float_meter declares single_phase, three_phase" in wrong.stderr
    other = _regmap("read", str(meters), "--bus", "line1", "--device", "m1", "--variant", "three_phase", "voltage_l1")
    assert other.returncode == 2 and "--variant three_phase: the plant says m1 is single_phase" in other.stderr
    offline = _regmap("read", str(METER), "--tcp", "127.0.0.1:9", "--variant", "single_phase", "voltage_l2")
    assert offline.returncode == 2 and "nothing was read" in offline.stderr  # refused before a connection is tried


def test_simulate_listens_at_a_loopback_bus_address_and_warns_of_a_remote_one(tmp_path: Path, meters: Path) -> None:
    port = load_plant(meters).buses[0].tcp.port  # type: ignore[union-attr]
    process = subprocess.Popen(
        [REGMAP, "simulate", str(meters), "--bus", "line1"], cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True
    )
    try:
        assert process.stdout is not None
        banner = process.stdout.readline()
        assert f"on 127.0.0.1:{port} " in banner, banner
        read = _regmap("read", str(meters), "--bus", "line1", "--device", "m3", "voltage_l2")  # no --tcp: the plant's address
        assert read.returncode == 0, read.stderr
    finally:
        process.terminate()
        process.wait(timeout=10)
    # a bus on another machine (192.0.2.10: TEST-NET, never contacted): the default address, and a word that the
    # plant's clients talk to the plant's address, not to this simulator (said before the port is bound)
    remote = tmp_path / "remote.yaml"
    remote.write_text(meters.read_text(encoding="utf-8").replace("host: 127.0.0.1", "host: 192.0.2.10"), encoding="utf-8")
    process = subprocess.Popen(
        [REGMAP, "simulate", str(remote), "--bus", "line1"], cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True
    )
    try:
        assert process.stdout is not None
        said = process.stdout.readline()
        assert said.startswith("regmap simulate: bus line1 is at 192.0.2.10:") and "not to this simulator" in said, said
    finally:
        process.terminate()
        process.wait(timeout=10)
