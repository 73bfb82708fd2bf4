"""Values <-> raw integers <-> register words, honouring type, scale, word order and pairing."""

from __future__ import annotations

import enum
from datetime import datetime
from decimal import Decimal
from fractions import Fraction
from typing import Any

from .spec import HIGH_FIRST, BitfieldSpec, Raw, RegisterSpec
from .timestamps import TimestampError, seconds_to_datetime, timestamp_seconds
from .types import FLOAT, INT, swap_bytes


class RangeError(ValueError):
    """A value outside the register's range; nothing was sent."""


class ReportedStateError(RangeError):
    """A write of a state the device only reports (an enum member with access r); nothing was sent."""


class DestructiveWriteError(RangeError):
    """A plain write of the value a destructive command writes, or that command unconfirmed; nothing was sent."""


def destructive_refusal(spec: RegisterSpec[Any], name: str) -> DestructiveWriteError:
    return DestructiveWriteError(
        f"{spec.label}: {name} is destructive (the map marks it: it loses data or state); "
        f"send it as the command {name}, confirmed with its name (regmap command ... {name} --confirm {name}; "
        f"in Python {name}(confirm={name!r}))"
    )


def _wire_order(spec: RegisterSpec[Any], words: list[int]) -> list[int]:
    """Words high word first, high byte first <-> the register's order on the wire (the swap is its own inverse)."""
    if spec.byte_order != HIGH_FIRST:
        words = swap_bytes(words)
    if spec.type_info.wide and spec.word_order != HIGH_FIRST:
        words = words[::-1]
    return words


def raw_to_words(spec: RegisterSpec[Any], raw: Raw, *, with_pair: bool = False) -> list[int]:
    """Words on the wire for a raw value (for a coil, its one bit). `with_pair` adds the unused high word of a paired register."""
    info = spec.type_info
    if info.is_string:
        return _wire_order(spec, _text_words(spec, str(raw)))
    if info.is_bool:
        return [1 if raw else 0]
    if isinstance(raw, str) or not info.raw_min <= raw <= info.raw_max or (info.kind == INT and not isinstance(raw, int)):
        raise RangeError(f"{spec.label}: raw value {raw!r} does not fit {spec.data_type}")
    words = _wire_order(spec, list(info.to_words(raw)))
    if with_pair and spec.paired:
        # The pair is one 32-bit parameter of which only the low word is used; its high word is
        # the sign extension (0 for every non-negative value, as the manual's frames show).
        return [0xFFFF if raw < 0 else 0x0000, *words]
    return words


def words_to_raw(spec: RegisterSpec[Any], words: list[int] | tuple[int, ...]) -> Raw:
    """Raw value from the register's own words (without the unused high word of a pair), or a coil's one bit."""
    info = spec.type_info
    if len(words) != spec.words:
        raise ValueError(f"{spec.label}: expected {spec.words} {spec.space_info.unit}(s), got {len(words)}")
    if info.is_bool:
        if words[0] not in (0, 1):
            raise ValueError(f"{spec.label}: a bit is 0 or 1, got {words[0]}")
        return words[0]
    if min(words) < 0 or max(words) > 0xFFFF:  # two C calls: the check every read makes, kept cheap
        raise ValueError(f"{spec.label}: a register word is 0..0xFFFF, got {list(words)}")
    ordered = _wire_order(spec, list(words))
    if info.is_string:
        return _words_text(spec, ordered)
    return info.from_words(ordered)


def _text_words(spec: RegisterSpec[Any], text: str) -> list[int]:
    """Text as register words: its bytes in `encoding`, first character in the high byte, padded to the register's length."""
    data = _encode_text(spec, text)
    data += (b" " if spec.padding == "space" else b"\0") * (2 * spec.words - len(data))
    return [data[i] << 8 | data[i + 1] for i in range(0, len(data), 2)]


def _words_text(spec: RegisterSpec[Any], words: list[int]) -> str:
    """The text in a string register: up to the first NUL, trailing padding removed; bytes the
    encoding cannot read become U+FFFD rather than fail the read."""
    data = b"".join(w.to_bytes(2, "big") for w in words).split(b"\0", 1)[0]
    if spec.padding == "space":
        data = data.rstrip(b" ")
    return data.decode(spec.encoding, errors="replace")


def _encode_text(spec: RegisterSpec[Any], text: str) -> bytes:
    try:
        data = text.encode(spec.encoding)
    except UnicodeEncodeError as exc:
        raise RangeError(f"{spec.label}: {text!r} cannot be written in {spec.encoding} ({exc.reason} at character {exc.start})") from None
    if b"\0" in data:
        raise RangeError(f"{spec.label}: text may not contain NUL (it ends the string on the wire)")
    if len(data) > 2 * spec.words:
        raise RangeError(f"{spec.label}: {text!r} is {len(data)} bytes in {spec.encoding}; the register holds {2 * spec.words}")
    return data


def scale_of(spec: RegisterSpec[Any]) -> Fraction:
    return Fraction(spec.scale_num, spec.scale_den)


def offset_of(spec: RegisterSpec[Any]) -> Fraction:
    return Fraction(spec.offset_num, spec.offset_den)


def raw_to_value(spec: RegisterSpec[Any], raw: int | float) -> int | float:
    """Engineering value: raw x scale + offset (an int when the scale is 1 and there is no offset)."""
    if spec.scale_num == spec.scale_den and spec.offset_num == 0:
        return raw
    # raw * num is exact and Python's int / int is correctly rounded: the same float as Fraction gives, faster.
    value = raw * spec.scale_num / spec.scale_den
    return value + spec.offset_num / spec.offset_den if spec.offset_num else value


_FLAGS = {"true": 1, "on": 1, "1": 1, "false": 0, "off": 0, "0": 0}


def value_to_raw(spec: RegisterSpec[Any], value: int | float | str | datetime) -> Raw:
    """Raw value for an engineering value, an enum member name, text, a flag or a timestamp's time; checks range and resolution."""
    info = spec.type_info
    if spec.scale_from is not None:  # the client's encode scales it by a freshly read factor (regmap_runtime.scaling)
        raise RangeError(f"{spec.label}: value = raw x 10^{spec.scale_from}; its scale factor must be read to write a value")
    if value is None:  # what a read of the "not available" marker returns: no value to write back
        raise RangeError(f"{spec.label}: None is no value (a read returns it for the device's 'not available' marker)")
    if spec.zone is not None:
        try:
            seconds = timestamp_seconds(value, spec.zone)
        except TimestampError as exc:
            raise RangeError(f"{spec.label}: {exc}") from None
        check_raw(spec, seconds)
        return seconds
    if isinstance(value, datetime):
        raise RangeError(f"{spec.label}: a time is for a timestamp register; this one is {spec.data_type}")
    if info.is_string:
        if not isinstance(value, str):
            raise RangeError(f"{spec.label}: a string register takes text, not {value!r}")
        check_raw(spec, value)
        return value
    if info.is_bool:
        return _flag(spec, value)
    number: int | float | Decimal
    if isinstance(value, str):
        if spec.enum is not None:
            member = enum_member(spec.enum, value)
            if member is not None:
                coded: int | float = float(member) if info.is_float else int(member)  # a setting coded as a float
                check_raw(spec, coded)
                return coded
        try:
            number = Decimal(value) if any(c in value for c in ".eEnN") else int(value, 0)
        except (ValueError, ArithmeticError):
            names = f"; one of {enum_names(spec.enum, spec.reported)}" if spec.enum is not None else ""
            raise RangeError(f"{spec.label}: {value!r} is not a number{names}") from None
    elif isinstance(value, enum.IntEnum | bool):
        number = int(value)
    else:
        number = value
    if isinstance(number, float | Decimal) and number != number:
        raise RangeError(f"{spec.label}: NaN is not a value")
    try:
        exact = Fraction(Decimal(str(number))) if isinstance(number, float | Decimal) else Fraction(number)
    except (ValueError, OverflowError, ArithmeticError):
        raise RangeError(f"{spec.label}: {value!r} is not a finite number") from None
    raw_exact = (exact - offset_of(spec)) / scale_of(spec)
    if info.is_float:
        try:
            raw_float = float(raw_exact)
        except OverflowError:
            raise RangeError(f"{spec.label}: {value} is beyond any {spec.data_type} value") from None
        check_raw(spec, raw_float)
        return _rounded_float(spec, raw_float)
    raw = round(raw_exact)
    if abs(raw_exact - raw) > Fraction(1, 1000):
        step = _fmt(spec.scale_num / spec.scale_den) if spec.scale_num != spec.scale_den else "1"
        raise RangeError(f"{spec.label}: {value} is not a multiple of the register's resolution {step}{_unit(spec)}")
    check_raw(spec, raw)
    return raw


def _rounded_float(spec: RegisterSpec[Any], raw: float) -> float:
    """The value the register's words hold (struct rounds to the nearest, ties to even: an f16 keeps 11
    bits, 0.1 is 0.0999755859375); checked again, so rounding never carries it past the range or to infinity."""
    info = spec.type_info
    try:
        held = float(info.from_words(info.to_words(raw)))
    except OverflowError:
        held = float("inf") if raw > 0 else float("-inf")
    if held != raw:
        check_raw(spec, held)
    return held


def _flag(spec: RegisterSpec[Any], value: int | float | str) -> int:
    if isinstance(value, str):
        flag = _FLAGS.get(value.strip().lower())
        if flag is None:
            raise RangeError(f"{spec.label}: {value!r} is not on/off (true, false, on, off, 1, 0)")
        return flag
    if value not in (0, 1):  # True and False are 1 and 0
        raise RangeError(f"{spec.label}: a {spec.space_info.name} is on or off (1 or 0), not {value!r}")
    return int(value)


def enum_member(enum_type: type[enum.IntEnum], text: str) -> enum.IntEnum | None:
    """The member named `text`, case-insensitively (`save_all_parameters`, `B38400`); a trailing
    underscore that keeps a generated name off a keyword may be left out."""
    wanted = text.strip().upper()
    for name, member in enum_type.__members__.items():
        if name == wanted or name.rstrip("_") == wanted:
            return member
    return None


def enum_names(enum_type: type[enum.IntEnum], reported: tuple[tuple[int, int], ...] = ()) -> str:
    """The members as `name=value`; those in `reported` (states the device only reports) left out: the values one may write."""
    return ", ".join(f"{m.name.lower()}={m.value}" for m in enum_type if not in_runs(m.value, reported))


def in_runs(raw: int, runs: tuple[tuple[int, int], ...]) -> bool:
    """Whether `raw` lies in one of the runs (first, last), both ends included."""
    return any(first <= raw <= last for first, last in runs)


def _refuse_reported(label: str, enum_type: type[enum.IntEnum] | None, reported: tuple[tuple[int, int], ...], raw: int) -> None:
    """A state the device only reports is read, never written: refused with its name and the values that may be written."""
    if not in_runs(raw, reported):
        return
    member = enum_type._value2member_map_.get(raw) if enum_type is not None else None
    name = member.name.lower() if isinstance(member, enum.IntEnum) else str(raw)
    choices = f"; write one of {enum_names(enum_type, reported)}" if enum_type is not None else ""
    raise ReportedStateError(f"{label}: {name} ({raw}) is a state the device only reports (access: r), never written{choices}")


def check_raw(spec: RegisterSpec[Any], raw: Raw) -> None:
    """The one check every raw value passes before it is sent or stored: the register's range,
    membership of its enum and never a state the device only reports (ReportedStateError), the fit
    of its text, 0/1 for a bit. A read decodes every member; only writes come through here."""
    info = spec.type_info
    if info.is_string:
        if not isinstance(raw, str):
            raise RangeError(f"{spec.label}: a string register takes text, not {raw!r}")
        _encode_text(spec, raw)
        return
    if isinstance(raw, str) or (isinstance(raw, float) and info.kind != FLOAT):
        raise RangeError(f"{spec.label}: raw value {raw!r} is not an integer")
    if spec.is_na(raw):
        raise RangeError(f"{spec.label}: raw {na_text(spec, raw)} is the device's 'not available' marker (na), never a value to write")
    if info.is_bool:
        if raw not in (0, 1):
            raise RangeError(f"{spec.label}: a {spec.space_info.name} is on or off (1 or 0), not {raw!r}")
        return
    if raw != raw:
        raise RangeError(f"{spec.label}: NaN is not a value")
    if not spec.raw_min <= raw <= spec.raw_max:
        if spec.scale_from is not None:  # its value depends on a factor read elsewhere: only the raw range is known here
            bounds = f"{_exact(spec.raw_min)}..{_exact(spec.raw_max)}"
            raise RangeError(f"{spec.label}: raw {_exact(raw)} is outside {bounds} (value = raw x 10^{spec.scale_from})")
        low, high = raw_to_value(spec, spec.raw_min), raw_to_value(spec, spec.raw_max)
        shown = _exact(raw_to_value(spec, raw))
        raise RangeError(f"{spec.label}: {shown}{_unit(spec)} is outside {_exact(low)}..{_exact(high)}{_unit(spec)}")
    if isinstance(raw, float) and spec.enum is not None and not spec.bitfields:
        # A setting coded as a float (a baud code 0-4 as an f32): only a member, exactly, is written.
        if not raw.is_integer() or int(raw) not in spec.enum._value2member_map_:
            raise RangeError(f"{spec.label}: {_exact(raw)} is not one of {enum_names(spec.enum, spec.reported)}")
        raw = int(raw)
    if not isinstance(raw, int):
        return
    if spec.enum is not None and not spec.bitfields and raw not in spec.enum._value2member_map_:
        raise RangeError(f"{spec.label}: {raw} is not one of {enum_names(spec.enum, spec.reported)}")
    _refuse_reported(spec.label, spec.enum, spec.reported, raw)
    destructive = spec.destructive_command(raw)
    if destructive is not None:
        raise destructive_refusal(spec, destructive)
    for field in spec.bitfields:
        value = (raw & field.mask) >> field.lsb
        reported = spec.reported_in(field.name)
        if field.enum is not None and value not in field.enum._value2member_map_:
            raise RangeError(f"{spec.label}.{field.name}: {value} is not one of {enum_names(field.enum, reported)}")
        _refuse_reported(f"{spec.label}.{field.name}", field.enum, reported, value)


def check_command(spec: RegisterSpec[Any], raw: int, confirmed: bool) -> None:
    """A command's value goes out as it is, except a destructive command's, which needs `confirmed`."""
    name = spec.destructive_command(raw)
    if name is not None and not confirmed:
        raise destructive_refusal(spec, name)


def na_text(spec: RegisterSpec[Any], raw: int | float) -> str:
    """A "not available" marker as datasheets print it: 0xFFFF (its bit pattern) for an integer, NaN for a float."""
    if isinstance(raw, float):
        return "NaN" if raw != raw else _exact(raw)
    return f"0x{raw & ((1 << spec.type_info.bits) - 1):0{spec.type_info.bits // 4}X}"


def _unit(spec: RegisterSpec[Any]) -> str:
    return f" {spec.unit}" if spec.unit else ""


def _fmt(value: int | float) -> str:
    return f"{value:g}" if isinstance(value, float) else str(value)


def _exact(value: int | float) -> str:
    """Every digit that tells the number apart (3600.0001 is not 3600), none more: 3600, not 3600.0."""
    text = repr(value)
    return text[:-2] if text.endswith(".0") else text


class Unlisted(int):
    """A raw value the register's enum does not list (no member of the map names it): the number is kept,
    typed apart from the members, so `read_x() -> Mode | Unlisted` says both outcomes."""


def decode_value(spec: RegisterSpec[Any], raw: Raw) -> Any:
    """The typed value a client returns: enum member, bitfield dict source, number, text or bool; None
    for the register's "not available" marker (`na`), which is never a value."""
    if (spec.na or spec.na_nan) and spec.is_na(raw):
        return None
    if isinstance(raw, str):
        return raw
    if spec.type_info.is_bool:
        return bool(raw)
    if spec.zone is not None and isinstance(raw, int):
        return seconds_to_datetime(raw, spec.zone)
    if spec.enum is not None and not spec.bitfields and isinstance(raw, float):
        if not raw.is_integer():
            return raw  # a float enum register's value that no member can be (2.5, NaN): the number, as read
        raw = int(raw)
    if spec.enum is not None and not spec.bitfields and isinstance(raw, int):
        try:
            return spec.enum(raw)
        except ValueError:
            return Unlisted(raw)  # a value the manual does not list: keep the number rather than fail the read
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
        names = f"; one of {enum_names(field.enum, spec.reported_in(field.name))}" if field.enum is not None else ""
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
