"""`regmap dump` and `regmap probe` on a plant's device: `PLANT --bus NAME --device NAME` takes the device's map and
slave id from the plant and the line from the bus, unless the command line overrides them."""

from __future__ import annotations

import argparse
import subprocess
import sys
from pathlib import Path

import pytest

from regmap.cli.common import device_and_link
from regmap.diagnostics import UsageError

from conftest import ROOT, SimulatorFactory

CELL1 = "examples/plants/cell1.yaml"


def _args(**given: object) -> argparse.Namespace:
    options: dict[str, object] = {
        "map": CELL1,
        "bus": "line1",
        "device": "axis_y",
        "tcp": None,
        "serial": None,
        "slave": None,
        "baud": None,
        "parity": None,
    }
    options |= {"stop_bits": None, "timeout": 1.0, "retries": 2, "rtu_over_tcp": False, "word_order": None}
    options.update(given)
    return argparse.Namespace(**options)


def test_the_bus_gives_the_line_and_the_plant_the_map_and_slave() -> None:
    device, link = device_and_link(_args())
    assert device.id == "idm_rs"
    assert (link.serial, link.tcp, link.slave, link.baud, link.parity, link.stop_bits) == ("/dev/ttyUSB0", None, 2, 38400, "even", 1)
    spindle, link = device_and_link(_args(device="spindle", tcp="127.0.0.1:5020", slave=9, baud=19200))
    assert spindle.id == "c630s"
    assert (link.serial, link.tcp, link.slave) == (None, "127.0.0.1:5020", 9)  # the command line wins


@pytest.mark.parametrize(
    ("given", "message"),
    [
        ({"device": None}, "name the device with --bus NAME --device NAME"),
        ({"bus": "line9"}, "--bus line9: examples/plants/cell1.yaml has no such bus (buses: line1)"),
        ({"device": "axis_z"}, "--device axis_z: bus line1 has no such device (devices: axis_x, axis_y, spindle)"),
        ({"map": "maps/idm_rs.yaml"}, "--bus and --device pick a device of a plant file; maps/idm_rs.yaml is a map"),
    ],
)
def test_a_wrong_plant_device_is_a_usage_error(given: dict[str, object], message: str) -> None:
    with pytest.raises(UsageError, match=message.replace("(", r"\(").replace(")", r"\)")):
        device_and_link(_args(**given))


def _regmap(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "regmap", *args], cwd=ROOT, capture_output=True, text=True, timeout=120, check=False)


def test_dump_and_probe_reach_the_plant_device_at_its_slave_id(simulator: SimulatorFactory) -> None:
    sim = simulator(Path(ROOT / "maps" / "idm_rs.yaml"), slave=2)  # answers slave 2 only: axis_y's id in the plant
    where = f"127.0.0.1:{sim.port}"
    dumped = _regmap("dump", CELL1, "--bus", "line1", "--device", "axis_y", "--tcp", where, "--csv", "--timeout", "0.5")
    assert dumped.returncode == 0, dumped.stderr
    assert "peak_current" in dumped.stdout
    probed = _regmap("probe", CELL1, "--bus", "line1", "--device", "axis_y", "--tcp", where, "--budget", "60", "--json")
    assert probed.returncode == 0, probed.stderr
    assert '"verdict": "agrees"' in probed.stdout and f'"where": "{where}"' in probed.stdout
    other = _regmap("dump", CELL1, "--bus", "line1", "--device", "axis_x", "--tcp", where, "--timeout", "0.3", "--retries", "0")
    assert other.returncode == 4  # slave 1 is not on this simulator: silence
    missing = _regmap("dump", CELL1, "--tcp", where)
    assert missing.returncode == 2 and "--bus NAME --device NAME" in missing.stderr and "Traceback" not in missing.stderr
