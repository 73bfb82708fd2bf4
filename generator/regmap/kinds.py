"""The model's kinds of value: word and byte order, poll class, access, data type (re-exported by `regmap.model`)."""

from __future__ import annotations

import enum

from regmap_runtime.types import TYPES, TypeInfo


class WordOrder(enum.Enum):
    """Which comes first on the wire: the high or the low word of a wide value (or byte of a word)."""

    HIGH_FIRST = "high_first"
    LOW_FIRST = "low_first"


ByteOrder = WordOrder
"""Bytes inside each word: the same two choices, kept apart in the model by field name."""


class PollClass(enum.Enum):
    """How often a poller reads a register: once (nameplate, limits), fast, normal (the default) or slow."""

    STATIC = "static"
    FAST = "fast"
    NORMAL = "normal"
    SLOW = "slow"


class Access(enum.Enum):
    READ = "r"
    READ_WRITE = "rw"
    WRITE = "w"

    @property
    def readable(self) -> bool:
        return self is not Access.WRITE

    @property
    def writable(self) -> bool:
        return self is not Access.READ


class DataType(enum.Enum):
    """A map's `type`; every fact about it comes from the runtime's one table, `regmap_runtime.types.TYPES`."""

    U16 = "u16"
    S16 = "s16"
    U32 = "u32"
    S32 = "s32"
    U64 = "u64"
    S64 = "s64"
    F16 = "f16"
    F32 = "f32"
    F64 = "f64"
    STRING = "string"
    BOOL = "bool"
    TIMESTAMP = "timestamp"  # seconds since 1970 in a u32, read as a time (Register.zone: utc or local)

    @property
    def info(self) -> TypeInfo:
        return TYPES[self._value_]  # `_value_`, not `value`: Enum's `value` descriptor is slow, and this is read often

    @property
    def words(self) -> int:
        return self.info.words

    @property
    def wide(self) -> bool:
        """More than one word, so the value has a word order."""
        return self.info.wide

    @property
    def bits(self) -> int:
        return self.info.bits

    @property
    def signed(self) -> bool:
        return self.info.signed

    @property
    def raw_min(self) -> int | float:
        return self.info.raw_min

    @property
    def raw_max(self) -> int | float:
        return self.info.raw_max

    @property
    def kind(self) -> str:
        return self.info.kind

    @property
    def numeric(self) -> bool:
        return self.info.numeric

    @property
    def is_float(self) -> bool:
        return self.info.is_float

    @property
    def is_string(self) -> bool:
        return self.info.is_string

    @property
    def is_bool(self) -> bool:
        return self.info.is_bool

    @property
    def is_timestamp(self) -> bool:
        return self.info.is_timestamp
