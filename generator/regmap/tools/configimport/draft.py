"""The registers read from a config, merged per address, and written as a map draft.

An entity becomes an `Imported` register; entities at one address merge into one register (binary sensors
with bitmasks into its bit fields, a select and a text sensor into one enum, a sensor and a number into
one read-write register). What a config says that a map cannot (a lambda, a filter other than multiply
and offset, a read-range break) becomes the register's `notes` and a line of the report, never code.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from decimal import Decimal
from fractions import Fraction
from typing import Any

from regmap.tools.spreadsheet.skeleton import head
from regmap.tools.spreadsheet.yamltext import block, flow, scalar
from regmap_runtime.spaces import SPACES
from regmap_runtime.types import TYPES

IDENTIFIER = re.compile(r"[a-z][a-z0-9_]*")


@dataclass
class Member:
    value: int
    title: str
    readable: bool = True
    writable: bool = True


@dataclass
class Flag:
    """A bit field: its mask in the register's value, and what it is called."""

    key: str
    mask: int
    title: str


@dataclass
class Imported:
    """One register as the config describes it (raw values: min/max before scale)."""

    key: str  # the entity's id or name: the register's name once made an identifier
    title: str
    address: int
    space: str  # holding, input, coil, discrete_input
    type: str  # a regmap type name
    origin: str  # file:line of the entity
    word_order: str = "high_first"
    byte_order: str = "high_first"
    words: int | None = None  # strings only
    writable: bool = False
    unit: str | None = None
    scale: Fraction = Fraction(1)
    offset: Fraction = Fraction(0)
    min: int | float | None = None
    max: int | float | None = None
    poll: str = "normal"
    members: list[Member] = field(default_factory=list)
    flags: list[Flag] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    count: int = 1  # Home Assistant's virtual_count + 1: this many at consecutive addresses (an array)
    group: str | None = None  # the map group it goes in (a SunSpec model); None: one group per space
    group_title: str | None = None
    default: int | str | None = None
    encoding: str | None = None  # of a string, when not ASCII
    na: list[int | float] = field(default_factory=list)  # raw values that mean "not available" (HA's nan_value)
    scale_from: str | None = None  # a scale-factor register's key: value = raw x 10^sf (a SunSpec sunssf point)

    @property
    def width(self) -> int:
        return self.words if self.words is not None else TYPES[self.type].words

    @property
    def stride(self) -> int:
        return 1 if self.type == "bool" else self.width

    @property
    def span(self) -> range:
        return range(self.address, self.address + self.stride * self.count)


@dataclass
class Device:
    """The registers of one device (one ESPHome controller, one HA hub + slave) and what the import said."""

    label: str
    slave: int | None = None
    serial: dict[str, Any] = field(default_factory=dict)
    interval: float = 60.0  # seconds between two updates (ESPHome's update_interval), for poll classes
    registers: list[Imported] = field(default_factory=list)

    def add(self, reg: Imported) -> str | None:
        """Add `reg`, merging it into the register already at its address when they agree on its reading;
        else why it was left out."""
        for other in self.registers:
            if other.space == reg.space and set(other.span) & set(reg.span):
                if other.count > 1 or reg.count > 1:
                    return f"{reg.key} at 0x{reg.address:04X} overlaps the run of {other.key} ({other.origin})"
                return _merge(other, reg)
        self.registers.append(reg)
        return None

    def signature(self) -> tuple[Any, ...]:
        """What makes two devices the same model: their registers' readings (not their names or slaves)."""
        return tuple(
            sorted(
                (r.space, r.address, r.count, r.type, r.width, r.word_order, r.byte_order, r.scale, r.offset, r.writable)
                for r in self.registers
            )
        )


@dataclass
class Import:
    """What a config gave: its devices, and the report (file:line: what became a note or was left out)."""

    devices: list[Device]
    report: list[str]


def _merge(into: Imported, reg: Imported) -> str | None:
    """Merge `reg` into `into` (the same address); a reason when they read the register differently."""
    same = (into.address, into.type, into.width, into.word_order, into.byte_order) == (
        reg.address,
        reg.type,
        reg.width,
        reg.word_order,
        reg.byte_order,
    )
    if not same:
        return (
            f"{reg.key} at 0x{reg.address:04X} reads it as {reg.type} ({reg.word_order}, {reg.byte_order}), but {into.key} "
            f"({into.origin}) reads 0x{into.address:04X} as {into.type} ({into.word_order}, {into.byte_order}); a register has one reading"
        )
    if reg.flags and not into.flags and not into.members and into.scale == 1 and not into.writable:
        into.key, into.title = reg.key, reg.title  # the raw sensor of a bit-field register is not a better name
    plain = (Fraction(1), Fraction(0))
    if (reg.scale, reg.offset) != plain and (into.scale, into.offset) in (plain, (reg.scale, reg.offset)):
        into.scale, into.offset = reg.scale, reg.offset
    elif (reg.scale, reg.offset) not in (plain, (into.scale, into.offset)):
        return f"{reg.key} scales 0x{reg.address:04X} by {reg.scale} (+{reg.offset}), {into.key} ({into.origin}) by {into.scale} (+{into.offset})"
    into.writable = into.writable or reg.writable
    into.unit = into.unit or reg.unit
    for attr in ("min", "max"):
        if getattr(into, attr) is None:
            setattr(into, attr, getattr(reg, attr))
    taken = {f.mask for f in into.flags}
    into.flags += [f for f in reg.flags if f.mask not in taken]
    for member in reg.members:
        known = next((m for m in into.members if m.value == member.value), None)
        if known is None:
            into.members.append(member)
        else:
            known.readable, known.writable = known.readable or member.readable, known.writable or member.writable
    into.notes += reg.notes
    if reg.poll != into.poll and "normal" in (reg.poll, into.poll):
        into.poll = reg.poll if into.poll == "normal" else into.poll
    return None


def identifier(text: str, fallback: str) -> str:
    """A snake_case name from an entity's id or name (`${x_device_id}_bus_voltage` -> `bus_voltage`)."""
    text = re.sub(r"^\$\{[^}]*\}_?", "", text)
    name = re.sub(r"[^a-z0-9]+", "_", text.lower()).strip("_")
    if not name or not name[0].isalpha():
        name = f"{fallback}_{name}" if name else fallback
    return name if len(name) <= MAX_NAME else name[:MAX_NAME].rstrip("_")


def fraction(value: Any) -> Fraction:
    return Fraction(Decimal(str(value)))


def scale_number(value: Fraction) -> int | float | str:
    """A scale as the map writes it: an integer, a decimal that reads back exactly, else the nearest float."""
    if value.denominator == 1:
        return value.numerator
    return float(value)


def _exact(value: Fraction) -> bool:
    d = value.denominator
    while d % 2 == 0:
        d //= 2
    while d % 5 == 0:
        d //= 5
    return d == 1


def _bits(mask: int) -> str | int:
    low = (mask & -mask).bit_length() - 1
    high = mask.bit_length() - 1
    return low if low == high else f"{low}-{high}"


def _contiguous(mask: int) -> bool:
    shifted = mask >> ((mask & -mask).bit_length() - 1)
    return shifted & (shifted + 1) == 0


def _function_codes(registers: list[Imported]) -> list[int]:
    codes: set[int] = set()
    for reg in registers:
        info = SPACES[reg.space]
        codes |= {code for op, code in info.codes.items() if op == "read" or reg.writable}
    return sorted(codes or {0x03})


class _Names:
    def __init__(self) -> None:
        self.taken: set[str] = set()

    def unique(self, name: str) -> str:
        base, n = name, 2
        while name in self.taken:
            name = f"{base[: MAX_NAME - 4]}_{n}"
            n += 1
        self.taken.add(name)
        return name


def _register_yaml(reg: Imported, name: str, enum: str | None) -> dict[str, Any]:
    out: dict[str, Any] = {"name": name, "address": reg.address}
    if reg.space != "holding":
        out["space"] = reg.space
    out["type"] = reg.type
    if reg.words is not None:
        out["words"] = reg.words
    if reg.encoding is not None:
        out["encoding"] = reg.encoding
    if reg.word_order != "high_first" and TYPES[reg.type].words > 1:
        out["word_order"] = reg.word_order
    if reg.byte_order != "high_first":
        out["byte_order"] = reg.byte_order
    out["access"] = "rw" if reg.writable and SPACES[reg.space].writable else "r"
    out["title"] = reg.title or name
    if reg.unit:
        out["unit"] = reg.unit
    if reg.scale != 1:
        out["scale"] = scale_number(reg.scale)
        if not _exact(reg.scale):
            reg.notes.append(f"scale {reg.scale} has no exact decimal; written as the nearest float")
    if reg.offset != 0:
        out["offset"] = scale_number(reg.offset)
    if reg.na:
        out["na"] = list(reg.na)
    if reg.scale_from is not None:
        out["scale_from"] = reg.scale_from
    info = TYPES[reg.type]
    if info.numeric:
        for key in ("min", "max"):
            value = getattr(reg, key)
            if value is not None and info.raw_min <= value <= info.raw_max:
                out[key] = value
            elif value is not None:
                reg.notes.append(f"{key}: raw {value} does not fit {reg.type} (the config's value type): left out")
        if "min" in out and "max" in out and out["min"] > out["max"]:
            reg.notes.append(f"min {out.pop('min')} above max {out.pop('max')}: both left out")
    if enum is not None:
        out["enum"] = enum
    if reg.flags:
        fields = []
        names = _Names()
        for flag in sorted(reg.flags, key=lambda f: f.mask & -f.mask):
            fields.append({"name": names.unique(identifier(flag.key, "bit")), "bits": _bits(flag.mask), "title": flag.title or flag.key})
        out["bitfields"] = fields
    if reg.default is not None:
        out["default"] = reg.default
    if reg.poll != "normal":
        out["poll"] = reg.poll
    out["source"] = reg.origin
    if reg.notes:
        out["notes"] = " ".join(n if n.endswith(".") else n + "." for n in reg.notes)
    return out


def _array_yaml(reg: Imported, entry: dict[str, Any]) -> dict[str, Any]:
    """A run of `count` equal registers (HA's virtual_count) as an array of one member."""
    name, title, origin = entry.pop("name"), entry.pop("title"), entry.pop("source")
    del entry["address"]
    array: dict[str, Any] = {"array": name, "title": title, "count": reg.count, "index_base": 0, "base": reg.address, "stride": reg.stride}
    array["element_title"] = f"{title} {{n}}"
    array["source"] = origin
    array["members"] = [{"name": "value", "word_offset": 0, **entry, "title": title}]
    return array


def _usable_flags(reg: Imported, report: list[str]) -> None:
    """Bit fields must be contiguous and may not overlap; a mask that is neither is kept as a note."""
    kept: list[Flag] = []
    used = 0
    for flag in reg.flags:
        if not _contiguous(flag.mask) or flag.mask & used or flag.mask >> (16 * reg.width):
            reg.notes.append(f"bitmask 0x{flag.mask:X} ({flag.title}) is not one run of bits apart from the others: not a field")
            report.append(f"{reg.origin}: bitmask 0x{flag.mask:X} of {flag.key} kept as a note (not one run of free bits)")
            continue
        used |= flag.mask
        kept.append(flag)
    reg.flags = kept
    if reg.flags and (reg.members or TYPES[reg.type].kind != "int"):
        reg.notes.append("bit fields: " + ", ".join(f"{f.title} 0x{f.mask:X}" for f in reg.flags))
        report.append(f"{reg.origin}: bitmasks of {reg.key} kept as a note (the register also has labels, or is not an integer)")
        reg.flags = []


def map_text(device: Device, device_id: str, vendor: str, model: str, source: str, report: list[str]) -> str:
    """The map draft of one device: the registers sorted by space and address, one group per space."""
    serial = {"baud": 9600, "parity": "none", "stop_bits": 1, **device.serial}
    lines = head(
        device_id,
        vendor,
        model,
        made_by=f"a draft imported from {source} by `regmap import`",
        function_codes=_function_codes(device.registers),
    )
    lines = lines.replace("    baud: 19200 ", f"    baud: {serial['baud']} ").replace(
        "    baud_rates: [9600, 19200]", f"    baud_rates: [{serial['baud']}]"
    )
    lines = lines.replace("    parity: none ", f"    parity: {serial['parity']} ").replace(
        "    stop_bits: 1 ", f"    stop_bits: {serial['stop_bits']} "
    )
    if device.slave is not None:
        lines = lines.replace("  slave_ids: {min: 1, max: 247}", f"  slave_ids: {{min: {min(device.slave, 1)}, max: 247}}")
    out = [lines.rstrip("\n")]
    names = _Names()
    enums: list[str] = []
    groups: dict[str, list[str]] = {}
    titles: dict[str, str] = {}
    for reg in sorted(device.registers, key=lambda r: (list(SPACES).index(r.space), r.address)):
        group = reg.group or reg.space
        titles.setdefault(group, reg.group_title or SPACES[reg.space].title.capitalize())
        _usable_flags(reg, report)
        name = names.unique(identifier(reg.key, "register"))
        enum = None
        if reg.members and TYPES[reg.type].kind == "int":
            enum = name
            taken: set[str] = set()
            enums += [f"  {enum}:", f"    title: {scalar(reg.title or name)}", "    values:"]
            for m in sorted(reg.members, key=lambda m: m.value):
                member: dict[str, Any] = {"value": m.value, "name": _member_name(m.title, m.value, taken), "title": m.title}
                if not m.writable:
                    member["access"] = "r"
                elif not m.readable:
                    member["access"] = "w"
                enums.append(f"      - {flow(member)}")
        elif reg.members:
            reg.notes.append("labels: " + ", ".join(f"{m.value} = {m.title}" for m in reg.members))
        entry = _register_yaml(reg, name, enum)
        if reg.count > 1:
            entry = _array_yaml(reg, entry)
        groups.setdefault(group, []).extend(block(entry, 6, "- "))
    if enums:
        out += ["enums:", *enums]
    out.append("groups:" if groups else "groups: []")
    for group, lines_ in groups.items():
        out += [
            f"  - id: {group}",
            f"    title: {scalar(titles[group])}",
            f"    source: {scalar(source)}",
            "    registers:",
            *lines_,
        ]
    out += ["examples: []", "errata: []"]
    return "\n".join(out) + "\n"


MAX_NAME = 64  # the map's limit on a name
NAME_CHARS = 48  # of a name made from a title: room for a `_<value>` that makes it unique, within the map's 64


def _cut(name: str) -> str:
    return name if len(name) <= NAME_CHARS else name[:NAME_CHARS].rsplit("_", 1)[0]


def _member_name(title: str, value: int, taken: set[str]) -> str:
    name = _cut(re.sub(r"[^a-z0-9]+", "_", title.lower()).strip("_"))
    if not name or not name[0].isalpha():
        name = f"value_{name or value}".replace("-", "minus_")
    if name in taken:
        name = f"{name}_{value}".replace("-", "minus_")
    taken.add(name)
    return name
