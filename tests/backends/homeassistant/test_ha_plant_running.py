"""Home Assistant really polling a plant (issue 32): the proof that the generated configuration is *used*.

Home Assistant itself (the hass tool env's pinned version, started offline by tests/support/hass_offline.py)
runs the generated package of cell1, its bus moved to Modbus TCP on 127.0.0.1 and served by regmap's
simulator (tests/support/plant_tcp_bus.py: `regmap simulate PLANT --bus`), each drive started from different register values. Its recorder
writes SQLite; the test reads the states it recorded and checks that every entity of every device reaches
the value its simulator holds (read back with `regmap dump`, scaled as the map says), that an automation's
call of one generated command script wrote the command register of the right slave exactly once (and that
the drive acted on it), and that HA's entity registry holds every unique_id with no `_2` entity id.

What it waits for, each with its own deadline: HA's "Home Assistant initialized" line (startup), the
command's write in the simulator's log, and the recorded states reaching the simulators' values.
"""

from __future__ import annotations

import json
import subprocess
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest
import yaml

from regmap.backends.homeassistant import render_plant
from regmap.frontend.plant import load_plant
from regmap.homeauto.selection import select
from regmap.model import Device
from regmap.plant import Plant, PlantDevice

from conftest import ROOT
from support.hass_recorder import recorded_states
from support.hass_running import running_hass
from support.homeauto_yaml import ha_slug, load
from support.plant_tcp_bus import REGMAP, ServedBus, free_port, serve_bus, write_plant

CELL1 = ROOT / "examples" / "plants" / "cell1.yaml"
STARTUP_S = 300  # HA imports and sets up in seconds to a minute; a loaded machine gets room
WRITE_S = 180  # the automation waits for the drive's first value, then calls the script
STATES_S = 120  # every entity polls every 10 s (settings 300 s, but their values do not change)
PRESSED = ("axis_y", "reset_current_alarm")  # device, command: clears the drive's current alarm (effect: clear)
CLEARED = "current_alarm"


@dataclass(frozen=True)
class Expected:
    name: str  # the entity's name (HA's friendly_name)
    check: Callable[[str], bool]
    shows: str  # what the state should be, for the failure message


def _tcp_plant(tmp_path: Path, port: int) -> Plant:
    """cell1's devices at their slave ids, the bus a Modbus TCP endpoint on 127.0.0.1:port."""
    cell1 = load_plant(CELL1)
    (bus,) = cell1.buses
    devices = [(d.name, (CELL1.parent / d.map_path).resolve(), d.slave) for d in bus.devices]
    return load_plant(write_plant(tmp_path / "plant.yaml", cell1.id, [(bus.name, f"tcp: {{host: 127.0.0.1, port: {port}}}", devices)]))


def _seed(dev: PlantDevice) -> dict[str, int]:
    """Start values for the device's selected registers that differ from drive to drive (a state file the
    simulator loads): an entity reading another slave's register then shows another value."""
    values: dict[str, int] = {}
    for i, reg in enumerate(select(dev.device, None).registers):
        if not reg.access.readable or reg.type.is_string or reg.type.is_float:
            continue
        if reg.enum is not None and not reg.bitfields:
            members = [m.value for m in reg.enum.members if m.readable and reg.raw_min <= m.value <= reg.raw_max]
            members = [v for v in members if v != 0] or members
            values[reg.name] = members[(dev.slave + i) % len(members)]
        elif reg.type.is_bool:
            values[reg.name] = (dev.slave + i) % 2
        else:
            low, high = int(reg.raw_min), int(reg.raw_max)
            values[reg.name] = low + (dev.slave * 7919 + i * 104729) % (high - low + 1)
    return values


def _configuration(config: Path, package: str, script: str, waited: str) -> None:
    (config / "cell1.yaml").write_text(package, encoding="utf-8")
    automation = {
        "id": "regmap_press_one_command",
        "alias": "regmap test: press one generated command script",
        "trigger": [{"platform": "homeassistant", "event": "start"}],
        "action": [
            {  # the hub is connected once the drive's first value is in
                "wait_template": "{{ states.sensor | selectattr('name', 'search', '^" + waited + " ') | map(attribute='state')"
                " | reject('in', ['unknown', 'unavailable']) | list | count > 0 }}",
                "timeout": WRITE_S,
                "continue_on_timeout": False,
            },
            {"service": f"script.{script}"},
        ],
    }
    basics = {
        "name": "regmap plant test",
        "latitude": 0,
        "longitude": 0,
        "elevation": 0,
        "unit_system": "metric",
        "time_zone": "UTC",
        "currency": "EUR",
        "country": "DE",
    }
    rest = {
        "recorder": {"db_url": f"sqlite:///{config / 'recorder.db'}", "commit_interval": 1},
        "automation": [automation],
        "logger": {"default": "info"},
    }
    # The package goes in with HA's own `!include`, which the safe dumper cannot write: one line by hand.
    text = yaml.safe_dump({"homeassistant": basics}, sort_keys=False) + "  packages:\n    cell1: !include cell1.yaml\n"
    (config / "configuration.yaml").write_text(text + yaml.safe_dump(rest, sort_keys=False), encoding="utf-8")


def _dump(dev: PlantDevice, bus: ServedBus) -> dict[str, Any]:
    """The device's registers as its simulator holds them, read over the bus with `regmap dump` (by name)."""
    result = subprocess.run(
        [REGMAP, "dump", dev.device.source_path, "--tcp", f"127.0.0.1:{bus.port}", "--slave", str(dev.slave), "--json"],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert result.returncode == 0, result.stderr[-2000:]
    return {row["register"]: row["raw"] for row in json.loads(result.stdout)}


def _number(precision: int, value: float) -> Callable[[str], bool]:
    def check(state: str) -> bool:
        try:
            return abs(float(state) - value) <= 0.5 * 10.0**-precision + 1e-9
        except ValueError:
            return False

    return check


def _sensor_expected(device: Device, entity: dict[str, Any], raw: dict[str, Any]) -> Expected:
    reg = device.covering(int(entity["address"]), entity["input_type"])
    assert reg is not None, entity
    value = float(raw[reg.name] * reg.scale + reg.offset)
    precision = int(entity.get("precision", 0))
    return Expected(entity["name"], _number(precision, value), f"{value:.{precision}f}")


def _template_expected(device: Device, unique_rest: str, entity: dict[str, Any], raw: dict[str, Any]) -> Expected:
    """A label sensor (`<register>_label`) shows the manual's label; a flag (`<register>_<field>`) on or off."""
    if unique_rest.endswith("_label"):
        reg = device.register(unique_rest.removesuffix("_label"))
        assert reg.enum is not None
        labels = {m.value: " ".join(m.title.split()) or m.name for m in reg.enum.members if m.readable}
        label = labels.get(raw[reg.name], str(raw[reg.name]))
        return Expected(entity["name"], lambda state: state == label, label)
    reg, field = next((r, f) for r in device.registers for f in r.bitfields if f"{r.name}_{f.name}" == unique_rest)
    on = "on" if raw[reg.name] & field.mask else "off"
    return Expected(entity["name"], lambda state: state == on, on)


def _expected(plant: Plant, package: dict[str, Any], raws: dict[str, dict[str, Any]]) -> list[Expected]:
    (hub,) = package["modbus"]
    # cell1's default selections make sensors and templates only; binary sensors or switches would need their own check here
    assert not {"binary_sensors", "switches"} & set(hub)
    by_slave = {dev.slave: dev for dev in plant.devices}
    out = [_sensor_expected(by_slave[e["slave"]].device, e, raws[by_slave[e["slave"]].name]) for e in hub["sensors"]]
    for block in package["template"]:
        for entity in (e for entities in block.values() for e in entities):
            dev = next(d for d in plant.devices if entity["unique_id"].startswith(f"{plant.id}_{d.name}_"))
            rest = entity["unique_id"].removeprefix(f"{plant.id}_{dev.name}_")
            out.append(_template_expected(dev.device, rest, entity, raws[dev.name]))
    return out


def _recorded(db: Path) -> dict[str, tuple[str, str]]:
    """friendly_name -> (entity id, latest state) from the recorder's tables."""
    return {name: (entity_id, state) for name, (entity_id, state, _) in recorded_states(db).items()}


def _wait(what: str, deadline_s: float, ready: Callable[[], bool], process: subprocess.Popen[bytes], log: Path) -> float:
    start = time.monotonic()
    while time.monotonic() - start < deadline_s:
        if ready():
            return time.monotonic() - start
        if process.poll() is not None:
            pytest.fail(f"Home Assistant exited ({process.returncode}) while waiting for {what}:\n{_tail(log)}")
        time.sleep(1)
    pytest.fail(f"waited {deadline_s:.0f} s for {what}:\n{_tail(log)}")


def _tail(log: Path) -> str:
    return "\n".join(log.read_text(encoding="utf-8", errors="replace").splitlines()[-40:]) if log.exists() else "(no log)"


@pytest.mark.timeout(STARTUP_S + WRITE_S + STATES_S + 300)
def test_home_assistant_polls_the_plant_and_presses_one_command(tmp_path: Path) -> None:
    plant = _tcp_plant(tmp_path, free_port())
    (bus,) = plant.buses
    (text,) = render_plant(plant).values()
    package = load(text)
    _, pressed = plant.device(PRESSED[0])
    command = next(c for c in pressed.device.commands if c.name == PRESSED[1])
    (script,) = [
        script_id
        for script_id, s in package["script"].items()
        if any(
            step.get("data", {}).get("slave") == pressed.slave
            and step["data"]["address"] == command.register.address
            and step["data"]["value"] == command.raw_value()
            for step in s["sequence"]
            if "service" in step
        )
    ]
    states: dict[str, Path] = {}
    for dev in bus.devices:
        states[dev.name] = tmp_path / f"{dev.name}.state.json"
        body = {"device": dev.device.id, "map_version": dev.device.info.map_version, "registers": _seed(dev)}
        states[dev.name].write_text(json.dumps(body), encoding="utf-8")
    config = tmp_path / "config"
    config.mkdir()
    _configuration(config, text, script, PRESSED[0])
    log = tmp_path / "hass.log"
    with serve_bus(plant, bus, tmp_path, states) as served:
        before = {dev.name: _dump(dev, served) for dev in bus.devices}
        assert before["axis_x"] != before["axis_y"]  # the two drives of one map hold different values
        assert before[PRESSED[0]][CLEARED] != 0
        with running_hass(config, log) as process:
            home_log = config / "home-assistant.log"
            started = _wait(
                "Home Assistant to start",
                STARTUP_S,
                lambda: home_log.exists() and "Home Assistant initialized in" in home_log.read_text(errors="replace"),
                process,
                log,
            )
            print(f"Home Assistant started in {started:.1f} s")
            _wait(f"script.{script} to write", WRITE_S, lambda: bool(served.writes(PRESSED[0])), process, home_log)
            raws = {dev.name: _dump(dev, served) for dev in bus.devices}
            assert raws[PRESSED[0]][CLEARED] == 0  # the drive acted on the command: its alarm is cleared
            assert raws["axis_x"][CLEARED] == before["axis_x"][CLEARED]  # the other drive of that map was not written
            expected = _expected(plant, package, raws)
            db = config / "recorder.db"

            def reached() -> bool:
                recorded = _recorded(db)
                return all(e.name in recorded and e.check(recorded[e.name][1]) for e in expected)

            try:
                _wait("every entity to reach its simulator's value", STATES_S, reached, process, home_log)
            except pytest.fail.Exception:
                recorded = _recorded(db)
                wrong = [
                    (e.name, recorded.get(e.name), e.shows) for e in expected if e.name not in recorded or not e.check(recorded[e.name][1])
                ]
                pytest.fail(f"{len(wrong)} of {len(expected)} entities are not their simulator's value: {wrong[:20]}")
            recorded = _recorded(db)
            # HA made each entity id of its name alone: no two names met in one id (it would add `_2`)
            assert [recorded[e.name][0].split(".", 1)[1] for e in expected] == [ha_slug(e.name) for e in expected]
            write = (pressed.slave, 0x06, command.register.address, command.raw_value().to_bytes(2, "big"))
            assert served.writes(PRESSED[0]) == [write]  # exactly once, at the pressed drive's slave id
            assert [served.writes(d.name) for d in bus.devices if d.name != PRESSED[0]] == [[], []]
            print(f"{len(expected)} entities of {len(bus.devices)} devices reached their simulators' values")
    registry = json.loads((config / ".storage" / "core.entity_registry").read_text(encoding="utf-8"))["data"]["entities"]
    registered = {e["unique_id"]: e["entity_id"] for e in registry if e["platform"] in ("modbus", "template")}
    (hub,) = package["modbus"]
    generated = [e["unique_id"] for e in hub["sensors"]] + [
        e["unique_id"] for block in package["template"] for entities in block.values() for e in entities
    ]
    assert sorted(registered) == sorted(generated)
