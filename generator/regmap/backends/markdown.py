"""Markdown back end: a reference page per map, an index page, and a bitfield diagram (SVG) per bitfield register.

The views below compute every cell; the templates only print. Map text reaches a page in one of
two ways: a plain `str` field goes through the template's `md` filter, and an `Md` field is a cell
a view assembled from `md_text`-escaped map text and validated identifiers (`DocId`), printed as
is. Anchors are explicit `<a id="...">` tags: a register's anchor is its name, every other anchor
has a hyphenated prefix (`array-`, `enum-`, `example-`, `erratum-` ...), and every generated heading
has a hyphen in its slug, so no two ids on a page can collide.
"""

from __future__ import annotations

import functools
import importlib.util
import json
import re
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from fractions import Fraction
from typing import TYPE_CHECKING, Any, ClassVar

from regmap.backends.common import read_plan, runtime_specs
from regmap.diagnostics import UsageError
from regmap.generate import Files, Target
from regmap.model import (
    Access,
    ArrayDef,
    Bitfield,
    Command,
    DataType,
    Device,
    EnumType,
    Erratum,
    Example,
    ExampleValue,
    Group,
    Register,
    WordOrder,
)
from regmap.render import environment, header_lines, md_text
from regmap_runtime.codec import raw_to_words, words_to_raw
from regmap_runtime.rtu import (
    READ_HOLDING,
    STANDARD_EXCEPTIONS,
    WRITE_MULTIPLE,
    WRITE_SINGLE,
    Frame,
    build_write_multiple,
    build_write_single,
    crc_bytes,
    crc_ok,
    parse_frame,
    to_hex,
)
from regmap_runtime.spec import RegisterSpec

if TYPE_CHECKING:
    from mkdocs.config.defaults import MkDocsConfig
    from mkdocs.structure.files import Files as MkDocsFiles

INDEX_PAGE = "index.md"
DASH = "—"
FUNCTION_NAMES = {
    0x01: "read coils",
    0x02: "read discrete inputs",
    READ_HOLDING: "read holding registers",
    0x04: "read input registers",
    0x05: "write single coil",
    WRITE_SINGLE: "write single register",
    0x08: "diagnostics",
    0x0F: "write multiple coils",
    WRITE_MULTIPLE: "write multiple registers",
    0x17: "read/write multiple registers",
}
ACCESS_SHORT = {Access.READ: "R", Access.READ_WRITE: "R/W", Access.WRITE: "W"}
ACCESS_LONG = {Access.READ: "read only", Access.READ_WRITE: "read/write", Access.WRITE: "write only"}
TYPE_LONG = {
    DataType.U16: "unsigned 16-bit",
    DataType.S16: "signed 16-bit",
    DataType.U32: "unsigned 32-bit",
    DataType.S32: "signed 32-bit",
}


# ---------------------------------------------------------------------------------------------- text types

_DOC_ID = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")


class DocId(str):
    """A map identifier (register, enum, example, erratum ...) that is safe as an HTML id, inside a
    Markdown code span and as a file name."""

    def __new__(cls, name: str) -> DocId:
        if not _DOC_ID.match(name):
            raise UsageError(f"{name!r} cannot name an anchor or a file in the docs; use letters, digits and _")
        return super().__new__(cls, name)


class Md(str):
    """Markdown a view assembled from escaped map text and validated identifiers: printed as is."""


def _md(text: str | None) -> Md:
    return Md(md_text(text))


def _code(name: str) -> Md:
    return Md(f"`{DocId(name)}`")


def _link(label: str, anchor: str, page: str = "") -> Md:
    return Md(f"[{label}]({page}#{anchor})")


def _anchor(prefix: str, *names: str) -> str:
    return "-".join([prefix, *(DocId(n) for n in names)])


_BLOCK_START = re.compile(r"^(?:[#>+\-]|\d+[.)])")


def _paragraph(text: str | None) -> Md:
    """Escaped text that stays one paragraph: a leading `#`, `>`, `-`, `+`, `1.` or `~~~` would start
    a block (`md_text` already folds the text onto one line and escapes everything inline)."""
    escaped = md_text(text)
    match = _BLOCK_START.match(escaped)
    if match:
        marker = match.group(0)
        escaped = (marker[:-1] + "\\" + marker[-1] if marker[0].isdigit() else "\\" + marker) + escaped[len(marker) :]
    elif escaped.startswith("~"):
        escaped = "&#126;" + escaped[1:]
    return Md(escaped)


def _html_comment(line: str) -> str:
    """A header line that cannot end the HTML comment it sits in."""
    return line.replace("--", "- -").replace(">", "&gt;")


def _sources(source: Sequence[str]) -> str:
    return ", ".join(source) if source else DASH


def _join(parts: Iterable[str], sep: str = ", ") -> Md:
    return Md(sep.join(parts))


# ---------------------------------------------------------------------------------------------- numbers


def _num(value: Fraction | int | float) -> str:
    if isinstance(value, Fraction) and value.denominator == 1:
        return str(value.numerator)
    if isinstance(value, int):
        return str(value)
    return f"{float(value):.10g}"


def _hex(value: int, words: int = 1) -> str:
    return f"0x{value:0{4 * words}X}"


def _hex_byte(value: int) -> str:
    return f"0x{value:02X}"


def _address(address: int) -> Md:
    return Md(f"`{_hex(address)}`")


def _eng(reg: Register, raw: int) -> str:
    return _num(raw * reg.scale)


def _unit_suffix(reg: Register) -> Md:
    return Md(f" {md_text(reg.unit)}") if reg.unit else Md("")


def _raw_literal(reg: Register, raw: int) -> str:
    """Bit words read best in hex, everything else in decimal."""
    if reg.bitfields and raw >= 0:
        return _hex(raw, reg.words)
    return str(raw)


def _enum_label(e: EnumType, raw: int) -> Md | None:
    member = e.by_value(raw)
    return None if member is None else _code(member.name)


# ---------------------------------------------------------------------------------------------- views


@dataclass(frozen=True)
class Fact:
    label: str
    value: Md


@dataclass(frozen=True)
class QuickRow:
    param: str
    address: Md  # hex, then decimal in parentheses
    name: Md
    title: str
    title_zh: str
    access: str
    type: str
    range: Md
    default: Md
    unit: str
    takes_effect: str


@dataclass(frozen=True)
class EnumRow:
    value: str
    hex: str
    name: Md
    symbol: str
    title: str
    title_zh: str
    description: str


@dataclass(frozen=True)
class EnumView:
    anchor: str
    heading: Md
    title: str
    title_zh: str
    description: Md
    source: str
    rows: tuple[EnumRow, ...]
    used_by: Md


@dataclass(frozen=True)
class BitRow:
    bits: str
    mask: str
    name: Md
    title: str
    title_zh: str
    values: Md
    description: str


@dataclass(frozen=True)
class BitfieldView:
    diagram: str  # path of the SVG, relative to the page
    alt: str
    rows: tuple[BitRow, ...]


@dataclass(frozen=True)
class RegisterView:
    template: ClassVar[str] = "docs/_register.md.jinja"
    level: str  # heading marker: a register is a level-4 heading, an array member level 5
    anchor: str
    heading: Md
    facts: tuple[Fact, ...]
    description: Md
    notes: Md
    enum: EnumView | None
    bitfields: BitfieldView | None


@dataclass(frozen=True)
class MemberRow:
    offset: int
    address: Md
    name: Md
    registers: Md
    title: str
    title_zh: str
    type: str
    access: str
    range: Md
    default: Md
    unit: str


@dataclass(frozen=True)
class ArrayView:
    template: ClassVar[str] = "docs/_array.md.jinja"
    anchor: str
    heading: Md
    summary: Md
    facts: tuple[Fact, ...]
    description: Md
    notes: Md
    members: tuple[MemberRow, ...]
    details: tuple[RegisterView, ...]  # members with values, bitfields, notes or errata
    element_header: tuple[Md, ...]
    elements: tuple[tuple[Md, ...], ...]


@dataclass(frozen=True)
class GroupView:
    anchor: str
    ref_anchor: str
    heading: Md
    description: Md
    source: str
    quick: tuple[QuickRow, ...]
    items: tuple[RegisterView | ArrayView, ...]


@dataclass(frozen=True)
class TimingView:
    baud: str
    receive_to_send: str
    wait_after_receive: str
    send_to_receive: str
    total: str


@dataclass(frozen=True)
class CommandView:
    anchor: str
    name: Md
    title: str
    title_zh: str
    register: Md
    writes: Md
    frame: Md
    description: str
    source: str


@dataclass(frozen=True)
class FaultView:
    anchor: str
    code: str
    value: str
    name: Md
    title: str
    title_zh: str
    kind: str
    resettable: str
    description: str
    source: str


@dataclass(frozen=True)
class ExceptionView:
    code: str
    name: Md
    title: str
    title_zh: str
    source: str


@dataclass(frozen=True)
class ByteRow:
    offset: str
    hex: str
    field: Md
    meaning: Md


@dataclass(frozen=True)
class FrameView:
    label: str
    hex: str
    rows: tuple[ByteRow, ...]
    problems: tuple[str, ...]


@dataclass(frozen=True)
class DecodedRow:
    register: Md
    address: Md
    raw: str
    value: Md
    recorded: Md


@dataclass(frozen=True)
class ExampleView:
    anchor: str
    heading: Md
    meaning: Md
    meaning_zh: str
    facts: tuple[Fact, ...]
    frames: tuple[FrameView, ...]
    decoded: tuple[DecodedRow, ...]
    notes: Md


@dataclass(frozen=True)
class ReadingView:
    source: str
    says: str


@dataclass(frozen=True)
class ErratumView:
    anchor: str
    heading: Md
    readings: tuple[ReadingView, ...]
    choice: Md
    reason: Md
    links: tuple[Fact, ...]


@dataclass(frozen=True)
class DevicePage:
    header: tuple[str, ...]
    title: Md
    description: Md
    overview: tuple[Fact, ...]
    transport_notes: Md
    timing: tuple[TimingView, ...]
    groups: tuple[GroupView, ...]
    enums: tuple[EnumView, ...]
    commands: tuple[CommandView, ...]
    faults: tuple[FaultView, ...]
    exceptions: tuple[ExceptionView, ...]
    exceptions_note: Md
    examples: tuple[ExampleView, ...]
    errata: tuple[ErratumView, ...]


# ---------------------------------------------------------------------------------------------- registers


def _reg_anchor(reg: Register) -> str:
    return _anchor("array", reg.array.array) if reg.array is not None else DocId(reg.name)


def _reg_link(reg: Register, *, param: bool = True) -> Md:
    label = _link(_code(reg.name), _reg_anchor(reg))
    if param and reg.param:
        return Md(f"{label} ({md_text(reg.param)})")
    return label


def _type_text(reg: Register) -> str:
    text = reg.type.value
    if reg.words == 2:
        order = "high" if reg.word_order is WordOrder.HIGH_FIRST else "low"
        text += f", 2 words, {order} first"
    if reg.paired:
        text += ", paired"
    return text


def _range(reg: Register, *, full: bool) -> Md:
    """Engineering range; `full` adds the unit and the raw integers (the quick reference has a unit column)."""
    if reg.min is None and reg.max is None:
        return _md(reg.range_text) if reg.range_text and not full else Md(DASH)
    low, high = reg.raw_min, reg.raw_max
    text = f"{_eng(reg, low)} … {_eng(reg, high)}"
    if full:
        text += _unit_suffix(reg) + (f" (raw {low} … {high})" if reg.scaled else "")
    return Md(text)


def _default(reg: Register, *, full: bool) -> Md:
    if reg.default is None:
        return Md(DASH)
    value = reg.default
    if reg.bitfields:
        return Md(f"{_hex(value, reg.words)} ({value})" if full else _hex(value, reg.words))
    text = _eng(reg, value)
    if full:
        text += _unit_suffix(reg) + (f" (raw {value})" if reg.scaled else "")
    label = _enum_label(reg.enum, value) if reg.enum is not None else None
    return Md(f"{text} = {label}" if label else text)


def _address_facts(reg: Register) -> Md:
    if reg.words == 2:
        text = f"{_address(reg.address)}–{_address(reg.last_address)} ({reg.address}–{reg.last_address})"
    else:
        text = f"{_address(reg.address)} ({reg.address})"
    if reg.paired:
        text += (
            f"; low word of a 32-bit pair whose unused high word is {_address(reg.first_address)}:"
            " single writes (0x06) go to the listed address, block reads and writes start at the high word"
        )
    return Md(text)


def _quick_row(reg: Register) -> QuickRow:
    if reg.words == 2:
        address = Md(f"{_address(reg.address)}–{_address(reg.last_address)} ({reg.address}–{reg.last_address})")
    else:
        address = Md(f"{_address(reg.address)} ({reg.address})")
    return QuickRow(
        param=reg.param or DASH,
        address=address,
        name=_link(_code(reg.name), DocId(reg.name)),
        title=reg.title,
        title_zh=reg.title_zh or DASH,
        access=ACCESS_SHORT[reg.access],
        type=_type_text(reg),
        range=_range(reg, full=False),
        default=_default(reg, full=False),
        unit=reg.unit or DASH,
        takes_effect=reg.takes_effect.replace("_", " ") if reg.takes_effect else DASH,
    )


class _Context:
    """What the views of one device share: specs for decoding, the example and errata cross-links."""

    def __init__(self, device: Device) -> None:
        self.device = device
        self.specs: dict[str, RegisterSpec[Any]] = {s.name: s for s in runtime_specs(device)}
        self.examples_by_register: dict[str, list[str]] = {}
        self.responses: dict[str, list[str]] = {}
        self.enum_users: dict[str, list[Md]] = {}
        for ex in device.examples:
            if ex.request is not None:
                self.responses.setdefault(ex.request, []).append(ex.id)
        for e in device.enums:
            self.enum_users[e.name] = []
        seen: set[tuple[str, str]] = set()
        for reg in device.registers:
            owner = reg.array.array + "." + reg.array.member if reg.array else reg.name
            label = (
                Md(f"{_link(_code(reg.array.array), _anchor('array', reg.array.array))} member {_code(reg.array.member)}")
                if reg.array
                else _link(_code(reg.name), DocId(reg.name))
            )
            if reg.enum is not None and (reg.enum.name, owner) not in seen:
                seen.add((reg.enum.name, owner))
                self.enum_users[reg.enum.name].append(label)
            for b in reg.bitfields:
                if b.enum is not None and (b.enum.name, owner + ":" + b.name) not in seen:
                    seen.add((b.enum.name, owner + ":" + b.name))
                    self.enum_users[b.enum.name].append(Md(f"{label} bits {b.bits_text} ({_code(b.name)})"))

    def example_links(self, names: Iterable[str]) -> Md:
        ids: list[str] = []
        for name in names:
            for ex in self.examples_by_register.get(name, []):
                if ex not in ids:
                    ids.append(ex)
        return _join(_link(_code(i), _anchor("example", i)) for i in ids)


def diagram_path(device: Device, reg: Register) -> str:
    """Where a bitfield register's diagram lives, relative to the docs root; an array's elements share one."""
    owner = f"{reg.array.array}_{reg.array.member}" if reg.array else reg.name
    return f"{DocId(device.id)}/{DocId(owner)}.svg"


def _errata_links(ids: Iterable[str]) -> Md:
    unique: list[str] = []
    for i in ids:
        if i not in unique:
            unique.append(i)
    return _join(_link(md_text(i), _anchor("erratum", i)) for i in unique)


def _enum_view(ctx: _Context, e: EnumType) -> EnumView:
    rows = tuple(
        EnumRow(
            value=str(m.value),
            hex=_hex_byte(m.value) if 0 <= m.value <= 0xFF else _hex(m.value) if m.value >= 0 else DASH,
            name=_code(m.name),
            symbol=m.symbol or "",
            title=m.title,
            title_zh=m.title_zh or "",
            description=m.description,
        )
        for m in e.members
    )
    return EnumView(
        anchor=_anchor("enum", e.name),
        heading=Md(f"{_code(e.name)} — {md_text(e.title)}"),
        title=e.title,
        title_zh=e.title_zh or "",
        description=_paragraph(e.description),
        source=_sources(e.source),
        rows=rows,
        used_by=_join(ctx.enum_users.get(e.name, [])),
    )


def _bit_values(b: Bitfield) -> Md:
    if b.enum is not None:
        return Md(f"{_link(_code(b.enum.name), _anchor('enum', b.enum.name))} ({md_text(b.enum.title)})")
    if b.width == 1:
        return Md("0 / 1")
    return Md(f"0 … {b.max_value}")


def _bitfield_view(ctx: _Context, reg: Register) -> BitfieldView:
    rows = tuple(
        BitRow(
            bits=b.bits_text,
            mask=_hex(b.mask, reg.words),
            name=_code(b.name),
            title=b.title,
            title_zh=b.title_zh or "",
            values=_bit_values(b),
            description=b.description,
        )
        for b in sorted(reg.bitfields, key=lambda b: b.lsb)
    )
    owner = f"{DocId(reg.array.array)} member {DocId(reg.array.member)}" if reg.array else DocId(reg.name)
    return BitfieldView(diagram=diagram_path(ctx.device, reg), alt=f"Bit layout of {owner}", rows=rows)


def _register_facts(ctx: _Context, reg: Register, errata: Sequence[str], example_names: Sequence[str]) -> tuple[Fact, ...]:
    facts = [Fact("Address", _address_facts(reg))]
    if reg.param:
        facts.append(Fact("Parameter", _md(reg.param)))
    facts.append(Fact("Type", Md(f"{reg.type.value} ({TYPE_LONG[reg.type]})")))
    facts.append(Fact("Access", Md(ACCESS_LONG[reg.access])))
    if reg.min is not None or reg.max is not None:
        facts.append(Fact("Range", _range(reg, full=True)))
    if reg.range_text:
        facts.append(Fact("Range as printed", _md(reg.range_text)))
    facts.append(Fact("Default", _default(reg, full=True)))
    if reg.scaled:
        facts.append(Fact("Scale", Md(f"raw × {_num(reg.scale)} = value{' in ' + md_text(reg.unit) if reg.unit else ''}")))
    if reg.unit:
        facts.append(Fact("Unit", _md(reg.unit)))
    if reg.enum is not None:
        facts.append(Fact("Values", _link(_code(reg.enum.name), _anchor("enum", reg.enum.name))))
    if reg.takes_effect:
        facts.append(Fact("Takes effect", Md(reg.takes_effect.replace("_", " "))))
    if reg.settable:
        facts.append(Fact("Settable", Md(reg.settable.replace("_", " "))))
    if reg.modes:
        facts.append(Fact("Control modes", _md(", ".join(reg.modes))))
    facts.append(Fact("Source", _md(_sources(reg.source))))
    if errata:
        facts.append(Fact("Errata", _errata_links(errata)))
    links = ctx.example_links(example_names)
    if links:
        facts.append(Fact("Examples", links))
    return tuple(facts)


def _heading(reg: Register) -> Md:
    param = f"{md_text(reg.param)} " if reg.param else ""
    zh = f" ({md_text(reg.title_zh)})" if reg.title_zh else ""
    return Md(f"{param}{_code(reg.name)} — {md_text(reg.title)}{zh}")


def _register_view(ctx: _Context, reg: Register) -> RegisterView:
    return RegisterView(
        level="####",
        anchor=DocId(reg.name),
        heading=_heading(reg),
        facts=_register_facts(ctx, reg, reg.errata, [reg.name]),
        description=_paragraph(reg.description),
        notes=_paragraph(reg.notes),
        enum=_enum_view(ctx, reg.enum) if reg.enum is not None else None,
        bitfields=_bitfield_view(ctx, reg) if reg.bitfields else None,
    )


def _formula(array: ArrayDef, first: int) -> tuple[str, str]:
    """Address of element n of a member, in hex and decimal: `0x6201 + 8n` / `25089 + 8n`."""
    step = "n" if array.stride == 1 else f"{array.stride}n"
    if array.index_base:
        step = f"(n − {array.index_base})" if array.stride == 1 else f"{array.stride}(n − {array.index_base})"
    return f"{_hex(first)} + {step}", f"{first} + {step}"


def _array_view(ctx: _Context, array: ArrayDef) -> ArrayView:
    device = ctx.device
    indexes = range(array.first_index, array.last_index + 1)
    by_member = {m.name: [device.register(f"{array.name}_{n}_{m.name}") for n in indexes] for m in array.members}
    rows: list[MemberRow] = []
    details: list[RegisterView] = []
    for m in array.members:
        regs = by_member[m.name]
        first = regs[0]
        hex_formula, _ = _formula(array, first.address)
        address = Md(f"`{hex_formula}`" + (" (2 words)" if first.words == 2 else ""))
        errata = [e for r in regs for e in r.errata]
        rows.append(
            MemberRow(
                offset=m.offset,
                address=address,
                name=_code(m.name),
                registers=Md(f"`{DocId(array.name)}_<n>_{DocId(m.name)}`"),
                title=first.title,
                title_zh=first.title_zh or DASH,
                type=_type_text(first),
                access=ACCESS_SHORT[first.access],
                range=_range(first, full=False),
                default=_default(first, full=False),
                unit=first.unit or DASH,
            )
        )
        if first.enum is not None or first.bitfields or first.description or first.notes or errata:
            facts = [Fact("Address", Md(f"{address}, n = {array.first_index} … {array.last_index}"))]
            if first.param and regs[-1].param:
                facts.append(Fact("Parameter", _md(f"{first.param} … {regs[-1].param}")))
            facts += [f for f in _register_facts(ctx, first, errata, [r.name for r in regs]) if f.label not in ("Address", "Parameter")]
            details.append(
                RegisterView(
                    level="#####",
                    anchor=_anchor("array", array.name, m.name),
                    heading=Md(
                        f"Member {_code(m.name)} — {md_text(first.title)}" + (f" ({md_text(first.title_zh)})" if first.title_zh else "")
                    ),
                    facts=tuple(facts),
                    description=_paragraph(first.description),
                    notes=_paragraph(first.notes),
                    enum=_enum_view(ctx, first.enum) if first.enum is not None else None,
                    bitfields=_bitfield_view(ctx, first) if first.bitfields else None,
                )
            )
    elements = []
    for i, n in enumerate(indexes):
        regs = [by_member[m.name][i] for m in array.members]
        params = [r.param for r in regs if r.param]
        param_text = md_text(f"{params[0]} … {params[-1]}" if len(params) > 1 else params[0]) if params else DASH
        title = md_text(array.element_title.replace("{n}", str(n))) if array.element_title else DASH
        elements.append((Md(str(n)), Md(title), Md(param_text), *(_address(r.address) for r in regs)))
    last = device.register(f"{array.name}_{array.last_index}_{array.members[-1].name}")
    hex_formula, dec_formula = _formula(array, array.base)
    summary = Md(
        f"{array.count} elements, n = {array.first_index} … {array.last_index}. Element n starts at "
        f"`{hex_formula}` ({dec_formula}); a member at offset k sits k words further. "
        f"Element registers are named `{DocId(array.name)}_<n>_<member>`."
    )
    facts = [
        Fact("Addresses", Md(f"{_address(array.base)} … {_address(last.last_address)} ({array.base} … {last.last_address})")),
        Fact("Stride", Md(f"{array.stride} word{'s' if array.stride != 1 else ''} per element")),
        Fact("Elements", Md(f"{array.count}, numbered from {array.index_base}")),
    ]
    if array.element_title:
        facts.append(Fact("Element title", _md(array.element_title)))
    facts.append(Fact("Source", _md(_sources(array.source))))
    zh = f" ({md_text(array.title_zh)})" if array.title_zh else ""
    return ArrayView(
        anchor=_anchor("array", array.name),
        heading=Md(f"Array {_code(array.name)} — {md_text(array.title)}{zh}"),
        summary=summary,
        facts=tuple(facts),
        description=_paragraph(array.description),
        notes=_paragraph(array.notes),
        members=tuple(rows),
        details=tuple(details),
        element_header=(Md("n"), Md("Element"), Md("Parameters"), *(_code(m.name) for m in array.members)),
        elements=tuple(elements),
    )


def _array_quick_rows(ctx: _Context, array: ArrayDef) -> list[QuickRow]:
    out = []
    for m in array.members:
        first = ctx.device.register(f"{array.name}_{array.first_index}_{m.name}")
        last = ctx.device.register(f"{array.name}_{array.last_index}_{m.name}")
        hex_formula, dec_formula = _formula(array, first.address)
        params = f"{first.param} … {last.param}" if first.param and last.param else DASH
        out.append(
            QuickRow(
                param=params,
                address=Md(f"`{hex_formula}` ({dec_formula})"),
                name=_link(Md(f"`{DocId(array.name)}_<n>_{DocId(m.name)}`"), _anchor("array", array.name)),
                title=first.title,
                title_zh=first.title_zh or DASH,
                access=ACCESS_SHORT[first.access],
                type=_type_text(first),
                range=_range(first, full=False),
                default=_default(first, full=False),
                unit=first.unit or DASH,
                takes_effect=first.takes_effect.replace("_", " ") if first.takes_effect else DASH,
            )
        )
    return out


def _group_view(ctx: _Context, group: Group) -> GroupView:
    arrays = {a.name: a for a in group.arrays}
    quick: list[QuickRow] = []
    items: list[RegisterView | ArrayView] = []
    done: set[str] = set()
    for reg in group.registers:
        if reg.array is None:
            quick.append(_quick_row(reg))
            items.append(_register_view(ctx, reg))
        elif reg.array.array not in done:
            done.add(reg.array.array)
            array = arrays[reg.array.array]
            quick.extend(_array_quick_rows(ctx, array))
            items.append(_array_view(ctx, array))
    zh = f" ({md_text(group.title_zh)})" if group.title_zh else ""
    return GroupView(
        anchor=_anchor("group", group.id),
        ref_anchor=_anchor("ref", group.id),
        heading=Md(f"{md_text(group.title)}{zh} — group {_code(group.id)}"),
        description=_paragraph(group.description),
        source=_sources(group.source),
        quick=tuple(quick),
        items=tuple(items),
    )


# ---------------------------------------------------------------------------------------------- frames


def _offsets(start: int, length: int) -> str:
    return str(start) if length == 1 else f"{start}–{start + length - 1}"


def _function_meaning(device: Device, function: int) -> Md:
    base = function & 0x7F
    name = FUNCTION_NAMES.get(base, "unknown function")
    supported = "" if base in device.transport.function_codes else " (not supported by this device)"
    if function & 0x80:
        return Md(f"`{_hex_byte(function)}` = `{_hex_byte(base)}` + `0x80`: exception response to {name}{supported}")
    return Md(f"`{_hex_byte(function)}` {name}{supported}")


def _slave_meaning(device: Device, slave: int) -> Md:
    t = device.transport
    if t.broadcast_id is not None and slave == t.broadcast_id:
        return Md(f"{slave}: broadcast, no slave replies")
    if not t.slave_min <= slave <= t.slave_max:
        return Md(f"slave {slave} (outside the documented {t.slave_min} … {t.slave_max})")
    return Md(f"slave {slave}")


def _word_owner(device: Device, address: int) -> Md:
    reg = device.covering(address)
    if reg is None:
        return Md("no documented register")
    link = _reg_link(reg)
    if reg.paired and address < reg.address:
        return Md(f"unused high word of {link}")
    if reg.words == 2:
        high = (address == reg.address) == (reg.word_order is WordOrder.HIGH_FIRST)
        return Md(f"{'high' if high else 'low'} word of {link}")
    return link


def _value_text(reg: Register, raw: int) -> Md:
    if reg.bitfields:
        parts = []
        covered = 0
        for b in sorted(reg.bitfields, key=lambda b: b.lsb):
            covered |= b.mask
            field = (raw & b.mask) >> b.lsb
            label = _enum_label(b.enum, field) if b.enum is not None else None
            parts.append(f"{DocId(b.name)} = {label or field}")
        rest = raw & ~covered & ((1 << reg.type.bits) - 1)
        if rest:
            parts.append(f"undefined bits {_hex(rest, reg.words)}")
        return Md(", ".join(parts))
    text = _eng(reg, raw) + _unit_suffix(reg)
    label = _enum_label(reg.enum, raw) if reg.enum is not None else None
    if reg.enum is not None:
        return Md(f"{text} = {label}" if label else f"{text} (not a listed value)")
    return Md(text)


def _word_meaning(device: Device, address: int | None, word: int) -> tuple[Md, Md]:
    if address is None:
        return Md("Data word"), Md(f"{word} ({_hex(word)}); address unknown")
    owner = _word_owner(device, address)
    reg = device.covering(address)
    value = f"{word} ({_hex(word)})"
    if reg is not None and reg.words == 1 and address == reg.address:
        raw = word - 0x10000 if reg.signed and word & 0x8000 else word
        value = f"{_hex(word)} → {_value_text(reg, raw)}"
    return Md(f"Register {_address(address)}"), Md(f"{owner}: {value}")


def _frame_view(ctx: _Context, label: str, frame: bytes, direction: str, start: int | None) -> tuple[FrameView, Frame]:
    device = ctx.device
    parsed = parse_frame(frame, direction)
    rows: list[ByteRow] = []
    pos = 0

    def take(length: int, field: str | Md, meaning: Md) -> bytes:
        nonlocal pos
        chunk = frame[pos : pos + length]
        rows.append(ByteRow(offset=_offsets(pos, len(chunk)), hex=to_hex(chunk), field=Md(field), meaning=meaning))
        pos += len(chunk)
        return chunk

    def data_words(first: int | None, data_end: int) -> None:
        i = 0
        while pos + 2 <= data_end:
            word = int.from_bytes(frame[pos : pos + 2], "big")
            field, meaning = _word_meaning(device, None if first is None else first + i, word)
            take(2, field, meaning)
            i += 1

    end = len(frame) - 2
    take(1, "Slave id", _slave_meaning(device, parsed.slave))
    take(1, "Function", _function_meaning(device, parsed.function))
    address, count = parsed.address, parsed.count
    if parsed.kind in ("read_request", "write_multiple_response", "write_multiple_request") and address is not None and count is not None:
        take(2, "Start address", Md(f"{_address(address)} ({address}): {_word_owner(device, address)}"))
        last = address + count - 1
        take(2, "Register count", Md(f"{count} register{'s' if count != 1 else ''}: {_address(address)} … {_address(last)}"))
        if parsed.kind == "write_multiple_request" and parsed.byte_count is not None:
            take(1, "Byte count", Md(f"{parsed.byte_count} bytes"))
            data_words(address, end)
    elif parsed.kind == "read_response" and parsed.byte_count is not None:
        take(1, "Byte count", Md(f"{parsed.byte_count} bytes = {parsed.byte_count // 2} register{'s' if parsed.byte_count != 2 else ''}"))
        data_words(start, end)
    elif parsed.kind == "write_single" and address is not None:
        take(2, "Address", Md(f"{_address(address)} ({address}): {_word_owner(device, address)}"))
        if pos + 2 <= end:
            take(2, "Value", _word_meaning(device, address, int.from_bytes(frame[pos : pos + 2], "big"))[1])
    elif parsed.kind == "exception" and parsed.exception_code is not None:
        code = parsed.exception_code
        known = device.transport.exception(code)
        meaning = (
            f"{md_text(known.title)}" + (f" ({md_text(known.title_zh)})" if known.title_zh else "")
            if known is not None
            else STANDARD_EXCEPTIONS.get(code, "unknown exception") + " (standard Modbus meaning; not listed by the manual)"
        )
        take(1, "Exception code", Md(f"`{_hex_byte(code)}` {meaning}"))
    if pos < end:
        take(end - pos, "Data", Md("not decoded" if parsed.kind == "unknown" else "bytes the frame layout does not account for"))
    crc = int.from_bytes(frame[-2:], "little")
    if crc_ok(frame):
        crc_text = f"`{_hex(crc)}`, sent low byte first: valid"
    else:
        crc_text = f"`{_hex(crc)}`: **wrong**, the CRC of the preceding bytes is `{to_hex(crc_bytes(frame[:-2]))}`"
    take(2, "CRC", Md(crc_text))
    return FrameView(label=label, hex=to_hex(frame), rows=tuple(rows), problems=parsed.problems), parsed


def _span(parsed: Frame, start: int | None) -> range:
    """Addresses a frame touches: the request's range, or the response's data words from the request's start."""
    if parsed.kind == "read_response":
        return range(start, start + len(parsed.words)) if start is not None else range(0)
    if parsed.address is not None and parsed.count is not None:
        return range(parsed.address, parsed.address + parsed.count)
    return range(0)


def _recorded(reg: Register, record: ExampleValue) -> Md:
    parts = []
    if record.raw is not None:
        parts.append("raw " + _raw_literal(reg, record.raw))
    if record.words is not None:
        parts.append("words " + ", ".join(_hex(w) for w in record.words))
    value = record.value
    if isinstance(value, str):
        parts.append(f"“{md_text(value)}”")
    elif value is not None:
        parts.append(_num(value) + _unit_suffix(reg))
    return Md("; ".join(parts) if parts else DASH)


def _decoded_rows(ctx: _Context, example: Example, parsed: Frame, start: int | None) -> list[DecodedRow]:
    device = ctx.device
    span = _span(parsed, start)
    has_data = parsed.kind in ("read_response", "write_single", "write_multiple_request")
    words = {a: w for a, w in zip(span, parsed.words, strict=False)} if has_data else {}
    regs: list[Register] = []
    for address in span:
        reg = device.covering(address)
        if reg is not None and reg not in regs:
            regs.append(reg)
    for v in example.values:
        if v.register not in regs:
            regs.append(v.register)
    rows = []
    for reg in regs:
        own = range(reg.address, reg.last_address + 1)
        decoded_raw: int | None = None
        if has_data and all(a in words for a in own):
            decoded_raw = words_to_raw(ctx.specs[reg.name], [words[a] for a in own])
            raw_text, value = _raw_literal(reg, decoded_raw), _value_text(reg, decoded_raw)
        elif has_data and any(a in words for a in own):
            present = [a for a in own if a in words]
            raw_text = ", ".join(_hex(words[a]) for a in present)
            value = Md(f"{len(present)} of {reg.words} words in this frame")
        else:
            raw_text, value = DASH, Md("read" if parsed.kind == "read_request" else DASH)
        record = next((v for v in example.values if v.register == reg), None)
        recorded = _recorded(reg, record) if record is not None else Md(DASH)
        if record is not None and record.raw is not None and decoded_raw is not None:
            recorded = Md(recorded + (" ✓" if record.raw == decoded_raw else " — **differs from the frame**"))
        where = Md(f"{_address(reg.address)}–{_address(reg.last_address)}") if reg.words == 2 else _address(reg.address)
        rows.append(DecodedRow(register=_reg_link(reg), address=where, raw=raw_text, value=value, recorded=recorded))
        ctx.examples_by_register.setdefault(reg.name, [])
        if example.id not in ctx.examples_by_register[reg.name]:
            ctx.examples_by_register[reg.name].append(example.id)
    return rows


def _example_view(ctx: _Context, example: Example) -> ExampleView:
    device = ctx.device
    start: int | None = None
    request: Example | None = None
    if example.request is not None:
        request = device.example(example.request)
        start = parse_frame(request.wire_frame, "request").address
    printed, parsed = _frame_view(ctx, "Frame as printed in the manual", example.frame, example.direction, start)
    frames = [printed]
    if example.corrected_frame is not None:
        corrected, parsed = _frame_view(ctx, "Frame regmap sends (corrected)", example.corrected_frame, example.direction, start)
        frames.append(corrected)
    facts = [Fact("Direction", Md(example.direction)), Fact("Source", _md(_sources(example.source)))]
    if request is not None:
        facts.append(Fact("Answers", _link(_code(request.id), _anchor("example", request.id))))
    answers = ctx.responses.get(example.id, [])
    if answers:
        facts.append(Fact("Answered by", _join(_link(_code(a), _anchor("example", a)) for a in answers)))
    if example.erratum is not None:
        facts.append(Fact("Erratum", _errata_links([example.erratum])))
    direction = "request" if example.direction == "request" else "response"
    return ExampleView(
        anchor=_anchor("example", example.id),
        heading=Md(f"{_code(example.id)} — {direction}, {md_text(_sources(example.source))}"),
        meaning=_paragraph(example.meaning),
        meaning_zh=example.meaning_zh or "",
        facts=tuple(facts),
        frames=tuple(frames),
        decoded=tuple(_decoded_rows(ctx, example, parsed, start)),
        notes=_paragraph(example.notes),
    )


# ---------------------------------------------------------------------------------------------- the rest


def _command_frame(ctx: _Context, cmd: Command) -> Md:
    """The frame a client sends for the command (to slave 1, with the smallest argument)."""
    reg = cmd.register
    argument = cmd.argument.min if cmd.argument is not None else None
    words = raw_to_words(ctx.specs[reg.name], cmd.raw_value(argument))
    frame = build_write_single(1, reg.address, words[0]) if len(words) == 1 else build_write_multiple(1, reg.address, words)
    suffix = f" ({DocId(cmd.argument.name)} = {argument})" if cmd.argument is not None else ""
    return Md(f"`{to_hex(frame)}`{suffix}")


def _command_view(ctx: _Context, cmd: Command) -> CommandView:
    reg = cmd.register
    writes = f"`{_hex(cmd.value, reg.words)}`"
    label = _enum_label(reg.enum, cmd.value) if reg.enum is not None else None
    if label:
        writes += f" = {label}"
    if cmd.argument is not None:
        arg = cmd.argument
        writes += f" + {_code(arg.name)} ({arg.min} … {arg.max}{', ' + md_text(arg.title) if arg.title else ''})"
    return CommandView(
        anchor=_anchor("command", cmd.name),
        name=_code(cmd.name),
        title=cmd.title,
        title_zh=cmd.title_zh or DASH,
        register=Md(f"{_reg_link(reg, param=False)} {_address(reg.address)}"),
        writes=Md(writes),
        frame=_command_frame(ctx, cmd),
        description=cmd.description or DASH,
        source=_sources(cmd.source),
    )


def _erratum_view(ctx: _Context, erratum: Erratum) -> ErratumView:
    device = ctx.device
    links: list[Fact] = []
    if erratum.registers:
        links.append(Fact("Registers", _join(_reg_link(device.register(n)) for n in erratum.registers)))
    examples = [ex.id for ex in device.examples if ex.erratum == erratum.id]
    if examples:
        links.append(Fact("Examples", _join(_link(_code(i), _anchor("example", i)) for i in examples)))
    return ErratumView(
        anchor=_anchor("erratum", erratum.id),
        heading=Md(f"{md_text(erratum.id)} — {md_text(erratum.title)}"),
        readings=tuple(ReadingView(source=_sources(r.source), says=r.says) for r in erratum.readings),
        choice=_paragraph(erratum.choice),
        reason=_paragraph(erratum.reason),
        links=tuple(links),
    )


def _overview(device: Device) -> tuple[Fact, ...]:
    info, t = device.info, device.transport
    vendor = md_text(info.vendor) + (f" ({md_text(info.vendor_zh)})" if info.vendor_zh else "")
    manual = [md_text(info.manual_title)]
    if info.manual_version:
        manual.append(f"version {md_text(info.manual_version)}")
    manual.append(f"file {md_text(info.manual_file)}")
    if info.manual_language:
        manual.append(f"language {md_text(info.manual_language)}")
    parity = {"none": "no parity", "even": "even parity", "odd": "odd parity"}.get(t.parity, f"parity {t.parity}")
    serial = f"{t.baud} baud, {t.data_bits} data bits, {md_text(parity)}, {t.stop_bits} stop bit{'s' if t.stop_bits != 1 else ''}"
    if t.baud_rates:
        serial += "; baud rates " + ", ".join(str(b) for b in t.baud_rates)
    functions = ", ".join(f"`{_hex_byte(c)}` {FUNCTION_NAMES.get(c, 'unknown function')}" for c in t.function_codes)
    limits = f"read {t.max_read_registers}, write {t.max_write_registers}"
    if t.max_message_bytes is not None:
        limits += f"; longest message {t.max_message_bytes} bytes"
    order = "high word first (at the lower address)" if t.word_order is WordOrder.HIGH_FIRST else "low word first (at the lower address)"
    facts = [
        Fact("Vendor", Md(vendor)),
        Fact("Model", _md(info.model)),
        Fact("Manual", Md(", ".join(manual))),
        Fact("Firmware", _md(info.firmware) if info.firmware else Md("not named by the manual")),
        Fact(
            "Map",
            Md(f"{md_text(device.source_path)}, version {md_text(info.map_version)}, fingerprint {md_text(device.fingerprint)}"),
        ),
        Fact("Serial defaults", Md(serial)),
        Fact("Slave ids", Md(f"{t.slave_min} … {t.slave_max}")),
        Fact("Broadcast", Md(f"id {t.broadcast_id} (no reply)" if t.broadcast_id is not None else "not supported")),
        Fact("Function codes", Md(functions)),
        Fact("Max registers per request", Md(limits)),
        Fact("32-bit word order", Md(order)),
    ]
    if t.word_order_register is not None:
        w = t.word_order_register
        facts.append(
            Fact("Word-order register", Md(f"{_reg_link(w.register)}: {w.high_first} = high word first, {w.low_first} = low word first"))
        )
    paired = [r for r in device.registers if r.paired]
    if paired:
        facts.append(
            Fact(
                "Paired registers",
                Md(
                    f"{len(paired)} registers: each listed address is the low word of a 32-bit pair whose unused high word sits at "
                    "address − 1; single writes (0x06) go to the listed address, block reads and writes start at the high word"
                ),
            )
        )
    crc = "low byte first (standard Modbus)" if t.crc_byte_order == "low_first" else md_text(t.crc_byte_order.replace("_", " "))
    facts.append(Fact("CRC byte order", Md(crc)))
    gaps = "tolerated: block reads may span gaps" if t.tolerates_gaps else "rejected: block reads never span gaps"
    facts.append(Fact("Undocumented addresses", Md(gaps)))
    if t.response_delay_ms is not None:
        facts.append(Fact("Response delay", Md(f"{_num(t.response_delay_ms)} ms")))
    facts.append(Fact("Reading everything", Md(f"{len(read_plan(device))} requests (the fewest the limits allow)")))
    facts.append(Fact("Source", _md(_sources(t.source))))
    return tuple(facts)


def _timing(device: Device) -> tuple[TimingView, ...]:
    def ms(value: float | None) -> str:
        return DASH if value is None else _num(value)

    return tuple(
        TimingView(
            baud=str(row.baud),
            receive_to_send=ms(row.receive_to_send_ms),
            wait_after_receive=ms(row.wait_after_receive_ms),
            send_to_receive=ms(row.send_to_receive_ms),
            total=ms(row.total_ms),
        )
        for row in device.transport.timing
    )


def device_page(device: Device) -> DevicePage:
    """Every view of one device's page."""
    if device.id == INDEX_PAGE.removesuffix(".md"):
        raise UsageError(f"{device.source_path}: a device cannot be called {device.id!r}: its page would replace the docs index")
    ctx = _Context(device)
    examples = tuple(_example_view(ctx, ex) for ex in device.examples)  # first: registers link to them
    t = device.transport
    exceptions = tuple(
        ExceptionView(code=_hex_byte(e.code), name=_code(e.name), title=e.title, title_zh=e.title_zh or DASH, source=_sources(e.source))
        for e in t.exceptions
    )
    note = (
        Md("")
        if exceptions
        else Md("The manual lists no exception codes; a device may still answer with the standard Modbus codes 0x01 … 0x04.")
    )
    return DevicePage(
        header=tuple(_html_comment(line) for line in header_lines(device, "regmap generate")),
        title=Md(f"{md_text(device.info.vendor)} {md_text(device.info.model)}"),
        description=_paragraph(device.info.description),
        overview=_overview(device),
        transport_notes=_paragraph(t.notes),
        timing=_timing(device),
        groups=tuple(_group_view(ctx, g) for g in device.groups),
        enums=tuple(_enum_view(ctx, e) for e in device.enums),
        commands=tuple(_command_view(ctx, c) for c in device.commands),
        faults=tuple(
            FaultView(
                anchor=_anchor("fault", f.name),
                code=f.code,
                value=_hex(f.value) if f.value is not None else DASH,
                name=_code(f.name),
                title=f.title,
                title_zh=f.title_zh or DASH,
                kind=f.kind,
                resettable={True: "yes", False: "no", None: "not stated"}[f.resettable],
                description=f.description or DASH,
                source=_sources(f.source),
            )
            for f in device.faults
        ),
        exceptions=exceptions,
        exceptions_note=note,
        examples=examples,
        errata=tuple(_erratum_view(ctx, e) for e in device.errata),
    )


# ---------------------------------------------------------------------------------------------- diagrams

LANE_BITS = 8  # bits per row of a diagram: 16-bit registers draw as two rows, MSB row on top
DIAGRAM_WIDTH = 800
CHAR_WIDTH = 8.5  # average width of a 14 px sans-serif character, for wrapping names
MAX_LINES = 3


def _wrap(name: str, bits: int) -> str:
    """Break a snake_case name after underscores so that each line fits the field's width."""
    fit = max(3, int(bits * DIAGRAM_WIDTH / LANE_BITS / CHAR_WIDTH) - 1)
    lines: list[str] = []
    for part in re.findall(r"[^_]+_?|_", name):
        if lines and len(lines[-1]) + len(part) <= fit:
            lines[-1] += part
        else:
            lines.append(part)
    if len(lines) > MAX_LINES:
        lines = [*lines[: MAX_LINES - 1], "".join(lines[MAX_LINES - 1 :])[: fit - 1] + "…"]
    return "\n".join(lines)


def bitfield_svg(device: Device, reg: Register) -> str:
    """The register's bit layout drawn by wavedrom's `reg` renderer; unused bits shaded."""
    if importlib.util.find_spec("wavedrom") is None:  # pragma: no cover - wavedrom is a declared dependency
        raise UsageError("wavedrom is not installed; it draws the bitfield diagrams of the docs (pip install wavedrom)")
    fields: list[dict[str, Any]] = []
    position = 0
    for b in sorted(reg.bitfields, key=lambda b: b.lsb):
        if b.lsb > position:
            fields.append({"bits": b.lsb - position})
        fields.append({"bits": b.width, "name": _wrap(DocId(b.name), b.width)})
        position = b.msb + 1
    if position < reg.type.bits:
        fields.append({"bits": reg.type.bits - position})
    source = {"reg": fields, "config": {"bits": reg.type.bits, "lanes": reg.type.bits // LANE_BITS, "hspace": DIAGRAM_WIDTH, "vspace": 110}}
    owner = f"{reg.array.array} member {reg.array.member}" if reg.array else reg.name
    svg = _drawing(json.dumps(source, sort_keys=True)).replace(_TITLE_SLOT, f"Bit layout of {owner}", 1)
    header = "".join(f"<!-- {_html_comment(line)} -->\n" for line in header_lines(device, "regmap generate"))
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + header + svg + "\n"


_TITLE_SLOT = "REGMAP_TITLE_SLOT"  # identifiers and fixed words only go in here, so no XML escaping is needed


@functools.lru_cache(maxsize=256)
def _drawing(source: str) -> str:
    """wavedrom's SVG for one layout; registers sharing a layout (DI1..DI7) are drawn once."""
    import wavedrom  # type: ignore[import-untyped,import-not-found,unused-ignore]

    drawing = wavedrom.render(source)
    drawing.set_desc(title=_TITLE_SLOT)
    text: str = drawing.tostring()
    return text


# ---------------------------------------------------------------------------------------------- target


def render_device(device: Device) -> Files:
    page = device_page(device)
    files: Files = {f"{DocId(device.id)}.md": environment().get_template("docs/device.md.jinja").render(page=page)}
    for reg in device.registers:
        if reg.bitfields:
            path = diagram_path(device, reg)
            if path not in files:  # array elements share their member's diagram
                files[path] = bitfield_svg(device, reg)
    return files


@dataclass(frozen=True)
class IndexRow:
    page: str
    device: Md
    vendor: Md
    model: str
    manual: Md
    version: str
    fingerprint: str
    registers: int
    examples: int
    errata: int


def render_shared(devices: Sequence[Device]) -> Files:
    rows = []
    for d in sorted(devices, key=lambda d: d.id):
        info = d.info
        manual = md_text(info.manual_title) + (f", {md_text(info.manual_version)}" if info.manual_version else "")
        rows.append(
            IndexRow(
                page=f"{DocId(d.id)}.md",
                device=_code(d.id),
                vendor=Md(md_text(info.vendor) + (f" ({md_text(info.vendor_zh)})" if info.vendor_zh else "")),
                model=info.model,
                manual=Md(manual),
                version=info.map_version,
                fingerprint=d.fingerprint,
                registers=len(d.registers),
                examples=len(d.examples),
                errata=len(d.errata),
            )
        )
    header = ["Generated by regmap from the maps listed below - do not edit.", "Regenerate with `regmap generate`."]
    text = environment().get_template("docs/index.md.jinja").render(header=[_html_comment(h) for h in header], devices=rows)
    return {INDEX_PAGE: text}


TARGET = Target(name="markdown", subdir="docs", per_device=render_device, shared=render_shared)


# ---------------------------------------------------------------------------------------------- mkdocs hook
# mkdocs.yml names this file under `hooks:`. The generated pages are plain Markdown that also reads
# well on a code host; what only the site needs (the project's own pages, a stylesheet for the wide
# tables) is added here, at build time, rather than written into generated/docs.

SITE_CSS = "css/regmap.css"


def on_config(config: MkDocsConfig) -> MkDocsConfig:
    """mkdocs hook: load the stylesheet `on_files` adds."""
    if SITE_CSS not in config.extra_css:
        config.extra_css.append(SITE_CSS)
    return config


def on_files(files: MkDocsFiles, config: MkDocsConfig) -> MkDocsFiles:
    """mkdocs hook: add the project's own pages (docs/*.md beside mkdocs.yml, the map format) and
    the stylesheet to the site whose pages `regmap generate` wrote."""
    from pathlib import Path

    from mkdocs.exceptions import PluginError
    from mkdocs.structure.files import File

    project_docs = Path(config.config_file_path).parent / "docs"
    for path in sorted(project_docs.glob("*.md")):
        if files.get_file_from_path(path.name) is not None:
            raise PluginError(f"docs/{path.name} and a generated page have the same name")
        files.append(File.generated(config, path.name, abs_src_path=str(path)))
    files.append(File.generated(config, SITE_CSS, content=environment().get_template("docs/regmap.css.jinja").render()))
    return files
