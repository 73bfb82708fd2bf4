"""Registers only some variants have (issue #34's float meter: voltage_l2 on the three-phase model only) never
share a read with registers a variant lacking them has: on a single-phase meter such a read fails with
exception 0x02 and takes every entity in it down. The ESPHome ranges (`esphome config`'s output through the
ported `create_register_ranges_`) and the read plan both back ends start from are split by variant set,
and both files' headers say which entities only some variants have."""

from __future__ import annotations

import re
from collections.abc import Callable
from pathlib import Path

import pytest

from regmap.backends.esphome import render_device as esphome_files
from regmap.backends.esphome import render_plant as esphome_plant
from regmap.backends.homeassistant import render_device as hass_files
from regmap.backends.homeassistant import render_plant as hass_plant
from regmap.frontend import load_map
from regmap.frontend.plant import load_plant
from regmap.homeauto.entities import planned
from regmap.model import Device, Register
from regmap.plant import Plant

from conftest import ROOT
from support.esphome_ranges import items_of, ranges
from support.homeauto_yaml import esphome_config, load
from support.plant_tcp_bus import write_plant

FLOAT_METER = ROOT / "tests" / "maps" / "fixtures" / "float_meter.yaml"
ESP_SPACE = {"holding": "holding", "read": "input", "coil": "coil", "discrete_input": "discrete_input"}
ALL = ("*",)


def _slow_l2(tmp_path: Path) -> Path:
    """The fixture with voltage_l2 polled at the slow rate, like the registers on either side of it
    (pulse_count, last_reset): only its variant set keeps it out of their read."""
    text = FLOAT_METER.read_text(encoding="utf-8")
    line = re.search(r"^.*name: voltage_l2,.*$", text, re.MULTILINE)
    assert line is not None and "poll: fast}" in line[0]
    path = tmp_path / "float_meter_slow_l2.yaml"
    path.write_text(text.replace(line[0], line[0].replace("poll: fast}", "poll: slow}")), encoding="utf-8")
    return path


@pytest.fixture(params=["fixture", "slow_l2"])
def meter(request: pytest.FixtureRequest, tmp_path: Path) -> Device:
    return load_map(FLOAT_METER if request.param == "fixture" else _slow_l2(tmp_path))


def _variant_sets(device: Device, regs: list[Register]) -> set[tuple[str, ...]]:
    return {tuple(sorted(r.variants)) for r in regs}


def _at(device: Device, space: str, address: int) -> Register:
    (reg,) = [r for r in device.registers if r.space == space and r.address == address]
    return reg


def test_no_esphome_range_mixes_variant_sets(meter: Device, esphome: Path, tmp_path: Path) -> None:
    (package,) = esphome_files(meter, ALL).values()
    out = esphome_config(esphome, tmp_path, package)
    config = load("\n".join(line for line in out.splitlines() if not re.match(r"^(INFO|WARNING|DEBUG) ", line)))
    reads = ranges(items_of(config))
    l2 = [r for r in reads if any(_at(meter, ESP_SPACE[i.register_type], i.address).name == "voltage_l2" for i in r.items)]
    assert len(l2) == 1, [(r.start, r.count) for r in reads]
    for r in reads:
        regs = [_at(meter, ESP_SPACE[i.register_type], i.address) for i in r.items]
        assert len(_variant_sets(meter, regs)) == 1, (r.register_type, hex(r.start), r.count, [reg.name for reg in regs])


def test_the_read_plan_neither_mixes_nor_bridges_variant_sets(meter: Device) -> None:
    """A read of registers every variant has never covers voltage_l2's words, not even as a gap it bridges."""
    blocks = planned(meter, [r for r in meter.registers if r.access.readable])
    l2 = meter.register("voltage_l2")
    for block, _, _ in blocks:
        regs = [meter.register(spec.name) for spec in block.registers]
        assert len(_variant_sets(meter, regs)) == 1, [reg.name for reg in regs]
        if regs != [l2]:
            assert not (block.space == l2.space and block.address < l2.address + l2.words and l2.address < block.address + block.count), (
                hex(block.address),
                block.count,
                [reg.name for reg in regs],
            )


def _note(device: Device) -> str:
    having = device.register("voltage_l2").variants
    lacking = [v.name for v in device.info.variants if v.name not in having]
    assert having and lacking
    return (
        f"Only on variant {', '.join(having)}: voltage_l2 (on {', '.join(lacking)} the device answers them with an exception:"
        " the entities become unavailable)."
    )


def _header(text: str) -> list[str]:
    return [line for line in text.splitlines() if line.startswith("#")]


@pytest.mark.parametrize("render", [esphome_files, hass_files], ids=["esphome", "homeassistant"])
def test_the_header_names_the_entities_only_some_variants_have(render: Callable[[Device, tuple[str, ...]], dict[str, str]]) -> None:
    device = load_map(FLOAT_METER)
    (text,) = render(device, ALL).values()
    header = _header(text)
    assert f"# {_note(device)}" in header, header
    assert sum("Only on variant" in line for line in header) == 1


@pytest.mark.parametrize("render", [esphome_plant, hass_plant], ids=["esphome", "homeassistant"])
def test_a_plant_header_names_them_per_device(render: Callable[[Plant], dict[str, str]], tmp_path: Path) -> None:
    plant = load_plant(
        write_plant(
            tmp_path / "plant.yaml",
            "meters",
            [("line", "serial: {port: /dev/ttyUSB0, baud: 9600, parity: none}", [("meter", FLOAT_METER, 1)])],
        )
    )
    (text,) = render(plant).values()
    assert f"# meter: {_note(plant.devices[0].device)}" in _header(text), _header(text)
