"""Register descriptions as the runtime sees them: plain data that generated modules declare."""

from __future__ import annotations

import dataclasses
import enum
from dataclasses import dataclass
from functools import cached_property
from typing import Any, Generic, Self, TypeVar

from .align import Alignment
from .errors import AccessError, FirmwareError
from .spaces import DEFAULT_SPACE, SPACES, Space
from .types import TYPES, TypeInfo

HIGH_FIRST = "high_first"
LOW_FIRST = "low_first"

T = TypeVar("T")

Raw = int | float | str
"""A register's value as the wire carries it, before scale and offset: an integer, an IEEE float,
text (a string register) or 0/1 (a coil or discrete input)."""


POLL_CLASSES = ("static", "fast", "normal", "slow")
"""How often a poller reads a register: once (nameplate, limits), fast, normal (the default) or slow."""


def poll_class(poll: object) -> str:
    """The poll class named by `poll`: one of POLL_CLASSES, or an enum member whose value is one
    (regmap.model.PollClass); anything else is a ValueError that lists the classes."""
    name = getattr(poll, "value", poll)
    if not isinstance(name, str) or name not in POLL_CLASSES:
        raise ValueError(f"unknown poll class {poll!r}: one of {', '.join(POLL_CLASSES)}")
    return name


def parse_version(text: str) -> tuple[int, ...]:
    """A firmware version as numbers, so that 2.10 sorts after 2.9."""
    return tuple(int(part) for part in text.split("."))


def gate_admits(first: str | None, until: str | None, version: tuple[int, ...]) -> bool:
    """Whether a register gated from `first` (inclusive) until `until` (exclusive) exists in `version`."""
    if first is not None and version < parse_version(first):
        return False
    return not (until is not None and version >= parse_version(until))


def gate_text(first: str | None, until: str | None) -> str | None:
    """A firmware gate as people read it: `firmware >= 2.1`, `firmware < 3.0`, `2.1 <= firmware < 3.0`."""
    if first is not None and until is not None:
        return f"{first} <= firmware < {until}"
    if first is not None:
        return f"firmware >= {first}"
    if until is not None:
        return f"firmware < {until}"
    return None


def variant_has(variants: tuple[str, ...], variant: str | None) -> bool:
    """Whether a register present on `variants` (() for every variant) exists on `variant` (None: any)."""
    return not variants or variant is None or variant in variants


def na_marks(na: tuple[int | float, ...], na_nan: bool, raw: object) -> bool:
    """Whether `raw` is a "not available" marker: one of the raw values `na`, or (with `na_nan`) any NaN."""
    if isinstance(raw, float) and raw != raw:
        return na_nan
    return isinstance(raw, int | float) and not isinstance(raw, bool) and raw in na


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
    min: int | float | None = None
    max: int | float | None = None
    unit: str | None = None
    param: str | None = None
    enum: type[enum.IntEnum] | None = None
    bitfields: tuple[BitfieldSpec, ...] = ()
    bitfield_type: type[Any] | None = None  # a BitfieldValue subclass
    follows_device_order: bool = True  # False when the map fixes this register's word order itself
    space: str = DEFAULT_SPACE  # a name in regmap_runtime.spaces.SPACES
    byte_order: str = HIGH_FIRST  # bytes inside each word
    offset_num: int = 0  # value = raw x scale + offset_num / offset_den
    offset_den: int = 1
    string_words: int = 0  # a string register's length in words
    encoding: str = "ascii"
    padding: str = "nul"  # nul or space
    firmware_from: str | None = None  # first firmware version that has the register
    firmware_until: str | None = None  # first firmware version that no longer has it
    poll: str = "normal"  # static, fast, normal, slow
    # Enum members the device only reports (access r: read, never written), as runs (first, last) of raw values;
    # reported_fields: the same per bitfield, (field name, runs).
    reported: tuple[tuple[int, int], ...] = ()
    reported_fields: tuple[tuple[str, tuple[tuple[int, int], ...]], ...] = ()
    # The values destructive commands write, (first, last, command name): only that command, confirmed, sends them.
    destructive: tuple[tuple[int, int, str], ...] = ()
    trigger: bool = False  # a write makes the device act (a command, a trigger): sent once, never repeated
    na: tuple[int | float, ...] = ()  # raw values that mean "not available": read as None, never written
    na_nan: bool = False  # any NaN means "not available"
    variants: tuple[str, ...] = ()  # the device variants that have the register; () every variant
    zone: str | None = None  # a timestamp's clock: utc or local (regmap_runtime.timestamps)
    scale_from: str | None = None  # an s16 register's name: value = raw x 10^sf (regmap_runtime.scaling)

    @cached_property
    def type_info(self) -> TypeInfo:
        return TYPES[self.data_type]

    @cached_property
    def space_info(self) -> Space:
        return SPACES[self.space]

    @cached_property
    def words(self) -> int:
        """Addresses the register takes: register words, or one bit for a coil or discrete input."""
        return self.string_words if self.type_info.is_string else self.type_info.words

    @property
    def kind(self) -> str:
        return self.type_info.kind

    def exists_in(self, version: tuple[int, ...]) -> bool:
        """Whether firmware `version` has this register (its `firmware_from`/`firmware_until` gate)."""
        return gate_admits(self.firmware_from, self.firmware_until, version)

    @property
    def firmware_text(self) -> str | None:
        """The gate as people read it: `firmware >= 2.1`, `firmware < 3.0`, `2.1 <= firmware < 3.0`."""
        return gate_text(self.firmware_from, self.firmware_until)

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
    def type_min(self) -> int | float:
        return self.type_info.raw_min

    @property
    def type_max(self) -> int | float:
        return self.type_info.raw_max

    @property
    def raw_min(self) -> int | float:
        return self.type_min if self.min is None else self.min

    @property
    def raw_max(self) -> int | float:
        return self.type_max if self.max is None else self.max

    def on_variant(self, variant: str | None) -> bool:
        """Whether device variant `variant` has this register (None: not known, every register may be there)."""
        return variant_has(self.variants, variant)

    def present(self, version: tuple[int, ...] | None, variant: str | None) -> bool:
        """Whether a device of firmware `version` and `variant` (None: not known) has this register."""
        return (version is None or self.exists_in(version)) and self.on_variant(variant)

    def is_na(self, raw: object) -> bool:
        """Whether `raw` is the register's "not available" marker (`na`): no value, read as None."""
        return na_marks(self.na, self.na_nan, raw)

    def destructive_command(self, raw: object) -> str | None:
        """The destructive command whose value `raw` is, or None."""
        if not isinstance(raw, int):
            return None
        return next((name for first, last, name in self.destructive if first <= raw <= last), None)

    def reported_in(self, field: str) -> tuple[tuple[int, int], ...]:
        """The runs of values of bitfield `field` that the device only reports (never written)."""
        return next((runs for name, runs in self.reported_fields if name == field), ())

    @property
    def label(self) -> str:
        return f"{self.name} ({self.param})" if self.param else self.name

    def in_word_order(self, word_order: str | None) -> Self:
        """The spec in the word order the device uses now, when that is not the map's (a device whose word-order register was changed)."""
        if self.follows_device_order and word_order and self.wide and self.word_order != word_order:
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
    max_read_coils: int = 2000
    max_write_coils: int = 1968
    firmware_register: str | None = None  # name of the register that reports the firmware version
    firmware_format: str = "decimal"  # decimal, major_minor, string
    firmware_decimals: int = 0
    also_readable: frozenset[tuple[str, int]] = frozenset()  # (space, address) undocumented, but a device profile saw them answer
    variants: tuple[str, ...] = ()  # the device's variants (models, options) whose registers differ
    read_alignment: int = 1  # reads of aligned_spaces start on a multiple of this and cover a multiple of it
    aligned_spaces: tuple[str, ...] = ()
    alignment_exempt: tuple[tuple[str, int, int], ...] = ()  # (space, address, count): reads the manual allows anyway
    misaligned_exception: int | None = None  # what the device answers a misaligned read with
    word_order_register: str | None = None  # the register that sets the word order, and what to write to it:
    word_order_values: tuple[Raw | None, Raw | None, Raw | None] = (None, None, None)  # high_first, low_first, swap

    @cached_property
    def alignment(self) -> Alignment | None:
        """The read-alignment rule (None: the device answers reads at any address)."""
        if self.read_alignment == 1:
            return None
        return Alignment(self.read_alignment, self.aligned_spaces, self.alignment_exempt, self.misaligned_exception)

    @cached_property
    def documented(self) -> frozenset[tuple[str, int]] | None:
        """(space, address) of every word the device answers, or None when it tolerates reads of any address."""
        if self.tolerates_gaps:
            return None
        own = frozenset((r.space, a) for r in self.registers if r.readable for a in range(r.first_address, r.address + r.words))
        return own | self.also_readable

    def documented_in(self, version: tuple[int, ...] | None, variant: str | None = None) -> frozenset[tuple[str, int]] | None:
        """`documented` for a device running firmware `version` (None: not known) of `variant`: a register the
        version or the variant lacks is not there to read."""
        if self.tolerates_gaps:
            return None
        own = frozenset(
            (r.space, a)
            for r in self.registers
            if r.readable and r.present(version, variant)
            for a in range(r.first_address, r.address + r.words)
        )
        return own | self.also_readable

    def check_variant(self, variant: str | None) -> str | None:
        """`variant` when the map declares it (None: not known); a ValueError names the variants it declares."""
        if variant is not None and variant not in self.variants:
            raise ValueError(f"{self.id} has no variant {variant!r} (its map declares: {', '.join(self.variants) or 'none'})")
        return variant

    def read_limit(self, space: str) -> int:
        """Most addresses one read request of `space` may cover."""
        return self.max_read_coils if SPACES[space].bits else self.max_read_registers

    def write_limit(self, space: str) -> int:
        """Most addresses one multiple-write request of `space` may cover."""
        return self.max_write_coils if SPACES[space].bits else self.max_write_registers

    def firmware_version(self, raw: Raw) -> tuple[int, ...]:
        """The firmware version its register's raw value reports, as numbers (2.10 -> (2, 10))."""
        if self.firmware_format == "string":
            return version_in_text(str(raw))
        number = int(raw)
        if self.firmware_format == "major_minor":
            return (number >> 8, number & 0xFF)
        if self.firmware_decimals == 0:
            return (number,)
        scale = 10**self.firmware_decimals
        return (number // scale, number % scale)

    def firmware_text(self, raw: Raw) -> str:
        """The firmware version as the device's documents write it: 125 with 2 decimals is "1.25",
        105 is "1.05", 0x0203 as major_minor is "2.3"; a version string is kept as the device sent it."""
        if self.firmware_format == "string":
            return str(raw).strip()
        version = self.firmware_version(raw)
        if self.firmware_format == "decimal" and self.firmware_decimals:
            return f"{version[0]}.{version[1]:0{self.firmware_decimals}d}"
        return ".".join(str(part) for part in version)


def refuse_absent(spec: RegisterSpec[Any], version: tuple[int, ...] | None, version_text: str | None, variant: str | None) -> None:
    """A register the connected variant lacks (AccessError) or its firmware `version` lacks (FirmwareError): nothing is sent."""
    if not spec.on_variant(variant):
        raise AccessError(
            f"{spec.label} exists only on the variant(s) {', '.join(spec.variants)}; this client is for {variant}: nothing was sent"
        )
    if version is not None and not spec.exists_in(version):
        gate = spec.firmware_text
        raise FirmwareError(
            f"{spec.label} exists only with {gate}; the device reports firmware {version_text}: nothing was sent",
            spec.name,
            gate,
            version_text,
        )


def version_in_text(text: str) -> tuple[int, ...]:
    """The first dotted number in a version string: "V2.10 build 7" -> (2, 10)."""
    digits = ""
    for char in text:
        if char.isdigit() or (char == "." and digits and digits[-1] != "."):
            digits += char
        elif digits:
            break
    digits = digits.rstrip(".")
    if not digits:
        raise ValueError(f"no version number in {text!r}")
    return parse_version(digits)
