"""The Markdown docs name an f16 register's type (16-bit IEEE 754 half-precision float) and its byte order."""

from __future__ import annotations

from pathlib import Path

from regmap.frontend import load_map
from regmap.generate import render

from support.half_map import write_half_map


def test_the_docs_say_half_precision_and_the_byte_order(tmp_path: Path) -> None:
    device = load_map(write_half_map(tmp_path))
    (text,) = [t for name, t in render([device], ["markdown"])["markdown"].items() if name.endswith("half_sensor.md")]
    assert text.count("16-bit IEEE 754 half-precision float") >= len([r for r in device.registers if r.type.value == "f16"])
    assert "Word and byte order" in text
