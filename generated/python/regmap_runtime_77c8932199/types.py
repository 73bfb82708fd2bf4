"""The one table of data types: how many register words each takes, its signedness, kind and codec.

The model (`regmap.model.DataType`), the runtime (`RegisterSpec`, the codec) and every back end read
their facts from here; a back end keeps only its own spelling of a type (`int16_t`, "signed 16-bit").
"""

from __future__ import annotations

import struct
from dataclasses import dataclass, field

WORD_BITS = 16


@dataclass(frozen=True)
class TypeInfo:
    """One data type. `codec` is the `struct` format of the whole value, big-endian (high word first)."""

    name: str
    words: int
    signed: bool
    kind: str  # "int" for now; room for "float", "string", "bool"
    codec: str
    _value: struct.Struct = field(init=False, repr=False, compare=False)
    _words: struct.Struct = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "_value", struct.Struct(">" + self.codec))
        object.__setattr__(self, "_words", struct.Struct(f">{self.words}H"))

    @property
    def bits(self) -> int:
        return WORD_BITS * self.words

    @property
    def wide(self) -> bool:
        """More than one register word, so the value has a word order."""
        return self.words > 1

    @property
    def raw_min(self) -> int:
        return -(1 << (self.bits - 1)) if self.signed else 0

    @property
    def raw_max(self) -> int:
        return (1 << (self.bits - 1)) - 1 if self.signed else (1 << self.bits) - 1

    def to_words(self, raw: int) -> tuple[int, ...]:
        """The value's words, high word first (the caller checks the range)."""
        words: tuple[int, ...] = self._words.unpack(self._value.pack(raw))
        return words

    def from_words(self, words: list[int] | tuple[int, ...]) -> int:
        """The value of its words, high word first."""
        raw: int = self._value.unpack(self._words.pack(*words))[0]
        return raw


TYPES: dict[str, TypeInfo] = {
    t.name: t
    for t in (
        TypeInfo("u16", words=1, signed=False, kind="int", codec="H"),
        TypeInfo("s16", words=1, signed=True, kind="int", codec="h"),
        TypeInfo("u32", words=2, signed=False, kind="int", codec="I"),
        TypeInfo("s32", words=2, signed=True, kind="int", codec="i"),
    )
}
