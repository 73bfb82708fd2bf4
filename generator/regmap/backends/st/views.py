"""The views of one device's Structured Text: enums, constants, raw read-plan blocks, the typed values
and the functions. Every identifier, literal and statement is computed here, once per dialect; the
templates only print, escaping map text with `st_comment`."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from regmap.backends.st.names import Scope, StIdentifier, st_hex, st_int, st_real, st_string
from regmap.backends.text import eng, titled
from regmap.diagnostics import Diagnostic
from regmap.model import Access, Bitfield, Command, DataType, Device, EnumType, Register, WordOrder
from regmap.render import header_lines
from regmap.runtime_bridge import read_plan


@dataclass(frozen=True)
class Dialect:
    """What differs between CODESYS / TwinCAT and plain IEC 61131-3 (OpenPLC / matiec)."""

    name: str
    title: str
    pragmas: tuple[str, ...]  # before every enum type
    enum_base: bool  # `(...) UINT;`: CODESYS' enum base type
    qualified_enums: bool  # `E_X.MEMBER` (qualified_only) rather than the bare `MEMBER`

    def member(self, type_name: str, member: str) -> str:
        return f"{type_name}.{member}" if self.qualified_enums else member


CODESYS = Dialect("codesys", "CODESYS / TwinCAT 3", ("{attribute 'qualified_only'}", "{attribute 'strict'}"), True, True)
IEC = Dialect("iec", "IEC 61131-3 (OpenPLC / matiec)", (), False, False)
DIALECTS = (CODESYS, IEC)

NATURAL = {DataType.U16: "UINT", DataType.S16: "INT", DataType.U32: "UDINT", DataType.S32: "DINT"}
ACCESS_MEMBER = {Access.READ: "R", Access.WRITE: "W", Access.READ_WRITE: "RW"}


@dataclass(frozen=True)
class Const:
    name: str
    type: str
    value: str
    comment: str = ""  # plain text; the template escapes it


@dataclass(frozen=True)
class Member:
    name: str
    type: str
    comment: str = ""


@dataclass(frozen=True)
class EnumValue:
    name: str
    value: str
    comment: str


@dataclass(frozen=True)
class EnumView:
    type_name: str
    base: str
    comment: str
    members: tuple[EnumValue, ...]


@dataclass(frozen=True)
class StructView:
    type_name: str
    comment: str
    members: tuple[Member, ...]


@dataclass(frozen=True)
class FunctionView:
    name: str
    returns: str
    comment: str
    inputs: tuple[Member, ...]
    in_outs: tuple[Member, ...]
    locals: tuple[Member, ...]
    body: tuple[str, ...]  # ST statements, indented by the template


@dataclass(frozen=True)
class Section:
    comment: str
    consts: tuple[Const, ...]


def _sentence(text: str | None) -> str:
    text = " ".join((text or "").split())
    return text if not text or text[-1] in ".!?。" else text + "."


def sentences(*parts: str | None) -> str:
    return " ".join(filter(None, (_sentence(p) for p in parts)))


def _manual(source: tuple[str, ...]) -> str:
    return f"Manual {', '.join(source)}." if source else ""


class Names:
    """The names of one device: every global one passes one case-insensitive scope."""

    def __init__(self, device: Device, dialect: Dialect, problems: list[Diagnostic]) -> None:
        self.device = device
        self.dialect = dialect
        self.problems = problems
        self.prefix = device.id
        self.globals = Scope(device, "a global name", problems)
        self.access_type = self.type("E", "ACCESS", what="the access type")

    def const(self, *parts: str, what: str, pos: Any = None) -> str:
        return self.globals.add(StIdentifier(self.prefix, *parts), what, pos)

    def type(self, kind: str, *parts: str, what: str, pos: Any = None) -> str:
        return self.globals.add(StIdentifier(kind, self.prefix, *parts), what, pos)

    def function(self, *parts: str, what: str, pos: Any = None) -> str:
        return self.globals.add(StIdentifier("F", self.prefix, *parts), what, pos)

    def scope(self, what: str) -> Scope:
        return Scope(self.device, what, self.problems)

    def enum_type(self, e: EnumType) -> str:
        return StIdentifier("E", self.prefix, e.name)  # declared once, by `enum_views`


def owner(reg: Register) -> str:
    """The name shared by every element of an array member (`pr_path_position`), else the register's."""
    return f"{reg.array.array}_{reg.array.member}" if reg.array else reg.name


def configurable(device: Device, reg: Register) -> bool:
    """A 32-bit register whose word order follows the device's word-order parameter (C630S P0C-26)."""
    return reg.words == 2 and device.transport.word_order_register is not None and not reg.word_order_fixed


def needs_order_input(device: Device, regs: Sequence[Register]) -> bool:
    return any(configurable(device, r) for r in regs)


# -- enums -------------------------------------------------------------------------------------


def _enum_base(e: EnumType) -> str:
    values = [m.value for m in e.members]
    if all(0 <= v <= 0xFFFF for v in values):
        return "UINT"
    if all(-(1 << 15) <= v < (1 << 15) for v in values):
        return "INT"
    return "DINT"


def enum_views(names: Names, dialect: Dialect) -> list[EnumView]:
    views = []
    for e in names.device.enums:
        type_name = names.type("E", e.name, what=f"the type of enum {e.name}", pos=e.pos)
        scope = names.scope(f"a member of enum {e.name}")
        members = []
        for m in e.members:
            if not -(1 << 31) <= m.value < (1 << 31):
                names.globals._report(e.pos, f"enum {e.name} member {m.name} = {m.value} does not fit a DINT, an ST enum's widest base")
            members.append(
                EnumValue(
                    scope.add(StIdentifier(m.name), f"member {m.name}", e.pos),
                    st_int(m.value),
                    sentences(titled(m.title, m.title_zh) + (f" [{m.symbol}]" if m.symbol else ""), m.description),
                )
            )
        comment = sentences(titled(e.title, e.title_zh), e.description, _manual(e.source))
        views.append(EnumView(type_name, _enum_base(e) if dialect.enum_base else "", comment, tuple(members)))
    return views


def enum_functions(names: Names, dialect: Dialect, enums: Sequence[EnumView]) -> list[FunctionView]:
    """FROM_RAW (a raw number into the enum, FALSE for a value the manual does not list) and
    TO_RAW of every enum: a CASE each way, which strict enums and matiec both accept."""
    functions = []
    for e, view in zip(names.device.enums, enums, strict=True):
        from_raw = names.function(e.name, "FROM_RAW", what=f"the decoder of enum {e.name}", pos=e.pos)
        to_raw = names.function(e.name, "TO_RAW", what=f"the encoder of enum {e.name}", pos=e.pos)
        cases = [f"    {m.value}: eValue := {dialect.member(view.type_name, m.name)};" for m in view.members]
        functions.append(
            FunctionView(
                from_raw,
                "BOOL",
                f"{view.type_name} of a raw value; FALSE (eValue unchanged) for a value the manual does not list.",
                (Member("nRaw", "DINT"),),
                (Member("eValue", view.type_name),),
                (),
                ("CASE nRaw OF", *cases, "ELSE", f"    {from_raw} := FALSE;", "    RETURN;", "END_CASE", f"{from_raw} := TRUE;"),
            )
        )
        back = [f"    {dialect.member(view.type_name, m.name)}: {to_raw} := {m.value};" for m in view.members]
        functions.append(
            FunctionView(
                to_raw,
                "DINT",
                f"The raw value of a {view.type_name}.",
                (Member("eValue", view.type_name),),
                (),
                (),
                ("CASE eValue OF", *back, "END_CASE"),
            )
        )
    return functions


# -- constants ---------------------------------------------------------------------------------


def register_consts(names: Names, reg: Register) -> Section:
    what = f"register {reg.name}"
    t = NATURAL[reg.type]
    consts = [
        Const(names.const(reg.name, "ADDR", what=what, pos=reg.pos), "UINT", st_hex(reg.address)),
        Const(names.const(reg.name, "WORDS", what=what, pos=reg.pos), "UINT", st_int(reg.words)),
        Const(
            names.const(reg.name, "ACCESS", what=what, pos=reg.pos),
            names.access_type,
            names.dialect.member(names.access_type, ACCESS_MEMBER[reg.access]),
        ),
        Const(names.const(reg.name, "RAW_MIN", what=what, pos=reg.pos), t, st_int(reg.raw_min)),
        Const(names.const(reg.name, "RAW_MAX", what=what, pos=reg.pos), t, st_int(reg.raw_max)),
    ]
    if reg.default is not None:
        consts.append(Const(names.const(reg.name, "DEFAULT", what=what, pos=reg.pos), t, st_int(reg.default)))
    consts += [
        Const(names.const(reg.name, "SCALE_NUM", what=what, pos=reg.pos), "DINT", st_int(reg.scale.numerator), "value = raw * NUM / DEN"),
        Const(names.const(reg.name, "SCALE_DEN", what=what, pos=reg.pos), "DINT", st_int(reg.scale.denominator)),
    ]
    if reg.words == 2:
        order = "device word order (parameter)" if configurable(names.device, reg) else f"{reg.word_order.value.replace('_', ' ')}"
        consts.append(
            Const(
                names.const(reg.name, "HIGH_WORD_FIRST", what=what, pos=reg.pos),
                "BOOL",
                "TRUE" if reg.word_order is WordOrder.HIGH_FIRST else "FALSE",
                order if not configurable(names.device, reg) else f"{order}; this is its default",
            )
        )
    if reg.paired:
        consts.append(
            Const(
                names.const(reg.name, "FIRST_ADDR", what=what, pos=reg.pos),
                "UINT",
                st_hex(reg.first_address),
                "the unused high word a block read or a write starts at",
            )
        )
    return Section(_register_comment(reg), tuple(consts))


def _register_comment(reg: Register) -> str:
    facts = [f"{reg.type.value} {reg.access.value}"]
    if reg.unit:
        facts.append(f"unit {reg.unit}")
    if reg.scaled:
        facts.append(f"scale {eng(reg, 1)}")
    if reg.enum is not None:
        facts.append(f"values: enum {reg.enum.name}")
    if reg.paired:
        facts.append("low word of a 32-bit pair")
    return sentences(f"{reg.label}: {titled(reg.title, reg.title_zh)}", ", ".join(facts), _manual(reg.source))


def bitfield_consts(names: Names, reg: Register) -> Section | None:
    if not reg.bitfields:
        return None
    digits = 4 * reg.words
    consts = []
    for b in reg.bitfields:
        what = f"bitfield {b.name} of {owner(reg)}"
        consts.append(
            Const(names.const(owner(reg), b.name, "MASK", what=what, pos=b.pos), _word(reg), st_hex(b.mask, digits), _bitfield_comment(b))
        )
        consts.append(Const(names.const(owner(reg), b.name, "SHIFT", what=what, pos=b.pos), "UINT", st_int(b.lsb)))
    return Section(f"Bitfields of {owner(reg)}.", tuple(consts))


def _bitfield_comment(b: Bitfield) -> str:
    head = f"bit{'s' if b.width > 1 else ''} {b.bits_text} {b.name}: {titled(b.title, b.title_zh)}"
    return sentences(head, f"Values: enum {b.enum.name}" if b.enum else None, b.description)


def _word(reg: Register) -> str:
    return "DWORD" if reg.words == 2 else "WORD"


def array_consts(names: Names) -> list[Section]:
    sections = []
    for a in names.device.arrays:
        what = f"array {a.name}"
        consts = [
            Const(names.const(a.name, "BASE", what=what), "UINT", st_hex(a.base)),
            Const(names.const(a.name, "FIRST", what=what), "UINT", st_int(a.first_index)),
            Const(names.const(a.name, "LAST", what=what), "UINT", st_int(a.last_index)),
            Const(names.const(a.name, "COUNT", what=what), "UINT", st_int(a.count)),
            Const(names.const(a.name, "STRIDE", what=what), "UINT", st_int(a.stride)),
        ]
        consts += [Const(names.const(a.name, m.name, "OFFSET", what=what), "UINT", st_int(m.offset), m.title) for m in a.members]
        comment = sentences(
            titled(a.title, a.title_zh)
            + ": member m of element n is at BASE + STRIDE * (n - FIRST) + OFFSET of m; every element's address is a constant below",
            _manual(a.source),
        )
        sections.append(Section(comment, tuple(consts)))
    return sections


def command_consts(names: Names) -> list[Section]:
    sections = []
    for cmd in names.device.commands:
        what = f"command {cmd.name}"
        reg = cmd.register
        consts = [
            Const(names.const("CMD", cmd.name, "ADDR", what=what, pos=cmd.pos), "UINT", st_hex(reg.address)),
            Const(names.const("CMD", cmd.name, "VALUE", what=what, pos=cmd.pos), NATURAL[reg.type], st_int(cmd.value)),
        ]
        if cmd.argument is not None:
            arg = cmd.argument
            consts.append(Const(names.const("CMD", cmd.name, arg.name, "MIN", what=what, pos=cmd.pos), "DINT", st_int(arg.min), arg.title))
            consts.append(Const(names.const("CMD", cmd.name, arg.name, "MAX", what=what, pos=cmd.pos), "DINT", st_int(arg.max)))
        how = f"write {cmd.value}" + (f" + {cmd.argument.name}" if cmd.argument else "") + f" to {reg.label}"
        sections.append(
            Section(sentences(f"{titled(cmd.title, cmd.title_zh)}: {how}", cmd.description, _manual(cmd.source)), tuple(consts))
        )
    return sections


def device_consts(names: Names) -> Section:
    d = names.device
    t = d.transport
    c = names.const
    consts = [
        Const(c("MAP_VERSION", what="the map version"), "STRING", st_string(d.info.map_version)),
        Const(c("MAP_FINGERPRINT", what="the map fingerprint"), "STRING", st_string(d.fingerprint)),
        Const(
            c("DEFAULT_BAUD", what="the baud rate"),
            "UDINT",
            st_int(t.baud),
            "baud rates: " + ", ".join(map(str, t.baud_rates)) if t.baud_rates else "",
        ),
        Const(c("PARITY", what="the parity"), "STRING", st_string(t.parity)),
        Const(c("DATA_BITS", what="the data bits"), "UINT", st_int(t.data_bits)),
        Const(c("STOP_BITS", what="the stop bits"), "UINT", st_int(t.stop_bits)),
        Const(c("SLAVE_MIN", what="the slave ids"), "UINT", st_int(t.slave_min)),
        Const(c("SLAVE_MAX", what="the slave ids"), "UINT", st_int(t.slave_max)),
        Const(c("HAS_BROADCAST", what="broadcast"), "BOOL", "TRUE" if t.broadcast_id is not None else "FALSE"),
    ]
    if t.broadcast_id is not None:
        consts.append(Const(c("BROADCAST_ID", what="broadcast"), "UINT", st_int(t.broadcast_id), "a request to it is not answered"))
    consts += [
        Const(c("MAX_READ_REGISTERS", what="the read limit"), "UINT", st_int(t.max_read_registers)),
        Const(c("MAX_WRITE_REGISTERS", what="the write limit"), "UINT", st_int(t.max_write_registers)),
        Const(
            c("HIGH_WORD_FIRST", what="the word order"),
            "BOOL",
            "TRUE" if t.word_order is WordOrder.HIGH_FIRST else "FALSE",
            "order of the words of 32-bit values" + (" (the default of the word-order parameter)" if t.word_order_register else ""),
        ),
    ]
    if t.word_order_register is not None:
        w = t.word_order_register
        consts += [
            Const(
                c("WORD_ORDER_REGISTER_ADDR", what="the word-order parameter"),
                "UINT",
                st_hex(w.register.address),
                f"{w.register.label} selects the word order",
            ),
            Const(c("WORD_ORDER_HIGH_FIRST", what="the word-order parameter"), NATURAL[w.register.type], st_int(w.high_first)),
            Const(c("WORD_ORDER_LOW_FIRST", what="the word-order parameter"), NATURAL[w.register.type], st_int(w.low_first)),
        ]
    if t.max_message_bytes is not None:
        consts.append(Const(c("MAX_MESSAGE_BYTES", what="the message limit"), "UINT", st_int(t.max_message_bytes)))
    if t.response_delay_ms is not None:
        consts.append(
            Const(c("RESPONSE_DELAY_US", what="the response delay"), "UDINT", st_int(round(t.response_delay_ms * 1000)), "response delay")
        )
    consts += [
        Const(c("EXCEPTION", e.name, what=f"exception {e.name}"), "USINT", st_int(e.code), titled(e.title, e.title_zh))
        for e in t.exceptions
    ]
    return Section("The device and its serial line.", tuple(consts))


# -- read plan: raw blocks and their decoders --------------------------------------------------


@dataclass(frozen=True)
class Block:
    address: int
    count: int
    struct: StructView
    registers: tuple[Register, ...]
    consts: tuple[Const, ...]
    decode: FunctionView


def _raw_member_type(reg: Register) -> str:
    if reg.words == 2:
        return "ARRAY[0..1] OF WORD"
    return "WORD" if reg.bitfields else NATURAL[reg.type]


def _combine(device: Device, reg: Register, words: str) -> list[str]:
    """Statements that set `dw` from a 32-bit register's two words (`<words>[0]`, `[1]`) in wire order."""
    high_first = f"dw := SHL(WORD_TO_DWORD({words}[0]), 16) OR WORD_TO_DWORD({words}[1]);"
    low_first = f"dw := SHL(WORD_TO_DWORD({words}[1]), 16) OR WORD_TO_DWORD({words}[0]);"
    if configurable(device, reg):
        return ["IF bHighWordFirst THEN", f"    {high_first}", "ELSE", f"    {low_first}", "END_IF;"]
    return [high_first if reg.word_order is WordOrder.HIGH_FIRST else low_first]


class Values:
    """The typed values struct (`ST_<DEV>_VALUES`): one member per readable register, and one per bitfield."""

    def __init__(self, names: Names, dialect: Dialect) -> None:
        self.names = names
        self.dialect = dialect
        self.scope = names.scope("a member of the values struct")
        self.members: list[Member] = []
        self.type_name = names.type("ST", "VALUES", what="the values struct")

    def add(self, reg: Register) -> list[str]:
        """Declare the register's members; the statements that decode it from `stRaw`."""
        names = self.names
        member = self.scope.add(StIdentifier(reg.name), f"register {reg.name}", reg.pos)
        raw = f"stRaw.{member}"
        target = f"stValues.{member}"
        natural = NATURAL[reg.type]
        lines: list[str] = []
        if reg.words == 2:
            lines += _combine(names.device, reg, raw)
            value = f"DWORD_TO_{natural}(dw)"
        else:
            value = raw
        comment = _register_comment(reg)
        if reg.bitfields:
            self.members.append(Member(member, _word(reg), comment))
            lines.append(f"{target} := {'dw' if reg.words == 2 else raw};")
            for b in reg.bitfields:
                field = self.scope.add(StIdentifier(reg.name, b.name), f"bitfield {b.name} of {reg.name}", b.pos)
                getter = f"{getter_name(names, reg, b)}({target})"
                if b.enum is not None:
                    self.members.append(Member(field, names.enum_type(b.enum), _bitfield_comment(b)))
                    decoder = StIdentifier("F", names.prefix, b.enum.name, "FROM_RAW")
                    lines += [
                        f"IF NOT {decoder}(nRaw := UINT_TO_DINT({getter}), eValue := stValues.{field}) THEN",
                        "    bOk := FALSE;",
                        "END_IF;",
                    ]
                else:
                    self.members.append(Member(field, "BOOL" if b.width == 1 else "UINT", _bitfield_comment(b)))
                    lines.append(f"stValues.{field} := {getter};")
        elif reg.enum is not None:
            self.members.append(Member(member, names.enum_type(reg.enum), comment))
            decoder = StIdentifier("F", names.prefix, reg.enum.name, "FROM_RAW")
            as_dint = value if natural == "DINT" else f"{natural}_TO_DINT({value})"
            lines += [f"IF NOT {decoder}(nRaw := {as_dint}, eValue := {target}) THEN", "    bOk := FALSE;", "END_IF;"]
        elif reg.scaled:
            self.members.append(Member(member, "REAL", comment))
            ratio = f"{st_real(reg.scale.numerator)} / {st_real(reg.scale.denominator)}"
            lines.append(f"{target} := LREAL_TO_REAL({natural}_TO_LREAL({value}) * {ratio});")
        else:
            self.members.append(Member(member, natural, comment))
            lines.append(f"{target} := {value};")
        return lines

    def struct(self) -> StructView:
        return StructView(
            self.type_name, "Decoded values of every readable register (the Python client's read_all()).", tuple(self.members)
        )


def getter_name(names: Names, reg: Register, b: Bitfield) -> StIdentifier:
    return StIdentifier("F", names.prefix, owner(reg), "GET", b.name)


def blocks(names: Names, values: Values) -> list[Block]:
    device = names.device
    out = []
    plan = read_plan(device)
    for index, block in enumerate(plan):
        tag = f"{block.address:04X}"
        what = f"read block {index} at 0x{tag}"
        regs = tuple(device.register(spec.name) for spec in block.registers)
        scope = names.scope(f"a member of raw block 0x{tag}")
        members: list[Member] = []
        at_address = {r.address: r for r in regs}
        address = block.address
        end = block.address + block.count
        while address < end:
            reg = at_address.get(address)
            if reg is None:
                pair = at_address.get(address + 1)
                why = (
                    f"unused high word of {pair.label}" if pair is not None and pair.paired else "a word no register of the read describes"
                )
                members.append(Member(scope.add(StIdentifier("RESERVED", f"{address:04X}"), why), "WORD", why))
                address += 1
                continue
            members.append(
                Member(
                    scope.add(StIdentifier(reg.name), f"register {reg.name}", reg.pos),
                    _raw_member_type(reg),
                    f"{reg.label} at {st_hex(address)}",
                )
            )
            address += reg.words
        struct = StructView(
            names.type("ST", "RAW", tag, what=what),
            f"Read block {index}: {block.count} words from {st_hex(block.address)} in wire order (one Modbus read-holding-registers request).",
            tuple(members),
        )
        consts = (
            Const(names.const("BLOCK", tag, "ADDR", what=what), "UINT", st_hex(block.address)),
            Const(names.const("BLOCK", tag, "COUNT", what=what), "UINT", st_int(block.count)),
        )
        body = ["bOk := TRUE;"]
        for reg in regs:
            body += values.add(reg)
        name = names.function("DECODE", tag, what=what)
        body.append(f"{name} := bOk;")
        inputs = [Member("stRaw", struct.type_name)]
        if needs_order_input(device, regs):
            inputs.append(Member("bHighWordFirst", "BOOL", "the device's word-order parameter"))
        local = [Member("bOk", "BOOL")]
        if any(r.words == 2 for r in regs):
            local.append(Member("dw", "DWORD"))
        decode = FunctionView(
            name,
            "BOOL",
            f"Decode read block {index} into stValues; FALSE when a register holds a value its enum does not list (that member keeps its old value).",
            tuple(inputs),
            (Member("stValues", values.type_name),),
            tuple(local),
            tuple(body),
        )
        out.append(Block(block.address, block.count, struct, regs, consts, decode))
    return out


# -- bitfield accessors and encoders -------------------------------------------------------------


def owners(device: Device) -> list[list[Register]]:
    """Registers grouped by owner: one list per plain register, one per array member (its elements)."""
    grouped: dict[str, list[Register]] = {}
    for reg in device.registers:
        grouped.setdefault(owner(reg), []).append(reg)
    return list(grouped.values())


def bitfield_functions(names: Names) -> list[FunctionView]:
    functions = []
    for regs in owners(names.device):
        reg = regs[0]
        word = _word(reg)
        for b in reg.bitfields:
            # Literals, not the MASK / SHIFT constants: an IEC function cannot see global variables.
            mask = st_hex(b.mask, 4 * reg.words)
            shift = st_int(b.lsb)
            what = f"the accessors of bitfield {b.name} of {owner(reg)}"
            get = names.globals.add(getter_name(names, reg, b), what, b.pos)
            put = names.function(owner(reg), "SET", b.name, what=what, pos=b.pos)
            to_uint = f"{word}_TO_UINT(SHR(nWord AND {mask}, {shift}))"
            get_body: tuple[str, ...]
            set_body: tuple[str, ...]
            if b.width == 1:
                get_body = (f"{get} := (nWord AND {mask}) <> 0;",)
                set_body = ("IF bValue THEN", f"    {put} := nWord OR {mask};", "ELSE", f"    {put} := nWord AND NOT {mask};", "END_IF;")
                value = Member("bValue", "BOOL")
                returns = "BOOL"
            else:
                get_body = (f"{get} := {to_uint};",)
                set_body = (f"{put} := (nWord AND NOT {mask}) OR (SHL(UINT_TO_{word}(nValue), {shift}) AND {mask});",)
                value = Member("nValue", "UINT")
                returns = "UINT"
            functions.append(
                FunctionView(
                    get, returns, f"Bits {b.bits_text} ({b.name}) of a {owner(reg)} word.", (Member("nWord", word),), (), (), get_body
                )
            )
            functions.append(
                FunctionView(
                    put,
                    word,
                    f"The {owner(reg)} word with bits {b.bits_text} ({b.name}) replaced; every other bit kept.",
                    (Member("nWord", word), value),
                    (),
                    (),
                    set_body,
                )
            )
    return functions


def _range_lines(name: str, lo: int, hi: int) -> list[str]:
    return [f"IF nRaw < {lo} OR nRaw > {hi} THEN", f"    {name} := FALSE;", "    RETURN;", "END_IF;"]


def _put_words(device: Device, reg: Register, output: str) -> list[str]:
    natural = NATURAL[reg.type]
    if reg.words == 1:
        word = f"{natural}_TO_WORD(LINT_TO_{natural}(nRaw))"
        if not reg.paired:
            return [f"{output} := {word};"]
        return [
            "IF nRaw < 0 THEN",
            f"    {output}[0] := 16#FFFF;",
            "ELSE",
            f"    {output}[0] := 16#0000;",
            "END_IF;",
            f"{output}[1] := {word};",
        ]
    lines = [f"dw := {natural}_TO_DWORD(LINT_TO_{natural}(nRaw));"]
    high = [f"{output}[0] := DWORD_TO_WORD(SHR(dw, 16));", f"{output}[1] := DWORD_TO_WORD(dw);"]
    low = [f"{output}[0] := DWORD_TO_WORD(dw);", f"{output}[1] := DWORD_TO_WORD(SHR(dw, 16));"]
    if configurable(device, reg):
        return [*lines, "IF bHighWordFirst THEN", *("    " + s for s in high), "ELSE", *("    " + s for s in low), "END_IF;"]
    return [*lines, *(high if reg.word_order is WordOrder.HIGH_FIRST else low)]


def encoders(names: Names) -> list[FunctionView]:
    """An encoder per writable register (one per array member when its elements share the range):
    the value into the words to write, or FALSE (words unchanged) when the Python client would
    refuse it (out of range, not a multiple of the resolution, not a member of the enum)."""
    device = names.device
    functions = []
    for regs in owners(device):
        reg = regs[0]
        if not reg.access.writable:
            continue
        uniform = len({(r.raw_min, r.raw_max) for r in regs}) == 1
        for r in [reg] if uniform else regs:
            functions.append(_encoder(names, r, owner(r) if uniform else r.name))
    return functions


def _encoder(names: Names, reg: Register, label: str) -> FunctionView:
    device = names.device
    name = names.function("ENCODE", label, what=f"the encoder of {label}", pos=reg.pos)
    natural = NATURAL[reg.type]
    inputs: list[Member] = []
    local = [Member("nRaw", "LINT")]
    body: list[str] = []
    checked = (reg.raw_min, reg.raw_max) != (reg.type.raw_min, reg.type.raw_max)
    if reg.bitfields:
        inputs.append(Member("nValue", _word(reg), "the whole word; build it with the SET functions"))
        body.append(f"nRaw := {natural}_TO_LINT({_word(reg)}_TO_{natural}(nValue));")
        for b in reg.bitfields:
            if b.enum is not None:
                local_name = StIdentifier("e", b.name)
                local.append(Member(local_name, names.enum_type(b.enum)))
                decoder = StIdentifier("F", names.prefix, b.enum.name, "FROM_RAW")
                body += [
                    f"IF NOT {decoder}(nRaw := UINT_TO_DINT({getter_name(names, reg, b)}(nValue)), eValue := {local_name}) THEN",
                    f"    {name} := FALSE;",
                    "    RETURN;",
                    "END_IF;",
                ]
    elif reg.enum is not None:
        inputs.append(Member("eValue", names.enum_type(reg.enum)))
        body.append(f"nRaw := DINT_TO_LINT({StIdentifier('F', names.prefix, reg.enum.name, 'TO_RAW')}(eValue));")
        checked = True
    elif reg.scaled:
        inputs.append(Member("fValue", "LREAL", f"in {reg.unit}" if reg.unit else "engineering value"))
        local.append(Member("rRaw", "LREAL"))
        ratio = f"{st_real(reg.scale.denominator)} / {st_real(reg.scale.numerator)}"
        body += [
            f"rRaw := fValue * {ratio};",
            f"IF NOT (rRaw >= {st_real(reg.raw_min - 1)} AND rRaw <= {st_real(reg.raw_max + 1)}) THEN",  # NaN fails too
            f"    {name} := FALSE;",
            "    RETURN;",
            "END_IF;",
            "nRaw := LREAL_TO_LINT(rRaw);",
            "IF ABS(rRaw - LINT_TO_LREAL(nRaw)) > 0.001 THEN",
            f"    {name} := FALSE;",
            "    RETURN;",
            "END_IF;",
        ]
        checked = True
    else:
        inputs.append(Member("nValue", natural))
        body.append(f"nRaw := {natural}_TO_LINT(nValue);")
    if checked:
        body += _range_lines(name, reg.raw_min, reg.raw_max)
    if configurable(device, reg):
        inputs.append(Member("bHighWordFirst", "BOOL", "the device's word-order parameter"))
    if reg.words == 2:
        local.append(Member("dw", "DWORD"))
    output = "nWord" if reg.words == 1 and not reg.paired else "aWords"
    out_type = "WORD" if output == "nWord" else "ARRAY[0..1] OF WORD"
    body += _put_words(device, reg, output)
    body.append(f"{name} := TRUE;")
    where = "FIRST_ADDR (the pair's unused high word first)" if reg.paired else "ADDR"
    comment = sentences(
        f"The word{'s' if output == 'aWords' else ''} to write to {label} (at its {where})",
        f"range {eng(reg, reg.raw_min)}..{eng(reg, reg.raw_max)}{f' {reg.unit}' if reg.unit else ''}",
        "FALSE, the words unchanged, when the Python client would refuse the value",
    )
    return FunctionView(name, "BOOL", comment, tuple(inputs), (Member(output, out_type),), tuple(local), tuple(body))


def _encoder_input(reg: Register) -> str:
    if reg.bitfields or not (reg.enum is not None or reg.scaled):
        return "nValue"
    return "eValue" if reg.enum is not None else "fValue"


def command_functions(names: Names) -> list[FunctionView]:
    functions = []
    for cmd in names.device.commands:
        if cmd.argument is None:
            continue
        functions.append(_command_function(names, cmd))
    return functions


def _command_function(names: Names, cmd: Command) -> FunctionView:
    arg = cmd.argument
    assert arg is not None
    reg = cmd.register
    name = names.function("CMD", cmd.name, what=f"the helper of command {cmd.name}", pos=cmd.pos)
    body = [
        f"IF nValue < {arg.min} OR nValue > {arg.max} THEN",
        f"    {name} := FALSE;",
        "    RETURN;",
        "END_IF;",
        f"nRaw := DINT_TO_LINT({cmd.value} + nValue);",
        *_range_lines(name, reg.raw_min, reg.raw_max),
        *_put_words(names.device, reg, "nWord" if reg.words == 1 and not reg.paired else "aWords"),
        f"{name} := TRUE;",
    ]
    inputs = [Member("nValue", "DINT", arg.title or arg.name)]
    if configurable(names.device, reg):
        inputs.append(Member("bHighWordFirst", "BOOL"))
    output = "nWord" if reg.words == 1 and not reg.paired else "aWords"
    local = [Member("nRaw", "LINT"), *([Member("dw", "DWORD")] if reg.words == 2 else [])]
    return FunctionView(
        name,
        "BOOL",
        f"The word(s) of command {cmd.name} ({cmd.value} + {arg.name}); FALSE when {arg.name} is outside {arg.min}..{arg.max}.",
        tuple(inputs),
        (Member(output, "WORD" if output == "nWord" else "ARRAY[0..1] OF WORD"),),
        tuple(local),
        tuple(body),
    )


# -- the whole device --------------------------------------------------------------------------


def device_views(device: Device, dialect: Dialect, problems: list[Diagnostic]) -> dict[str, Any]:
    names = Names(device, dialect, problems)
    enums = enum_views(names, dialect)
    values = Values(names, dialect)
    plan = blocks(names, values)
    registers = []
    for reg in device.registers:
        registers.append(register_consts(names, reg))
    bitfields = []
    for regs in owners(device):
        section = bitfield_consts(names, regs[0])
        if section is not None:
            bitfields.append(section)
    access = EnumView(
        names.access_type,
        "UINT" if dialect.enum_base else "",
        "Access of a register.",
        (EnumValue("R", "1", "read only"), EnumValue("W", "2", "write only"), EnumValue("RW", "3", "read and write")),
    )
    functions = [*enum_functions(names, dialect, enums), *bitfield_functions(names)]
    functions += [b.decode for b in plan]
    functions += encoders(names)
    functions += command_functions(names)
    writable = next((r for r in device.registers if r.access.writable and r.array is None and not r.bitfields), None)
    example = None
    if writable is not None:
        example = {
            "register": writable,
            "encoder": StIdentifier("F", device.id, "ENCODE", writable.name),
            "addr": StIdentifier(device.id, writable.name, "FIRST_ADDR" if writable.paired else "ADDR"),
            "words": writable.span if writable.paired else writable.words,
            "input": _encoder_input(writable),
        }
    plan_len = Const(
        names.const("READ_PLAN_LEN", what="the read plan"), "UINT", st_int(len(plan)), "requests that read every readable register"
    )
    return {
        "header": header_lines(device, "regmap generate"),
        "device": device,
        "dialect": dialect,
        "enums": [access, *enums],
        "device_consts": device_consts(names),
        "registers": registers,
        "arrays": array_consts(names),
        "bitfields": bitfields,
        "commands": command_consts(names),
        "plan": plan,
        "plan_len": plan_len,
        "values": values.struct(),
        "functions": functions,
        "order_input": needs_order_input(device, device.registers),
        "example": example,
    }
