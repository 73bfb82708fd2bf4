"""The one table of data types: how many register words each takes, its signedness, kind and codec.

The model (`regmap.model.DataType`), the runtime (`RegisterSpec`, the codec) and every back end read
their facts from here; a back end keeps only its own spelling of a type (`int16_t`, "signed 16-bit").

Kinds: "int" (u16..s64, and timestamp: an unsigned 32-bit count of seconds, read as a time), "float" (IEEE 754 f16/f32/f64; struct's "e" is half precision), "string" (N words of text, N given by the
register) and "bool" (one coil or discrete input: a bit, not a word).
"""

from __future__ import annotations

import struct
from dataclasses import dataclass, field

WORD_BITS = 16

INT, FLOAT, STRING, BOOL = "int", "float", "string", "bool"

# Largest finite values, so a float register's range check has bounds like an integer's.
_FLOAT_MAX: dict[int, float] = {
    2: struct.unpack(">e", b"\x7b\xff")[0],  # 65504
    4: struct.unpack(">f", b"\x7f\x7f\xff\xff")[0],
    8: struct.unpack(">d", b"\x7f\xef\xff\xff\xff\xff\xff\xff")[0],
}


@dataclass(frozen=True)
class TypeInfo:
    """One data type. `codec` is the `struct` format of the whole value, big-endian (high word first);
    a string has no fixed codec and `words == 0` (the register says how many)."""

    name: str
    words: int
    signed: bool
    kind: str
    codec: str
    _value: struct.Struct | None = field(init=False, repr=False, compare=False)
    _words: struct.Struct | None = field(init=False, repr=False, compare=False)
    # Worked out once: every decoded read asks them.
    wide: bool = field(init=False, repr=False, compare=False)  # more than one register word, so the value has a word order
    is_float: bool = field(init=False, repr=False, compare=False)
    is_string: bool = field(init=False, repr=False, compare=False)
    is_bool: bool = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        fixed = self.kind in (INT, FLOAT)
        object.__setattr__(self, "_value", struct.Struct(">" + self.codec) if fixed else None)
        object.__setattr__(self, "_words", struct.Struct(f">{self.words}H") if fixed else None)
        object.__setattr__(self, "wide", self.words > 1 and self.kind != STRING)
        object.__setattr__(self, "is_float", self.kind == FLOAT)
        object.__setattr__(self, "is_string", self.kind == STRING)
        object.__setattr__(self, "is_bool", self.kind == BOOL)

    @property
    def bits(self) -> int:
        return 1 if self.kind == BOOL else WORD_BITS * self.words

    @property
    def numeric(self) -> bool:
        """A number that may have a scale, an offset, a range and a unit."""
        return self.kind in (INT, FLOAT)

    @property
    def is_timestamp(self) -> bool:
        """Seconds since 1970 (a u32 on the wire), read and written as a time (`regmap_runtime.timestamps`)."""
        return self.name == "timestamp"

    @property
    def has_byte_order(self) -> bool:
        """Made of register words, whose two bytes a device may swap (not a coil's bit)."""
        return self.kind != BOOL

    @property
    def raw_min(self) -> int | float:
        if self.kind == FLOAT:
            return -_FLOAT_MAX[self.words * 2]
        if self.kind == BOOL:
            return 0
        return -(1 << (self.bits - 1)) if self.signed else 0

    @property
    def raw_max(self) -> int | float:
        if self.kind == FLOAT:
            return _FLOAT_MAX[self.words * 2]
        if self.kind == BOOL:
            return 1
        return (1 << (self.bits - 1)) - 1 if self.signed else (1 << self.bits) - 1

    def to_words(self, raw: int | float) -> tuple[int, ...]:
        """The value's words, high word first, high byte first (the caller checks the range)."""
        if self._value is None or self._words is None:
            return (int(raw),)  # bool: one bit
        words: tuple[int, ...] = self._words.unpack(self._value.pack(raw))
        return words

    def from_words(self, words: list[int] | tuple[int, ...]) -> int | float:
        """The value of its words, high word first, high byte first."""
        if self._value is None or self._words is None:
            return 1 if words[0] else 0
        raw: int | float = self._value.unpack(self._words.pack(*words))[0]
        return raw


TYPES: dict[str, TypeInfo] = {
    t.name: t
    for t in (
        TypeInfo("u16", words=1, signed=False, kind=INT, codec="H"),
        TypeInfo("s16", words=1, signed=True, kind=INT, codec="h"),
        TypeInfo("u32", words=2, signed=False, kind=INT, codec="I"),
        TypeInfo("s32", words=2, signed=True, kind=INT, codec="i"),
        TypeInfo("u64", words=4, signed=False, kind=INT, codec="Q"),
        TypeInfo("s64", words=4, signed=True, kind=INT, codec="q"),
        TypeInfo("f32", words=2, signed=True, kind=FLOAT, codec="f"),
        TypeInfo("f64", words=4, signed=True, kind=FLOAT, codec="d"),
        TypeInfo("string", words=0, signed=False, kind=STRING, codec=""),
        TypeInfo("bool", words=1, signed=False, kind=BOOL, codec=""),
        # Added types go last, so the C header's type numbers of the older ones stay.
        TypeInfo("timestamp", words=2, signed=False, kind=INT, codec="I"),
        TypeInfo("f16", words=1, signed=True, kind=FLOAT, codec="e"),
    )
}


def swap_bytes(words: list[int] | tuple[int, ...]) -> list[int]:
    """Each word with its two bytes exchanged (a device whose byte_order is low_first)."""
    return [((w & 0xFF) << 8) | (w >> 8) for w in words]
