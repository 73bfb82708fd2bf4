"""Plain-text spellings back ends and tools share: a title with its Chinese title, numbers, engineering
values, articles.

Each back end escapes the result for its own target (`py_doc`, `c_comment`, `md_text`) and keeps its
own spelling where the targets truly differ (C number literals, the manual-section sentence ...).
Two spellings of a number exist on purpose: the documents print 10 significant digits (`number`),
the field tools print every digit a value has (`number_text`, `eng(..., every_digit=True)`).
"""

from __future__ import annotations

import functools
import math
import struct
from fractions import Fraction

from regmap.model import Device, Register
from regmap_runtime.spaces import SPACES
from regmap_runtime.timestamps import time_text

BIT_NAMES = {0: "off", 1: "on"}


def titled(title: str, title_zh: str | None) -> str:
    """`Peak current (峰值电流)`: the manual's title, with the Chinese one when the map gives it."""
    return f"{title} ({title_zh})" if title_zh else title


def article(noun: str) -> str:
    """`an input register`, `a coil`, `an f32 register`, `a u16 register`: as the noun is read aloud."""
    if noun[1:2].isdigit():  # f32, s16, u64: the letter is read by its name ("ef", "ess", "you")
        return f"{'an' if noun[:1] in 'aefhilmnorsx' else 'a'} {noun}"
    return f"{'an' if noun[:1] in 'aeiou' else 'a'} {noun}"


def space_label(space: str) -> str:
    """`coil`, `input register`: how a message names one address of a space (its title, singular)."""
    return SPACES[space].title.removesuffix("s")


def number(value: Fraction | int | float) -> str:
    """A number as the docs and comments print it: integers exactly, anything else to 10 significant digits
    (an exact decimal of more digits in full)."""
    if isinstance(value, Fraction) and value.denominator == 1:
        return str(value.numerator)
    if isinstance(value, int):
        return str(value)
    if isinstance(value, Fraction):
        exact = exact_decimal(value) or ""
        if len(exact.lstrip("-0").replace(".", "")) > 10:
            return exact  # an exact decimal of more digits than 10 (a counter x 0.001): 123456789.012, not 123456789
    return f"{float(value):.10g}"


def number_text(value: int | float, data_type: str | None = None) -> str:
    """A number as people write it: integers as they are, floats in the fewest digits that give the
    same value back (an f32 in the fewest that give the same 32 bits: 0.1, not 0.10000000149011612)."""
    if not isinstance(value, float):
        return str(value)
    if not math.isfinite(value):
        return str(value)
    text = repr(value)
    if data_type == "f32":
        bits = struct.pack(">f", value)
        for digits in range(1, 10):
            short = f"{value:.{digits}g}"
            try:
                same = struct.pack(">f", float(short)) == bits
            except OverflowError:  # rounded past float32's largest value
                continue
            if same:
                text = repr(float(short))
                break
    if "e" in text:
        mantissa, _, exponent = text.partition("e")
        return f"{mantissa}e{int(exponent)}"
    return text[:-2] if text.endswith(".0") else text


def exact_decimal(value: Fraction) -> str | None:
    """`18446744073709551.615`: a fraction written exactly in decimals, or None when no finite decimal
    writes it (1/3)."""
    places = _decimal_places(value.denominator)
    if places is None:
        return None
    digits = str(abs(value.numerator * 10**places // value.denominator)).rjust(places + 1, "0")
    sign = "-" if value < 0 else ""
    return sign + (f"{digits[:-places]}.{digits[-places:]}" if places else digits)


def _decimal_places(denominator: int) -> int | None:
    """How many decimals write 1/denominator exactly (2**a * 5**b needs max(a, b)), or None when no finite decimal does."""
    twos = fives = 0
    while denominator % 2 == 0:
        denominator, twos = denominator // 2, twos + 1
    while denominator % 5 == 0:
        denominator, fives = denominator // 5, fives + 1
    return max(twos, fives) if denominator == 1 else None


def eng(reg: Register, raw: int | float | str, *, every_digit: bool = False) -> str:
    """The engineering value of a raw register value (raw x scale + offset); text as a quoted
    string, a coil as on/off. A float raw is scaled as a float (it is no exact fraction).

    The documents round to 10 significant digits; `every_digit` (the field tools) prints an exact
    decimal in full, and a float in the fewest digits that give it back."""
    if isinstance(raw, str):
        return '"' + raw + '"'
    if reg.type.is_bool:
        return BIT_NAMES[1 if raw else 0]
    if reg.zone is not None and isinstance(raw, int):
        return time_text(raw, reg.zone)  # a timestamp: ISO 8601, Z for utc, no zone for local
    if not every_digit:
        if type(raw) is int and not reg.scaled and not reg.offset_set:
            return str(raw)  # most registers: what the exact fraction below prints, without its arithmetic (issue #36)
        if isinstance(raw, float):
            return number(raw * float(reg.scale) + float(reg.offset))
        scale, offset = reg.scale, reg.offset
        return _scaled_text(raw, scale.numerator, scale.denominator, offset.numerator, offset.denominator)
    if isinstance(raw, float):
        scaled = reg.scaled or reg.offset_set
        return number_text(raw * float(reg.scale) + float(reg.offset) if scaled else raw, None if scaled else reg.type.value)
    exact = Fraction(raw) * reg.scale + reg.offset
    return exact_decimal(exact) or number_text(float(exact))


# How many engineering values `_scaled_number` keeps: a run over three maps meets a few hundred; a process that
# generates for hours keeps no more than this.
_SCALED_CACHE_SIZE = 1 << 15


@functools.lru_cache(maxsize=_SCALED_CACHE_SIZE)  # registers share scales, offsets and limits: each value is worked out once
def _scaled_number(raw: int, scale: Fraction, offset: Fraction) -> str:
    """`number` of raw x scale + offset, kept by those exact values (Fraction arithmetic and the decimal test are slow)."""
    return number(raw * scale + offset if offset else raw * scale)  # adding a Fraction 0 costs a gcd


@functools.lru_cache(maxsize=_SCALED_CACHE_SIZE)
def _scaled_text(raw: int, scale_num: int, scale_den: int, offset_num: int, offset_den: int) -> str:
    """`_scaled_number` kept by the ratios' integers: a key of ints hashes in C, a Fraction's hash is Python code
    (two of them cost more than the look-up saves, for the thousand values the back ends ask of a run)."""
    return _scaled_number(raw, Fraction(scale_num, scale_den), Fraction(offset_num, offset_den))


def zone_text(reg: Register) -> str:
    """What a timestamp register counts, for docs and comments (empty for any other register)."""
    if reg.zone == "utc":
        return "seconds since 1970-01-01T00:00:00Z (UTC)"
    if reg.zone == "local":
        return "seconds since 1970-01-01T00:00 on the device's local clock (no zone)"
    return ""


def na_mark(reg: Register, raw: int | float) -> str:
    """A "not available" marker as datasheets print it: the bit pattern of an integer (0xFFFF, 0x8000 of an
    s16), a float's value."""
    if isinstance(raw, float):
        return "NaN" if math.isnan(raw) else number(raw)
    return f"0x{raw & ((1 << reg.type.bits) - 1):0{reg.type.bits // 4}X}"


def na_list(reg: Register) -> str:
    """Every "not available" marker of `reg`: `0x7FFF, 0xFFFF`, `NaN`."""
    return ", ".join([na_mark(reg, raw) for raw in reg.na] + (["NaN"] if reg.na_nan else []))


def variants_text(device: Device, reg: Register) -> str:
    """The variants that have `reg`, by name and title: `three_phase (Three-phase model)`."""
    titles = {v.name: v.title for v in device.info.variants}
    return ", ".join(f"{name} ({titles[name]})" if name in titles else name for name in reg.variants)


def sentences(*parts: str | None) -> str:
    """The parts as sentences, for generated comments: each one's whitespace made single spaces and ended by a full stop
    unless it ends one already, the empty ones left out. A loop (no generator, no call per part): every register's,
    enum's and function's comment of the C and ST back ends is made here."""
    out = []
    for text in parts:
        if not text:
            continue
        # Most map text has its words apart by single spaces already: printable (no whitespace but the space) with no
        # space doubled or at an end, the split and join would give it back as it is.
        if not (text.isprintable() and "  " not in text and text[0] != " " and text[-1] != " "):
            text = " ".join(text.split())
            if not text:
                continue
        out.append(text if text[-1] in ".!?。" else text + ".")
    return " ".join(out)


def manual_sections(source: tuple[str, ...]) -> str:
    """The manual sections a fact comes from, as a sentence of a generated comment."""
    return f"Manual {', '.join(source)}." if source else ""
