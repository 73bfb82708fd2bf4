"""The ESPHome package of a plant (issue 32): a uart and modbus per serial bus, a modbus_controller per
device at its slave id, every id and name prefixed by the device, so one map appears twice."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

from regmap.backends.esphome import render_device, render_plant
from regmap.diagnostics import MapError
from regmap.frontend.plant import load_plant
from regmap.plant import Plant

from conftest import ROOT
from support.homeauto_yaml import esphome_config, load, resolve
from support.plant_tcp_bus import MAPS, write_plant
from support.plants import write_meter_plant

CELL1 = ROOT / "examples" / "plants" / "cell1.yaml"
PLATFORMS = ("sensor", "binary_sensor", "text_sensor", "number", "select", "switch", "button")


@pytest.fixture(scope="module")
def cell1() -> Plant:
    return load_plant(CELL1)


def _data(text: str) -> dict[str, Any]:
    data = load(text)
    assert isinstance(data, dict)
    return data


def _package(plant: Plant) -> tuple[str, dict[str, Any]]:
    (text,) = render_plant(plant).values()
    return text, _data(text)


def _entities(data: dict[str, Any]) -> list[dict[str, Any]]:
    return [e for platform in PLATFORMS for e in data.get(platform, [])]


def test_a_controller_per_device_on_its_bus(cell1: Plant) -> None:
    _, data = _package(cell1)
    subs = data["substitutions"]
    (uart,) = data["uart"]
    assert (uart["id"], uart["baud_rate"], uart["parity"], uart["stop_bits"], uart["data_bits"]) == ("line1_uart", 38400, "EVEN", 1, 8)
    assert data["modbus"] == [{"id": "line1_modbus", "uart_id": "line1_uart"}]
    controllers = data["modbus_controller"]
    assert [(resolve(c["id"], subs), c["modbus_id"], int(resolve(c["address"], subs))) for c in controllers] == [
        ("axis_x_controller", "line1_modbus", 1),
        ("axis_y_controller", "line1_modbus", 2),
        ("spindle_controller", "line1_modbus", 3),
    ]
    assert all(c["max_cmd_retries"] == 0 for c in controllers)


def test_every_entity_is_its_devices_under_its_name(cell1: Plant) -> None:
    """Each device holds its map's single-device entities, with ids and names prefixed by the device's
    name and its controller; the same map twice gives two distinct sets."""
    _, data = _package(cell1)
    subs = data["substitutions"]
    entities = _entities(data)
    ids = [resolve(e["id"], subs) for e in entities]
    names = [resolve(e["name"], subs) for e in entities]
    assert len(set(ids)) == len(ids) and len(set(names)) == len(names)
    for dev in cell1.devices:
        single = _data(next(iter(render_device(dev.device).values())))
        single_subs = single["substitutions"]
        expected = [
            (
                resolve(e["id"], single_subs).replace(dev.device.id + "_", dev.name + "_", 1),
                f"{dev.name} {resolve(e['name'], single_subs)}",
            )
            for e in _entities(single)
        ]
        mine = [(i, n) for i, n in zip(ids, names, strict=True) if i.startswith(dev.name + "_")]
        assert mine == expected
        for e in _entities(data):
            if resolve(e["id"], subs).startswith(dev.name + "_") and "modbus_controller_id" in e:
                assert resolve(e["modbus_controller_id"], subs) == f"{dev.name}_controller"


def test_a_tcp_bus_is_named_as_not_generated(tmp_path: Path) -> None:
    line1 = ("line1", "serial: {port: /dev/ttyUSB0, baud: 38400, parity: even}", [("axis_x", MAPS / "idm_rs.yaml", 1)])
    gw = ("gw", "tcp: {host: 10.0.0.5}", [("spindle", MAPS / "c630s.yaml", 3)])
    path = write_plant(tmp_path / "plant.yaml", "mixed", [line1, gw])
    text, data = _package(load_plant(path))
    assert "# Not generated: bus gw (Modbus TCP" in text
    assert [c["modbus_id"] for c in data["modbus_controller"]] == ["line1_modbus"]
    assert not any(resolve(e["id"], data["substitutions"]).startswith("spindle_") for e in _entities(data))


def test_esphome_config_accepts_the_plant_with_three_controllers(esphome: Path, tmp_path: Path, cell1: Plant) -> None:
    text, data = _package(cell1)
    checked = _data(esphome_config(esphome, tmp_path, text))  # the configuration as ESPHome validated it
    controllers = [(c["id"], c["address"]) for c in checked["modbus_controller"]]
    assert controllers == [("axis_x_controller", 1), ("axis_y_controller", 2), ("spindle_controller", 3)]
    assert len(_entities(checked)) == len(_entities(data))  # nothing dropped


def test_two_devices_that_would_share_an_object_id_are_refused(tmp_path: Path) -> None:
    """`sp` + "Encoder position deviation counter" and `sp_encoder` + "Position deviation counter" give
    ESPHome one object id: refused at the second device's line (ESPHome would refuse the whole file)."""
    c630s = MAPS / "c630s.yaml"
    line1 = ("line1", "serial: {port: /dev/ttyUSB0, baud: 19200, parity: none}", [("sp", c630s, 1), ("sp_encoder", c630s, 2)])
    path = write_plant(tmp_path / "plant.yaml", "clash", [line1])
    with pytest.raises(MapError) as caught:
        render_plant(load_plant(path))
    assert str(caught.value) == (
        f"{path}:8:9: devices 'sp' and 'sp_encoder' give ESPHome the same id sensor.sp_encoder_position_deviation_counter; rename one of them"
    )


def test_a_device_of_a_variant_has_only_that_variants_entities_and_says_so(tmp_path: Path) -> None:
    """Two float meters on a serial line, single- and three-phase: only the three-phase one has voltage_l2's sensor
    (and a read of its address), and each one's header line names what its variant left out."""
    plant = load_plant(write_meter_plant(tmp_path, "meters", "serial: {port: /dev/ttyUSB0, baud: 9600, parity: none}"))
    text, data = _package(plant)
    subs = data["substitutions"]
    ids = {resolve(e["id"], subs) for e in _entities(data)}
    assert "m3_voltage_l2" in ids and "m1_voltage_l2" not in ids
    assert {i.removeprefix("m3_") for i in ids if i.startswith("m3_")} - {i.removeprefix("m1_") for i in ids if i.startswith("m1_")} == {
        "voltage_l2"
    }
    header = [line for line in text.splitlines() if line.startswith("#")]
    assert any(
        line.startswith("# m1 (") and "Variant single_phase: left out, as that variant lacks them: voltage_l2." in line for line in header
    )
    assert not any("Only on variant" in line for line in header)


def test_esphome_config_accepts_the_plant_of_two_variants(esphome: Path, tmp_path: Path) -> None:
    plant = load_plant(write_meter_plant(tmp_path, "meters", "serial: {port: /dev/ttyUSB0, baud: 9600, parity: none}"))
    text, data = _package(plant)
    checked = _data(esphome_config(esphome, tmp_path, text))
    assert [(c["id"], c["address"]) for c in checked["modbus_controller"]] == [("m1_controller", 1), ("m3_controller", 3)]
    ids = {e["id"] for e in _entities(checked)}
    assert len(ids) == len(_entities(data)) and "m3_voltage_l2" in ids and "m1_voltage_l2" not in ids
