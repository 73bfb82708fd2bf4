"""The views of one device's Structured Text: enums, constants, raw read-plan blocks, the typed values
and the functions. Every identifier, literal and statement is computed here, once per device: what a
dialect writes its own way (an enum value, a text type) waits as a `MemberConst` / `TextConst` /
`TextMember` until `spelled` with that dialect's `Notation`. The templates only print, escaping map text
with `st_comment`."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from regmap.backends.st.codec import NATURAL, Notation, swapped
from regmap.backends.st.names import Scope, StIdentifier, st_hex, st_int, st_real, st_string
from regmap.backends.st.view_types import (
    Const,
    EnumValue,
    EnumView,
    FunctionView,
    Member,
    MemberConst,
    Section,
    SectionToSpell,
    TextConst,
    new_const,
)
from regmap.core.text import manual_sections, number, sentences, titled, zone_text
from regmap.diagnostics import Diagnostic
from regmap.model import Access, Bitfield, Device, EnumType, PollClass, Register, WordOrder
from regmap.runtime_bridge import runtime_device

# By the access's value string (`_value_`), as the map writes it.
ACCESS_MEMBER = {access._value_: member for access, member in ((Access.READ, "R"), (Access.WRITE, "W"), (Access.READ_WRITE, "RW"))}


class Names:
    """The names of one device, the same in every dialect: every global one passes one case-insensitive scope."""

    def __init__(self, device: Device, problems: list[Diagnostic]) -> None:
        self.device = device
        self.problems = problems
        self.prefix = device.id
        self.globals = Scope(device, "a global name", problems)
        self.access_type = self.type("E", "ACCESS", what="the access type")
        self._comments: dict[int, str] = {}  # by the register's identity: its constants and its decoder ask

    def register_comment(self, reg: Register) -> str:
        """The register's comment (its constants' section, its member of the values struct), described once."""
        comment = self._comments.get(id(reg))
        if comment is None:
            comment = self._comments[id(reg)] = _describe(reg)
        return comment

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
    return reg.wide and reg.words == 2 and device.transport.word_order_register is not None and not reg.word_order_fixed


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


def enum_views(names: Names) -> list[EnumView]:
    """Every enum with its base type; a notation without one (plain IEC) drops it (`SpelledViews.enums`)."""
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
        comment = sentences(titled(e.title, e.title_zh), e.description, manual_sections(e.source))
        views.append(EnumView(type_name, _enum_base(e), comment, tuple(members)))
    return views


def enum_functions(names: Names, notation: Notation, enums: Sequence[EnumView]) -> list[FunctionView]:
    """FROM_RAW (a raw number into the enum, FALSE for a value the manual does not list) and
    TO_RAW of every enum: a CASE each way, which strict enums and matiec both accept."""
    functions = []
    for e, view in zip(names.device.enums, enums, strict=True):
        from_raw = names.function(e.name, "FROM_RAW", what=f"the decoder of enum {e.name}", pos=e.pos)
        to_raw = names.function(e.name, "TO_RAW", what=f"the encoder of enum {e.name}", pos=e.pos)
        spelled = [notation.member(view.type_name, m.name) for m in view.members]  # each member as both CASEs name it
        cases = [f"    {m.value}: eValue := {member};" for m, member in zip(view.members, spelled, strict=True)]
        functions.append(
            FunctionView(
                from_raw,
                "BOOL",
                f"{view.type_name} of a raw value; FALSE (eValue unchanged) for a value the manual does not list.",
                (Member("nRaw", "DINT"),),
                (Member("eValue", view.type_name),),
                (),
                ("CASE nRaw OF", *cases, "ELSE", f"    {from_raw} := FALSE;", "    RETURN;", "END_CASE;", f"{from_raw} := TRUE;"),
            )
        )
        back = [f"    {member}: {to_raw} := {m.value};" for m, member in zip(view.members, spelled, strict=True)]
        functions.append(
            FunctionView(
                to_raw,
                "DINT",
                f"The raw value of a {view.type_name}.",
                (Member("eValue", view.type_name),),
                (),
                (),
                ("CASE eValue OF", *back, "END_CASE;"),
            )
        )
    return functions


# -- constants ---------------------------------------------------------------------------------


POLL_VALUE = {PollClass.STATIC: 0, PollClass.FAST: 1, PollClass.NORMAL: 2, PollClass.SLOW: 3}
"""The poll-class constants' values (`<DEV>_POLL_STATIC` ... `_SLOW`)."""


def _literal(reg: Register, raw: int | float | str) -> str:
    if reg.type.is_string:
        return st_string(str(raw))
    if reg.type.is_bool:
        return "TRUE" if raw else "FALSE"
    if reg.type.is_float:
        return st_real(float(raw))
    return st_int(int(raw))


def _ratio(value: int) -> str:
    """DINT where the part fits, else LINT (an offset of a 64-bit counter may be large)."""
    return "DINT" if -(1 << 31) <= value < (1 << 31) else "LINT"


def _typed_const(name: str, reg: Register, value: str, comment: str = "") -> Const | TextConst:
    """A constant of the register's raw type."""
    if reg.type.is_string:
        return TextConst(name, 2 * reg.words, value, comment)
    return Const(name, NATURAL[reg.type], value, comment)


def register_consts(names: Names, reg: Register) -> SectionToSpell:
    what = f"register {reg.name}"
    c = StIdentifier.stem(names.prefix, reg.name).declared_in(names.globals, what, reg.pos)

    consts: list[Const | MemberConst | TextConst] = [
        new_const((c("ADDR"), "UINT", st_hex(reg.address), "")),
        new_const((c("WORDS"), "UINT", st_int(reg.words), "")),
        MemberConst(c("ACCESS"), names.access_type, ACCESS_MEMBER[reg.access._value_]),
    ]
    space = reg.space_info
    if space.name != "holding":
        writes = ", ".join(f"{op.replace('_', ' ')} 16#{code:02X}" for op, code in space.codes.items() if op != "read")
        consts.append(
            new_const(
                (
                    c("FUNCTION"),
                    "USINT",
                    st_hex(space.read, 2),
                    f"read with function 16#{space.read:02X} ({space.title})" + (f"; {writes}" if writes else ""),
                )
            )
        )
    if reg.type.numeric:
        consts += [
            new_const((c("RAW_MIN"), NATURAL[reg.type], _literal(reg, reg.raw_min), "")),
            new_const((c("RAW_MAX"), NATURAL[reg.type], _literal(reg, reg.raw_max), "")),
        ]
    elif reg.type.is_string:
        consts.append(
            new_const(
                (
                    c("BYTES"),
                    "UINT",
                    st_int(2 * reg.words),
                    f"text bytes ({reg.encoding}, padded with {'spaces' if reg.padding == 'space' else 'NUL'})",
                )
            )
        )
    if reg.default is not None:
        consts.append(_typed_const(c("DEFAULT"), reg, _literal(reg, reg.default)))
    if reg.type.numeric:
        consts += [
            new_const((c("SCALE_NUM"), "DINT", st_int(reg.scale.numerator), "value = raw * NUM / DEN")),
            new_const((c("SCALE_DEN"), "DINT", st_int(reg.scale.denominator), "")),
        ]
    if reg.offset_set:
        consts += [
            new_const(
                (
                    c("OFFSET_NUM"),
                    _ratio(reg.offset.numerator),
                    st_int(reg.offset.numerator),
                    "value = raw * SCALE_NUM / SCALE_DEN + OFFSET_NUM / OFFSET_DEN",
                )
            ),
            new_const((c("OFFSET_DEN"), _ratio(reg.offset.denominator), st_int(reg.offset.denominator), "")),
        ]
    if reg.wide:
        order = "device word order (parameter)" if configurable(names.device, reg) else f"{reg.word_order._value_.replace('_', ' ')}"
        consts.append(
            new_const(
                (
                    c("HIGH_WORD_FIRST"),
                    "BOOL",
                    "TRUE" if reg.word_order is WordOrder.HIGH_FIRST else "FALSE",
                    order if not configurable(names.device, reg) else f"{order}; this is its default",
                )
            )
        )
    if swapped(reg):
        consts.append(
            new_const((c("HIGH_BYTE_FIRST"), "BOOL", "FALSE", "each word arrives with its low byte first (ROL(word, 8) restores it)"))
        )
    if reg.paired:
        consts.append(
            new_const((c("FIRST_ADDR"), "UINT", st_hex(reg.first_address), "the unused high word a block read or a write starts at"))
        )
    if reg.firmware is not None:
        consts += firmware_consts(names, reg.name, reg.firmware.first, reg.firmware.until, what, reg.pos)
    consts += variants_const(names, reg.name, reg.variants, what, reg.pos)
    if reg.poll is not PollClass.NORMAL:
        consts.append(new_const((c("POLL"), "USINT", st_int(POLL_VALUE[reg.poll]), f"poll class {reg.poll.value}")))
    return SectionToSpell(names.register_comment(reg), tuple(consts))


def firmware_raw(names: Names, version: str) -> int | None:
    """The smallest raw value of the firmware register whose version is at least `version` (the
    versions grow with the raw value), or None when the device reports its version as text."""
    device = names.device
    firmware = device.info.firmware_register
    if firmware is None or firmware.format == "string" or not firmware.register.type.numeric:
        return None
    spec = runtime_device(device)
    wanted = tuple(int(p) for p in version.split("."))
    low, high = int(firmware.register.raw_min), int(firmware.register.raw_max) + 1
    while low < high:
        mid = (low + high) // 2
        if spec.firmware_version(mid) >= wanted:
            high = mid
        else:
            low = mid + 1
    return low


def firmware_consts(names: Names, label: str, first: str | None, until: str | None, what: str, pos: Any) -> list[Const]:
    """X_FIRMWARE_FROM / X_FIRMWARE_UNTIL: the firmware register's raw values between which X exists
    (FROM inclusive, UNTIL exclusive), or the version texts when the device reports text."""
    firmware = names.device.info.firmware_register
    out = []
    for key, version in (("FROM", first), ("UNTIL", until)):
        if version is None:
            continue
        raw = firmware_raw(names, version)
        name = names.const(label, "FIRMWARE", key, what=what, pos=pos)
        if raw is None or firmware is None:
            out.append(Const(name, "STRING", st_string(version), f"firmware {'>=' if key == 'FROM' else '<'} {version}"))
        elif raw > firmware.register.raw_max:
            names.globals._report(pos, f"firmware {version} of {label} is past every value {firmware.register.name} can report")
        else:
            relation = ">=" if key == "FROM" else "<"
            out.append(
                Const(
                    name,
                    NATURAL[firmware.register.type],
                    st_int(raw),
                    f"exists while {firmware.register.name} {relation} this (firmware {relation} {version})",
                )
            )
    return out


# Device variants: a DWORD bit per declared variant; a register or read block only some have gets their mask.
VARIANT_TYPE = "DWORD"  # a variant is a bit of it
VARIANT_BITS = 32


def _bit(device: Device, name: str) -> int:
    return 1 << [v.name for v in device.info.variants].index(name)


def variant_consts(names: Names) -> list[Const]:
    """<DEV>_VARIANT_<NAME>: one bit per declared variant, in the map's order (none for a map without variants)."""
    device = names.device
    if len(device.info.variants) > VARIANT_BITS:
        names.globals._report(
            device.info.id_pos, f"{len(device.info.variants)} variants: Structured Text gives each one bit of a DWORD (at most 32)"
        )
        return []
    return [
        Const(names.const("VARIANT", v.name, what=f"variant {v.name}"), VARIANT_TYPE, st_hex(_bit(device, v.name), 8), v.title)
        for v in device.info.variants
    ]


def variants_mask(device: Device, variants: Sequence[str]) -> int:
    """The bits of `variants`."""
    mask = 0
    for name in variants:
        mask |= _bit(device, name)
    return mask


def variants_const(names: Names, label: str, variants: Sequence[str], what: str, pos: Any) -> list[Const]:
    """<label>_VARIANTS: the mask of the variants that have it (none when every variant has it)."""
    if not variants or len(names.device.info.variants) > VARIANT_BITS:
        return []
    mask = st_hex(variants_mask(names.device, variants), 8)
    return [Const(names.const(label, "VARIANTS", what=what, pos=pos), VARIANT_TYPE, mask, f"only on {', '.join(variants)}")]


def _describe(reg: Register) -> str:
    facts = [f"{reg.type._value_} {reg.access._value_}"]  # _value_: an enum's .value is a Python-level property in 3.11
    if reg.zone is not None:  # the count a DT holds: UDINT_TO_DT (matiec, CODESYS, TwinCAT) gives the date and time
        facts.append(f"UDINT {zone_text(reg)}; UDINT_TO_DT of it is the DT, DT_TO_UDINT the way back (no zone converted)")
    if reg.unit:
        facts.append(f"unit {reg.unit}")
    if reg.scaled:
        facts.append(f"scale {number(reg.scale)}")
    if reg.scale_from is not None:
        facts.append(f"value = raw x 10^{reg.scale_from} (LREAL)")
    if reg.enum is not None:
        facts.append(f"values: enum {reg.enum.name}")
    if reg.paired:
        facts.append("low word of a 32-bit pair")
    if reg.space != "holding":
        facts.append(reg.space_info.title)
    if reg.offset_set:
        facts.append(f"offset {number(reg.offset)}")
    if swapped(reg):
        facts.append("bytes swapped")
    if reg.firmware is not None:
        facts.append(reg.firmware.text)
    if reg.poll is not PollClass.NORMAL:
        facts.append(f"poll {reg.poll._value_}")
    return sentences(f"{reg.label}: {titled(reg.title, reg.title_zh)}", ", ".join(facts), manual_sections(reg.source))


def bitfield_consts(names: Names, reg: Register) -> Section | None:
    if not reg.bitfields:
        return None
    digits = 4 * reg.words
    consts = []
    label = owner(reg)
    for b in reg.bitfields:
        what = f"bitfield {b.name} of {label}"
        consts.append(
            Const(names.const(label, b.name, "MASK", what=what, pos=b.pos), _word(reg), st_hex(b.mask, digits), _bitfield_comment(b))
        )
        consts.append(Const(names.const(label, b.name, "SHIFT", what=what, pos=b.pos), "UINT", st_int(b.lsb)))
    return Section(f"Bitfields of {label}.", tuple(consts))


def _bitfield_comment(b: Bitfield) -> str:
    head = f"bit{'s' if b.width > 1 else ''} {b.bits_text} {b.name}: {titled(b.title, b.title_zh)}"
    return sentences(head, f"Values: enum {b.enum.name}" if b.enum else None, b.description)


def _word(reg: Register) -> str:
    return {2: "DWORD", 4: "LWORD"}.get(reg.words, "WORD")


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
            manual_sections(a.source),
        )
        sections.append(Section(comment, tuple(consts)))
    return sections


def command_consts(names: Names) -> list[SectionToSpell]:
    sections = []
    for cmd in names.device.commands:
        what = f"command {cmd.name}"
        reg = cmd.register
        consts: list[Const | MemberConst | TextConst] = [
            Const(names.const("CMD", cmd.name, "ADDR", what=what, pos=cmd.pos), "UINT", st_hex(reg.address)),
            _typed_const(names.const("CMD", cmd.name, "VALUE", what=what, pos=cmd.pos), reg, st_int(cmd.value)),
        ]
        if cmd.argument is not None:
            arg = cmd.argument
            consts.append(Const(names.const("CMD", cmd.name, arg.name, "MIN", what=what, pos=cmd.pos), "DINT", st_int(arg.min), arg.title))
            consts.append(Const(names.const("CMD", cmd.name, arg.name, "MAX", what=what, pos=cmd.pos), "DINT", st_int(arg.max)))
        how = f"write {cmd.value}" + (f" + {cmd.argument.name}" if cmd.argument else "") + f" to {reg.label}"
        sections.append(
            SectionToSpell(
                sentences(f"{titled(cmd.title, cmd.title_zh)}: {how}", cmd.description, manual_sections(cmd.source)), tuple(consts)
            )
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
        ]
        kind = NATURAL[w.register.type]
        float_register = w.register.type.is_float

        def literal(value: int | float) -> str:
            return st_real(value) if float_register else st_int(int(value))

        if w.swap_value is not None:
            consts.append(
                Const(
                    c("WORD_ORDER_SWAP", what="the word-order parameter"),
                    kind,
                    literal(w.swap_value),
                    "written (in the current word order) to swap the word order; a trigger: send it once",
                )
            )
        else:
            assert w.high_first is not None and w.low_first is not None
            consts += [
                Const(c("WORD_ORDER_HIGH_FIRST", what="the word-order parameter"), kind, literal(w.high_first)),
                Const(c("WORD_ORDER_LOW_FIRST", what="the word-order parameter"), kind, literal(w.low_first)),
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
