"""Views of registers, arrays, groups, enums and bitfields."""

from __future__ import annotations

from collections.abc import Sequence

from regmap.backends.markdown import text as md
from regmap.backends.markdown.diagrams import diagram_path
from regmap.backends.markdown.text import DocId, Md, md_text
from regmap.backends.markdown.views import (
    ArrayView,
    BitfieldView,
    BitRow,
    Context,
    EnumRow,
    EnumView,
    FactPair,
    GroupView,
    MemberRow,
    QuickRow,
    RegisterView,
    ValueCells,
)
from regmap.backends.markdown.wire import (
    POLL_MEANING,
    Uses,
    gate_fact,
    gate_text,
    has_conversion,
    order_fact,
    order_suffix,
    scale_fact,
    shared,
    space_cell,
    space_fact,
    type_fact,
)
from regmap.core.text import eng, na_list, number, variants_text
from regmap.model import Access, ArrayDef, Bitfield, DataType, EnumType, FirmwareGate, Group, PollClass, Register
from regmap.render import hex2
from regmap_runtime.spaces import DEFAULT_SPACE, SPACES

# By the access's value string (`reg.access._value_`), as the map writes it.
ACCESS_SHORT = {"r": "R", "rw": "R/W", "w": "W"}
ACCESS_LONG = {"r": "read only", "rw": "read/write", "w": "write only"}
NEW_WIDE = (DataType.U64, DataType.S64, DataType.F16, DataType.F32, DataType.F64)  # their details state the word and byte order


def _type_text(reg: Register) -> str:
    text = reg.type._value_ + order_suffix(reg)  # _value_: the member's value, without Enum.value's Python descriptor
    if reg.paired:
        text += ", paired"
    return text


def _raw(value: int | float) -> str:
    return number(value) if isinstance(value, float) else str(value)


def _value_cells(ctx: Context, reg: Register) -> ValueCells:
    """The register's range and default, as its table row and as its facts show them: worked out once per register,
    as the quick reference and the register's section (or an array's member table and details) both print them."""
    cells = ctx.value_cells.get(reg.name)
    if cells is None:
        cells = ctx.value_cells[reg.name] = ValueCells(*_range(reg), *_default(reg))
    return cells


def _range(reg: Register) -> tuple[Md, Md]:
    """Engineering range: the row's cell, and the fact, which adds the unit and the raw values (the quick
    reference has a unit column)."""
    if reg.min is None and reg.max is None:
        return md.escaped(reg.range_text) if reg.range_text else Md(md.DASH), Md(md.DASH)  # the facts have no range then
    low, high = reg.raw_min, reg.raw_max
    if reg.scale_from is not None:  # the value's scale is read at run time: only the raw range is known
        raw = Md(f"raw {_raw(low)} … {_raw(high)}")
        return raw, raw
    text = f"{eng(reg, low)} … {eng(reg, high)}"
    return Md(text), Md(text + md.unit_suffix(reg) + (f" (raw {_raw(low)} … {_raw(high)})" if has_conversion(reg) else ""))


def _default(reg: Register) -> tuple[Md, Md]:
    """The default: the row's cell, and the fact, which adds the unit and the raw value."""
    if reg.default is None:
        return Md(md.DASH), Md(md.DASH)
    value = reg.default
    if isinstance(value, str):
        quoted = Md(md_text(eng(reg, value)))  # text: quoted, escaped
        return quoted, quoted
    if reg.bitfields and isinstance(value, int):
        bits = md.hex_value(value, reg.words)
        return Md(bits), Md(f"{bits} ({value})")
    if reg.scale_from is not None:
        raw = Md(f"raw {_raw(value)}")
        return raw, raw
    text = eng(reg, value)
    full = text + md.unit_suffix(reg) + (f" (raw {_raw(value)})" if has_conversion(reg) else "")
    label = md.enum_label(reg.enum, value) if reg.enum is not None and isinstance(value, int) else None
    if label:
        return Md(f"{text} = {label}"), Md(f"{full} = {label}")
    return Md(text), Md(full)


def _addresses(reg: Register) -> str:
    """The register's address (first and last, for more than one word) in hex, then in decimal."""
    if reg.words > 1:
        return f"{md.address(reg.address)}–{md.address(reg.last_address)} ({reg.address}–{reg.last_address})"
    return f"{md.address(reg.address)} ({reg.address})"


def _address_facts(reg: Register, text: str) -> Md:
    """The Address fact: the register's addresses (`_addresses`, as its quick-reference row has them), and its pair."""
    if reg.paired:
        text += (
            f"; low word of a 32-bit pair whose unused high word is {md.address(reg.first_address)}:"
            " single writes (0x06) go to the listed address, block reads and writes start at the high word"
        )
    return Md(text)


def _extra_cells(uses: Uses, reg: Register) -> tuple[Md, ...]:
    """The columns only some devices have: space, firmware gate, poll class (`extra_headers` names them)."""
    if not (uses.gates or uses.poll or uses.other_spaces):  # most devices
        return ()
    cells = []
    if uses.other_spaces:
        cells.append(Md(space_cell(reg)))
    if uses.gates:
        cells.append(Md(gate_text(reg.firmware) if reg.firmware is not None else md.DASH))
    if uses.poll:
        cells.append(Md(reg.poll._value_))
    return tuple(cells)


def extra_headers(uses: Uses) -> tuple[str, ...]:
    return tuple(h for h, used in (("Space", uses.other_spaces), ("Firmware", uses.gates), ("Poll", uses.poll)) if used)


def _quick_row(ctx: Context, reg: Register, param: str, address: Md, name: Md) -> QuickRow:
    """A row of the quick reference: where the register is and what it is called (the caller's, as an
    array member reads differently), then the register's own columns."""
    cells = _value_cells(ctx, reg)
    return QuickRow(
        extra=_extra_cells(ctx.uses, reg),
        param=param,
        address=address,
        name=name,
        title=reg.title,
        title_zh=reg.title_zh or md.DASH,
        access=ACCESS_SHORT[reg.access._value_],
        type=_type_text(reg),
        range=cells.range,
        default=cells.default,
        unit=reg.unit or md.DASH,
        takes_effect=reg.takes_effect.replace("_", " ") if reg.takes_effect else md.DASH,
    )


def enum_view(ctx: Context, e: EnumType) -> EnumView:
    """The view of a value table: built once per device, as the table and every register using it show the same."""
    built = ctx.enum_views.get(id(e))
    if built is None:
        built = ctx.enum_views[id(e)] = _enum_view(ctx, e)
    return built


def _enum_view(ctx: Context, e: EnumType) -> EnumView:
    directed = any(m.access is not Access.READ_WRITE for m in e.members)
    rows = tuple(
        EnumRow(
            value=str(m.value),
            hex=hex2(m.value) if 0 <= m.value <= 0xFF else md.hex_value(m.value) if m.value >= 0 else md.DASH,
            name=md.code(m.name),
            symbol=m.symbol or "",
            title=m.title,
            title_zh=m.title_zh or "",
            description=m.description,
            direction=ACCESS_LONG[m.access._value_] if directed else "",
        )
        for m in e.members
    )
    return EnumView(
        anchor=md.anchor("enum", e.name),
        heading=Md(f"{md.code(e.name)} — {md_text(e.title)}"),
        title=e.title,
        title_zh=e.title_zh or "",
        description=md.paragraph(e.description),
        source=md.sources(e.source),
        rows=rows,
        used_by=md.join(ctx.enum_users.get(e.name, [])),
        directed=directed,
        table="\n".join([r.row for r in rows]),
    )


def _bit_values(b: Bitfield) -> Md:
    if b.enum is not None:
        return Md(f"{md.link(md.code(b.enum.name), md.anchor('enum', b.enum.name))} ({md_text(b.enum.title)})")
    if b.width == 1:
        return Md("0 / 1")
    return Md(f"0 … {b.max_value}")


def _bitfield_view(ctx: Context, reg: Register) -> BitfieldView:
    rows = tuple(
        BitRow(
            bits=b.bits_text,
            mask=md.hex_value(b.mask, reg.words),
            name=md.code(b.name),
            title=b.title,
            title_zh=b.title_zh or "",
            values=_bit_values(b),
            description=b.description,
        )
        for b in sorted(reg.bitfields, key=lambda b: b.lsb)
    )
    owner = f"{DocId(reg.array.array)} member {DocId(reg.array.member)}" if reg.array else DocId(reg.name)
    return BitfieldView(diagram=diagram_path(ctx.device, reg), alt=f"Bit layout of {owner}", rows=rows)


def _register_facts(
    ctx: Context, reg: Register, address: Md, param: Md | None, errata: Sequence[str], example_names: Sequence[str]
) -> tuple[FactPair, ...]:
    """The facts table of a register, or of an array member (whose caller says its address and parameters)."""
    facts: list[FactPair] = [("Address", address)]
    cells = _value_cells(ctx, reg)
    if param:
        facts.append(("Parameter", param))
    if ctx.uses.other_spaces:
        facts.append(("Space", Md(space_fact(reg))))
    facts.append(("Type", md.escaped(type_fact(reg))))
    if reg.type.info.has_byte_order and (ctx.uses.byte_order or reg.type in NEW_WIDE):
        facts.append(("Word and byte order", Md(order_fact(reg))))
    facts.append(("Access", Md(ACCESS_LONG[reg.access._value_])))
    if ctx.device.is_trigger(reg):
        facts.append(("Trigger", Md("a write makes the device act: sent once, never retried")))
    if reg.min is not None or reg.max is not None:
        facts.append(("Range", cells.range_fact))
    if reg.range_text:
        facts.append(("Range as printed", md.escaped(reg.range_text)))
    facts.append(("Default", cells.default_fact))
    if reg.scale_from is not None:
        sf = md.reg_link(ctx.device.register(reg.scale_from), param=False)
        unit = f" in {md_text(reg.unit)}" if reg.unit else ""
        facts.append(("Scale", Md(f"value = raw × 10^{sf}{unit}: the scale factor is read from the device with it")))
    if has_conversion(reg):
        label = "Scale and offset" if reg.offset_set else "Scale"
        facts.append((label, Md(scale_fact(reg, md_text(reg.unit) if reg.unit else ""))))
    if reg.unit:
        facts.append(("Unit", md.escaped(reg.unit)))
    if reg.enum is not None:
        facts.append(("Values", md.link(md.code(reg.enum.name), md.anchor("enum", reg.enum.name))))
    if reg.takes_effect:
        facts.append(("Takes effect", Md(reg.takes_effect.replace("_", " "))))
    if reg.settable:
        facts.append(("Settable", Md(reg.settable.replace("_", " "))))
    if reg.modes:
        facts.append(("Control modes", md.escaped(", ".join(reg.modes))))
    if reg.firmware is not None:
        facts.append(("Firmware", Md(gate_fact(reg.firmware))))
    if reg.variants:
        facts.append(("Variants", md.escaped(f"only on {variants_text(ctx.device, reg)}; other variants do not have it")))
    if reg.has_na:
        facts.append(("Not available", md.escaped(f"{na_list(reg)}: the device's marker for no value; read as none, never written")))
    if ctx.uses.poll:
        facts.append(("Poll class", Md(POLL_MEANING[reg.poll._value_])))
    facts.append(("Source", md.escaped(md.sources(reg.source))))
    if errata:
        facts.append(("Errata", md.errata_links(errata)))
    links = ctx.example_links(example_names)
    if links:
        facts.append(("Examples", links))
    return tuple(facts)


def _heading(reg: Register) -> Md:
    param = f"{md_text(reg.param)} " if reg.param else ""
    zh = f" ({md_text(reg.title_zh)})" if reg.title_zh else ""
    return Md(f"{param}{md.code(reg.name)} — {md_text(reg.title)}{zh}")


def _register_view(ctx: Context, reg: Register, anchor: DocId, addresses: str) -> RegisterView:
    param = md.escaped(reg.param) if reg.param else None
    return RegisterView(
        level="####",
        anchor=anchor,
        heading=_heading(reg),
        facts=_register_facts(ctx, reg, _address_facts(reg, addresses), param, reg.errata, [reg.name]),
        description=md.paragraph(reg.description),
        notes=md.paragraph(reg.notes),
        enum=enum_view(ctx, reg.enum) if reg.enum is not None else None,
        bitfields=_bitfield_view(ctx, reg) if reg.bitfields else None,
    )


def _formula(array: ArrayDef, first: int) -> tuple[str, str]:
    """Address of element n of a member, in hex and decimal: `0x6201 + 8n` / `25089 + 8n`."""
    step = "n" if array.stride == 1 else f"{array.stride}n"
    if array.index_base:
        step = f"(n − {array.index_base})" if array.stride == 1 else f"{array.stride}(n − {array.index_base})"
    return f"{md.hex_value(first)} + {step}", f"{first} + {step}"


def _array_view(ctx: Context, array: ArrayDef) -> ArrayView:
    device = ctx.device
    indexes = range(array.first_index, array.last_index + 1)
    by_member = {m.name: [device.register(f"{array.name}_{n}_{m.name}") for n in indexes] for m in array.members}
    rows: list[MemberRow] = []
    details: list[RegisterView] = []
    for m in array.members:
        regs = by_member[m.name]
        first = regs[0]
        hex_formula, _ = _formula(array, first.address)
        address = Md(f"`{hex_formula}`" + (f" ({first.words} words)" if first.words > 1 else ""))
        errata = [e for r in regs for e in r.errata]
        cells = _value_cells(ctx, first)
        rows.append(
            MemberRow(
                extra=_extra_cells(ctx.uses, first),
                offset=m.offset,
                address=address,
                name=md.code(m.name),
                registers=Md(f"`{DocId(array.name)}_<n>_{DocId(m.name)}`"),
                title=first.title,
                title_zh=first.title_zh or md.DASH,
                type=_type_text(first),
                access=ACCESS_SHORT[first.access._value_],
                range=cells.range,
                default=cells.default,
                unit=first.unit or md.DASH,
            )
        )
        if first.enum is not None or first.bitfields or first.description or first.notes or errata or first.scale_from:  # says raw x 10^sf
            where = Md(f"{address}, n = {array.first_index} … {array.last_index}")
            param_range = md.escaped(f"{first.param} … {regs[-1].param}") if first.param and regs[-1].param else None
            facts = _register_facts(ctx, first, where, param_range, errata, [r.name for r in regs])
            details.append(
                RegisterView(
                    level="#####",
                    anchor=md.anchor("array", array.name, m.name),
                    heading=Md(
                        f"Member {md.code(m.name)} — {md_text(first.title)}" + (f" ({md_text(first.title_zh)})" if first.title_zh else "")
                    ),
                    facts=facts,
                    description=md.paragraph(first.description),
                    notes=md.paragraph(first.notes),
                    enum=enum_view(ctx, first.enum) if first.enum is not None else None,
                    bitfields=_bitfield_view(ctx, first) if first.bitfields else None,
                )
            )
    elements = []
    for i, n in enumerate(indexes):
        regs = [by_member[m.name][i] for m in array.members]
        params = [r.param for r in regs if r.param]
        param_text = md_text(f"{params[0]} … {params[-1]}" if len(params) > 1 else params[0]) if params else md.DASH
        title = md_text(array.element_title.replace("{n}", str(n))) if array.element_title else md.DASH
        elements.append((Md(str(n)), Md(title), Md(param_text), *(md.address(r.address) for r in regs)))
    last = device.register(f"{array.name}_{array.last_index}_{array.members[-1].name}")
    hex_formula, dec_formula = _formula(array, array.base)
    unit = "bit" if SPACES[last.space].bits else "word"  # a coil or discrete input array counts bit addresses
    summary = Md(
        f"{array.count} elements, n = {array.first_index} … {array.last_index}. Element n starts at "
        f"`{hex_formula}` ({dec_formula}); a member at offset k sits k {unit}s further. "
        f"Element registers are named `{DocId(array.name)}_<n>_<member>`."
    )
    array_facts = [
        ("Addresses", Md(f"{md.address(array.base)} … {md.address(last.last_address)} ({array.base} … {last.last_address})")),
        ("Stride", Md(f"{array.stride} {unit}{'s' if array.stride != 1 else ''} per element")),
        ("Elements", Md(f"{array.count}, numbered from {array.index_base}")),
    ]
    if array.element_title:
        array_facts.append(("Element title", md.escaped(array.element_title)))
    array_facts.append(("Source", md.escaped(md.sources(array.source))))
    zh = f" ({md_text(array.title_zh)})" if array.title_zh else ""
    return ArrayView(
        anchor=md.anchor("array", array.name),
        heading=Md(f"Array {md.code(array.name)} — {md_text(array.title)}{zh}"),
        summary=summary,
        facts=tuple(array_facts),
        description=md.paragraph(array.description),
        notes=md.paragraph(array.notes),
        members=tuple(rows),
        details=tuple(details),
        element_header=(Md("n"), Md("Element"), Md("Parameters"), *(md.code(m.name) for m in array.members)),
        elements=tuple(elements),
    )


def _array_quick_rows(ctx: Context, array: ArrayDef) -> list[QuickRow]:
    out = []
    for m in array.members:
        first = ctx.device.register(f"{array.name}_{array.first_index}_{m.name}")
        last = ctx.device.register(f"{array.name}_{array.last_index}_{m.name}")
        hex_formula, dec_formula = _formula(array, first.address)
        params = f"{first.param} … {last.param}" if first.param and last.param else md.DASH
        name = md.link(Md(f"`{DocId(array.name)}_<n>_{DocId(m.name)}`"), md.anchor("array", array.name))
        out.append(_quick_row(ctx, first, params, Md(f"`{hex_formula}` ({dec_formula})"), name))
    return out


def group_view(ctx: Context, group: Group) -> GroupView:
    arrays = {a.name: a for a in group.arrays}
    quick: list[QuickRow] = []
    items: list[RegisterView | ArrayView] = []
    done: set[str] = set()
    for reg in group.registers:
        if reg.array is None:
            addresses, anchor = _addresses(reg), DocId(reg.name)
            quick.append(_quick_row(ctx, reg, reg.param or md.DASH, Md(addresses), md.link(md.code(reg.name), anchor)))
            items.append(_register_view(ctx, reg, anchor, addresses))
        elif reg.array.array not in done:
            done.add(reg.array.array)
            array = arrays[reg.array.array]
            quick.extend(_array_quick_rows(ctx, array))
            items.append(_array_view(ctx, array))
    zh = f" ({md_text(group.title_zh)})" if group.title_zh else ""
    return GroupView(
        anchor=md.anchor("group", group.id),
        ref_anchor=md.anchor("ref", group.id),
        heading=Md(f"{md_text(group.title)}{zh} — group {md.code(group.id)}"),
        description=md.paragraph(group.description),
        source=md.sources(group.source),
        shared=_group_facts(ctx, group),
        quick=tuple(quick),
        items=tuple(items),
    )


def _group_facts(ctx: Context, group: Group) -> Md:
    """What every register of the group shares (a group's `space`, `firmware` and `poll`, which its
    registers inherit), said once above them; empty when they share nothing new."""
    regs = group.registers
    parts = []
    space = shared(regs, "space")
    if isinstance(space, str) and space != DEFAULT_SPACE:
        parts.append(SPACES[space].title)
    gate = shared(regs, "firmware")
    if isinstance(gate, FirmwareGate):
        parts.append(gate_text(gate))
    poll = shared(regs, "poll")
    if isinstance(poll, PollClass) and poll is not PollClass.NORMAL:
        parts.append(f"poll class {poll._value_}")
    return Md(f"Every register of this group: {', '.join(parts)}.") if parts else Md("")
