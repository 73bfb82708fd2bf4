"""Round trips: every shipped map and fixture -> ESPHome / Home Assistant config -> `regmap import` -> the config again,
whose entities equal the first's (addresses, register types, value types and their word order, bit masks, scale,
offset, options, text sizes); and a config written from a real meter's register table, imported and generated again."""

from __future__ import annotations

from fractions import Fraction
from pathlib import Path
from typing import Any

import pytest

from regmap.backends.esphome.package import package
from regmap.backends.homeassistant.hub import DATA_TYPE, hub
from regmap.frontend import load_map
from regmap.homeauto.selection import select
from regmap.model import DataType, Device
from regmap.tools.configimport.hastruct import structure_fields
from regmap.tools.configimport.reader import read_config, substitute

from conftest import MAPS, ROOT
from support.homeauto_roundtrip import EVERYTHING, esphome_entities, esphome_round_trip, ha_entities, ha_round_trip, reimport

MAP_FILES = sorted(MAPS) + sorted((ROOT / "tests" / "maps" / "fixtures").glob("*.yaml"))
COMMUNITY = Path(__file__).parent / "community"
LAMBDA = -1  # the last item of an ESPHome entity's key: whether it reads through a lambda


@pytest.mark.parametrize("path", MAP_FILES, ids=[p.stem for p in MAP_FILES])
def test_esphome_entities_come_back_equal(path: Path, tmp_path: Path) -> None:
    """What ESPHome reads with a value type comes back exactly. A value the back end reads through a lambda (a
    double, a byte-swapped word: ESPHome has no value type for them) cannot be read back from the lambda's code:
    the import keeps the lambda as a note and reports it, and the register comes back at its address and register
    type."""
    device = load_map(path)
    first, again, report = esphome_round_trip(device, tmp_path)
    plain = [e for e in first if not e[LAMBDA]]
    assert [e for e in plain if e not in again] == []
    coded = [e for e in first if e[LAMBDA] and e[0] != "text_sensor"]  # text: regmap's own lambda again
    if not coded:
        assert again == first
    for entity in coded:
        assert any(a[1:3] == entity[1:3] for a in again), entity  # a field read by a lambda: its register's flags came back
    assert len([line for line in report if "lambda kept as a note" in line]) >= len({e[:3] for e in coded})


def _padded_reads_as_plain(device: Device) -> tuple[list[tuple[Any, ...]], int]:
    """An aligned device's HA entities with each padded `custom` read (a whole unit for one value) as the plain read
    of the value it unpacks, and how many there were: an HA config cannot say that a device demands whole units."""
    data = hub(device, select(device, EVERYTHING))
    padded = 0
    for h in data:
        for e in h.get("sensors", []):
            if e.get("data_type") == "custom":
                (field,), _ = structure_fields(e.pop("structure"), e.pop("count"))
                e["address"] = int(e["address"]) + field.word_offset
                e["data_type"] = DATA_TYPE[DataType(field.type)]
                padded += 1
    return ha_entities(data), padded


@pytest.mark.parametrize("path", MAP_FILES, ids=[p.stem for p in MAP_FILES])
def test_home_assistant_entities_come_back_equal(path: Path, tmp_path: Path) -> None:
    device = load_map(path)
    first, again, report = ha_round_trip(device, tmp_path)
    if device.transport.read_alignment is None:
        assert again == first
        assert report == []
        return
    plain, padded = _padded_reads_as_plain(device)
    assert padded and again == plain  # the values come back at their own addresses; the alignment is reported, not guessed
    assert len(report) == padded and all("add transport.read_alignment (not inferred)" in line for line in report), report


def test_the_round_trips_cover_every_value_type_and_word_order() -> None:
    """The maps under test give the round trips every ESPHome value type regmap emits, and each HA swap."""
    value_types, swaps = set(), set()
    for path in MAP_FILES:
        device = load_map(path)
        value_types |= {e[3] for e in esphome_entities(package(device, select(device, EVERYTHING))) if e[3]}
        swaps |= {e[4] for e in ha_entities(hub(device, select(device, EVERYTHING)))}
    assert {"U_WORD", "S_WORD", "U_DWORD", "S_DWORD", "U_DWORD_R", "S_DWORD_R", "FP32", "FP32_R", "U_QWORD", "S_QWORD"} <= value_types
    assert {None, "byte", "word", "word_byte"} <= swaps


def _input_entities(path: Path) -> list[tuple[object, ...]]:
    config = read_config(path.read_text(encoding="utf-8"), path.name)
    subs = {k: str(v) for k, v in config.data["substitutions"].items()}
    return esphome_entities(substitute(config.data, subs, set()))


def test_a_community_esphome_config_imports_and_generates_the_same_entities(tmp_path: Path) -> None:
    source = COMMUNITY / "sdm72d_m_esphome.yaml"
    (device,), report = reimport(source.read_text(encoding="utf-8"), tmp_path, "sdm72d_m")
    assert len(device.registers) == 9 and {r.space for r in device.registers} == {"input"}
    generated = esphome_entities(package(device, select(device, None)))
    given = _input_entities(source)
    assert [e[:LAMBDA] for e in generated] == [e[:LAMBDA] for e in given]
    assert report == [
        "sdm72d_m.yaml:75: total_energy: filters kept as a note: {delta: 0.01}",
        "sdm72d_m.yaml:122: export_power: lambda kept as a note",
    ]
    assert device.transport.baud == 9600 and device.register("total_power").scale == Fraction(1, 1000)


def test_a_community_home_assistant_config_imports_and_generates_the_same_entities(tmp_path: Path) -> None:
    source = COMMUNITY / "sdm72d_m_homeassistant.yaml"
    devices, _ = reimport(source.read_text(encoding="utf-8"), tmp_path, "plant")
    meters = next(d for d in devices if d.id == "meters_slave_1")
    given = read_config(source.read_text(encoding="utf-8"), source.name).data["modbus"][0]
    generated = ha_entities(hub(meters, select(meters, None)))
    slave_1 = ha_entities([{"sensors": [{"data_type": "int16", **e} for e in given["sensors"] if e["slave"] == 1]}])
    assert generated == slave_1
