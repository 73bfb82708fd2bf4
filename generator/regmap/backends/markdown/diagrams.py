"""Bitfield diagrams: a register's bit layout drawn by wavedrom's `reg` renderer (SVG)."""

from __future__ import annotations

import functools
import importlib.util
import json
import re
from typing import Any

from regmap.backends.markdown import text as md
from regmap.backends.markdown.text import DocId
from regmap.diagnostics import UsageError
from regmap.model import Device, Register
from regmap.render import header_lines


def diagram_path(device: Device, reg: Register) -> str:
    """Where a bitfield register's diagram lives, relative to the docs root; an array's elements share one."""
    owner = f"{reg.array.array}_{reg.array.member}" if reg.array else reg.name
    return f"{DocId(device.id)}/{DocId(owner)}.svg"


LANE_BITS = 8  # bits per row of a diagram: 16-bit registers draw as two rows, MSB row on top
DIAGRAM_WIDTH = 800
CHAR_WIDTH = 8.5  # average width of a 14 px sans-serif character, for wrapping names
MAX_LINES = 3


def _wrap(name: str, bits: int) -> str:
    """Break a snake_case name after underscores so that each line fits the field's width."""
    fit = max(3, int(bits * DIAGRAM_WIDTH / LANE_BITS / CHAR_WIDTH) - 1)
    lines: list[str] = []
    for part in re.findall(r"[^_]+_?|_", name):
        if lines and len(lines[-1]) + len(part) <= fit:
            lines[-1] += part
        else:
            lines.append(part)
    if len(lines) > MAX_LINES:
        lines = [*lines[: MAX_LINES - 1], "".join(lines[MAX_LINES - 1 :])[: fit - 1] + "…"]
    return "\n".join(lines)


def bitfield_svg(device: Device, reg: Register) -> str:
    """The register's bit layout drawn by wavedrom's `reg` renderer; unused bits shaded."""
    if importlib.util.find_spec("wavedrom") is None:  # pragma: no cover - wavedrom is a declared dependency
        raise UsageError("wavedrom is not installed; it draws the bitfield diagrams of the docs (pip install wavedrom)")
    fields: list[dict[str, Any]] = []
    position = 0
    for b in sorted(reg.bitfields, key=lambda b: b.lsb):
        if b.lsb > position:
            fields.append({"bits": b.lsb - position})
        fields.append({"bits": b.width, "name": _wrap(DocId(b.name), b.width)})
        position = b.msb + 1
    if position < reg.type.bits:
        fields.append({"bits": reg.type.bits - position})
    source = {"reg": fields, "config": {"bits": reg.type.bits, "lanes": reg.type.bits // LANE_BITS, "hspace": DIAGRAM_WIDTH, "vspace": 110}}
    owner = f"{reg.array.array} member {reg.array.member}" if reg.array else reg.name
    svg = _drawing(json.dumps(source, sort_keys=True)).replace(_TITLE_SLOT, f"Bit layout of {owner}", 1)
    header = "".join(f"<!-- {md.html_comment(line)} -->\n" for line in header_lines(device, "regmap generate"))
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + header + svg + "\n"


_TITLE_SLOT = "REGMAP_TITLE_SLOT"  # identifiers and fixed words only go in here, so no XML escaping is needed


@functools.lru_cache(maxsize=256)
def _drawing(source: str) -> str:
    """wavedrom's SVG for one layout; registers sharing a layout (DI1..DI7) are drawn once."""
    from wavedrom.bitfield import BitField  # type: ignore[import-untyped,import-not-found,unused-ignore]

    # What wavedrom.render(source) does for a `reg` source, without its YAML round trip of our JSON (a no-op for it).
    drawing = BitField().renderJson(json.loads(source))
    drawing.set_desc(title=_TITLE_SLOT)
    text: str = drawing.tostring()
    return text
