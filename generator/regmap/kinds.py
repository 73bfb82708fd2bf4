"""The model's kinds of value: word and byte order, poll class, access, data type (re-exported by `regmap.model`)."""

from __future__ import annotations

import enum

from regmap_runtime.types import TYPES, TypeInfo


class _Kind(enum.Enum):
    """A kind whose members hash in C: Python 3.11's `Enum.__hash__` is Python code, and the back ends look tables up
    by these members for every register. A member equals only itself, so its identity is a sound hash."""

    __hash__ = object.__hash__


class WordOrder(_Kind):
    """Which comes first on the wire: the high or the low word of a wide value (or byte of a word)."""

    HIGH_FIRST = "high_first"
    LOW_FIRST = "low_first"


ByteOrder = WordOrder
"""Bytes inside each word: the same two choices, kept apart in the model by field name."""


class PollClass(_Kind):
    """How often a poller reads a register: once (nameplate, limits), fast, normal (the default) or slow."""

    STATIC = "static"
    FAST = "fast"
    NORMAL = "normal"
    SLOW = "slow"


class _AccessFacts:  # declared outside the enum's body, so mypy takes neither for a member
    readable: bool
    writable: bool


class Access(_AccessFacts, _Kind):
    READ = "r"
    READ_WRITE = "rw"
    WRITE = "w"


for _access in Access:  # worked out once per member: asked of every register, many times
    _access.readable = _access is not Access.WRITE
    _access.writable = _access is not Access.READ
del _access


class _TypeFacts:  # each read from the runtime's table once, when the module loads: back ends ask them of every register
    words: int
    wide: bool  # more than one word, so the value has a word order
    bits: int
    signed: bool
    raw_min: int | float
    raw_max: int | float
    kind: str
    numeric: bool
    is_float: bool
    is_string: bool
    is_bool: bool
    is_timestamp: bool


class DataType(_TypeFacts, _Kind):
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
        return TYPES[self._value_]


for _type in DataType:
    _info = _type.info
    _type.words, _type.wide, _type.bits, _type.signed = _info.words, _info.wide, _info.bits, _info.signed
    _type.raw_min, _type.raw_max, _type.kind, _type.numeric = _info.raw_min, _info.raw_max, _info.kind, _info.numeric
    _type.is_float, _type.is_string, _type.is_bool, _type.is_timestamp = _info.is_float, _info.is_string, _info.is_bool, _info.is_timestamp
del _type, _info
