"""f16 in Home Assistant: a half-float register is `data_type: float16` (HA 2024.3 and later; struct 'e', one
register), a byte-swapped one `swap: byte`; `hass --script check_config` accepts the hub, HA's own table says
float16 is struct 'e' over one register, and HA -> `regmap import` -> HA gives the same entities back."""

from __future__ import annotations

import subprocess
from pathlib import Path
from typing import Any

import pytest

from regmap.backends.homeassistant.hub import render_hub
from regmap.frontend import load_map
from regmap.homeauto.selection import select
from regmap.model import Device

from support.half_map import write_half_map
from support.hass_running import check_config
from support.homeauto_roundtrip import EVERYTHING, ha_round_trip
from support.homeauto_yaml import load


@pytest.fixture
def device(tmp_path: Path) -> Device:
    return load_map(write_half_map(tmp_path))


def _hub(device: Device) -> str:
    (text,) = render_hub(device, select(device, EVERYTHING)).values()
    return text


def _sensors(text: str) -> dict[int, dict[str, Any]]:
    (hub,) = load(text)["modbus"]
    return {int(e["address"]): e for e in hub["sensors"]}


def test_every_f16_register_is_a_float16_sensor(device: Device) -> None:
    sensors = _sensors(_hub(device))
    halves = [r for r in device.registers if r.type.value == "f16" and r.enum is None]
    assert halves and {r.address for r in halves} <= set(sensors)
    for reg in halves:
        entity = sensors[reg.address]
        assert entity["data_type"] == "float16", entity
        assert entity.get("swap") == ("byte" if reg.byte_order.value == "low_first" else None), entity
        assert "count" not in entity  # float16 is one register: HA refuses a count with it


def test_home_assistant_accepts_the_hub_and_reads_float16_as_struct_e(hass: Path, device: Device, tmp_path: Path) -> None:
    work = tmp_path / "ha"
    work.mkdir()
    check_config(hass, work, _hub(device))
    program = (
        "from homeassistant.components.modbus.validators import DEFAULT_STRUCT_FORMAT\n"
        "entry = DEFAULT_STRUCT_FORMAT['float16']\nprint(entry.struct_id, entry.register_count)\n"
    )
    python = hass.with_name("python")
    table = subprocess.run([str(python), "-c", program], capture_output=True, text=True, timeout=120, check=False)
    assert table.stdout.split() == ["e", "1"], table.stderr[-2000:]


def test_home_assistant_round_trip_gives_float16_back(device: Device, tmp_path: Path) -> None:
    first, again, report = ha_round_trip(device, tmp_path)
    assert any(e[3] == "float16" for e in first)
    assert again == first, report
    assert not [line for line in report if "float16" in line], report
