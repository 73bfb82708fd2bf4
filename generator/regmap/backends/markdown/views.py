"""The views of one device's page (every cell computed; the templates only print), and the context
the views of one device share.

The views are NamedTuples, not frozen dataclasses: as immutable, and a class costs a sixth as much to create
(this module made 21 of them at every import, ~18 ms of CPU)."""

from __future__ import annotations

from collections.abc import Iterable

from regmap.backends.markdown import text as md
from regmap.backends.markdown.text import DocId, Md, md_text
from regmap.backends.markdown.wire import uses
from regmap.core.decoding import RegisterSpecs
from regmap.model import Device
from regmap.records import NamedTuple


def table_row(cells: Iterable[str]) -> str:
    """A Markdown table row of cells that are ready to print (one string for the template, not two pieces a cell)."""
    return "| " + " | ".join(cells) + " |"


class Fact(NamedTuple):
    label: str
    value: Md

    @property
    def row(self) -> str:
        return f"| {self.label} | {self.value} |"


# A fact as a register's facts table has it, label and value: a plain pair costs less than a Fact.
FactPair = tuple[str, Md]


def fact_rows(facts: Iterable[FactPair]) -> str:
    """The rows of a facts table, one a line: one string for the template, not a loop over a dozen rows per register."""
    return "\n".join([f"| {label} | {value} |" for label, value in facts])


class ValueCells(NamedTuple):
    """A register's range and default as a table row shows them, and as its facts do (with the unit and the raw values)."""

    range: Md
    range_fact: Md
    default: Md
    default_fact: Md


class QuickRow(NamedTuple):
    extra: tuple[Md, ...]  # the space, firmware and poll columns of a device that uses them
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

    @property
    def row(self) -> str:
        return table_row(
            (
                md_text(self.param),
                self.address,
                self.name,
                md_text(self.title),
                md_text(self.title_zh),
                self.access,
                self.type,
                self.range,
                self.default,
                md_text(self.unit),
                md_text(self.takes_effect),
                *self.extra,
            )
        )


class EnumRow(NamedTuple):
    value: str
    hex: str
    name: Md
    symbol: str
    title: str
    title_zh: str
    description: str
    direction: str  # "read only" (a state the device reports), "write only" (a command), "read/write"; "" when the enum has no directions

    @property
    def row(self) -> str:
        """The row of its table: with the Direction column when the enum has directions."""
        directed = (self.direction,) if self.direction else ()
        return table_row(
            (
                self.value,
                self.hex,
                self.name,
                *directed,
                md_text(self.symbol),
                md_text(self.title),
                md_text(self.title_zh),
                md_text(self.description),
            )
        )


_DIRECTED_HEADER = (
    "Direction: read only is a state the device reports and is never written; write only is a command it accepts.\n\n"
    "| Value | Hex | Name | Direction | Symbol | Meaning | 中文 | Notes |\n"
    "|---:|---|---|---|---|---|---|---|\n"
)
_PLAIN_HEADER = "| Value | Hex | Name | Symbol | Meaning | 中文 | Notes |\n|---:|---|---|---|---|---|---|\n"


class EnumView(NamedTuple):
    anchor: str
    heading: Md
    title: str
    title_zh: str
    description: Md
    source: str
    rows: tuple[EnumRow, ...]
    used_by: Md
    directed: bool  # some member goes one way only: the table has a Direction column
    table: str  # the rows, one a line: built once, as the table is printed again under every register using it

    @property
    def block(self) -> str:
        """The whole value table as a page prints it (description, direction note, header, rows, source): one string, not
        an include per register that shows the table (the template's line ends it, then a blank line)."""
        parts = [f"{self.description}\n\n"] if self.description else []
        parts.append(_DIRECTED_HEADER if self.directed else _PLAIN_HEADER)
        parts.append(f"{self.table}\n\nSource: {md_text(self.source)}.\n")
        return "".join(parts)


class BitRow(NamedTuple):
    bits: str
    mask: str
    name: Md
    title: str
    title_zh: str
    values: Md
    description: str

    @property
    def row(self) -> str:
        return table_row(
            (self.bits, f"`{self.mask}`", self.name, md_text(self.title), md_text(self.title_zh), self.values, md_text(self.description))
        )


class BitfieldView(NamedTuple):
    diagram: str  # path of the SVG, relative to the page
    alt: str
    rows: tuple[BitRow, ...]

    @property
    def table(self) -> str:
        return "\n".join([r.row for r in self.rows])


class RegisterView(NamedTuple):
    level: str  # heading marker: a register is a level-4 heading, an array member level 5
    anchor: str
    heading: Md
    facts: tuple[FactPair, ...]
    description: Md
    notes: Md
    enum: EnumView | None
    bitfields: BitfieldView | None

    @property
    def template(self) -> str:
        return ""  # device.md.jinja prints its section itself

    @property
    def sections(self) -> tuple[RegisterView, ...]:
        """The register sections device.md.jinja prints after the item's template: a register's own."""
        return (self,)

    @property
    def fact_rows(self) -> str:
        return fact_rows(self.facts)


class MemberRow(NamedTuple):
    extra: tuple[Md, ...]
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

    @property
    def row(self) -> str:
        return table_row(
            (
                str(self.offset),
                self.address,
                self.name,
                self.registers,
                md_text(self.title),
                md_text(self.title_zh),
                self.type,
                self.access,
                self.range,
                self.default,
                md_text(self.unit),
                *self.extra,
            )
        )


class ArrayView(NamedTuple):
    anchor: str
    heading: Md
    summary: Md
    facts: tuple[FactPair, ...]
    description: Md
    notes: Md
    members: tuple[MemberRow, ...]
    details: tuple[RegisterView, ...]  # members with values, bitfields, notes or errata
    element_header: tuple[Md, ...]
    elements: tuple[tuple[Md, ...], ...]

    @property
    def template(self) -> str:
        return "_array.md.jinja"

    @property
    def sections(self) -> tuple[RegisterView, ...]:
        """The register sections device.md.jinja prints after the array's: its members with details."""
        return self.details

    @property
    def member_rows(self) -> str:
        return "\n".join([m.row for m in self.members])

    @property
    def element_rows(self) -> str:
        """The element table's rows, one a line (a cell is ready to print)."""
        return "\n".join(["|" + "".join([f" {cell} |" for cell in row]) for row in self.elements])

    @property
    def fact_rows(self) -> str:
        return fact_rows(self.facts)


class GroupView(NamedTuple):
    anchor: str
    ref_anchor: str
    heading: Md
    description: Md
    source: str
    shared: Md  # what every register of the group shares: space, firmware gate, poll class
    quick: tuple[QuickRow, ...]
    items: tuple[RegisterView | ArrayView, ...]

    @property
    def quick_rows(self) -> str:
        return "\n".join([r.row for r in self.quick])


class TimingView(NamedTuple):
    baud: str
    receive_to_send: str
    wait_after_receive: str
    send_to_receive: str
    total: str


class CommandView(NamedTuple):
    anchor: str
    name: Md
    title: str
    title_zh: str
    register: Md
    writes: Md
    frame: Md
    description: str
    source: str
    destructive: bool  # loses data or state (factory defaults, initialisation, encoder reset, software reset, forced enable)

    @property
    def row(self) -> str:
        name = f'<a id="{self.anchor}"></a>{self.name}' + (" **destructive**" if self.destructive else "")
        cells = (md_text(self.title), md_text(self.title_zh), self.register, self.writes, self.frame, md_text(self.description))
        return table_row((name, *cells, md_text(self.source)))


class FaultView(NamedTuple):
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

    @property
    def row(self) -> str:
        code = f'<a id="{self.anchor}"></a>{md_text(self.code)}'
        cells = (self.value, self.name, md_text(self.title), md_text(self.title_zh), md_text(self.kind), self.resettable)
        return table_row((code, *cells, md_text(self.description), md_text(self.source)))


class ExceptionView(NamedTuple):
    code: str
    name: Md
    title: str
    title_zh: str
    source: str

    @property
    def row(self) -> str:
        return table_row((self.code, self.name, md_text(self.title), md_text(self.title_zh), md_text(self.source)))


class ByteRow(NamedTuple):
    offset: str
    hex: str
    field: Md
    meaning: Md


class FrameView(NamedTuple):
    label: str
    hex: str
    rows: tuple[ByteRow, ...]
    problems: tuple[str, ...]

    @property
    def table(self) -> str:
        """The byte table's rows, one a line: one string, not four cells a byte for the template to print."""
        return "\n".join([f"| {b.offset} | `{b.hex}` | {b.field} | {b.meaning} |" for b in self.rows])


class DecodedRow(NamedTuple):
    register: Md
    address: Md
    raw: str
    value: Md
    recorded: Md


class ExampleView(NamedTuple):
    anchor: str
    heading: Md
    meaning: Md
    meaning_zh: str
    facts: tuple[Fact, ...]
    frames: tuple[FrameView, ...]
    decoded: tuple[DecodedRow, ...]
    notes: Md

    @property
    def decoded_rows(self) -> str:
        return "\n".join([f"| {d.register} | {d.address} | {d.raw} | {d.value} | {d.recorded} |" for d in self.decoded])


class ReadingView(NamedTuple):
    source: str
    says: str


class ErratumView(NamedTuple):
    anchor: str
    heading: Md
    readings: tuple[ReadingView, ...]
    choice: Md
    reason: Md
    links: tuple[Fact, ...]


class DevicePage(NamedTuple):
    header: tuple[str, ...]
    title: Md
    description: Md
    overview: tuple[Fact, ...]
    transport_notes: Md
    timing: tuple[TimingView, ...]
    quick_note: Md
    extra_headers: tuple[str, ...]  # the quick reference's and member tables' optional columns
    groups: tuple[GroupView, ...]
    enums: tuple[EnumView, ...]
    commands: tuple[CommandView, ...]
    any_destructive: bool  # some command is destructive: the table is followed by what that means
    faults: tuple[FaultView, ...]
    exceptions: tuple[ExceptionView, ...]
    exceptions_note: Md
    examples: tuple[ExampleView, ...]
    errata: tuple[ErratumView, ...]


_NO_LINKS = Md("")


class Context:
    """What the views of one device share: register look-ups and specs, the example and errata cross-links."""

    def __init__(self, device: Device) -> None:
        self.device = device
        self.uses = uses(device)
        self.registers = RegisterSpecs(device)
        self.examples_by_register: dict[str, list[str]] = {}
        self.responses: dict[str, list[str]] = {}
        self.enum_users: dict[str, list[Md]] = {}
        self.enum_views: dict[int, EnumView] = {}  # by id() of the EnumType (the device holds each for the run)
        self.value_cells: dict[str, ValueCells] = {}  # by register name
        for ex in device.examples:
            if ex.request is not None:
                self.responses.setdefault(ex.request, []).append(ex.id)
        for e in device.enums:
            self.enum_users[e.name] = []
        seen: set[tuple[str, str]] = set()
        for reg in device.registers:
            if reg.enum is None and not reg.bitfields:
                continue  # no value table to list it under (most registers), told without a generator over no bitfields
            if reg.enum is None and not any(b.enum is not None for b in reg.bitfields):
                continue  # nor one of its fields: its label is not needed
            owner = reg.array.array + "." + reg.array.member if reg.array else reg.name
            label = (
                Md(f"{md.link(md.code(reg.array.array), md.anchor('array', reg.array.array))} member {md.code(reg.array.member)}")
                if reg.array
                else md.link(md.code(reg.name), DocId(reg.name))
            )
            if reg.enum is not None and (reg.enum.name, owner) not in seen:
                seen.add((reg.enum.name, owner))
                self.enum_users[reg.enum.name].append(label)
            for b in reg.bitfields:
                if b.enum is not None and (b.enum.name, owner + ":" + b.name) not in seen:
                    seen.add((b.enum.name, owner + ":" + b.name))
                    self.enum_users[b.enum.name].append(Md(f"{label} bits {b.bits_text} ({md.code(b.name)})"))

    def example_links(self, names: Iterable[str]) -> Md:
        ids: list[str] = []
        for name in names:
            for ex in self.examples_by_register.get(name, []):
                if ex not in ids:
                    ids.append(ex)
        if not ids:  # most registers are in no example
            return _NO_LINKS
        return md.join([md.link(md.code(i), md.anchor("example", i)) for i in ids])
