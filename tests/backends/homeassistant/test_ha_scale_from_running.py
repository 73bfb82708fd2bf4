"""Home Assistant (the hass tool env's 2024.3, offline) polling `regmap simulate` of the scale_from fixture over
Modbus TCP with the generated package (every register selected, the hub moved from the serial line to the
simulator's port): each template sensor must record the value the Python client (`regmap dump`) reads -- with
a negative sf (12.34 A), a positive one, and nothing (unavailable) where the point or its sf reads 'not
available'. An automation then calls the generated set script: at sf 1, three values the runtime refuses (no
whole multiple of 10^sf, outside the raw range, not a number) must send nothing and a fourth exactly one write
of its raw value; with the sf reading 'not available' a value that sf 1 would take must send nothing.
HA's log says how each call's condition came out; the simulator's log holds every write it received.
A plant of two inverters on one TCP bus (`regmap simulate PLANT --bus`): each device's templates show its own
slave's values."""

from __future__ import annotations

import json
import re
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import pytest
import yaml

from regmap.backends.homeassistant import render_device, render_plant
from regmap.frontend import load_map
from regmap.frontend.plant import load_plant

from conftest import ROOT, SimulatorFactory
from support.hass_recorder import recorded_states
from support.hass_running import hub_on_tcp, running_hass
from support.homeauto_yaml import load
from support.plant_tcp_bus import free_port, serve_bus, write_plant

MAP = ROOT / "tests" / "maps" / "scaled_from" / "inverter.yaml"
REGMAP = str(Path(sys.executable).parent / "regmap")
STARTUP_S, STATES_S = 300, 180
# Raw values the simulator holds: a negative sf (a), the point's own n/a (w), its sf's n/a (wh), a positive sf.
SEED = {"a": 1234, "a_sf": -2, "w": -32768, "w_sf": 1, "wh": 123456, "wh_sf": -32768, "wmax_lim_pct": 1000, "wmax_lim_pct_sf": 1}
REFUSED: tuple[object, ...] = (15, 20000, "abc")  # at sf 1: not a multiple of 10; raw 2000 > 1000; not a number
ACCEPTED, ACCEPTED_RAW = 2500, 250
# case -> (raw values the simulator starts from, the values the automation passes to the script, the raw value written)
CASES: dict[str, tuple[dict[str, int], tuple[object, ...], list[int]]] = {
    "sf_known": (SEED, (*REFUSED, ACCEPTED), [ACCEPTED_RAW]),
    "sf_not_available": (SEED | {"wmax_lim_pct_sf": -32768}, (ACCEPTED,), []),
}
CONDITION = re.compile(r"\[homeassistant\.components\.script\.sf_inverter_set_wmax_lim_pct\] .*Test condition template: (True|False)")
SCRIPT = "script.sf_inverter_set_wmax_lim_pct"
NO_VALUE = ("unknown", "unavailable")
_WRITE = re.compile(r"> MBAP transaction \d+, unit (?P<unit>\d+), PDU (?P<pdu>(?:06|10)(?: [0-9a-fA-F]{2})+)$", re.MULTILINE)


def _writes(log: Path) -> list[bytes]:
    """The PDUs of the write requests (0x06, 0x10) the simulator logged."""
    text = log.read_text(encoding="utf-8") if log.exists() else ""
    return [bytes.fromhex(m["pdu"]) for m in _WRITE.finditer(text)]


def _dump(port: int, slave: int = 1) -> dict[str, Any]:
    """Each register's value as the Python client reads it (None: not available)."""
    result = subprocess.run(
        [REGMAP, "dump", str(MAP), "--tcp", f"127.0.0.1:{port}", "--slave", str(slave), "--json"],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=60,
        check=True,
    )
    return {row["register"]: row["value"] for row in json.loads(result.stdout)}


def _package_on_tcp(port: int) -> dict[str, Any]:
    """The generated package with its hub moved to the simulator's TCP port: only the connection keys change."""
    (text,) = render_device(load_map(MAP), ("*",)).values()
    package = load(text)
    hub_on_tcp(package, port)
    assert isinstance(package, dict)
    return package


def _configuration(config: Path, package: dict[str, Any] | str, values: tuple[object, ...]) -> None:
    config.mkdir()
    text = package if isinstance(package, str) else yaml.safe_dump(package, sort_keys=False, allow_unicode=True)
    (config / "inverter.yaml").write_text(text, encoding="utf-8")
    calls = [{"service": SCRIPT, "data": {"value": value}} for value in values]
    automation = {
        "id": "regmap_set_scaled_point",
        "alias": "regmap test: call the generated set script",
        "trigger": [{"platform": "homeassistant", "event": "start"}],
        "action": [{"wait_template": "{{ has_value('sensor.ac_current') }}", "timeout": STARTUP_S, "continue_on_timeout": False}, *calls],
    }
    basics = {"name": "regmap scale_from test", "latitude": 0, "longitude": 0, "elevation": 0, "unit_system": "metric", "time_zone": "UTC"}
    rest: dict[str, Any] = {
        "recorder": {"db_url": f"sqlite:///{config / 'recorder.db'}", "commit_interval": 1},
        "logger": {"default": "info"},
    }
    if calls:
        rest["automation"] = [automation]
    head = yaml.safe_dump({"homeassistant": basics}, sort_keys=False) + "  packages:\n    inverter: !include inverter.yaml\n"
    (config / "configuration.yaml").write_text(head + yaml.safe_dump(rest, sort_keys=False), encoding="utf-8")


def _shows(state: str | None, value: float | None) -> bool:
    if value is None:
        return state in NO_VALUE
    try:
        return state is not None and abs(float(state) - value) <= 1e-9 * max(1.0, abs(value))
    except ValueError:
        return False


def _conditions(log: Path) -> list[str]:
    """How each call of the set script's condition came out, from HA's log ("True": it went on to the write)."""
    return CONDITION.findall(log.read_text(errors="replace")) if log.exists() else []


@pytest.mark.timeout(STARTUP_S + STATES_S + 180)
@pytest.mark.parametrize("case", list(CASES))
def test_home_assistant_shows_scaled_values_and_the_script_sends_only_exact_ones(
    case: str, simulator: SimulatorFactory, tmp_path: Path
) -> None:
    seed, values, written = CASES[case]
    device = load_map(MAP)
    state = tmp_path / "inverter.state.json"
    state.write_text(json.dumps({"device": device.id, "map_version": device.info.map_version, "registers": seed}), encoding="utf-8")
    sim_log = tmp_path / "simulator.log"
    sim = simulator(MAP, "--state", str(state), "--log", str(sim_log))
    assert sim.port is not None
    client = _dump(sim.port)
    assert client["a"] == 12.34 and client["w"] is None and client["wh"] is None
    assert client["wmax_lim_pct"] == (10000 if seed["wmax_lim_pct_sf"] == 1 else None)
    package = _package_on_tcp(sim.port)
    points = [reg for reg in device.registers if reg.scale_from is not None]
    templates = {e["unique_id"]: e["name"] for block in package["template"] for e in block["sensor"]}
    expected = {templates[f"sf_inverter_{reg.name}"]: client[reg.name] for reg in points}
    config = tmp_path / "config"
    _configuration(config, package, values)

    home_log = config / "home-assistant.log"

    def settled(recorded: dict[str, str]) -> bool:
        called = len(_conditions(home_log)) == len(values) and len(_writes(sim_log)) >= len(written)
        return called and all(_shows(recorded.get(name), value) for name, value in expected.items())

    with running_hass(config, tmp_path / "hass.log") as process:
        started = time.monotonic()
        recorded: dict[str, str] = {}
        while time.monotonic() - started < STARTUP_S + STATES_S and process.poll() is None:
            recorded = {name: s for name, (_, s, _) in recorded_states(config / "recorder.db").items()}
            if settled(recorded):
                break
            time.sleep(1)
        time.sleep(3)  # a write after the last condition would show in the simulator's log by now
        tail = home_log.read_text(errors="replace")[-4000:] if home_log.exists() else ""
        assert settled(recorded), f"{ {name: recorded.get(name) for name in expected} } expected {expected}\n{tail}"
        assert _conditions(home_log) == ["False"] * (len(values) - len(written)) + ["True"] * len(written), tail
        assert _writes(sim_log) == [bytes([0x06, 0x00, 0x10]) + raw.to_bytes(2, "big") for raw in written], tail
        print(f"{case}: HA showed {expected}, sent {written}, {time.monotonic() - started:.1f} s after start")
    assert _dump(sim.port)["wmax_lim_pct"] == (ACCEPTED if written else None)


# The second inverter of the plant: other values, other signs of sf, none 'not available'.
SECOND = {"a": 500, "a_sf": 1, "w": -1500, "w_sf": -1, "wh": 123456, "wh_sf": 2, "wmax_lim_pct": 700, "wmax_lim_pct_sf": -1}


@pytest.mark.timeout(STARTUP_S + STATES_S + 180)
def test_home_assistant_shows_each_plant_devices_own_scaled_values(tmp_path: Path) -> None:
    line = [("line", f"tcp: {{host: 127.0.0.1, port: {free_port()}}}", [("inv1", MAP, 1), ("inv2", MAP, 2)])]
    plant = load_plant(write_plant(tmp_path / "plant.yaml", "pv", line))
    (bus,) = plant.buses
    (text,) = render_plant(plant).values()
    templates = {e["unique_id"]: e["name"] for block in load(text)["template"] for e in block["sensor"]}
    states: dict[str, Path] = {}
    for dev, seed in (("inv1", SEED), ("inv2", SECOND)):
        device = plant.device(dev)[1].device
        states[dev] = tmp_path / f"{dev}.state.json"
        body = {"device": device.id, "map_version": device.info.map_version, "registers": seed}
        states[dev].write_text(json.dumps(body), encoding="utf-8")
    config = tmp_path / "config"
    _configuration(config, text, ())
    with serve_bus(plant, bus, tmp_path, states) as served, running_hass(config, tmp_path / "hass.log") as process:
        clients = {dev.name: _dump(served.port, dev.slave) for dev in bus.devices}
        assert clients["inv2"]["a"] == 5000 and clients["inv2"]["w"] == -150.0 and clients["inv2"]["wh"] == 12345600
        expected = {name: clients[uid.split("_")[1]][uid.split("_", 2)[2]] for uid, name in templates.items()}
        assert len(expected) == 6 and expected["inv1 AC current"] == 12.34
        started = time.monotonic()
        recorded: dict[str, str] = {}
        while time.monotonic() - started < STARTUP_S + STATES_S and process.poll() is None:
            recorded = {name: s for name, (_, s, _) in recorded_states(config / "recorder.db").items()}
            if all(_shows(recorded.get(name), value) for name, value in expected.items()):
                break
            time.sleep(1)
        log = config / "home-assistant.log"
        tail = log.read_text(errors="replace")[-4000:] if log.exists() else ""
        shown = {name: recorded.get(name) for name in expected}
        assert all(_shows(shown[name], value) for name, value in expected.items()), f"{shown} expected {expected}\n{tail}"
        print(f"plant: HA showed {shown}, {time.monotonic() - started:.1f} s after start")
