"""Home Assistant (the hass tool env's 2024.3, offline) polling a timestamp register: the float meter fixture's
`last_reset` (UTC seconds, low word first) on a Modbus TCP bus served by `regmap simulate PLANT --bus`, from a
state file. HA's modbus sensor reads the raw seconds; the generated template sensor (device_class timestamp,
`as_datetime` of them) must record the aware UTC time the Python client reads from the same words."""

from __future__ import annotations

import json
import time
from datetime import UTC, datetime
from pathlib import Path

import pytest
import yaml

from regmap.backends.homeassistant import render_plant
from regmap.frontend.plant import load_plant

from conftest import FIXTURE_MAPS
from support.hass_recorder import recorded_states
from support.hass_running import running_hass
from support.homeauto_yaml import load
from support.plant_tcp_bus import free_port, serve_bus, write_plant

METER = next(p for p in FIXTURE_MAPS if p.stem == "float_meter")
STARTUP_S, STATES_S = 300, 180
SECONDS = 1709294400  # 2024-03-01T12:00:00Z


def _recorded(db: Path) -> dict[str, tuple[str, dict[str, object]]]:
    """friendly_name -> (latest state, its attributes) from the recorder's tables."""
    return {name: (state, attributes) for name, (_, state, attributes) in recorded_states(db).items()}


@pytest.mark.timeout(STARTUP_S + STATES_S + 120)
def test_home_assistant_shows_the_utc_timestamp_as_a_time(tmp_path: Path) -> None:
    port = free_port()
    plant = load_plant(
        write_plant(tmp_path / "plant.yaml", "tsplant", [("line", f"tcp: {{host: 127.0.0.1, port: {port}}}", [("meter", METER, 1)])])
    )
    (bus,) = plant.buses
    (text,) = render_plant(plant).values()
    package = load(text)
    (time_entity,) = [e for block in package["template"] for e in block.get("sensor", []) if e["unique_id"].endswith("_last_reset_time")]
    assert time_entity["device_class"] == "timestamp"
    state = tmp_path / "meter.state.json"
    device = plant.devices[0].device
    state.write_text(
        json.dumps({"device": device.id, "map_version": device.info.map_version, "registers": {"last_reset": SECONDS}}), encoding="utf-8"
    )
    config = tmp_path / "config"
    config.mkdir()
    (config / "plant.yaml").write_text(text, encoding="utf-8")
    basics = {
        "name": "regmap timestamp test",
        "latitude": 0,
        "longitude": 0,
        "elevation": 0,
        "unit_system": "metric",
        "time_zone": "Europe/Berlin",
    }
    rest = {"recorder": {"db_url": f"sqlite:///{config / 'recorder.db'}", "commit_interval": 1}, "logger": {"default": "info"}}
    head = yaml.safe_dump({"homeassistant": basics}, sort_keys=False) + "  packages:\n    plant: !include plant.yaml\n"
    (config / "configuration.yaml").write_text(head + yaml.safe_dump(rest, sort_keys=False), encoding="utf-8")
    expected = datetime.fromtimestamp(SECONDS, UTC)
    with serve_bus(plant, bus, tmp_path, {"meter": state}), running_hass(config, tmp_path / "hass.log") as process:
        deadline = time.monotonic() + STARTUP_S + STATES_S
        recorded: dict[str, tuple[str, dict[str, object]]] = {}
        while time.monotonic() < deadline and process.poll() is None:
            recorded = _recorded(config / "recorder.db")
            shown = recorded.get(time_entity["name"])
            if shown is not None and shown[0] not in ("unknown", "unavailable"):
                break
            time.sleep(1)
        log = (config / "home-assistant.log").read_text(errors="replace") if (config / "home-assistant.log").exists() else ""
        assert time_entity["name"] in recorded, f"not recorded: {sorted(recorded)}\n{log[-3000:]}"
        shown_state, attributes = recorded[time_entity["name"]]
        assert datetime.fromisoformat(shown_state) == expected, (shown_state, expected)  # the instant, whatever HA's own zone
        assert attributes.get("device_class") == "timestamp", attributes
