"""Home Assistant (the hass tool env's pinned version, offline) polling the generated plant package of two float
meters on one Modbus TCP bus, one single-phase and one three-phase, each served as its variant by
`regmap simulate PLANT --bus` (tests/support/plant_tcp_bus.py): the single-phase meter answers voltage_l2 with
exception 0x02. Because the plant names each meter's variant, the package has no voltage_l2 entity for the
single-phase meter, so every entity of both meters reaches the value its simulator holds and none is unavailable."""

from __future__ import annotations

import json
import time
from pathlib import Path
from typing import Any

import pytest
import yaml

from regmap.backends.homeassistant import render_plant
from regmap.frontend.plant import load_plant
from regmap.model import Register

from support.hass_recorder import recorded_states
from support.hass_running import running_hass
from support.homeauto_yaml import load
from support.plant_tcp_bus import free_port, serve_bus
from support.plants import write_meter_plant

STARTUP_S, STATES_S = 300, 120  # deadlines for a loaded machine; both come well within 30 s on an idle one
# Raw values per meter (each register its own value, none a "not available" marker), different per meter.
SEED: dict[str, dict[str, float | int]] = {
    "m1": {"voltage_l1": 230.5, "current_l1": 5.25, "frequency": 50.0, "temperature": 231, "pulse_count": 1234, "last_reset": 1709294400},
    "m3": {
        "voltage_l1": 229.5,
        "current_l1": 7.5,
        "frequency": 49.5,
        "temperature": 198,
        "pulse_count": 4321,
        "voltage_l2": 231.5,
        "last_reset": 1709294400,
    },
}


def _shows_value(reg: Register, raw: float | int, precision: int, state: str) -> bool:
    value = float(raw * reg.scale + reg.offset)
    try:
        return abs(float(state) - value) <= 0.5 * 10.0**-precision + 1e-9
    except ValueError:
        return False


def _configuration(config: Path, package: dict[str, Any]) -> None:
    config.mkdir()
    (config / "meters.yaml").write_text(yaml.safe_dump(package, sort_keys=False, allow_unicode=True), encoding="utf-8")
    basics = {
        "name": "regmap plant variant test",
        "latitude": 0,
        "longitude": 0,
        "elevation": 0,
        "unit_system": "metric",
        "time_zone": "UTC",
    }
    rest = {"recorder": {"db_url": f"sqlite:///{config / 'recorder.db'}", "commit_interval": 1}, "logger": {"default": "info"}}
    head = yaml.safe_dump({"homeassistant": basics}, sort_keys=False) + "  packages:\n    meters: !include meters.yaml\n"
    (config / "configuration.yaml").write_text(head + yaml.safe_dump(rest, sort_keys=False), encoding="utf-8")


@pytest.mark.timeout(STARTUP_S + STATES_S + 120)
def test_home_assistant_shows_every_entity_of_both_variants_and_none_unavailable(tmp_path: Path) -> None:
    plant = load_plant(write_meter_plant(tmp_path, "meters", f"tcp: {{host: 127.0.0.1, port: {free_port()}}}"))
    (bus,) = plant.buses
    states: dict[str, Path] = {}
    for dev in bus.devices:
        states[dev.name] = tmp_path / f"{dev.name}.seed.json"
        body = {"device": dev.device.id, "map_version": dev.device.info.map_version, "registers": SEED[dev.name]}
        states[dev.name].write_text(json.dumps(body), encoding="utf-8")
    (text,) = render_plant(plant).values()
    package = load(text)
    assert isinstance(package, dict)
    (hub,) = package["modbus"]
    by_slave = {dev.slave: dev for dev in bus.devices}
    sensors: dict[str, tuple[str, Register, int]] = {}  # entity name -> (device, register, precision)
    for entity in hub["sensors"]:
        dev = by_slave[int(entity["slave"])]
        reg = dev.device.covering(int(entity["address"]), entity["input_type"])
        assert reg is not None, entity
        assert reg.on_variant(dev.variant), entity  # no entity of a register the device's variant lacks
        sensors[entity["name"]] = (dev.name, reg, int(entity.get("precision", 0)))
    assert {(d, r.name) for d, r, _ in sensors.values() if r.name == "voltage_l2"} == {("m3", "voltage_l2")}
    templates = [e["name"] for block in package.get("template", []) for entities in block.values() for e in entities]
    config = tmp_path / "config"
    _configuration(config, package)

    def settled(recorded: dict[str, str]) -> bool:
        values = all(
            name in recorded and reg.name in SEED[dev] and _shows_value(reg, SEED[dev][reg.name], precision, recorded[name])
            for name, (dev, reg, precision) in sensors.items()
            if reg.name in SEED[dev]
        )
        return values and all(recorded.get(name, "unknown") not in ("unknown", "unavailable") for name in [*sensors, *templates])

    with serve_bus(plant, bus, tmp_path, states) as served, running_hass(config, tmp_path / "hass.log") as process:
        started = time.monotonic()
        recorded: dict[str, str] = {}
        while time.monotonic() - started < STARTUP_S + STATES_S and process.poll() is None:
            recorded = {name: state for name, (_, state, _) in recorded_states(config / "recorder.db").items()}
            if settled(recorded):
                break
            time.sleep(1)
        log = config / "home-assistant.log"
        tail = log.read_text(errors="replace")[-3000:] if log.exists() else ""
        assert settled(recorded), f"{ {name: recorded.get(name) for name in [*sensors, *templates]} }\n{tail}"
        print(
            f"HA showed {len(sensors) + len(templates)} entities of two meters, none unavailable, {time.monotonic() - started:.1f} s after start"
        )
        exceptions = [
            line for line in served.log.read_text(encoding="utf-8").splitlines() if line.startswith("  < MBAP") and " PDU 8" in line
        ]
    assert not exceptions, exceptions[:5]  # not one read answered with an exception
