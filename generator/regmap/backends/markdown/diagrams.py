"""Bitfield diagrams: a register's bit layout as wavedrom's `reg` renderer draws it (SVG), written directly."""

from __future__ import annotations

import functools
import json
import re
from typing import Any

from regmap.backends.markdown import text as md
from regmap.backends.markdown.text import DocId
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
    """The register's bit layout as wavedrom's `reg` renderer draws it; unused bits shaded."""
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
    """The SVG wavedrom's `reg` renderer (wavedrom 2.0.3, through svgwrite) draws for one layout, written directly:
    importing wavedrom and svgwrite and building their element trees cost more than the rest of the docs (issue #36).
    Only what regmap's layouts use: fields with a name or none (unused bits), no attributes or types, no flips. The
    names are `DocId`s cut with `…`, so no text needs XML escaping. Registers sharing a layout (DI1..DI7) are drawn once."""
    layout = json.loads(source)
    config = layout["config"]
    hspace, vspace, lanes, bits = config["hspace"], config["vspace"], config["lanes"], config["bits"]
    mod = bits // lanes
    fields, lsb = [], 0
    for field in layout["reg"]:
        fields.append((lsb, lsb + field["bits"] - 1, field.get("name")))
        lsb += field["bits"]
    width, height = hspace + 9, vspace * lanes + 5
    out = [
        f'<svg baseProfile="full" class="WaveDrom" height="{height}" version="1.1" viewBox="0,0,{width},{height}" width="{width}" '
        'xmlns="http://www.w3.org/2000/svg" xmlns:ev="http://www.w3.org/2001/xml-events" xmlns:xlink="http://www.w3.org/1999/xlink">'
        f"<title>{_TITLE_SLOT}</title><defs />"
    ]
    for index in range(lanes):
        out.append(
            '<g font-family="sans-serif" font-size="14" font-weight="normal" text-anchor="middle" '
            f'transform="translate(4.5,{(lanes - index - 1) * vspace + 0.5})">'
        )
        out.append(_cage(fields, index, mod, hspace, vspace))
        out.append(_labels(fields, index, mod, hspace / mod, vspace))
        out.append("</g>")
    out.append("</svg>")
    return "".join(out)


def _line(x1: float, x2: float, y1: float, y2: float) -> str:
    return f'<line x1="{x1}" x2="{x2}" y1="{y1}" y2="{y2}" />'


def _cage(fields: list[tuple[int, int, str | None]], index: int, mod: int, hspace: int, vspace: int) -> str:
    """The lane's frame and bit separators: a full line where a field starts (and at the lane's left), ticks elsewhere."""
    out = [f'<g stroke="black" stroke-linecap="round" stroke-width="1" transform="translate(0,{vspace / 4})">']
    out += [_line(0, hspace, 0, 0), _line(0, 0, 0, vspace / 2), _line(0, hspace, vspace / 2, vspace / 2)]
    starts = {lsb for lsb, _, _ in fields}
    bit = index * mod
    for j in range(mod, 0, -1):
        x = j * (hspace / mod)
        if j == mod or bit in starts:
            out.append(_line(x, x, 0, vspace / 2))
        else:
            out += [_line(x, x, 0, vspace / 16), _line(x, x, vspace * 7 / 16, vspace * 7 / 16 + vspace / 16)]
        bit += 1
    out.append("</g>")
    return "".join(out)


def _text(body: str, x: float | None, y: float | None = None) -> str:
    """wavedrom's `get_text`; a name's zero coordinate is left out (a bit number's is not: wavedrom passes it in a list)."""
    return "<text" + (f' x="{x}"' if x is not None else "") + (f' y="{y}"' if y is not None else "") + f"><tspan>{body}</tspan></text>"


def _labels(fields: list[tuple[int, int, str | None]], index: int, mod: int, step: float, vspace: int) -> str:
    """The lane's bit numbers, field names and shaded unused bits (wavedrom's `labelArr`)."""
    bits, names, blanks = [], [], []
    for first, last, name in fields:
        lsbm, msbm, lsb, msb = 0, mod - 1, index * mod, (index + 1) * mod - 1
        if first // mod == index:
            lsbm, lsb = first % mod, first
            if last // mod == index:
                msbm, msb = last % mod, last
        elif last // mod == index:
            msbm, msb = last % mod, last
        else:
            continue  # a field that only crosses this lane is not labelled in it (as wavedrom does)
        bits.append(_text(str(lsb), step * (mod - lsbm - 1)))
        if lsbm != msbm:
            bits.append(_text(str(msb), step * (mod - msbm - 1)))
        if name:
            x = step * (mod - ((msbm + lsbm) / 2) - 1)
            lines = name.split("\n")
            names += [_text(line, x or None, (-(len(lines) - 1) / 2 + i) * 14 or None) for i, line in enumerate(lines)]
        else:
            insert = step * (mod - msbm - 1)
            blanks.append(f'<rect height="{vspace / 2}" style="fill-opacity:0.1" width="{step * (msbm - lsbm + 1)}" x="{insert}" y="0" />')
    return (
        '<g text-anchor="middle"><g>'
        + _group(f"translate(0,{vspace / 4})", blanks)
        + _group(f"translate({step / 2},{vspace / 5})", bits)
        + _group(f"translate({step / 2},{vspace / 2 + 4})", names)
        + _group(f"translate({step / 2},{vspace})", [])
        + "</g></g>"
    )


def _group(transform: str, children: list[str]) -> str:
    return f'<g transform="{transform}">{"".join(children)}</g>' if children else f'<g transform="{transform}" />'
