"""How map text and raw values are spelled in an ESPHome package: names, units and HEXBYTES."""

from __future__ import annotations

from regmap.model import Register, WordOrder


def esp_text(text: str) -> str:
    """Map text as an ESPHome name or label: `$` would start a substitution or a Jinja expression, and
    ESPHome reserves `/` in names (URL paths; `_validate_no_slash`); both become their look-alikes."""
    return esp_unit(text).replace("/", "\u2044")


def esp_unit(text: str) -> str:
    """A unit as the map gives it (ESPHome checks units for length only); only `$`, which would start
    a substitution, becomes its look-alike."""
    return " ".join(text.split()).replace("$", "\uff04")


def num(value: float) -> float | int:
    return int(value) if value == int(value) else value


def wire_words(reg: Register, raw: int) -> list[int]:
    """The wire words of a raw value, in the register's word order."""
    unsigned = raw & ((1 << reg.type.bits) - 1)
    words = [(unsigned >> (16 * i)) & 0xFFFF for i in reversed(range(reg.words))]
    return words if reg.word_order is WordOrder.HIGH_FIRST else words[::-1]


def hexbytes(reg: Register, raw: int) -> str:
    """What ESPHome's `raw_encode: HEXBYTES` makes of a register holding `raw`: its wire bytes, `%02x` each."""
    return "".join(f"{w:04x}" for w in wire_words(reg, raw))
