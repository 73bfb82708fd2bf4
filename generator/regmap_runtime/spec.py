"""Register descriptions as the runtime sees them: plain data that generated modules declare."""

from __future__ import annotations

import dataclasses
import enum
from dataclasses import dataclass
from functools import cached_property
from typing import Any, Generic, Self, TypeVar

from .spaces import DEFAULT_SPACE
from .types import TYPES, TypeInfo

HIGH_FIRST = "high_first"
LOW_FIRST = "low_first"

T = TypeVar("T")


@dataclass(frozen=True)
class BitfieldSpec:
    name: str
    lsb: int
    width: int
    enum: type[enum.IntEnum] | None = None

    @property
    def mask(self) -> int:
        return ((1 << self.width) - 1) << self.lsb


@dataclass(frozen=True)
class RegisterSpec(Generic[T]):
    """One register. `T` is the Python type a read returns (float, int, an IntEnum, a bitfield class)."""

    name: str
    address: int
    data_type: str  # a name in regmap_runtime.types.TYPES
    access: str  # r rw w
    word_order: str = HIGH_FIRST
    paired: bool = False
    scale_num: int = 1
    scale_den: int = 1
    min: int | None = None
    max: int | None = None
    unit: str | None = None
    param: str | None = None
    enum: type[enum.IntEnum] | None = None
    bitfields: tuple[BitfieldSpec, ...] = ()
    bitfield_type: type[Any] | None = None  # a BitfieldValue subclass
    follows_device_order: bool = True  # False when the map fixes this register's word order itself
    space: str = DEFAULT_SPACE  # a name in regmap_runtime.spaces.SPACES

    @cached_property
    def type_info(self) -> TypeInfo:
        return TYPES[self.data_type]

    @cached_property
    def words(self) -> int:
        return self.type_info.words

    @property
    def wide(self) -> bool:
        """More than one word, so the value has a word order."""
        return self.type_info.wide

    @property
    def signed(self) -> bool:
        return self.type_info.signed

    @property
    def bits(self) -> int:
        return self.type_info.bits

    @cached_property
    def first_address(self) -> int:
        return self.address - 1 if self.paired else self.address

    @property
    def span(self) -> int:
        return self.words + (1 if self.paired else 0)

    @property
    def readable(self) -> bool:
        return self.access != "w"

    @property
    def writable(self) -> bool:
        return self.access != "r"

    @property
    def type_min(self) -> int:
        return self.type_info.raw_min

    @property
    def type_max(self) -> int:
        return self.type_info.raw_max

    @property
    def raw_min(self) -> int:
        return self.type_min if self.min is None else self.min

    @property
    def raw_max(self) -> int:
        return self.type_max if self.max is None else self.max

    @property
    def label(self) -> str:
        return f"{self.name} ({self.param})" if self.param else self.name

    def in_word_order(self, word_order: str | None) -> Self:
        """The spec in the word order the device uses now, when that is not the map's (a device whose word-order register was changed)."""
        if word_order and self.wide and self.follows_device_order and self.word_order != word_order:
            return dataclasses.replace(self, word_order=word_order)
        return self


class Readable(RegisterSpec[T]):
    """A register a client may read."""


class Writable(RegisterSpec[T]):
    """A register a client may write."""


class ReadOnly(Readable[T]):
    pass


class WriteOnly(Writable[T]):
    pass


class ReadWrite(Readable[T], Writable[T]):
    pass


@dataclass(frozen=True)
class DeviceSpec:
    """What a client needs to know about the device as a whole."""

    id: str
    map_version: str
    fingerprint: str
    registers: tuple[RegisterSpec[Any], ...]
    baud: int
    parity: str
    data_bits: int
    stop_bits: int
    max_read_registers: int
    max_write_registers: int
    word_order: str
    broadcast_id: int | None
    function_codes: tuple[int, ...]
    tolerates_gaps: bool
    exceptions: tuple[tuple[int, str, str], ...] = ()  # (code, name, meaning)
    also_readable: frozenset[tuple[str, int]] = frozenset()  # (space, address) undocumented, but a device profile saw them answer

    @cached_property
    def documented(self) -> frozenset[tuple[str, int]] | None:
        """(space, address) of every word the device answers, or None when it tolerates reads of any address."""
        if self.tolerates_gaps:
            return None
        own = frozenset((r.space, a) for r in self.registers if r.readable for a in range(r.first_address, r.address + r.words))
        return own | self.also_readable
