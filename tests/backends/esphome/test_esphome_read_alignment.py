"""Issue #34's float meter answers only reads that start on an even address and cover an even count. ESPHome's
modbus_controller forms its reads itself from the items (`create_register_ranges_`); the package's items,
as `esphome config` validates and prints them, make only reads the device answers, and each item finds its
own register's bytes in its read."""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import pytest

from regmap.backends.esphome import render_device
from regmap.frontend import load_map

from conftest import ROOT
from support.esphome_ranges import Item, items_of, ranges
from support.homeauto_yaml import esphome_config, load

FLOAT_METER = load_map(ROOT / "tests" / "maps" / "fixtures" / "float_meter.yaml")
EXEMPT = {("holding", 0x0104, 1)}  # the CT ratio alone (read_alignment.exempt)
SPACE = {"read": "input", "holding": "holding"}


def _package(patterns: tuple[str, ...] | None) -> str:
    (text,) = render_device(FLOAT_METER, patterns).values()
    return text


def _validated(esphome: Path, tmp_path: Path, package: str) -> dict[str, Any]:
    out = esphome_config(esphome, tmp_path, package)
    body = "\n".join(line for line in out.splitlines() if not re.match(r"^(INFO|WARNING|DEBUG) ", line))
    data = load(body)
    assert isinstance(data, dict)
    return data


def _answered(space: str, address: int, count: int) -> bool:
    return (address % 2 == 0 and count % 2 == 0) or (space, address, count) in EXEMPT


def _check(items: list[Item]) -> int:
    reads = ranges(items)
    for r in reads:
        space = SPACE[r.register_type]
        assert _answered(space, r.start, r.count), (r.register_type, hex(r.start), r.count, [i.name for i in r.items])
        for item in r.items:  # the item's bytes are its register's: ESPHome reads them at its final offset
            assert r.start + item.offset // 2 == item.address, (item.name, hex(r.start), item.offset, hex(item.address))
    return len(reads)


@pytest.mark.parametrize("patterns", [None, ("*",)], ids=["default", "all"])
def test_esphome_reads_of_the_float_meter_are_aligned(esphome: Path, tmp_path: Path, patterns: tuple[str, ...] | None) -> None:
    config = _validated(esphome, tmp_path, _package(patterns))
    items = items_of(config)
    assert any(i.address == 0x0007 and i.register_type == "read" for i in items)  # humidity, at an odd address, is there
    assert _check(items) >= 3


def test_the_range_emulation_sees_a_misaligned_read() -> None:
    """The check can fail: the items of the package before alignment (each at its own address and count)."""
    data = load(_package(("*",)))
    items = items_of(data)
    for item in items:
        words = 1 if item.register_type == "read" and item.address in (6, 7) else item.count  # temperature, humidity: one word each
        item.start, item.offset, item.count, item.size = item.address, 0, words, 2 * words
    with pytest.raises(AssertionError):
        _check(items)
