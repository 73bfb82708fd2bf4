"""The Home Assistant package of a plant (issue 32): one hub per bus, every device's entities named,
unique_id'd and addressed after it, accepted whole by HA's config check with nothing dropped."""

from __future__ import annotations

import re
import subprocess
from pathlib import Path
from typing import Any

import pytest

from regmap.backends.homeassistant import render_device, render_plant
from regmap.frontend.plant import load_plant
from regmap.plant import Plant

from conftest import ROOT
from support.hass_running import check_config
from support.homeauto_yaml import ha_slug, load
from support.plant_tcp_bus import MAPS, REGMAP, write_plant
from support.plants import write_meter_plant

CELL1 = ROOT / "examples" / "plants" / "cell1.yaml"
ENTITY_KEYS = ("sensors", "binary_sensors", "switches")


def _two_buses(tmp_path: Path) -> Plant:
    """cell1's drives split over a serial line and a TCP gateway, with the same map twice on one bus."""
    idm_rs = MAPS / "idm_rs.yaml"
    line1 = (
        "line1",
        "serial: {port: /dev/ttyUSB1, baud: 19200, parity: none, stop_bits: 2}",
        [("axis_x", idm_rs, 4), ("axis_y", idm_rs, 5)],
    )
    gw = ("gw", "tcp: {host: 10.0.0.5, port: 1502}", [("spindle", MAPS / "c630s.yaml", 7)])
    return load_plant(write_plant(tmp_path / "plant.yaml", "cell2", [line1, gw]))


def _package(plant: Plant) -> dict[str, Any]:
    (text,) = render_plant(plant).values()
    data = load(text)
    assert isinstance(data, dict)
    return data


def _single(plant: Plant, name: str) -> dict[str, Any]:
    """The single-device package of the device's map (the plant must hold all of it, renamed)."""
    _, dev = plant.device(name)
    (text,) = render_device(dev.device).values()
    data = load(text)
    assert isinstance(data, dict)
    return data


def _entities(hub: dict[str, Any]) -> list[dict[str, Any]]:
    return [e for key in ENTITY_KEYS for e in hub.get(key, [])]


def _templates(package: dict[str, Any]) -> list[dict[str, Any]]:
    return [e for block in package.get("template", []) for entities in block.values() for e in entities]


@pytest.fixture(scope="module")
def cell1() -> Plant:
    return load_plant(CELL1)


def test_one_hub_per_bus_with_the_plant_line_settings(tmp_path: Path) -> None:
    plant = _two_buses(tmp_path)
    hubs = _package(plant)["modbus"]
    assert [h["name"] for h in hubs] == ["cell2_line1", "cell2_gw"]
    serial, tcp = hubs
    assert {k: serial[k] for k in ("type", "method", "port", "baudrate", "parity", "stopbits", "bytesize")} == {
        "type": "serial",
        "method": "rtu",
        "port": "/dev/ttyUSB1",
        "baudrate": 19200,
        "parity": "N",
        "stopbits": 2,
        "bytesize": 8,
    }
    assert {k: tcp[k] for k in ("type", "host", "port")} == {"type": "tcp", "host": "10.0.0.5", "port": 1502}
    assert "baudrate" not in tcp
    assert {e["slave"] for e in _entities(serial)} == {4, 5}
    assert {e["slave"] for e in _entities(tcp)} == {7}


def test_every_entity_carries_its_device_and_slave(cell1: Plant) -> None:
    """Each device's entities are its map's single-device entities, with its name before the name,
    <plant>_<device>_ before the unique_id, and its slave id: none dropped, none shared."""
    package = _package(cell1)
    (hub,) = package["modbus"]
    entities = _entities(hub)
    templates = _templates(package)
    for bus in cell1.buses:
        for dev in bus.devices:
            single = _single(cell1, dev.name)
            (single_hub,) = single["modbus"]
            unique = f"{cell1.id}_{dev.name}_"
            mine = [e for e in entities if e["unique_id"].startswith(unique)]
            expected = [
                (f"{dev.name} {e['name']}", unique + e["unique_id"].removeprefix(dev.device.id + "_"), e["address"])
                for e in _entities(single_hub)
            ]
            assert [(e["name"], e["unique_id"], e["address"]) for e in mine] == expected
            assert {e["slave"] for e in mine} == {dev.slave}
            mine_t = [e for e in templates if e["unique_id"].startswith(unique)]
            assert [e["name"] for e in mine_t] == [f"{dev.name} {e['name']}" for e in _templates(single)]
    names = [e["name"] for e in entities + templates]
    ids = [e["unique_id"] for e in entities + templates]
    assert len(set(names)) == len(names) and len(set(ids)) == len(ids)
    assert len(entities) == sum(len(_entities(_single(cell1, d.name)["modbus"][0])) for d in cell1.devices)


def test_templates_and_scripts_address_their_own_device(cell1: Plant) -> None:
    package = _package(cell1)
    (hub,) = package["modbus"]
    sensors = {ha_slug(e["name"]): e for e in hub["sensors"]}
    for template in _templates(package):
        sources = set(re.findall(r"states\('sensor\.(\w+)'\)", template["state"]))
        assert len(sources) == 1, template
        (source,) = sources
        assert source in sensors, f"{template['name']} reads sensor.{source}, which no entity of the plant is"
        device = template["name"].split()[0]
        assert sensors[source]["name"].split()[0] == device, (template["name"], source)
        assert template["unique_id"].startswith(f"{cell1.id}_{device}_")
    scripts = package["script"]
    assert len(scripts) == sum(len(_single(cell1, d.name).get("script", {})) for d in cell1.devices)
    for script_id, script in scripts.items():
        dev_name = next(d.name for d in cell1.devices if script_id.startswith(d.name + "_"))
        _, dev = cell1.device(dev_name)
        (write,) = [step for step in script["sequence"] if "service" in step]
        assert write["data"]["hub"] == "cell1_line1"
        assert write["data"]["slave"] == dev.slave, script_id
        assert script["alias"].removeprefix("DESTRUCTIVE: ").startswith(f"{dev_name} ")
        if script["alias"].startswith("DESTRUCTIVE"):
            assert script["sequence"][0]["condition"] == "template" and "confirm" in script["fields"]


def test_check_config_accepts_the_plant_with_nothing_dropped(hass: Path, tmp_path: Path, cell1: Plant) -> None:
    """HA's own config check reads the whole plant: no duplicate hub, no entity dropped (its `--info modbus`
    lists every unique_id the file holds)."""
    (text,) = render_plant(cell1).values()
    out = check_config(hass, tmp_path, text, "modbus")
    assert "Successful config" in out, out[-4000:]
    for word in ("duplicate", "not loaded", "invalid", "Incorrect config", "Failed config", "components.modbus"):
        assert word.lower() not in out.lower(), [line for line in out.splitlines() if word.lower() in line.lower()]
    (hub,) = load(text)["modbus"]
    generated = sorted(e["unique_id"] for e in _entities(hub))
    checked = sorted(re.findall(r"^\s+unique_id: (\S+)", out, re.MULTILINE))
    assert checked == generated
    assert len(generated) == 90  # iDM-RS 18 + 18, C630S 54: the default selections' entities


def test_two_devices_that_would_share_an_entity_id_are_refused_at_the_second(tmp_path: Path) -> None:
    """`sp` + "Encoder position deviation counter" and `sp_encoder` + "Position deviation counter" are both
    sensor.sp_encoder_position_deviation_counter: refused at the second device's line, nothing written."""
    c630s = MAPS / "c630s.yaml"
    path = write_plant(
        tmp_path / "plant.yaml", "clash", [("line1", "tcp: {host: 127.0.0.1}", [("sp", c630s, 1), ("sp_encoder", c630s, 2)])]
    )
    out = tmp_path / "out"
    result = subprocess.run(
        [REGMAP, "generate", str(path), "--target", "homeassistant", "--out", str(out)],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert result.returncode == 1, result.stderr
    assert result.stderr.strip() == (
        f"{path}:8:9: devices 'sp' and 'sp_encoder' give Home Assistant the same id"
        " sensor.sp_encoder_position_deviation_counter; rename one of them"
    )
    assert not out.exists()


def _meters(tmp_path: Path, bus: str) -> Plant:
    """Two float meters the plant names a variant of (m1 single-phase, m3 three-phase) and one it does not (m0)."""
    path = write_meter_plant(tmp_path, "meters", bus)
    text = path.read_text(encoding="utf-8")
    m0 = next(line for line in text.splitlines() if "name: m1," in line).replace("m1", "m0").replace("slave: 1", "slave: 9")
    path.write_text(text + m0.replace(", variant: single_phase", "") + "\n", encoding="utf-8")
    return load_plant(path)


def test_a_device_of_a_variant_has_only_that_variants_entities_and_says_so(tmp_path: Path) -> None:
    """voltage_l2 is the three-phase model's alone: the single-phase meter has no entity for it, the three-phase
    one has, and a meter the plant names no variant of keeps every entity (its header says which answer only
    on which variant); each variant device's header line names what was left out."""
    plant = _meters(tmp_path, "serial: {port: /dev/ttyUSB0, baud: 9600, parity: none}")
    (text,) = render_plant(plant).values()
    (hub,) = load(text)["modbus"]
    ids = {e["unique_id"] for e in _entities(hub)}
    assert "meters_m3_voltage_l2" in ids and "meters_m0_voltage_l2" in ids and "meters_m1_voltage_l2" not in ids
    single = {i.removeprefix("meters_m1_") for i in ids if i.startswith("meters_m1_")}
    three = {i.removeprefix("meters_m3_") for i in ids if i.startswith("meters_m3_")}
    every = {i.removeprefix("meters_m0_") for i in ids if i.startswith("meters_m0_")}
    assert three - single == {"voltage_l2"} and three == every  # the one entity the single-phase model lacks
    header = [line for line in text.splitlines() if line.startswith("#")]
    assert any(
        line.startswith("# m1 (") and "Variant single_phase: left out, as that variant lacks them: voltage_l2." in line for line in header
    )
    assert any(line.startswith("# m3 (") and "Variant three_phase: it has every one selected." in line for line in header)
    assert any(line.startswith("# m0: Only on variant three_phase: voltage_l2") for line in header), header
    assert not any(line.startswith(("# m1: Only on variant", "# m3: Only on variant")) for line in header)
