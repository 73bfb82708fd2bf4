"""Home Assistant's `data_type: custom` with a `structure` (a Python struct format) -> the registers it reads.

HA joins the `count` registers high byte first and unpacks the bytes with `struct.unpack(structure, ...)`
(homeassistant/components/modbus/base_platform.py). Each value the structure holds is a register of ours
when it starts on a word and fills whole words (a half float, 'e', is an f16); a byte-sized value has no regmap type.
"""

from __future__ import annotations

import re
import struct
from dataclasses import dataclass

ORDERS = {"<": "little", ">": "big", "!": "big", "=": "native", "@": "native"}
_ITEM = re.compile(r"\s*(\d*)([a-zA-Z?])")
_INTEGERS = {2: "16", 4: "32", 8: "64"}
_FLOATS = {"e": "f16", "f": "f32", "d": "f64"}


class StructureError(ValueError):
    """A structure regmap cannot read as registers; the message says why."""


@dataclass(frozen=True)
class Field:
    """One value of the structure: its word offset from the first register, type and orders."""

    word_offset: int
    type: str
    word_order: str
    byte_order: str
    size: int  # registers it fills
    words: int | None = None  # strings only


def structure_fields(structure: str, count: int) -> tuple[list[Field], str]:
    """The values `structure` unpacks from `count` registers, and the byte order it was read with."""
    prefix = structure[:1] if structure[:1] in ORDERS else "@"
    body = structure[1:] if structure[:1] in ORDERS else structure
    try:
        size = struct.calcsize(structure)
    except struct.error as exc:
        raise StructureError(f"structure {structure!r}: {exc}") from exc
    if size != 2 * count:
        raise StructureError(f"structure {structure!r} is {size} bytes, but count {count} reads {2 * count}")
    # Native order is the host's: little-endian on every machine Home Assistant runs on.
    little = ORDERS[prefix] in ("little", "native")
    order = "low_first" if little else "high_first"
    fields: list[Field] = []
    done = ""  # the part of the format read so far, for the offset of the next value
    at = 0
    while at < len(body):
        match = _ITEM.match(body, at)
        if match is None:
            if body[at:].strip():
                raise StructureError(f"structure {structure!r}: cannot read {body[at:]!r}")
            break
        at = match.end()
        repeat, code = int(match.group(1) or 1), match.group(2)
        if code == "x":
            done += f"{repeat}x"
            continue
        if code == "s":
            start = struct.calcsize(prefix + done)
            _check_words(structure, code, start, repeat)
            fields.append(Field(start // 2, "string", "high_first", "high_first", repeat // 2, words=repeat // 2))
            done += f"{repeat}{code}"
            continue
        for _ in range(repeat):
            start = struct.calcsize(f"{prefix}{done}0{code}")  # native order aligns each value as C would
            width = struct.calcsize(prefix + code)
            _check_words(structure, code, start, width)
            fields.append(Field(start // 2, _type(structure, code, width), order, order, width // 2))
            done += f"0{code}{code}"
    return fields, ORDERS[prefix]


def _type(structure: str, code: str, width: int) -> str:
    if code in _FLOATS:
        return _FLOATS[code]
    if code in "hHiIlLqQ":
        return ("s" if code.islower() else "u") + _INTEGERS[width]
    raise StructureError(f"structure {structure!r}: '{code}' ({width} byte(s)) is not a whole-register value")


def _check_words(structure: str, code: str, start: int, width: int) -> None:
    if start % 2 or width % 2:
        raise StructureError(f"structure {structure!r}: '{code}' at byte {start} ({width} byte(s)) does not fill whole registers")
