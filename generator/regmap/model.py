"""The intermediate model: one frozen `Device` per map, arrays expanded and references resolved.

Every back end (Python, C, Markdown) and every runtime tool reads only this model. Values that
back ends would otherwise compute (masks, widths, raw ranges, scale fractions) are computed here.
"""

from __future__ import annotations

from dataclasses import field, replace
from fractions import Fraction

from regmap.kinds import Access as Access
from regmap.kinds import ByteOrder as ByteOrder
from regmap.kinds import DataType as DataType
from regmap.kinds import PollClass as PollClass
from regmap.kinds import WordOrder as WordOrder
from regmap.records import cached_property, dataclass
from regmap.transport import BadCrc as BadCrc
from regmap.transport import DeviceIdentification as DeviceIdentification
from regmap.transport import ModbusException as ModbusException
from regmap.transport import ReadAlignment as ReadAlignment
from regmap.transport import ServerId as ServerId
from regmap.transport import TimingRow as TimingRow
from regmap.transport import Transport as Transport
from regmap.transport import WordOrderRegister as WordOrderRegister
from regmap_runtime.spaces import DEFAULT_SPACE, SPACES, Space
from regmap_runtime.spec import gate_admits, gate_text, na_marks, variant_has

SourcePos = tuple[int, int]
"""(line, column) of an item in its map file, so a problem found late still prints file:line:col."""


@dataclass(frozen=True)
class FirmwareGate:
    """Firmware versions that have a register: from `first` (inclusive) until `until` (exclusive)."""

    first: str | None = None
    until: str | None = None

    def admits(self, version: tuple[int, ...]) -> bool:
        return gate_admits(self.first, self.until, version)

    @property
    def text(self) -> str:
        """How docs and diff show it: `firmware >= 2.1`, `firmware < 3.0`, `2.1 <= firmware < 3.0`."""
        return gate_text(self.first, self.until) or "any firmware"


@dataclass(frozen=True)
class EnumMember:
    value: int
    name: str
    title: str
    title_zh: str | None = None
    symbol: str | None = None
    description: str = ""
    source: tuple[str, ...] = ()
    access: Access = Access.READ_WRITE  # READ: a state the device only reports, never written

    @property
    def writable(self) -> bool:
        return self.access.writable

    @property
    def readable(self) -> bool:
        return self.access.readable


@dataclass(frozen=True)
class EnumType:
    name: str
    title: str
    members: tuple[EnumMember, ...]
    title_zh: str | None = None
    description: str = ""
    source: tuple[str, ...] = ()
    pos: SourcePos | None = field(default=None, compare=False, repr=False)

    def member(self, name: str) -> EnumMember | None:
        return next((m for m in self.members if m.name == name), None)

    def by_value(self, value: int | float) -> EnumMember | None:
        return next((m for m in self.members if m.value == value), None)


@dataclass(frozen=True)
class Bitfield:
    name: str
    lsb: int
    msb: int
    title: str
    title_zh: str | None = None
    description: str = ""
    enum: EnumType | None = None
    pos: SourcePos | None = field(default=None, compare=False, repr=False)

    @property
    def width(self) -> int:
        return self.msb - self.lsb + 1

    @property
    def mask(self) -> int:
        """Mask of the field in place (already shifted)."""
        return ((1 << self.width) - 1) << self.lsb

    @property
    def max_value(self) -> int:
        return (1 << self.width) - 1

    @property
    def bits_text(self) -> str:
        return str(self.lsb) if self.lsb == self.msb else f"{self.lsb}-{self.msb}"


@dataclass(frozen=True)
class ArrayMember:
    name: str
    offset: int
    words: int
    title: str


@dataclass(frozen=True)
class ArrayDef:
    """A repeated block, kept beside its expanded registers so back ends can print formulas."""

    name: str
    title: str
    count: int
    index_base: int
    base: int
    stride: int
    members: tuple[ArrayMember, ...]
    title_zh: str | None = None
    description: str = ""
    element_title: str = ""
    group: str = ""
    source: tuple[str, ...] = ()
    notes: str = ""

    @property
    def first_index(self) -> int:
        return self.index_base

    @property
    def last_index(self) -> int:
        return self.index_base + self.count - 1

    def element_address(self, index: int, member: ArrayMember) -> int:
        return self.base + (index - self.index_base) * self.stride + member.offset


@dataclass(frozen=True)
class ArrayRef:
    array: str
    index: int
    member: str


@dataclass(frozen=True)
class Register:
    name: str
    address: int
    type: DataType
    access: Access
    title: str
    group: str
    param: str | None = None
    word_order: WordOrder = WordOrder.HIGH_FIRST
    word_order_fixed: bool = False  # the map fixes it; otherwise it follows the device's (configurable) order
    unit: str | None = None
    scale: Fraction = Fraction(1)
    min: int | float | None = None
    max: int | float | None = None
    default: int | float | str | None = None
    enum: EnumType | None = None
    bitfields: tuple[Bitfield, ...] = ()
    takes_effect: str | None = None
    settable: str | None = None
    modes: tuple[str, ...] = ()
    paired: bool = False
    title_zh: str | None = None
    description: str = ""
    range_text: str | None = None
    source: tuple[str, ...] = ()
    notes: str = ""
    array: ArrayRef | None = None
    errata: tuple[str, ...] = ()
    space: str = DEFAULT_SPACE  # a name in regmap_runtime.spaces.SPACES
    byte_order: ByteOrder = ByteOrder.HIGH_FIRST
    offset: Fraction = Fraction(0)  # value = raw x scale + offset
    string_words: int = 0  # a string register's length in words
    encoding: str = "ascii"  # a string register's text encoding (a Python codec name)
    padding: str = "nul"  # what fills a string register after its text: nul or space
    firmware: FirmwareGate | None = None
    poll: PollClass = PollClass.NORMAL
    trigger: bool = False  # a write makes the device act: sent once, never retried (see Device.is_trigger)
    na: tuple[int | float, ...] = ()  # raw values that mean "not available": read as no value, never written
    na_nan: bool = False  # any NaN of a float register means "not available"
    variants: tuple[str, ...] = ()  # the device variants (models, options) that have it; () every variant
    zone: str | None = None  # a timestamp's clock: utc or local (regmap_runtime.timestamps); None for other types
    scale_from: str | None = None  # an s16 register's name: value = raw x 10^sf, sf its raw value read at run time
    pos: SourcePos | None = field(default=None, compare=False, repr=False)

    @cached_property  # asked of every register many times by every back end
    def words(self) -> int:
        """Addresses the register takes: register words, or one bit for a coil or discrete input."""
        return self.string_words if self.type.is_string else self.type.words

    @cached_property
    def space_info(self) -> Space:
        return SPACES[self.space]

    @cached_property
    def offset_set(self) -> bool:
        return self.offset != 0

    @cached_property
    def wide(self) -> bool:
        """More than one word, so the value has a word order."""
        return self.type.wide

    @cached_property
    def signed(self) -> bool:
        return self.type.signed

    @cached_property
    def first_address(self) -> int:
        """First address the register occupies on the bus (the unused high word of a pair)."""
        return self.address - 1 if self.paired else self.address

    @cached_property
    def span(self) -> int:
        """Words from `first_address` that belong to this register."""
        return self.words + (1 if self.paired else 0)

    @cached_property
    def last_address(self) -> int:
        return self.address + self.words - 1

    @cached_property
    def raw_min(self) -> int | float:
        return self.min if self.min is not None else self.type.raw_min

    @cached_property
    def raw_max(self) -> int | float:
        return self.max if self.max is not None else self.type.raw_max

    @cached_property
    def scaled(self) -> bool:
        return self.scale != 1

    @cached_property
    def has_na(self) -> bool:
        """The device sends a "not available" marker in this register (`na`)."""
        return bool(self.na) or self.na_nan

    def is_na(self, raw: object) -> bool:
        """Whether `raw` is this register's "not available" marker."""
        return na_marks(self.na, self.na_nan, raw)

    @property
    def na_bits(self) -> tuple[int, ...]:
        """The bits of each `na` marker, as the words carry them high word first (an s16's -32768 is 0x8000,
        a float's its IEEE 754 bits): what back ends compare a register's assembled word(s) with."""
        patterns = []
        for mark in self.na:
            pattern = 0
            for word in self.type.info.to_words(mark):
                pattern = pattern << 16 | word
            patterns.append(pattern)
        return tuple(patterns)

    def on_variant(self, variant: str | None) -> bool:
        """Whether `variant` has the register (None: the variant is not known, so every register may be there)."""
        return variant_has(self.variants, variant)

    @property
    def label(self) -> str:
        """How a person names it: the manual's id when there is one."""
        return f"{self.param} {self.name}" if self.param else self.name


@dataclass(frozen=True)
class Group:
    id: str
    title: str
    registers: tuple[Register, ...]
    arrays: tuple[ArrayDef, ...] = ()
    title_zh: str | None = None
    description: str = ""
    source: tuple[str, ...] = ()


@dataclass(frozen=True)
class CommandArgument:
    name: str
    min: int
    max: int
    title: str = ""


@dataclass(frozen=True)
class CommandEffect:
    """What the device does on the command (read by the simulator)."""

    kind: str  # save, restore_defaults, clear
    register: Register | None = None
    value: int = 0
    after_read: int | None = None


@dataclass(frozen=True)
class Command:
    name: str
    title: str
    register: Register
    value: int
    argument: CommandArgument | None = None
    effect: CommandEffect | None = None
    title_zh: str | None = None
    description: str = ""
    source: tuple[str, ...] = ()
    destructive: bool = False  # loses data or state: one deliberate step away in every artefact
    pos: SourcePos | None = field(default=None, compare=False, repr=False)

    @property
    def raw_values(self) -> tuple[int, int]:
        """The first and last raw value the command can write (value + its argument's range)."""
        if self.argument is None:
            return self.value, self.value
        return self.value + self.argument.min, self.value + self.argument.max

    def raw_value(self, argument: int | None = None) -> int:
        if self.argument is None:
            return self.value
        if argument is None or not self.argument.min <= argument <= self.argument.max:
            raise ValueError(f"command {self.name} needs {self.argument.name} in {self.argument.min}..{self.argument.max}, got {argument}")
        return self.value + argument


@dataclass(frozen=True)
class Fault:
    code: str
    name: str
    title: str
    kind: str
    value: int | None = None
    title_zh: str | None = None
    resettable: bool | None = None
    description: str = ""
    source: tuple[str, ...] = ()


@dataclass(frozen=True)
class ExampleValue:
    """What an example frame carries for one register: its raw value, or (for a frame that
    carries only some of a 32-bit register's words) the words themselves."""

    register: Register
    raw: int | float | str | None = None
    words: tuple[int, ...] | None = None
    value: float | str | bool | None = None
    not_available: bool = False  # the frame carries the register's "not available" marker (value null in the map)


@dataclass(frozen=True)
class Example:
    id: str
    source: tuple[str, ...]
    direction: str
    frame: bytes
    meaning: str
    request: str | None = None
    meaning_zh: str | None = None
    values: tuple[ExampleValue, ...] = ()
    erratum: str | None = None
    corrected_frame: bytes | None = None
    notes: str = ""

    @property
    def wire_frame(self) -> bytes:
        """The frame a correct device or master puts on the wire."""
        return self.corrected_frame if self.corrected_frame is not None else self.frame


@dataclass(frozen=True)
class Reading:
    source: tuple[str, ...]
    says: str


@dataclass(frozen=True)
class Erratum:
    id: str
    title: str
    readings: tuple[Reading, ...]
    choice: str
    reason: str
    registers: tuple[str, ...] = ()


@dataclass(frozen=True)
class Variant:
    """A model or option of the device whose registers differ (a four-string inverter): registers name theirs."""

    name: str
    title: str
    description: str = ""


@dataclass(frozen=True)
class DeviceInfo:
    id: str
    vendor: str
    model: str
    manual_title: str
    manual_file: str
    map_version: str
    vendor_zh: str | None = None
    description: str = ""
    manual_version: str | None = None
    manual_language: str | None = None
    firmware: str | None = None
    firmware_register: FirmwareRegister | None = None
    variants: tuple[Variant, ...] = ()
    id_pos: SourcePos | None = field(default=None, compare=False, repr=False)  # where the map gives the id (targets' reserved words)


@dataclass(frozen=True)
class FirmwareRegister:
    """The register that reports the firmware version, and how a version is read from it."""

    register: Register
    format: str  # decimal, major_minor, string
    decimals: int = 0
    source: tuple[str, ...] = ()


@dataclass(frozen=True)
class Device:
    info: DeviceInfo
    transport: Transport
    groups: tuple[Group, ...]
    enums: tuple[EnumType, ...]
    commands: tuple[Command, ...]
    faults: tuple[Fault, ...]
    examples: tuple[Example, ...]
    errata: tuple[Erratum, ...]
    source_path: str
    fingerprint: str
    registers: tuple[Register, ...] = field(default=())
    not_generated: tuple[str, ...] = ()  # registers a back end leaves out, each with why: listed in its files' headers

    @property
    def id(self) -> str:
        return self.info.id

    @property
    def arrays(self) -> tuple[ArrayDef, ...]:
        return tuple(a for g in self.groups for a in g.arrays)

    @cached_property
    def _by_name(self) -> dict[str, Register]:
        return {reg.name: reg for reg in self.registers}

    def register(self, name: str) -> Register:
        return self._by_name[name]

    def without_scale_from(self) -> Device:
        """The device as a back end that cannot scale by another register sees it: each `scale_from` register left
        out (never shown raw as if it were the value), and the commands and examples that touch one, each listed."""
        gone = {reg.name for reg in self.registers if reg.scale_from is not None}
        if not gone:
            return self

        def keep(reg: Register) -> bool:
            return reg.name not in gone

        # an array member scaled by a register goes with its elements (one factor scales them all)
        members_gone = {(r.array.array, r.array.member) for r in self.registers if r.array is not None and r.name in gone}

        def trim(a: ArrayDef) -> ArrayDef:
            return replace(a, members=tuple(m for m in a.members if (a.name, m.name) not in members_gone))

        def arrays(g: Group) -> tuple[ArrayDef, ...]:
            return tuple(t for t in map(trim, g.arrays) if t.members)

        examples = tuple(x for x in self.examples if all(keep(v.register) for v in x.values))
        commands = tuple(c for c in self.commands if keep(c.register))
        return replace(
            self,
            groups=tuple(replace(g, registers=tuple(filter(keep, g.registers)), arrays=arrays(g)) for g in self.groups),
            registers=tuple(filter(keep, self.registers)),
            examples=examples,
            commands=commands,
            not_generated=self.not_generated
            + tuple(f"{name} (scale_from)" for name in sorted(gone))
            + tuple(f"command {c.name} (writes a scale_from register)" for c in self.commands if c not in commands)
            + tuple(f"example {x.id} (carries a scale_from register)" for x in self.examples if x not in examples),
        )

    def example(self, example_id: str) -> Example:
        for ex in self.examples:
            if ex.id == example_id:
                return ex
        raise KeyError(example_id)

    @cached_property
    def _trigger_names(self) -> frozenset[str]:
        return frozenset(reg.name for reg in self.registers if reg.trigger) | {c.register.name for c in self.commands}

    @cached_property
    def _destructive_by_register(self) -> dict[str, tuple[Command, ...]]:
        by_register: dict[str, tuple[Command, ...]] = {}
        for c in self.commands:
            if c.destructive:
                by_register[c.register.name] = (*by_register.get(c.register.name, ()), c)
        return by_register

    def destructive_commands(self, reg: Register) -> tuple[Command, ...]:
        """The destructive commands that write `reg`: a plain write of their values is refused everywhere (each
        back end asks for every register: the commands are sorted by register once)."""
        return self._destructive_by_register.get(reg.name, ())

    def is_trigger(self, reg: Register) -> bool:
        """A write to `reg` makes the device act (the map says so, or a command writes it): never retried."""
        return reg.name in self._trigger_names

    def enum(self, name: str) -> EnumType:
        for en in self.enums:
            if en.name == name:
                return en
        raise KeyError(name)

    @cached_property
    def _owners(self) -> dict[tuple[str, int], Register]:
        owners: dict[tuple[str, int], Register] = {}
        for reg in self.registers:
            for address in range(reg.first_address, reg.last_address + 1):
                owners.setdefault((reg.space, address), reg)
        return owners

    def at_address(self, address: int, space: str = DEFAULT_SPACE) -> Register | None:
        """The register whose listed address (or any word of it) is `address` in `space`."""
        reg = self._owners.get((space, address))
        return reg if reg is not None and reg.address <= address else None

    def covering(self, address: int, space: str = DEFAULT_SPACE) -> Register | None:
        """The register that owns `address` in `space`, including the unused high word of a pair."""
        return self._owners.get((space, address))
