"""C back end: a header per map (`<device>.h`) plus the shared RTU helpers (`regmap_rtu.h`).

The views below compute every identifier, literal and expression; the templates only print, and
escape map text with `c_comment` / `c_str`. The headers are C99 and C++ (include and `extern "C"`
guards), static inline, allocation- and stdio-free.

`render_frames_test` emits a C program that rebuilds every request frame of a map's `examples`
with the header's helpers and parses every response frame; the tests compile and run it.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

from regmap.backends.common import read_plan
from regmap.diagnostics import UsageError
from regmap.generate import Files, Target
from regmap.keywords import C_KEYWORDS, CPP_KEYWORDS
from regmap.model import Access, ArrayDef, Bitfield, Command, Device, EnumType, Example, Register, WordOrder
from regmap.render import environment, header_lines
from regmap_runtime.rtu import (
    EXCEPTION_FLAG,
    READ_HOLDING,
    WRITE_MULTIPLE,
    WRITE_SINGLE,
    crc_ok,
    parse_frame,
)

SHARED_HEADER = "regmap_rtu.h"

# -- identifiers -----------------------------------------------------------------------------

# Names the headers this code includes (stdbool.h, stddef.h, stdint.h) define, and common macros.
STANDARD_NAMES = frozenset(
    [
        "NULL",
        "offsetof",
        "size_t",
        "ptrdiff_t",
        "max_align_t",
        "EOF",
        "errno",
        "assert",
        "main",
        "int8_t",
        "int16_t",
        "int32_t",
        "int64_t",
        "uint8_t",
        "uint16_t",
        "uint32_t",
        "uint64_t",
        "intptr_t",
        "uintptr_t",
        "intmax_t",
        "uintmax_t",
        "INT8_MAX",
        "INT16_MAX",
        "INT32_MAX",
        "INT64_MAX",
        "INT8_MIN",
        "INT16_MIN",
        "INT32_MIN",
        "INT64_MIN",
        "UINT8_MAX",
        "UINT16_MAX",
        "UINT32_MAX",
        "UINT64_MAX",
        "SIZE_MAX",
        "PTRDIFF_MAX",
        "PTRDIFF_MIN",
        "INTPTR_MAX",
        "UINTPTR_MAX",
    ]
)
_RESERVED = re.compile(r"^_|__|_t$")
_UPPER = re.compile(r"^[A-Z_][A-Z0-9_]*$")
_LOWER = re.compile(r"^[a-z_][a-z0-9_]*$")


def _check_reserved(name: str) -> None:
    # Leading underscores and `__` anywhere are reserved to the implementation (C 7.1.3, C++
    # [lex.name]); `_t` names to POSIX.
    if _RESERVED.search(name):
        raise UsageError(f"{name!r} is a reserved C identifier (leading underscore, '__' or a '_t' suffix); rename it in the map")


class CIdentifier(str):
    """An upper-case C identifier for macros and enum constants, joined from parts: `[A-Z_][A-Z0-9_]*`,
    never reserved. Upper-case names cannot be C or C++ keywords; they can be standard macros."""

    def __new__(cls, *parts: str) -> CIdentifier:
        name = "_".join(p for p in parts if p).upper()
        if not _UPPER.match(name):
            raise UsageError(f"{name!r} is not a valid C identifier")
        _check_reserved(name)
        if name in STANDARD_NAMES:
            raise UsageError(f"{name!r} is a name of the C standard library; rename it in the map")
        return super().__new__(cls, name)


class CSymbol(str):
    """A lower-case C identifier for functions, types, tables and parameters. A C or C++ keyword
    gets a trailing underscore (`register` -> `register_`); reserved names are refused."""

    def __new__(cls, *parts: str) -> CSymbol:
        name = "_".join(p for p in parts if p).lower()
        if not _LOWER.match(name):
            raise UsageError(f"{name!r} is not a valid C identifier")
        if name in C_KEYWORDS or name in CPP_KEYWORDS or name in STANDARD_NAMES:
            name += "_"
        _check_reserved(name)
        return super().__new__(cls, name)


class _Names:
    """Every file-scope name one header declares, so two map items never generate the same one."""

    def __init__(self, device: Device) -> None:
        self.device = device
        self.seen: dict[str, str] = {}

    def add(self, name: str, what: str) -> str:
        if name in self.seen:
            raise UsageError(
                f"{self.device.source_path}: generated C name {name} is used by both {self.seen[name]} and {what}; rename one in the map"
            )
        self.seen[name] = what
        return name


# -- literals --------------------------------------------------------------------------------


def c_unsigned(value: int) -> str:
    """An unsigned literal that keeps its value on 16-bit-int targets too."""
    return f"{value}u" if value <= 0xFFFF else f"{value}ul"


def c_hex(value: int) -> str:
    return f"0x{value:04X}u" if value <= 0xFFFF else f"0x{value:08X}ul"


def c_signed(value: int) -> str:
    """A signed literal safe inside a macro (parenthesised when negative; INT32_MIN spelled so it is an int)."""
    if value == -(1 << 31):
        return "(-2147483647 - 1)"
    return f"({value})" if value < 0 else str(value)


def c_raw(value: int, signed: bool) -> str:
    return c_signed(value) if signed else c_unsigned(value)


def c_float(value: Fraction) -> str:
    text = f"{float(value):.9g}"
    if not any(c in text for c in ".e"):
        text += ".0"
    return text + "f"


def _enum_literal(value: int) -> str:
    return f"0x{value:02X}" if value >= 0x10 else c_signed(value)


def _titled(title: str, title_zh: str | None) -> str:
    return f"{title} ({title_zh})" if title_zh else title


def _sections(source: tuple[str, ...]) -> str:
    return f"Manual {', '.join(source)}." if source else ""


def _eng(reg: Register, raw: int) -> str:
    value = raw * reg.scale
    return str(int(value)) if value.denominator == 1 else f"{float(value):.10g}"


ACCESS_MACRO = {Access.READ: "REGMAP_ACCESS_R", Access.READ_WRITE: "REGMAP_ACCESS_RW", Access.WRITE: "REGMAP_ACCESS_W"}
WORD_ORDER_MACRO = {WordOrder.HIGH_FIRST: "REGMAP_HIGH_FIRST", WordOrder.LOW_FIRST: "REGMAP_LOW_FIRST"}
PARITY_CHAR = {"none": "'N'", "even": "'E'", "odd": "'O'"}


# -- views -----------------------------------------------------------------------------------


@dataclass(frozen=True)
class Macro:
    name: str
    value: str
    comment: str = ""  # plain text; the template escapes it


@dataclass(frozen=True)
class EnumView:
    type_name: str
    comment: str
    members: tuple[Macro, ...]
    as_macros: bool  # a value does not fit an int, which a C enum constant must


@dataclass(frozen=True)
class BitfieldView:
    comment: str
    mask: Macro
    shift: Macro
    word_type: str
    getter: str
    setter: str


@dataclass(frozen=True)
class RegisterView:
    template: str
    comment: str
    description: str
    macros: tuple[Macro, ...]
    bitfields: tuple[BitfieldView, ...]


@dataclass(frozen=True)
class ElementTable:
    """Per-element values of an array member whose elements differ (e.g. a default per path)."""

    c_type: str
    name: str
    values: str


@dataclass(frozen=True)
class ArrayMemberView:
    comment: str
    description: str
    addr_macro: str
    offset: str
    pair_addr_macro: str | None
    addr_function: str
    macros: tuple[Macro, ...]
    tables: tuple[ElementTable, ...]
    bitfields: tuple[BitfieldView, ...]


@dataclass(frozen=True)
class ArrayView:
    template: str
    comment: str
    base: str  # names of the BASE, FIRST, COUNT and STRIDE macros
    first: str
    count: str
    stride: str
    macros: tuple[Macro, ...]
    check: str  # C condition: index n in range
    members: tuple[ArrayMemberView, ...]


@dataclass(frozen=True)
class GroupView:
    comment: str
    items: tuple[RegisterView | ArrayView, ...]


@dataclass(frozen=True)
class CommandView:
    comment: str
    addr: Macro
    value: Macro
    function: str
    argument: str  # "" when the command takes none
    argument_type: str
    argument_macros: tuple[Macro, ...]
    out_of_range: str  # C condition on the argument
    raw: str  # C expression of the raw value to write
    words: int
    word_order: str


@dataclass(frozen=True)
class PlanBlock:
    address: str
    count: str
    comment: str


class _Context:
    """Names for one device: macro prefix, function prefix, and the address expression of each register."""

    def __init__(self, device: Device) -> None:
        self.device = device
        self.names = _Names(device)
        self.prefix = CIdentifier(device.id)
        self.lower = device.id  # only ever the start of a name; CSymbol checks the whole name
        self.arrays = {a.name: a for a in device.arrays}

    def const(self, *parts: str, what: str = "") -> str:
        return self.names.add(CIdentifier(self.prefix, *parts), what or " ".join(parts))

    def symbol(self, *parts: str, what: str = "") -> str:
        return self.names.add(CSymbol(self.lower, *parts), what or " ".join(parts))

    def owner(self, reg: Register) -> str:
        """The name the macros of a register carry: its own, or `<array>_<member>` for an array element."""
        return f"{reg.array.array}_{reg.array.member}" if reg.array else reg.name

    def addr(self, reg: Register) -> str:
        """C expression of a register's listed address."""
        name = CIdentifier(self.prefix, self.owner(reg), "ADDR")
        return f"{name}({reg.array.index})" if reg.array else name

    def pair_addr(self, reg: Register) -> str:
        name = CIdentifier(self.prefix, self.owner(reg), "PAIR_ADDR")
        return f"{name}({reg.array.index})" if reg.array else name

    def member_const(self, reg: Register, suffix: str) -> str:
        return CIdentifier(self.prefix, self.owner(reg), suffix)

    def symbol_ref(self, *parts: str) -> str:
        """A function the header declares (referring to it does not declare it again)."""
        return CSymbol(self.lower, *parts)


def _sentence(text: str | None) -> str:
    text = " ".join((text or "").split())
    return text if not text or text[-1] in ".!?。" else text + "."


def _sentences(*parts: str | None) -> str:
    return " ".join(filter(None, (_sentence(p) for p in parts)))


def _register_facts(reg: Register, elements: Sequence[Register]) -> str:
    """Type, access, unit, scale, range, default and errata of a register (or of every element of an array member)."""
    facts = [f"{reg.type.value} {reg.access.value}"]
    if reg.unit:
        facts.append(f"unit {reg.unit}")
    if reg.scaled:
        facts.append(f"scale {_eng(reg, 1)}")
    if reg.min is not None or reg.max is not None:
        scaled = f" ({_eng(reg, reg.raw_min)}..{_eng(reg, reg.raw_max)}{f' {reg.unit}' if reg.unit else ''})" if reg.scaled else ""
        facts.append(f"raw {reg.raw_min}..{reg.raw_max}{scaled}")
    if reg.range_text:
        facts.append(f"printed range {reg.range_text}")
    defaults = {r.default for r in elements}
    if len(defaults) > 1:
        facts.append("default differs per element")
    elif reg.default is not None:
        facts.append(f"default {reg.default}" + (f" ({_eng(reg, reg.default)})" if reg.scaled else ""))
    if reg.enum is not None:
        facts.append(f"values: enum {reg.enum.name}")
    if reg.paired:
        facts.append("low word of a 32-bit pair whose unused high word is at ADDR - 1")
    if reg.takes_effect:
        facts.append(f"takes effect {reg.takes_effect.replace('_', ' ')}")
    errata = sorted({e for r in elements for e in r.errata})
    if errata:
        facts.append(f"errata {', '.join(errata)}")
    return ", ".join(facts)


def _register_comment(reg: Register, label: str, elements: Sequence[Register]) -> str:
    return _sentences(f"{label}: {_titled(reg.title, reg.title_zh)}", _register_facts(reg, elements), _sections(reg.source))


def _value_macros(ctx: _Context, reg: Register, owner: str, elements: Sequence[Register]) -> tuple[list[Macro], list[ElementTable]]:
    """The macros every register (or array member) gets. An array member whose elements differ in
    min, max or default gets a table indexed by n - FIRST instead of the macro."""
    macros = [
        Macro(ctx.const(owner, "WORDS"), c_unsigned(reg.words)),
        Macro(ctx.const(owner, "ACCESS"), ACCESS_MACRO[reg.access]),
        Macro(ctx.const(owner, "SIGNED"), "1" if reg.signed else "0"),
    ]
    tables = []
    if reg.words == 2:
        macros.append(Macro(ctx.const(owner, "WORD_ORDER"), WORD_ORDER_MACRO[reg.word_order]))
    for key in ("min", "max", "default"):
        values = [getattr(r, key) for r in elements]
        if len(set(values)) == 1:
            if values[0] is not None:
                macros.append(Macro(ctx.const(owner, key), c_raw(values[0], reg.signed)))
        elif None not in values:
            c_type = f"{'int' if reg.signed else 'uint'}{reg.type.bits}_t"
            tables.append(ElementTable(c_type, ctx.symbol(owner, key), ", ".join(c_raw(v, reg.signed) for v in values)))
    macros += [
        Macro(ctx.const(owner, "SCALE"), c_float(reg.scale)),
        Macro(ctx.const(owner, "SCALE_NUM"), str(reg.scale.numerator)),
        Macro(ctx.const(owner, "SCALE_DEN"), str(reg.scale.denominator)),
        Macro(ctx.const(owner, "PAIRED"), "1" if reg.paired else "0"),
    ]
    return macros, tables


def _bitfield_views(ctx: _Context, reg: Register, owner: str) -> tuple[BitfieldView, ...]:
    word_type = "uint32_t" if reg.words == 2 else "uint16_t"
    return tuple(
        BitfieldView(
            comment=_bitfield_comment(b),
            mask=Macro(ctx.const(owner, b.name, "MASK"), c_hex(b.mask)),
            shift=Macro(ctx.const(owner, b.name, "SHIFT"), c_unsigned(b.lsb)),
            word_type=word_type,
            getter=ctx.symbol(owner, "get", b.name),
            setter=ctx.symbol(owner, "set", b.name),
        )
        for b in reg.bitfields
    )


def _bitfield_comment(b: Bitfield) -> str:
    head = f"bit{'s' if b.width > 1 else ''} {b.bits_text} {b.name}: {_titled(b.title, b.title_zh)}"
    return _sentences(head, f"Values: enum {b.enum.name}" if b.enum else None, b.description)


def _register_view(ctx: _Context, reg: Register) -> RegisterView:
    values, _ = _value_macros(ctx, reg, reg.name, (reg,))
    macros = [Macro(ctx.const(reg.name, "ADDR", what=f"the address of register {reg.name}"), c_hex(reg.address)), *values]
    if reg.paired:
        macros.append(Macro(ctx.const(reg.name, "PAIR_ADDR"), c_hex(reg.first_address)))
    return RegisterView(
        template="c/register.h.jinja",
        comment=_register_comment(reg, reg.label, (reg,)),
        description=reg.description,
        macros=tuple(macros),
        bitfields=_bitfield_views(ctx, reg, reg.name),
    )


def _array_view(ctx: _Context, array: ArrayDef) -> ArrayView:
    base, first, _last, count, stride = macros = (
        Macro(ctx.const(array.name, "BASE"), c_hex(array.base)),
        Macro(ctx.const(array.name, "FIRST"), c_unsigned(array.first_index)),
        Macro(ctx.const(array.name, "LAST"), c_unsigned(array.last_index)),
        Macro(ctx.const(array.name, "COUNT"), c_unsigned(array.count)),
        Macro(ctx.const(array.name, "STRIDE"), c_unsigned(array.stride)),
    )
    # `n - FIRST < COUNT` on an unsigned n checks both bounds, without the `n >= 0` that -Wtype-limits flags.
    check = f"n - {first.name} < {count.name}"
    members = []
    for member in array.members:
        elements = [ctx.device.register(f"{array.name}_{n}_{member.name}") for n in range(array.first_index, array.last_index + 1)]
        reg = elements[0]
        owner = f"{array.name}_{member.name}"
        values, tables = _value_macros(ctx, reg, owner, elements)
        members.append(
            ArrayMemberView(
                comment=_register_comment(reg, f"{owner} (element {array.first_index}: {reg.label})", elements),
                description=reg.description,
                addr_macro=ctx.const(owner, "ADDR", what=f"the address of member {member.name} of array {array.name}"),
                offset=c_unsigned(member.offset),
                pair_addr_macro=ctx.const(owner, "PAIR_ADDR") if reg.paired else None,
                addr_function=ctx.symbol(owner, "addr"),
                macros=tuple(values),
                tables=tuple(tables),
                bitfields=_bitfield_views(ctx, reg, owner),
            )
        )
    comment = _sentences(
        _titled(array.title, array.title_zh)
        + f": {array.count} elements {array.first_index}..{array.last_index}; member m of element n is at"
        + f" BASE 0x{array.base:04X} + {array.stride} x (n - {array.first_index}) + offset of m",
        array.description,
        _sections(array.source),
    )
    return ArrayView(
        template="c/array.h.jinja",
        comment=comment,
        base=base.name,
        first=first.name,
        count=count.name,
        stride=stride.name,
        macros=macros,
        check=check,
        members=tuple(members),
    )


def _group_views(ctx: _Context) -> list[GroupView]:
    groups = []
    for group in ctx.device.groups:
        items: list[RegisterView | ArrayView] = []
        done: set[str] = set()
        for reg in group.registers:
            if reg.array is None:
                items.append(_register_view(ctx, reg))
            elif reg.array.array not in done:
                done.add(reg.array.array)
                items.append(_array_view(ctx, ctx.arrays[reg.array.array]))
        groups.append(GroupView(comment=_sentences(_titled(group.title, group.title_zh), _sections(group.source)), items=tuple(items)))
    return groups


def _enum_view(ctx: _Context, e: EnumType) -> EnumView:
    # A C enum constant is an int; a table with a value outside int becomes macros instead.
    as_macros = any(not -(1 << 31) <= m.value < (1 << 31) for m in e.members)
    members = tuple(
        Macro(
            ctx.const(e.name, m.name, what=f"member {m.name} of enum {e.name}"),
            c_raw(m.value, m.value < 0) if as_macros else _enum_literal(m.value),
            _sentences(_titled(m.title, m.title_zh) + (f" [{m.symbol}]" if m.symbol else ""), m.description),
        )
        for m in e.members
    )
    comment = _sentences(_titled(e.title, e.title_zh), e.description, _sections(e.source))
    return EnumView(type_name=ctx.symbol(e.name, what=f"the type of enum {e.name}"), comment=comment, members=members, as_macros=as_macros)


def _command_view(ctx: _Context, cmd: Command) -> CommandView:
    reg = cmd.register
    what = f"writes 0x{cmd.value:04X}" + (f" + {cmd.argument.name}" if cmd.argument else "") + f" to {reg.label} (0x{reg.address:04X})"
    comment = _sentences(f"{_titled(cmd.title, cmd.title_zh)}: {what}", cmd.description, _sections(cmd.source))
    value = Macro(ctx.const("CMD", cmd.name, "VALUE"), c_hex(cmd.value) if cmd.value >= 0 else c_signed(cmd.value))
    argument_macros: tuple[Macro, ...] = ()
    argument = argument_type = out_of_range = ""
    raw = value.name
    if cmd.argument is not None:
        arg = cmd.argument
        argument = CSymbol(arg.name)
        if argument in ("buf", "cap", "slave", "words"):  # the helper's other parameters
            argument = CSymbol(arg.name, "arg")
        lo = Macro(ctx.const("CMD", cmd.name, arg.name, "MIN"), c_signed(arg.min), arg.title)
        hi = Macro(ctx.const("CMD", cmd.name, arg.name, "MAX"), c_signed(arg.max))
        argument_macros = (lo, hi)
        if arg.min >= 0:
            # An unsigned parameter; no `< 0` test, which -Wtype-limits would flag.
            argument_type = "unsigned"
            upper = f"{argument} > (unsigned){hi.name}"
            out_of_range = upper if arg.min == 0 else f"{argument} < (unsigned){lo.name} || {upper}"
        else:
            argument_type = "long"
            out_of_range = f"{argument} < {lo.name} || {argument} > {hi.name}"
        raw = f"(unsigned long){value.name} + (unsigned long){argument}"
    return CommandView(
        comment=comment,
        addr=Macro(ctx.const("CMD", cmd.name, "ADDR"), ctx.addr(reg)),
        value=value,
        function=ctx.symbol("build", cmd.name, what=f"the helper of command {cmd.name}"),
        argument=argument,
        argument_type=argument_type,
        argument_macros=argument_macros,
        out_of_range=out_of_range,
        raw=raw,
        words=reg.words,
        word_order=ctx.member_const(reg, "WORD_ORDER") if reg.words == 2 else "",
    )


def _transport_macros(ctx: _Context) -> list[Macro]:
    t = ctx.device.transport
    macros = [
        Macro(ctx.const("DEFAULT_BAUD"), f"{t.baud}ul", "baud rates: " + ", ".join(str(b) for b in t.baud_rates) if t.baud_rates else ""),
        Macro(ctx.const("PARITY"), PARITY_CHAR[t.parity], f"parity {t.parity} (as libmodbus spells it)"),
        Macro(ctx.const("DATA_BITS"), c_unsigned(t.data_bits)),
        Macro(ctx.const("STOP_BITS"), c_unsigned(t.stop_bits)),
        Macro(ctx.const("SLAVE_MIN"), c_unsigned(t.slave_min)),
        Macro(ctx.const("SLAVE_MAX"), c_unsigned(t.slave_max)),
    ]
    if t.broadcast_id is not None:
        macros.append(Macro(ctx.const("HAS_BROADCAST"), "1"))
        macros.append(Macro(ctx.const("BROADCAST_ID"), c_unsigned(t.broadcast_id), "a request to it is not answered"))
    else:
        macros.append(Macro(ctx.const("HAS_BROADCAST"), "0", "the manual says the device does not support broadcast"))
    macros += [
        Macro(ctx.const("MAX_READ_REGISTERS"), c_unsigned(t.max_read_registers)),
        Macro(ctx.const("MAX_WRITE_REGISTERS"), c_unsigned(t.max_write_registers)),
    ]
    if t.max_message_bytes is not None:
        macros.append(Macro(ctx.const("MAX_MESSAGE_BYTES"), c_unsigned(t.max_message_bytes)))
    macros.append(Macro(ctx.const("WORD_ORDER"), WORD_ORDER_MACRO[t.word_order], "order of the words of 32-bit values"))
    if t.word_order_register is not None:
        w = t.word_order_register
        macros += [
            Macro(ctx.const("WORD_ORDER_REGISTER_ADDR"), ctx.addr(w.register), f"{w.register.label} selects the word order"),
            Macro(ctx.const("WORD_ORDER_REGISTER_HIGH_FIRST"), c_raw(w.high_first, w.register.signed)),
            Macro(ctx.const("WORD_ORDER_REGISTER_LOW_FIRST"), c_raw(w.low_first, w.register.signed)),
        ]
    if t.response_delay_ms is not None:
        macros.append(Macro(ctx.const("RESPONSE_DELAY_US"), f"{round(t.response_delay_ms * 1000)}ul", "response delay"))
    return macros


def _plan_blocks(ctx: _Context) -> list[PlanBlock]:
    blocks = []
    for block in read_plan(ctx.device):
        first, last = block.registers[0], block.registers[-1]
        names = [r.param or r.name for r in (first, last)]
        comment = names[0] if first is last else f"{names[0]} .. {names[1]} ({len(block.registers)} registers)"
        blocks.append(PlanBlock(address=c_hex(block.address), count=c_unsigned(block.count), comment=comment))
    return blocks


def device_context(device: Device) -> dict[str, Any]:
    ctx = _Context(device)
    info = device.info
    about = [
        f"{info.vendor}{f' ({info.vendor_zh})' if info.vendor_zh else ''} {info.model}"
        + (f": {info.description}" if info.description else ""),
        f"Manual: {info.manual_title}" + (f", version {info.manual_version}" if info.manual_version else "") + f" ({info.manual_file}).",
    ]
    if info.firmware:
        about.append(f"Firmware: {info.firmware}")
    transport = _transport_macros(ctx)
    exceptions = tuple(
        Macro(
            ctx.const("EXCEPTION", e.name, what=f"exception {e.name}"),
            f"0x{e.code:02X}",
            _sentences(_titled(e.title, e.title_zh), _sections(e.source)),
        )
        for e in device.transport.exceptions
    )
    enums = [_enum_view(ctx, e) for e in device.enums]
    groups = _group_views(ctx)
    commands = [_command_view(ctx, c) for c in device.commands]
    faults = [
        Macro(ctx.const("FAULT", f.name, what=f"fault {f.name}"), c_hex(f.value), f"{f.code} {_titled(f.title, f.title_zh)} ({f.kind})")
        for f in device.faults
        if f.value is not None
    ]
    return {
        "header": _header(device),
        "about": about,
        "device": device,
        "guard": CIdentifier("REGMAP", device.id, "H"),
        "shared_header": SHARED_HEADER,
        "max_read": CIdentifier(ctx.prefix, "MAX_READ_REGISTERS"),
        "max_write": CIdentifier(ctx.prefix, "MAX_WRITE_REGISTERS"),
        "map_version": ctx.const("MAP_VERSION"),
        "map_fingerprint": ctx.const("MAP_FINGERPRINT"),
        "transport": transport,
        "exception_type": ctx.symbol("exception") if exceptions else "",
        "exceptions": exceptions,
        "build_read": ctx.symbol("build_read"),
        "build_write_single": ctx.symbol("build_write_single"),
        "build_write_multiple": ctx.symbol("build_write_multiple"),
        "enums": enums,
        "groups": groups,
        "commands": commands,
        "faults": faults,
        "plan": _plan_blocks(ctx),
        "plan_len": ctx.const("READ_PLAN_LEN"),
        "plan_table": ctx.symbol("read_plan"),
    }


def _header(device: Device) -> list[str]:
    return header_lines(device, "regmap generate")


def render_device(device: Device) -> Files:
    env = environment()
    return {f"{device.id}.h": env.get_template("c/device.h.jinja").render(**device_context(device))}


def render_shared(devices: Sequence[Device]) -> Files:
    ids: dict[str, str] = {}
    for device in devices:
        if device.id in ids:
            raise UsageError(f"{device.source_path} and {ids[device.id]} both have device id {device.id!r}: their C headers would collide")
        ids[device.id] = device.source_path
    header = [
        "Generated by regmap - do not edit; regenerate with `regmap generate`.",
        "The same file for every map: device headers include it.",
    ]
    return {SHARED_HEADER: environment().get_template("c/regmap_rtu.h.jinja").render(header=header)}


TARGET = Target(name="c", subdir="c", per_device=render_device, shared=render_shared)


# -- the frames test program -----------------------------------------------------------------


@dataclass(frozen=True)
class Check:
    label: str
    got: str  # C expression
    want: str  # C expression


@dataclass(frozen=True)
class ScaledCheck:
    label: str
    raw: str
    scale: str
    value: str


@dataclass(frozen=True)
class FrameCase:
    template: str
    id: str
    comment: str
    frame: str  # C initialiser list of the frame's bytes
    slave: str
    call: str = ""  # request: the C call that builds the frame into `buf`
    words: tuple[str, ...] = ()  # write multiple: statements that fill `w`
    word_count: int = 0
    crc_wrong: bool = False  # the printed frame has a wrong CRC (an erratum without a correction)
    status: str = "REGMAP_OK"
    exception: str = ""
    checks: tuple[Check, ...] = ()
    scaled: tuple[ScaledCheck, ...] = ()


class _FrameError(ValueError):
    pass


class _Frames:
    """Turns the examples of one map into C test cases that use the header's names wherever the map has them."""

    def __init__(self, device: Device) -> None:
        self.device = device
        self.ctx = _Context(device)
        self.requests: dict[str, _Request] = {}

    # expressions -------------------------------------------------------------------------

    def address(self, address: int) -> str:
        """C expression of an address: a register's macro when the map has one, else the number."""
        for reg in self.device.registers:
            if reg.address == address:
                return self.ctx.addr(reg)
        for reg in self.device.registers:
            if reg.paired and reg.first_address == address:
                return self.ctx.pair_addr(reg)
            if reg.address < address <= reg.last_address:
                return f"(uint16_t)({self.ctx.addr(reg)} + {address - reg.address}u)"
        return c_hex(address)  # not a register of the map

    def count(self, address: int, count: int) -> str:
        reg = next((r for r in self.device.registers if r.address == address), None)
        if reg is not None and reg.words == count:
            return self.ctx.member_const(reg, "WORDS")
        return c_unsigned(count)

    def word_of(self, reg: Register, raw: int) -> str:
        """C expression of the word of a one-word register holding `raw`, built with the header's names."""
        if reg.bitfields:
            owner = self.ctx.owner(reg)
            expr = "0u"
            covered = 0
            for b in reg.bitfields:
                field = (raw & b.mask) >> b.lsb
                member = b.enum.by_value(field) if b.enum else None
                value = CIdentifier(self.ctx.prefix, b.enum.name, member.name) if b.enum and member else c_unsigned(field)
                expr = f"{CSymbol(self.ctx.lower, owner, 'set', b.name)}({expr}, {value})"
                covered |= b.mask
            rest = raw & 0xFFFF & ~covered
            return f"(uint16_t)({expr} | {c_hex(rest)})" if rest else expr
        if reg.enum is not None:
            member = reg.enum.by_value(raw)
            if member is not None:
                name = CIdentifier(self.ctx.prefix, reg.enum.name, member.name)
                return f"regmap_s16_to_word({name})" if reg.signed else name
        if reg.signed:
            return f"regmap_s16_to_word({c_signed(raw)})"
        return c_unsigned(raw)

    def command_call(self, reg: Register, raw: int, slave: str) -> str | None:
        """The header's command helper that writes `raw` to `reg`, when the map names one."""
        mine = [c for c in self.device.commands if c.register.name == reg.name]
        for c in mine:
            if c.argument is None and c.value == raw:
                return f"{CSymbol(self.ctx.lower, 'build', c.name)}(buf, sizeof buf, {slave})"
        for c in mine:
            if c.argument is not None and c.argument.min <= raw - c.value <= c.argument.max:
                return f"{CSymbol(self.ctx.lower, 'build', c.name)}(buf, sizeof buf, {slave}, {raw - c.value})"
        return None

    # cases ------------------------------------------------------------------------------

    def cases(self) -> list[FrameCase]:
        out = []
        for ex in self.device.examples:
            try:
                out.append(self.request(ex) if ex.direction == "request" else self.response(ex))
            except _FrameError as exc:
                raise UsageError(f"{self.device.source_path}: example {ex.id}: {exc}") from None
        return out

    def _base(self, ex: Example, template: str) -> dict[str, Any]:
        frame = ex.wire_frame
        return {
            "template": template,
            "id": ex.id,
            "comment": f"{ex.id} ({', '.join(ex.source)}): {ex.meaning}",
            "frame": ", ".join(f"0x{b:02X}" for b in frame),
            "slave": f"0x{frame[0]:02X}u",
            "crc_wrong": not crc_ok(frame),
        }

    def check_values_inside(self, ex: Example, start: int, count: int) -> None:
        """Every value an example gives must be carried by its frame (else the example contradicts itself)."""
        for v in ex.values:
            reg = v.register
            if (v.raw is not None or v.words is not None) and not (reg.first_address < start + count and start <= reg.last_address):
                raise _FrameError(
                    f"it gives a value for {reg.label} (0x{reg.address:04X}), which its frame"
                    f" (0x{start:04X}..0x{start + count - 1:04X}) does not carry"
                )

    def request(self, ex: Example) -> FrameCase:
        frame = ex.wire_frame
        parsed = parse_frame(frame, "request")
        if parsed.address is not None and parsed.kind != "unknown":
            self.check_values_inside(ex, parsed.address, parsed.count or 1)
        base = self._base(ex, "c/case_request.c.jinja")
        slave = base["slave"]
        if parsed.kind == "read_request" and parsed.address is not None and parsed.count is not None:
            self.requests[ex.id] = _Request(READ_HOLDING, parsed.address, parsed.count, ex)
            build = self.ctx.symbol_ref("build_read")
            call = f"{build}(buf, sizeof buf, {slave}, {self.address(parsed.address)}, {self.count(parsed.address, parsed.count)})"
            return FrameCase(**base, call=call)
        if parsed.kind == "write_single" and parsed.address is not None:
            self.requests[ex.id] = _Request(WRITE_SINGLE, parsed.address, 1, ex, parsed.words[0])
            call = self.single_write_command(ex, parsed.address, slave) or (
                f"{self.ctx.symbol_ref('build_write_single')}(buf, sizeof buf, {slave}, {self.address(parsed.address)},"
                f" {self.single_word(ex, parsed.address, parsed.words[0])})"
            )
            return FrameCase(**base, call=call)
        if parsed.kind == "write_multiple_request" and parsed.address is not None and parsed.count is not None:
            self.requests[ex.id] = _Request(WRITE_MULTIPLE, parsed.address, parsed.count, ex)
            build = self.ctx.symbol_ref("build_write_multiple")
            call = f"{build}(buf, sizeof buf, {slave}, {self.address(parsed.address)}, w, {c_unsigned(parsed.count)})"
            base["template"] = "c/case_request_multiple.c.jinja"
            words = self.multiple_words(ex, parsed.address, parsed.words)
            return FrameCase(**base, call=call, words=words, word_count=len(parsed.words))
        body = frame[2:-2]
        if len(body) == 4:
            # Another function code (the manual's example of an unsupported one): the generic builder.
            first, second = int.from_bytes(body[:2], "big"), int.from_bytes(body[2:], "big")
            self.requests[ex.id] = _Request(frame[1], first, second, ex)
            call = f"regmap_rtu_build_request(buf, sizeof buf, {slave}, 0x{frame[1]:02X}u, {c_hex(first)}, {c_hex(second)})"
            return FrameCase(**base, call=call)
        raise _FrameError(f"cannot rebuild a {parsed.kind} request of {len(frame)} bytes")

    def single_write_command(self, ex: Example, address: int, slave: str) -> str | None:
        for v in ex.values:
            if v.raw is not None and v.register.words == 1 and v.register.address == address:
                return self.command_call(v.register, v.raw, slave)
        return None

    def single_word(self, ex: Example, address: int, word: int) -> str:
        """The word of a 0x06 frame, from the example's values when they describe it."""
        for v in ex.values:
            reg = v.register
            if v.raw is not None and reg.words == 1 and reg.address == address:
                return self.word_of(reg, v.raw)
            if v.words is not None and reg.words == 2 and reg.address <= address <= reg.last_address:
                if len(v.words) != 1:
                    raise _FrameError(f"a 0x06 frame carries one word of {reg.name}, the example gives {len(v.words)}")
                return c_hex(v.words[0])  # one word of a 32-bit register, as the example gives it
        return c_hex(word)

    def multiple_words(self, ex: Example, start: int, frame_words: tuple[int, ...]) -> tuple[str, ...]:
        """Statements that fill `w` (the words of a 0x10 frame) from the example's values through the header's helpers."""
        count = len(frame_words)
        base = self.address(start)
        filled: set[int] = set()
        statements = []
        for v in ex.values:
            reg = v.register
            inside = [a for a in range(reg.first_address, reg.last_address + 1) if start <= a < start + count]
            if not inside or (v.raw is None and v.words is None):
                continue
            index = f"(unsigned)({self.ctx.addr(reg)} - {base})"
            if v.words is not None:
                own = [a for a in inside if a >= reg.address]
                if len(v.words) != len(own):
                    raise _FrameError(f"the frame carries {len(own)} words of {reg.name}, the example gives {len(v.words)}")
                for a, given in zip(own, v.words, strict=True):
                    statements.append(f"put(w, {count}u, {index} + {a - reg.address}u, {c_hex(given)});")
                    filled.add(a)
                continue
            raw = v.raw
            assert raw is not None
            if len(inside) != reg.span:
                raise _FrameError(f"the frame carries only part of {reg.name}, the example gives its whole raw value")
            if reg.words == 1:
                word = self.word_of(reg, raw)
                statements.append(f"put(w, {count}u, {index}, {word});")
                if reg.paired:
                    high = f"(unsigned)({self.ctx.pair_addr(reg)} - {base})"
                    signed = self.ctx.member_const(reg, "SIGNED")
                    statements.append(f"put(w, {count}u, {high}, regmap_pair_high_word({word}, {signed}));")
            else:
                func = "regmap_s32_to_words" if reg.signed else "regmap_u32_to_words"
                order = self.ctx.member_const(reg, "WORD_ORDER")
                statements.append(f"{func}({c_raw(raw, reg.signed)}, {order}, at(w, {count}u, {index}, 2u));")
            filled.update(inside)
        for offset, literal in enumerate(frame_words):
            if start + offset not in filled:
                statements.append(f"put(w, {count}u, {offset}u, {c_hex(literal)}); /* no value in the example */")
        return tuple(statements)

    def response(self, ex: Example) -> FrameCase:
        frame = ex.wire_frame
        base = self._base(ex, "c/case_response.c.jinja")
        slave = base["slave"]
        request = self.requests.get(ex.request) if ex.request else None
        if request is None:
            request = _request_from_response(frame)
        status, exception = "REGMAP_OK", ""
        if base["crc_wrong"]:
            status = "REGMAP_ERR_CRC"
        elif frame[1] & EXCEPTION_FLAG:
            status = "REGMAP_ERR_EXCEPTION"
            exception = self.exception_name(frame[2])
        if request.function in (READ_HOLDING, WRITE_SINGLE, WRITE_MULTIPLE) and request.example is not None:
            self.check_values_inside(ex, request.address, request.count)
        checks: list[Check] = []
        scaled: list[ScaledCheck] = []
        address = self.address(request.address)
        if request.function == READ_HOLDING:
            count = self.count(request.address, request.count)
            call = (
                f"regmap_rtu_parse_read_response(frame, sizeof frame, {slave}, {count}, words, sizeof words / sizeof words[0], &exception)"
            )
            if status == "REGMAP_OK" and request.example is not None:
                checks, scaled = self.read_checks(ex, request.address, request.count)
        elif request.function == WRITE_SINGLE:
            # The echo carries the request's word; the response's own values, when it has them, must give it too.
            described = ex if any(v.raw is not None or v.words is not None for v in ex.values) else request.example
            word = self.single_word(described, request.address, request.value) if described else c_hex(request.value)
            call = f"regmap_rtu_parse_write_single_response(frame, sizeof frame, {slave}, {address}, {word}, &exception)"
        elif request.function == WRITE_MULTIPLE:
            count = c_unsigned(request.count)
            call = f"regmap_rtu_parse_write_multiple_response(frame, sizeof frame, {slave}, {address}, {count}, &exception)"
        else:
            call = f"regmap_rtu_check_response(frame, sizeof frame, {slave}, 0x{request.function:02X}u, &exception)"
        return FrameCase(**base, call=call, status=status, exception=exception, checks=tuple(checks), scaled=tuple(scaled))

    def exception_name(self, code: int) -> str:
        e = self.device.transport.exception(code)
        if e is not None:
            return CIdentifier(self.ctx.prefix, "EXCEPTION", e.name)
        return STANDARD_EXCEPTION_MACROS.get(code, f"0x{code:02X}u")

    def read_checks(self, ex: Example, start: int, count: int) -> tuple[list[Check], list[ScaledCheck]]:
        """Checks that the words a read response carries give each value the example records."""
        checks: list[Check] = []
        scaled: list[ScaledCheck] = []
        base = self.address(start)
        for v in ex.values:
            reg = v.register
            own = [a for a in range(reg.address, reg.last_address + 1) if start <= a < start + count]
            if not own or (v.raw is None and v.words is None):
                continue
            index = f"(unsigned)({self.ctx.addr(reg)} - {base})"
            if v.words is not None:
                if len(v.words) != len(own):
                    raise _FrameError(f"the response carries {len(own)} words of {reg.name}, the example gives {len(v.words)}")
                for a, given in zip(own, v.words, strict=True):
                    checks.append(
                        Check(f"{reg.name} word {a - reg.address}", f"word_at(words, {count}u, {index} + {a - reg.address}u)", c_hex(given))
                    )
                continue
            raw = v.raw
            assert raw is not None
            if len(own) != reg.words:
                raise _FrameError(f"the response carries only part of {reg.name}, the example gives its whole raw value")
            word = f"word_at(words, {count}u, {index})"
            if reg.words == 1:
                raw_expr = f"regmap_s16_from_word({word})" if reg.signed else word
            else:
                func = "regmap_s32_from_words" if reg.signed else "regmap_u32_from_words"
                raw_expr = f"{func}(at(words, {count}u, {index}, 2u), {self.ctx.member_const(reg, 'WORD_ORDER')})"
            checks.append(Check(reg.name, raw_expr, c_raw(raw, reg.signed)))
            if reg.paired and reg.first_address >= start:
                high = f"word_at(words, {count}u, (unsigned)({self.ctx.pair_addr(reg)} - {base}))"
                signed = self.ctx.member_const(reg, "SIGNED")
                checks.append(Check(f"{reg.name} high word", high, f"regmap_pair_high_word({word}, {signed})"))
            if reg.bitfields and reg.words == 1:
                owner = self.ctx.owner(reg)
                for b in reg.bitfields:
                    getter = CSymbol(self.ctx.lower, owner, "get", b.name)
                    checks.append(Check(f"{reg.name}.{b.name}", f"{getter}({word})", c_unsigned((raw & b.mask) >> b.lsb)))
            elif reg.enum is not None and isinstance(v.value, str) and reg.enum.member(v.value) is not None:
                checks.append(Check(f"{reg.name} = {v.value}", raw_expr, CIdentifier(self.ctx.prefix, reg.enum.name, v.value)))
            elif isinstance(v.value, int | float) and not isinstance(v.value, bool) and reg.enum is None:
                scaled.append(ScaledCheck(reg.name, raw_expr, self.ctx.member_const(reg, "SCALE"), repr(float(v.value))))
        return checks, scaled


@dataclass(frozen=True)
class _Request:
    """What a response is checked against: the request it answers."""

    function: int
    address: int
    count: int
    example: Example | None = None
    value: int = 0  # the word of a write single


def _request_from_response(frame: bytes) -> _Request:
    """For a response that names no request: what the frame itself says it answers."""
    function = frame[1] & ~EXCEPTION_FLAG & 0xFF
    if function == READ_HOLDING and not frame[1] & EXCEPTION_FLAG:
        return _Request(function, 0, max(1, frame[2] // 2))
    if len(frame) == 8:
        field = int.from_bytes(frame[4:6], "big")
        return _Request(function, int.from_bytes(frame[2:4], "big"), field, value=field)
    return _Request(function, 0, 1)


STANDARD_EXCEPTION_MACROS = {
    0x01: "REGMAP_EXC_ILLEGAL_FUNCTION",
    0x02: "REGMAP_EXC_ILLEGAL_DATA_ADDRESS",
    0x03: "REGMAP_EXC_ILLEGAL_DATA_VALUE",
    0x04: "REGMAP_EXC_SERVER_DEVICE_FAILURE",
    0x05: "REGMAP_EXC_ACKNOWLEDGE",
    0x06: "REGMAP_EXC_SERVER_DEVICE_BUSY",
    0x08: "REGMAP_EXC_MEMORY_PARITY_ERROR",
    0x0A: "REGMAP_EXC_GATEWAY_PATH_UNAVAILABLE",
    0x0B: "REGMAP_EXC_GATEWAY_TARGET_FAILED",
}


def frames_test_context(device: Device) -> dict[str, Any]:
    return {"header": _header(device), "device": device, "include": f"{device.id}.h", "cases": _Frames(device).cases()}


def render_frames_test(device: Device) -> str:
    """A host C program (it uses stdio) that checks the header against every frame of the map's examples."""
    return environment().get_template("c/frames_test.c.jinja").render(**frames_test_context(device))
