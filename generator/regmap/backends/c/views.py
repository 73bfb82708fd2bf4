"""The views of one C header's items: registers, arrays, groups, enums and commands. Every identifier,
literal and expression is computed here; the templates only print, escaping map text with `c_comment`."""

from __future__ import annotations

from collections.abc import Sequence
from fractions import Fraction

from regmap.backends.c.names import (
    ACCESS_MACRO,
    C_TYPES,
    FLOAT_GUARD,
    FUNCTION_MACROS,
    PADDING_MACRO,
    PLAIN_TYPES,
    POLL_MACRO,
    SPACE_MACRO,
    TYPE_MACRO,
    WIRE_FUNCTIONS,
    WORD_ORDER_MACRO,
    CIdentifier,
    Context,
    CSymbol,
    Define,
    Macro,
    c_double,
    c_float,
    c_hex,
    c_raw,
    c_signed,
    c_unsigned,
    c_value,
    comment_text,
    define_lines,
    sentence_comment,
)
from regmap.backends.c.values import EnumCheckView, enum_checks, member_values, ratio_literal, register_values, values_text
from regmap.backends.c.variants import VariantView, variant_view, variants_macro
from regmap.core.text import eng, manual_sections, number, sentences, titled, zone_text
from regmap.diagnostics import UsageError, at
from regmap.model import ArrayDef, Bitfield, ByteOrder, Command, EnumType, PollClass, Register
from regmap.records import NamedTuple
from regmap.render import c_str
from regmap_runtime.spaces import DEFAULT_SPACE
from regmap_runtime.spec import parse_version


class EnumView(NamedTuple):
    type_name: str
    comment: str  # escaped for a C comment (sentence_comment)
    lines: str  # the members, one a line: `#define`s (as_macros) or the enum's constants
    as_macros: bool  # a value does not fit an int, which a C enum constant must
    checks: EnumCheckView


class BitfieldView(NamedTuple):
    comment: str  # escaped for a C comment (sentence_comment)
    mask: Macro
    shift: Macro
    word_type: str
    getter: str
    setter: str
    value_type: str  # the field's enum type, or the word type
    refused: str  # C condition on `value` under which the setter refuses it


class CodecView(NamedTuple):
    """A register's own value helpers: its words on the wire <-> its raw value, in its word and byte order."""

    template: str  # codec_word.h.jinja (one word), codec_words.h.jinja (wide), codec_string.h.jinja
    value_type: str
    from_wire: str
    to_wire: str
    shared_from: str
    shared_to: str
    words: str  # the WORDS macro
    word_order: str  # the WORD_ORDER macro ("" for one word and for strings)
    byte_order: str  # the BYTE_ORDER macro
    padding: str  # strings: the PADDING macro
    guard: str  # "" or the shared header's macro that says the C type is IEEE 754 (REGMAP_HAS_F32/F64)


class GateView(NamedTuple):
    """Whether a firmware version has the register (its `firmware` gate)."""

    function: str
    text: str
    condition: str  # C expression on `version`; "" when every version has it


class RegisterView(NamedTuple):
    template: str  # "": device.h.jinja prints a register itself (an ArrayView names its template)
    comment: str  # escaped for a C comment (sentence_comment)
    description: str  # escaped for a C comment (comment_text)
    defines: str  # the #define lines of its macros
    bitfields: tuple[BitfieldView, ...]
    codec: CodecView | None = None
    gate: GateView | None = None
    variant: VariantView | None = None
    values: str = ""  # the value helpers' C (values_text), printed as it is


class ElementTable(NamedTuple):
    """Per-element values of an array member whose elements differ (e.g. a default per path)."""

    c_type: str
    name: str
    values: tuple[str, ...]
    length: str  # the array's COUNT macro


class ArrayMemberView(NamedTuple):
    comment: str  # escaped for a C comment (sentence_comment)
    description: str  # escaped for a C comment (comment_text)
    addr_macro: str
    offset: str
    pair_addr_macro: str | None
    addr_function: str
    defines: str  # the #define lines of its macros
    tables: tuple[ElementTable, ...]
    bitfields: tuple[BitfieldView, ...]
    codec: CodecView | None = None
    gate: GateView | None = None
    variant: VariantView | None = None
    values: str = ""  # the value helpers' C (values_text), printed as it is


class ArrayView(NamedTuple):
    template: str
    comment: str
    base: str  # names of the BASE, FIRST, COUNT and STRIDE macros
    first: str
    count_name: str  # (a NamedTuple cannot have a field `count`)
    stride: str
    defines: str  # the #define lines of its macros
    check: str  # C condition: index n in range
    members: tuple[ArrayMemberView, ...]


class GroupView(NamedTuple):
    comment: str
    items: tuple[RegisterView | ArrayView, ...]


class CommandView(NamedTuple):
    comment: str
    addr: Macro
    value: Macro
    function: str
    argument: str  # "" when the command takes none
    argument_type: str
    argument_macros: tuple[Macro, ...]
    out_of_range: str  # C condition on the argument
    raw: str  # C expression of the raw value to write
    wide: bool  # more than one word: written with write multiple in `word_order`
    word_order: str
    confirm: str = ""  # a destructive command's name, which its helper's `confirm` must repeat ("" otherwise)


def _enum_literal(value: int) -> str:
    return f"0x{value:02X}" if value >= 0x10 else c_signed(value)


def _register_facts(reg: Register, elements: Sequence[Register]) -> str:
    """Type, access, unit, scale, range, default and errata of a register (or of every element of an array member)."""
    facts = [f"{reg.type._value_} {reg.access._value_}"]  # _value_: the member's value, without Enum.value's Python descriptor
    if reg.zone is not None:
        facts.append(f"raw uint32_t {zone_text(reg)}, never converted to another zone")
    if reg.space != DEFAULT_SPACE:
        facts.append(reg.space_info.title)
    if reg.type.is_string:
        padding = "space" if reg.padding == "space" else "NUL"
        facts.append(f"{reg.words} words of {reg.encoding} text, {padding} padded")
    if reg.unit:
        facts.append(f"unit {reg.unit}")
    if reg.scaled:
        facts.append(f"scale {number(reg.scale)}")
    if reg.offset_set:
        facts.append(f"offset {number(reg.offset)}")
    converted = reg.scaled or reg.offset_set or reg.zone is not None
    if reg.min is not None or reg.max is not None:
        scaled = f" ({eng(reg, reg.raw_min)}..{eng(reg, reg.raw_max)}{f' {reg.unit}' if reg.unit else ''})" if converted else ""
        facts.append(f"raw {reg.raw_min}..{reg.raw_max}{scaled}")
    if reg.range_text:
        facts.append(f"printed range {reg.range_text}")
    # A lone register is its own elements[0]: only an array member's elements can differ.
    if len(elements) > 1 and len({r.default for r in elements}) > 1:
        facts.append("default differs per element")
    elif reg.default is not None and (reg.type.is_string or reg.type.is_bool):
        facts.append(f"default {eng(reg, reg.default)}")
    elif reg.default is not None:
        facts.append(f"default {reg.default}" + (f" ({eng(reg, reg.default)})" if converted else ""))
    if reg.enum is not None:
        facts.append(f"values: enum {reg.enum.name}")
    if reg.paired:
        facts.append("low word of a 32-bit pair whose unused high word is at ADDR - 1")
    if reg.takes_effect:
        facts.append(f"takes effect {reg.takes_effect.replace('_', ' ')}")
    errata = reg.errata if len(elements) == 1 else [e for r in elements for e in r.errata]
    if errata:
        facts.append(f"errata {', '.join(sorted(set(errata)))}")
    if reg.type.info.has_byte_order and reg.byte_order is not ByteOrder.HIGH_FIRST:
        facts.append("bytes of each word low first")
    if reg.firmware is not None:
        facts.append(reg.firmware.text)
    if reg.variants:
        facts.append(f"only on variant{'s' if len(reg.variants) > 1 else ''} {', '.join(reg.variants)}")
    if reg.poll is not PollClass.NORMAL:
        facts.append(f"poll {reg.poll._value_}")
    return ", ".join(facts)


def _register_comment(reg: Register, label: str, elements: Sequence[Register]) -> str:
    """The register's comment, escaped for a C comment."""
    return sentence_comment(
        sentences(f"{label}: {titled(reg.title, reg.title_zh)}", _register_facts(reg, elements), manual_sections(reg.source))
    )


def modern(reg: Register) -> bool:
    """Whether a register uses anything the first maps' 16/32-bit holding registers did not (another
    space or type, swapped bytes, an offset, a firmware gate, a poll class): such a register gets the
    macros and helpers of those features; the others keep exactly the header they always had."""
    return (
        reg.type not in PLAIN_TYPES
        or reg.space != DEFAULT_SPACE
        or reg.byte_order is not ByteOrder.HIGH_FIRST
        or reg.offset_set
        or reg.firmware is not None
        or reg.poll is not PollClass.NORMAL
    )


def _literal(reg: Register, value: int | float | str) -> str:
    return c_str(value) if isinstance(value, str) else c_value(value, reg)


def _value_macros(
    ctx: Context, reg: Register, owner: str, elements: Sequence[Register], is_modern: bool
) -> tuple[list[Define], list[ElementTable]]:
    """The macros every register (or array member) gets. An array member whose elements differ in
    min, max or default gets a table indexed by n - FIRST instead of the macro."""
    numeric = reg.type.numeric
    stem = ctx.stem(owner)
    macros = [
        (ctx.owned(stem, owner, "BITS" if reg.space_info.bits else "WORDS"), c_unsigned(reg.words)),
        (ctx.owned(stem, owner, "ACCESS"), ACCESS_MACRO[reg.access._value_]),
    ]
    if numeric:
        macros.append((ctx.owned(stem, owner, "SIGNED"), "1" if reg.signed else "0"))
    tables = []
    if reg.wide:
        macros.append((ctx.owned(stem, owner, "WORD_ORDER"), WORD_ORDER_MACRO[reg.word_order._value_]))
    member = len(elements) > 1  # an array member, whose elements may differ (a lone register is its own elements[0])
    for key, value in (("min", reg.min), ("max", reg.max), ("default", reg.default)):
        if member:
            values = [getattr(r, key) for r in elements]
            if len(set(values)) > 1:
                if None not in values:
                    c_type = "char *const" if reg.type.is_string else C_TYPES[reg.type].value
                    count = CIdentifier(ctx.prefix, ctx.arrays[reg.array.array].name, "COUNT") if reg.array else c_unsigned(len(values))
                    tables.append(ElementTable(c_type, ctx.symbol(owner, key), tuple(_literal(reg, v) for v in values), count))
                continue
        if value is not None:
            macros.append((ctx.owned(stem, owner, key), _literal(reg, value)))
    if numeric and reg.scale_from is None:  # a scale_from register's scale is read at run time: no constant to mistake for it
        scale, num, den = _ratio_literals(ctx, reg, reg.scale)
        macros += [
            (ctx.owned(stem, owner, "SCALE"), scale),
            (ctx.owned(stem, owner, "SCALE_NUM"), num),
            (ctx.owned(stem, owner, "SCALE_DEN"), den),
        ]
    if numeric:
        macros.append((ctx.owned(stem, owner, "PAIRED"), "1" if reg.paired else "0"))
    if is_modern:
        macros += _feature_macros(ctx, reg, owner)
    macros += variants_macro(ctx, reg, owner)
    return macros, tables


def _ratio_literals(ctx: Context, reg: Register, ratio: Fraction) -> tuple[str, ...]:
    """A scale's or offset's value, numerator and denominator as the register's macros spell them; once per device
    for each ratio, type and signedness (most registers share a handful of scales)."""
    key = (ratio.numerator, ratio.denominator, reg.type.is_float, reg.signed)
    spelled = ctx.literals.get(key)
    if spelled is None:
        # A float register's scale and offset are doubles (its value is computed in floating point anyway).
        spell = c_double if reg.type.is_float else c_float
        spelled = ctx.literals[key] = (
            spell(ratio),
            ratio_literal(reg, ratio.numerator, ratio),
            ratio_literal(reg, ratio.denominator, ratio),
        )
    return spelled


def _feature_macros(ctx: Context, reg: Register, owner: str) -> list[Define]:
    """The macros of the features beyond the first maps' (space, type, byte order, offset, text, poll class, firmware gate)."""
    space = reg.space_info
    macros = [
        (ctx.const(owner, "SPACE"), SPACE_MACRO[space.name]),
        (ctx.const(owner, "READ_FUNCTION"), FUNCTION_MACROS[space.name]["read"]),
        (ctx.const(owner, "TYPE"), TYPE_MACRO[reg.type._value_]),
    ]
    if reg.type.info.has_byte_order:
        macros.append((ctx.const(owner, "BYTE_ORDER"), WORD_ORDER_MACRO[reg.byte_order._value_]))
    if reg.type.numeric:
        offset, num, den = _ratio_literals(ctx, reg, reg.offset)
        macros += [
            (ctx.const(owner, "OFFSET"), offset),
            (ctx.const(owner, "OFFSET_NUM"), num),
            (ctx.const(owner, "OFFSET_DEN"), den),
        ]
    if reg.type.is_string:
        macros += [
            (ctx.const(owner, "ENCODING"), c_str(reg.encoding)),
            (ctx.const(owner, "PADDING"), PADDING_MACRO[reg.padding]),
            (ctx.const(owner, "TEXT_SIZE"), c_unsigned(2 * reg.words + 1)),
        ]
    macros.append((ctx.const(owner, "POLL"), POLL_MACRO[reg.poll._value_]))
    gate = reg.firmware
    if gate is not None:
        for key, version in (("FROM", gate.first), ("UNTIL", gate.until)):
            if version is not None:
                try:
                    spelled = c_version(version)
                except ValueError as exc:
                    raise UsageError(str(at(ctx.device.source_path, reg.pos, f"{reg.name}: {exc}"))) from None
                macros += [
                    (ctx.const(owner, "FIRMWARE", key), spelled),
                    (ctx.const(owner, "FIRMWARE", key, "TEXT"), c_str(version)),
                ]
    return macros


def c_version(text: str) -> str:
    """A firmware version as the shared header's REGMAP_VERSION(major, minor); ValueError for one C cannot compare."""
    parts = parse_version(text)
    if len(parts) > 2 or any(p > 0xFFFF for p in parts):
        raise ValueError(f"firmware version {text} is not major.minor with parts up to 65535, which the C header compares")
    major, minor = (*parts, 0)[:2]
    return f"REGMAP_VERSION({major}u, {minor}u)"


def _codec_view(ctx: Context, reg: Register, owner: str, is_modern: bool) -> CodecView | None:
    """The value helpers of a modern register (a coil or discrete input needs none: its bit is its value)."""
    if not is_modern or reg.type.is_bool:
        return None
    shared_from, shared_to = WIRE_FUNCTIONS[reg.type._value_]
    if reg.type.is_string:
        template, value_type = "codec_string.h.jinja", "char"
    elif reg.words == 1:
        template, value_type = "codec_word.h.jinja", C_TYPES[reg.type].value
    else:
        template, value_type = "codec_words.h.jinja", C_TYPES[reg.type].value
    return CodecView(
        template=template,
        value_type=value_type,
        from_wire=ctx.symbol(owner, "from_wire"),
        to_wire=ctx.symbol(owner, "to_wire"),
        shared_from=shared_from,
        shared_to=shared_to,
        words=ctx.member_const(reg, "WORDS"),
        word_order=ctx.member_const(reg, "WORD_ORDER") if reg.wide else "",
        byte_order=ctx.member_const(reg, "BYTE_ORDER"),
        padding=ctx.member_const(reg, "PADDING") if reg.type.is_string else "",
        guard=FLOAT_GUARD.get(reg.type._value_, ""),
    )


def _gate_view(ctx: Context, reg: Register, owner: str) -> GateView | None:
    gate = reg.firmware
    if gate is None:
        return None
    conditions = []
    if gate.first is not None and any(parse_version(gate.first)):  # `version >= 0` is always true (and -Wtype-limits says so)
        conditions.append(f"version >= {ctx.member_const(reg, 'FIRMWARE_FROM')}")
    if gate.until is not None:
        conditions.append(f"version < {ctx.member_const(reg, 'FIRMWARE_UNTIL')}")
    return GateView(function=ctx.symbol(owner, "in_firmware"), text=gate.text, condition=" && ".join(conditions))


def _bitfield_views(ctx: Context, reg: Register, owner: str) -> tuple[BitfieldView, ...]:
    if not reg.bitfields:  # most registers
        return ()
    word_type = C_TYPES[reg.type].bits
    word_bits = 16 * reg.words
    views = []
    for b in reg.bitfields:
        typed = b.enum is not None and all(-(1 << 31) <= m.value < (1 << 31) for m in b.enum.members)
        value_type = ctx.symbol_ref(b.enum.name) if b.enum is not None and typed else word_type
        refused = []
        # An enum field refuses what its enum lacks, which covers a value wider than the field (the front end
        # checks every member fits); another refuses a value wider than the field where its type can hold one.
        if b.enum is None and b.width < word_bits:
            refused.append(f"value > {c_hex(b.max_value)}")
        if b.enum is not None:
            refused.append(f"!{ctx.symbol_ref(b.enum.name, 'is_member')}(value)")
        views.append(
            BitfieldView(
                comment=_bitfield_comment(b),
                mask=Macro(ctx.const(owner, b.name, "MASK"), c_hex(b.mask)),
                shift=Macro(ctx.const(owner, b.name, "SHIFT"), c_unsigned(b.lsb)),
                word_type=word_type,
                getter=ctx.symbol(owner, "get", b.name),
                setter=ctx.symbol(owner, "set", b.name),
                value_type=value_type,
                refused=" || ".join(refused),
            )
        )
    return tuple(views)


def _bitfield_comment(b: Bitfield) -> str:
    """The field's comment, escaped for a C comment."""
    head = f"bit{'s' if b.width > 1 else ''} {b.bits_text} {b.name}: {titled(b.title, b.title_zh)}"
    return sentence_comment(sentences(head, f"Values: enum {b.enum.name}" if b.enum else None, b.description))


def _register_view(ctx: Context, reg: Register) -> RegisterView:
    is_modern = modern(reg)
    values, _ = _value_macros(ctx, reg, reg.name, (reg,), is_modern)
    macros = [(ctx.const(reg.name, "ADDR", what=f"the address of register {reg.name}"), c_hex(reg.address)), *values]
    if reg.paired:
        macros.append((ctx.const(reg.name, "PAIR_ADDR"), c_hex(reg.first_address)))
    return RegisterView(
        template="",
        comment=_register_comment(reg, reg.label, (reg,)),
        description=comment_text(reg.description),
        defines=define_lines(macros),
        bitfields=_bitfield_views(ctx, reg, reg.name),
        codec=_codec_view(ctx, reg, reg.name, is_modern),
        gate=_gate_view(ctx, reg, reg.name),
        variant=variant_view(ctx, reg, reg.name),
        values=values_text(register_values(ctx, reg)),
    )


def _array_view(ctx: Context, array: ArrayDef) -> ArrayView:
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
        is_modern = modern(reg)
        values, tables = _value_macros(ctx, reg, owner, elements, is_modern)
        members.append(
            ArrayMemberView(
                comment=_register_comment(reg, f"{owner} (element {array.first_index}: {reg.label})", elements),
                description=comment_text(reg.description),
                addr_macro=ctx.const(owner, "ADDR", what=f"the address of member {member.name} of array {array.name}"),
                offset=c_unsigned(member.offset),
                pair_addr_macro=ctx.const(owner, "PAIR_ADDR") if reg.paired else None,
                addr_function=ctx.symbol(owner, "addr"),
                defines=define_lines(values),
                tables=tuple(tables),
                bitfields=_bitfield_views(ctx, reg, owner),
                codec=_codec_view(ctx, reg, owner, is_modern),
                gate=_gate_view(ctx, reg, owner),
                variant=variant_view(ctx, reg, owner),
                values=values_text(member_values(ctx, elements, owner)),
            )
        )
    comment = sentences(
        titled(array.title, array.title_zh)
        + f": {array.count} elements {array.first_index}..{array.last_index}; member m of element n is at"
        + f" BASE 0x{array.base:04X} + {array.stride} x (n - {array.first_index}) + offset of m",
        array.description,
        manual_sections(array.source),
    )
    return ArrayView(
        template="array.h.jinja",
        comment=comment,
        base=base.name,
        first=first.name,
        count_name=count.name,
        stride=stride.name,
        defines=define_lines(macros),
        check=check,
        members=tuple(members),
    )


def group_views(ctx: Context) -> list[GroupView]:
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
        groups.append(GroupView(comment=sentences(titled(group.title, group.title_zh), manual_sections(group.source)), items=tuple(items)))
    return groups


def enum_view(ctx: Context, e: EnumType) -> EnumView:
    # A C enum constant is an int; a table with a value outside int becomes macros instead.
    as_macros = any(not -(1 << 31) <= m.value < (1 << 31) for m in e.members)
    names = []
    lines = []
    last = len(e.members) - 1
    for i, m in enumerate(e.members):
        name = ctx.const(e.name, m.name, what=f"member {m.name} of enum {e.name}")
        comment = sentence_comment(sentences(titled(m.title, m.title_zh) + (f" [{m.symbol}]" if m.symbol else ""), m.description))
        if as_macros:
            lines.append(f"#define {name:<48} {c_raw(m.value, m.value < 0)} /* {comment} */")
        else:
            lines.append(f"    {name} = {_enum_literal(m.value)}{',' if i < last else ''} /* {comment} */")
        names.append(name)
    comment = sentence_comment(sentences(titled(e.title, e.title_zh), e.description, manual_sections(e.source)))
    return EnumView(
        type_name=ctx.symbol(e.name, what=f"the type of enum {e.name}"),
        comment=comment,
        lines="\n".join(lines),
        as_macros=as_macros,
        checks=enum_checks(ctx, e, names),
    )


def command_view(ctx: Context, cmd: Command) -> CommandView:
    reg = cmd.register
    what = f"writes 0x{cmd.value:04X}" + (f" + {cmd.argument.name}" if cmd.argument else "") + f" to {reg.label} (0x{reg.address:04X})"
    destructive = (
        f'Destructive (it loses data or state): builds nothing (returns 0) unless confirm is the string "{cmd.name}".'
        if cmd.destructive
        else ""
    )
    comment = sentences(f"{titled(cmd.title, cmd.title_zh)}: {what}", cmd.description, manual_sections(cmd.source), destructive)
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
        wide=reg.wide,
        word_order=ctx.member_const(reg, "WORD_ORDER") if reg.wide else "",
        confirm=cmd.name if cmd.destructive else "",
    )
