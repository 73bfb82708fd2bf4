"""Values <-> raw integers <-> register words, honouring type, scale, word order and pairing."""

from __future__ import annotations

import enum
import struct
from decimal import Decimal
from fractions import Fraction
from typing import Any

from .spec import HIGH_FIRST, BitfieldSpec, RegisterSpec


class RangeError(ValueError):
    """A value outside the register's range; nothing was sent."""


def raw_to_words(spec: RegisterSpec[Any], raw: int, *, with_pair: bool = False) -> list[int]:
    """Words on the wire for a raw value. `with_pair` adds the unused high word of a paired register."""
    info = spec.type_info
    if not info.raw_min <= raw <= info.raw_max:
        raise RangeError(f"{spec.label}: raw value {raw} does not fit {spec.data_type}")
    words = list(info.to_words(raw))
    if info.wide:
        return words if spec.word_order == HIGH_FIRST else words[::-1]
    if with_pair and spec.paired:
        # The pair is one 32-bit parameter of which only the low word is used; its high word is
        # the sign extension (0 for every non-negative value, as the manual's frames show).
        return [0xFFFF if raw < 0 else 0x0000, *words]
    return words


def words_to_raw(spec: RegisterSpec[Any], words: list[int] | tuple[int, ...]) -> int:
    """Raw value from the register's own words (without the unused high word of a pair)."""
    info = spec.type_info
    if len(words) != info.words:
        raise ValueError(f"{spec.label}: expected {info.words} word(s), got {len(words)}")
    try:
        return info.from_words(words if spec.word_order == HIGH_FIRST or not info.wide else words[::-1])
    except struct.error:
        raise ValueError(f"{spec.label}: a register word is 0..0xFFFF, got {list(words)}") from None


def scale_of(spec: RegisterSpec[Any]) -> Fraction:
    return Fraction(spec.scale_num, spec.scale_den)


def raw_to_value(spec: RegisterSpec[Any], raw: int) -> int | float:
    """Engineering value: raw x scale (an int when the scale is 1)."""
    if spec.scale_num == spec.scale_den:
        return raw
    # raw * num is exact and Python's int / int is correctly rounded: the same float as Fraction gives, faster.
    return raw * spec.scale_num / spec.scale_den


def value_to_raw(spec: RegisterSpec[Any], value: int | float | str) -> int:
    """Raw integer for an engineering value, or an enum member name; checks range and resolution."""
    number: int | float | Decimal
    if isinstance(value, str):
        if spec.enum is not None:
            member = enum_member(spec.enum, value)
            if member is not None:
                check_raw(spec, int(member))
                return int(member)
        try:
            number = Decimal(value) if any(c in value for c in ".eE") else int(value, 0)
        except (ValueError, ArithmeticError):
            names = f"; one of {enum_names(spec.enum)}" if spec.enum is not None else ""
            raise RangeError(f"{spec.label}: {value!r} is not a number{names}") from None
    elif isinstance(value, enum.IntEnum | bool):
        number = int(value)
    else:
        number = value
    if isinstance(number, float) and number != number:
        raise RangeError(f"{spec.label}: NaN is not a value")
    try:
        exact = Fraction(Decimal(str(number))) if isinstance(number, float | Decimal) else Fraction(number)
    except (ValueError, OverflowError, ArithmeticError):
        raise RangeError(f"{spec.label}: {value!r} is not a finite number") from None
    raw_exact = exact / scale_of(spec)
    raw = round(raw_exact)
    if abs(raw_exact - raw) > Fraction(1, 1000):
        step = _fmt(raw_to_value(spec, 1)) if spec.scale_num != spec.scale_den else "1"
        raise RangeError(f"{spec.label}: {value} is not a multiple of the register's resolution {step}{_unit(spec)}")
    check_raw(spec, raw)
    return raw


def enum_member(enum_type: type[enum.IntEnum], text: str) -> enum.IntEnum | None:
    """The member named `text`, case-insensitively (`save_all_parameters`, `B38400`); a trailing
    underscore that keeps a generated name off a keyword may be left out."""
    wanted = text.strip().upper()
    for name, member in enum_type.__members__.items():
        if name == wanted or name.rstrip("_") == wanted:
            return member
    return None


def enum_names(enum_type: type[enum.IntEnum]) -> str:
    return ", ".join(f"{m.name.lower()}={m.value}" for m in enum_type)


def check_raw(spec: RegisterSpec[Any], raw: int) -> None:
    """The one check every raw value passes before it is sent or stored: the register's range,
    and for an enum register membership of the enum."""
    if not spec.raw_min <= raw <= spec.raw_max:
        low, high = raw_to_value(spec, spec.raw_min), raw_to_value(spec, spec.raw_max)
        shown = _fmt(raw_to_value(spec, raw))
        raise RangeError(f"{spec.label}: {shown}{_unit(spec)} is outside {_fmt(low)}..{_fmt(high)}{_unit(spec)}")
    if spec.enum is not None and not spec.bitfields and raw not in spec.enum._value2member_map_:
        raise RangeError(f"{spec.label}: {raw} is not one of {enum_names(spec.enum)}")
    for field in spec.bitfields:
        value = (raw & field.mask) >> field.lsb
        if field.enum is not None and value not in field.enum._value2member_map_:
            raise RangeError(f"{spec.label}.{field.name}: {value} is not one of {enum_names(field.enum)}")


def _unit(spec: RegisterSpec[Any]) -> str:
    return f" {spec.unit}" if spec.unit else ""


def _fmt(value: int | float) -> str:
    return f"{value:g}" if isinstance(value, float) else str(value)


def decode_value(spec: RegisterSpec[Any], raw: int) -> Any:
    """The typed value a client returns: enum member, bitfield dict source, or number."""
    if spec.enum is not None and not spec.bitfields:
        try:
            return spec.enum(raw)
        except ValueError:
            return raw  # a value the manual does not list: keep the number rather than fail the read
    return raw_to_value(spec, raw)


def field_value(spec: RegisterSpec[Any], field: BitfieldSpec, text: str) -> int:
    """One bitfield's raw value from its text: an enum member name, `true`/`false`, or a number."""
    text = text.strip()
    if field.enum is not None:
        member = enum_member(field.enum, text)
        if member is not None:
            return int(member)
    flags = {"true": 1, "on": 1, "false": 0, "off": 0}
    if field.width == 1 and text.lower() in flags:
        return flags[text.lower()]
    try:
        value = int(text, 0)
    except ValueError:
        names = f"; one of {enum_names(field.enum)}" if field.enum is not None else ""
        raise RangeError(f"{spec.label}.{field.name}: {text!r} is not a number{names}") from None
    if not 0 <= value <= field.mask >> field.lsb:
        raise RangeError(f"{spec.label}.{field.name}: {value} does not fit in {field.width} bit(s)")
    if field.enum is not None and value not in field.enum._value2member_map_:
        raise RangeError(f"{spec.label}.{field.name}: {value} is not one of {enum_names(field.enum)}")
    return value


def parse_fields(spec: RegisterSpec[Any], text: str) -> tuple[int | None, dict[str, int]]:
    """`[BASE,]field:value,field:value` -> (the base word or None, {field: raw value}).

    Field names are case-insensitive; an unknown name is an error that lists the fields."""
    by_name = {f.name.lower(): f for f in spec.bitfields}
    base: int | None = None
    named: dict[str, int] = {}
    for position, part in enumerate(text.split(",")):
        name, sep, value_text = part.partition(":")
        if not sep:
            if position != 0:
                raise RangeError(f"{spec.label}: {part.strip()!r} is not field:value (a base word may only come first)")
            try:
                base = int(part.strip(), 0)
            except ValueError:
                raise RangeError(f"{spec.label}: {part.strip()!r} is not field:value (fields: {', '.join(by_name)})") from None
            continue
        field = by_name.get(name.strip().lower())
        if field is None:
            raise RangeError(f"{spec.label} has no bitfield {name.strip()!r} (fields: {', '.join(by_name)})")
        if field.name in named:
            raise RangeError(f"{spec.label}.{field.name} is given twice")
        named[field.name] = field_value(spec, field, value_text)
    return base, named


def merge_fields(spec: RegisterSpec[Any], base: int, named: dict[str, int]) -> int:
    """`base` with the named fields replaced and every other bit kept."""
    raw = base
    for field in spec.bitfields:
        if field.name in named:
            raw = (raw & ~field.mask) | (named[field.name] << field.lsb)
    return raw
