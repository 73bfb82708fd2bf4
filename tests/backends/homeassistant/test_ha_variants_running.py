"""Home Assistant (the hass tool env's pinned version, offline) polling the generated hub of issue #34's float
meter on a meter of one variant: `regmap simulate float_meter.yaml --variant NAME` over Modbus TCP, where the
registers the variant lacks answer exception 0x02. Every entity the variant has must reach the value the
simulator holds; an entity it lacks (voltage_l2 on the single-phase model) is unavailable and takes no other
entity with it, because no read of the generated hub holds registers of two variant sets."""

from __future__ import annotations

import json
import time
from pathlib import Path
from typing import Any

import pytest
import yaml

from regmap.backends.homeassistant import render_device
from regmap.frontend import load_map
from regmap.model import Device, Register

from conftest import FIXTURE_MAPS, SimulatorFactory
from support.hass_recorder import recorded_states
from support.hass_running import hub_on_tcp, running_hass
from support.homeauto_yaml import load

METER = next(p for p in FIXTURE_MAPS if p.stem == "float_meter")
STARTUP_S, STATES_S = 300, 120  # deadlines for a loaded machine; both come well within 30 s on an idle one
# What the simulated meter holds (raw values): each register a value of its own, none a "not available" marker.
SEED: dict[str, float | int] = {
    "voltage_l1": 230.5,
    "current_l1": 5.25,
    "frequency": 50.0,
    "temperature": 231,
    "pulse_count": 1234,
    "voltage_l2": 231.5,
    "last_reset": 1709294400,
}
NO_VALUE = ("unknown", "unavailable")


def _recorded(db: Path) -> dict[str, str]:
    """friendly_name -> latest state, from the recorder's tables."""
    return {name: state for name, (_, state, _) in recorded_states(db).items()}


def _hub_on_tcp(text: str, port: int) -> dict[str, Any]:
    """The generated package with its hub moved from the serial line to the simulator's TCP port: only the
    connection keys change, every entity stays as generated."""
    package = load(text)
    hub_on_tcp(package, port)
    assert isinstance(package, dict)
    return package


def _register(device: Device, entity: dict[str, Any]) -> Register:
    reg = device.covering(int(entity["address"]), entity["input_type"])
    assert reg is not None, entity
    return reg


def _shows_value(reg: Register, precision: int, state: str) -> bool:
    value = float(SEED[reg.name] * reg.scale + reg.offset)
    try:
        return abs(float(state) - value) <= 0.5 * 10.0**-precision + 1e-9
    except ValueError:
        return False


def _configuration(config: Path, package: dict[str, Any]) -> None:
    config.mkdir()
    (config / "meter.yaml").write_text(yaml.safe_dump(package, sort_keys=False, allow_unicode=True), encoding="utf-8")
    basics = {"name": "regmap variant test", "latitude": 0, "longitude": 0, "elevation": 0, "unit_system": "metric", "time_zone": "UTC"}
    rest = {"recorder": {"db_url": f"sqlite:///{config / 'recorder.db'}", "commit_interval": 1}, "logger": {"default": "info"}}
    head = yaml.safe_dump({"homeassistant": basics}, sort_keys=False) + "  packages:\n    meter: !include meter.yaml\n"
    (config / "configuration.yaml").write_text(head + yaml.safe_dump(rest, sort_keys=False), encoding="utf-8")


@pytest.mark.timeout(STARTUP_S + STATES_S + 120)
@pytest.mark.parametrize("variant", ["single_phase", "three_phase"])
def test_home_assistant_reads_what_the_variant_has_and_only_loses_what_it_lacks(
    variant: str, simulator: SimulatorFactory, tmp_path: Path
) -> None:
    device = load_map(METER)
    state = tmp_path / "meter.state.json"
    state.write_text(json.dumps({"device": device.id, "map_version": device.info.map_version, "registers": SEED}), encoding="utf-8")
    sim = simulator(METER, "--variant", variant, "--state", str(state))
    (text,) = render_device(device, None).values()
    package = _hub_on_tcp(text, sim.port or 0)
    (hub,) = package["modbus"]
    assert set(hub) & {"sensors", "binary_sensors", "switches"} == {"sensors"}  # the default selection: sensors and templates
    sensors = {e["name"]: (_register(device, e), int(e.get("precision", 0))) for e in hub["sensors"]}
    templates = [e["name"] for block in package.get("template", []) for entities in block.values() for e in entities]
    absent = {name for name, (reg, _) in sensors.items() if not reg.on_variant(variant)}
    assert {sensors[name][0].name for name in absent} == ({"voltage_l2"} if variant == "single_phase" else set())
    config = tmp_path / "config"
    _configuration(config, package)

    def settled(recorded: dict[str, str]) -> bool:
        values = all(
            name in recorded and _shows_value(reg, precision, recorded[name])
            for name, (reg, precision) in sensors.items()
            if name not in absent
        )
        missing = all(recorded.get(name) == "unavailable" for name in absent)
        return values and missing and all(recorded.get(name, "unknown") not in NO_VALUE for name in templates)

    with running_hass(config, tmp_path / "hass.log") as process:
        started = time.monotonic()
        recorded: dict[str, str] = {}
        while time.monotonic() - started < STARTUP_S + STATES_S and process.poll() is None:
            recorded = _recorded(config / "recorder.db")
            if settled(recorded):
                break
            time.sleep(1)
        log = config / "home-assistant.log"
        tail = log.read_text(errors="replace")[-3000:] if log.exists() else ""
        wanted = {name: recorded.get(name) for name in [*sensors, *templates]}
        assert settled(recorded), f"{variant}: {wanted}\n{tail}"
        print(
            f"{variant}: HA showed {len(sensors) + len(templates) - len(absent)} entities' values, {sorted(absent)} unavailable,"
            f" {time.monotonic() - started:.1f} s after start"
        )
