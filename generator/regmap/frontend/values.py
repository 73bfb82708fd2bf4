"""How the map's text values read: sources, scales, bit ranges, parameter-id rules, "not available" markers."""

from __future__ import annotations

import enum
import re
from collections.abc import Callable
from decimal import Decimal
from fractions import Fraction
from typing import Any, TypeVar

from regmap.kinds import Access, DataType, PollClass, WordOrder
from regmap.records import dataclass

_Member = TypeVar("_Member", bound=enum.Enum)


class _ByValue(dict[Any, _Member]):
    """An enum's members by value: a dict lookup, where calling the enum costs a metaclass call (five a register); an
    unknown value still gets the enum's own error."""

    def __init__(self, kind: type[_Member]) -> None:
        super().__init__((member.value, member) for member in kind)
        self.kind = kind

    def __missing__(self, value: Any) -> _Member:
        return self.kind(value)


DATA_TYPES = _ByValue(DataType)
ACCESSES = _ByValue(Access)
WORD_ORDERS = _ByValue(WordOrder)
BYTE_ORDERS = WORD_ORDERS  # ByteOrder is WordOrder
POLL_CLASSES = _ByValue(PollClass)


def _source(value: Any) -> tuple[str, ...]:
    if value is None:
        return ()
    return (value,) if isinstance(value, str) else tuple(value)


def _scale(value: Any) -> Fraction:
    # Decimal(str()) keeps 0.1 as 1/10 instead of the binary float's 3602879701896397/36028797018963968.
    key = (type(value), value)  # a map has few scales and offsets (most are the 1 and 0 every register takes)
    scale = _SCALES.get(key)
    if scale is None:
        scale = _SCALES[key] = Fraction(Decimal(str(value)))
    return scale


_SCALES: dict[tuple[type, Any], Fraction] = {}


def _bits(spec: int | str) -> tuple[int, int]:
    if isinstance(spec, int):
        return spec, spec
    low, high = (int(p) for p in spec.split("-"))
    return low, high


@dataclass(frozen=True)
class _ParamRule:
    regex: re.Pattern[str]
    format: str
    base: int
    group_stride: int
    index_stride: int
    group_radix: int
    index_radix: int

    def address_of(self, param: str) -> int | None:
        """The address this rule gives `param`, or None when the regex does not match.

        Raises ValueError when the regex matches but a group is not a number in its radix.
        """
        match = self.regex.fullmatch(param)
        if not match:
            return None
        index = _number(match.group("index"), self.index_radix, "index")
        group = _number(match.group("group"), self.group_radix, "group") if "group" in match.groupdict() and match.group("group") else 0
        return self.base + group * self.group_stride + index * self.index_stride

    def param_of(self, address: int) -> str | None:
        offset = address - self.base
        if offset < 0:
            return None
        group = offset // self.group_stride if self.group_stride else 0
        rest = offset - group * self.group_stride
        if rest % self.index_stride:
            return None
        text = self.format.format(group=group, index=rest // self.index_stride)
        try:
            return text if self.address_of(text) == address else None
        except ValueError:
            return None


_FORMAT_SPEC = re.compile(r"^(:0?[1-9]?[dxX]?)?$")


def _number(text: str | None, radix: int, what: str) -> int:
    try:
        return int(text or "", radix)
    except ValueError:
        raise ValueError(f"its {what} {text!r} is not a base-{radix} number") from None


def na_markers(marks: Any, dtype: DataType, problem: Callable[[int, str], None]) -> tuple[tuple[int | float, ...], bool]:
    """A register's `na` as raw values of its type, and whether any NaN is one: an integer (a signed
    register's may be written as its bit pattern, 0x8000 for an s16's -32768), a float's number, or
    `nan`. `problem(index, message)` reports a marker the type cannot have."""
    values: list[int | float] = []
    nan = False
    for i, mark in enumerate(marks):
        if mark == "nan":
            if not dtype.is_float:
                problem(i, f"`nan` marks a float as not available; a {dtype.value} has no NaN (give its raw value)")
            nan = True
            continue
        if isinstance(mark, bool) or (dtype.kind == "int" and not isinstance(mark, int)):
            problem(i, f"a 'not available' marker of a {dtype.value} register is an integer, not {mark!r}")
            continue
        if dtype.kind == "int" and dtype.signed and dtype.raw_max < mark < 1 << dtype.bits:
            mark -= 1 << dtype.bits  # the bit pattern the datasheet prints
        if not dtype.raw_min <= mark <= dtype.raw_max:
            problem(i, f"'not available' marker {mark} does not fit {dtype.value}")
        elif dtype.is_float and dtype.info.from_words(dtype.info.to_words(mark)) != mark:
            problem(i, f"'not available' marker {mark} is no {dtype.value} value (a NaN bit pattern is `nan`)")
        elif mark in values:
            problem(i, f"'not available' marker {mark} is given twice")
        else:
            values.append(mark)
    return tuple(values), nan


def serial_choices(serial: dict[str, Any], problem: Callable[[str, str], None]) -> tuple[tuple[int, ...], tuple[str, ...]]:
    """The baud rates and parities a device can be set to, each list holding the default (else `problem(key, message)`)."""
    rates, parities = tuple(serial.get("baud_rates", ())), tuple(serial.get("parities", ()))
    if rates and serial["baud"] not in rates:
        problem("baud", f"default baud {serial['baud']} is not among baud_rates {list(rates)}")
    if parities and serial["parity"] not in parities:
        problem("parity", f"default parity {serial['parity']!r} is not among parities {list(parities)}")
    return rates, parities
