"""The statements of one device's Structured Text: the raw read-plan blocks and their decoders, bitfield
accessors; the encoders and command helpers are in encoders.py."""

from __future__ import annotations

import operator
import weakref

from regmap.backends.st import scaling
from regmap.backends.st.codec import (
    NATURAL,
    Dialect,
    Helpers,
    Notation,
    assemble64,
    halves64,
    swapped,
    value_type,
)
from regmap.backends.st.names import StIdentifier, st_hex, st_int, st_real
from regmap.backends.st.view_types import Const, FunctionView, Member, Section, StructView, TextMember
from regmap.backends.st.views import (
    POLL_VALUE,
    Names,
    _bitfield_comment,
    _word,
    configurable,
    firmware_consts,
    needs_order_input,
    owner,
    variants_const,
)
from regmap.core.text import na_list
from regmap.model import Bitfield, DataType, Device, FirmwareGate, PollClass, Register, WordOrder
from regmap.records import cached_property, dataclass
from regmap.runtime_bridge import read_plan
from regmap_runtime.plan import ReadBlock

# How the README and the TwinCAT / CODESYS examples name each space's read.
SPACE_READ = {
    "holding": ("ReadRegs", "Read Holding Registers"),
    "input": ("ReadInputRegs", "Read Input Registers"),
    "coil": ("ReadCoils", "Read Coils"),
    "discrete_input": ("ReadInputStatus", "Read Discrete Inputs"),
}
SPACE_TAG = {"holding": "", "input": "INPUT", "coil": "COIL", "discrete_input": "DISCRETE"}


@dataclass(frozen=True)
class Block:
    address: int
    count: int
    struct: StructView
    registers: tuple[Register, ...]
    consts: tuple[Const, ...]
    decode: FunctionView  # for a dialect with UNIONs (CODESYS / TwinCAT)
    exact_decode: FunctionView  # for one without (its float helpers refuse infinity and NaN): only the comment differs
    space: str = "holding"
    bits: bool = False
    read_call: str = "ReadRegs"
    channel: str = "Read Holding Registers"
    function: int = 0x03

    def decoder(self, dialect: Dialect) -> FunctionView:
        return self.decode if dialect.unions else self.exact_decode

    @cached_property
    def const_lines(self) -> str:
        """The block's constants as the ST files declare them (the same in every dialect)."""
        return Section("", self.consts).lines


def _raw_member_type(reg: Register) -> str:
    if reg.words > 1 or reg.type.is_string:  # text is read by index, one word long or not
        return f"ARRAY[0..{reg.words - 1}] OF WORD"
    # a half: its bits; a scaled point: its word, for F_<DEV>_SCALED_<R>
    return "WORD" if reg.bitfields or swapped(reg) or reg.type is DataType.F16 or reg.scale_from else NATURAL[reg.type]


def _combine(device: Device, reg: Register, words: str) -> list[str]:
    """Statements that set `dw` from a 32-bit register's two words (`<words>[0]`, `[1]`) in wire order."""
    w0, w1 = (f"ROL({words}[{i}], 8)" if swapped(reg) else f"{words}[{i}]" for i in (0, 1))
    high_first = f"dw := SHL(WORD_TO_DWORD({w0}), 16) OR WORD_TO_DWORD({w1});"
    low_first = f"dw := SHL(WORD_TO_DWORD({w1}), 16) OR WORD_TO_DWORD({w0});"
    if configurable(device, reg):
        return ["IF bHighWordFirst THEN", f"    {high_first}", "ELSE", f"    {low_first}", "END_IF;"]
    return [high_first if reg.word_order is WordOrder.HIGH_FIRST else low_first]


class Values:
    """The typed values struct (`ST_<DEV>_VALUES`): one member per readable register, and one per bitfield."""

    def __init__(self, names: Names, helpers: Helpers) -> None:
        self.names = names
        self.helpers = helpers
        self.scope = names.scope("a member of the values struct")
        self.members: list[Member | TextMember] = []
        self.type_name = names.type("ST", "VALUES", what="the values struct")
        self.used: set[str] = set()  # helpers the decoders call: f32, f64, char
        # the scale factors: each gets an availability flag, FALSE until read (a point in another block waits for it)
        self.factors = {r.scale_from for r in names.device.registers if r.scale_from is not None}
        self._struct: StructView | None = None  # the struct of every notation, when they agree

    def add(
        self, reg: Register, locals_: dict[str, str], bit: tuple[int, int] | None = None, together: frozenset[str] = frozenset()
    ) -> list[str]:
        """Declare the register's members; the statements that decode it from `stRaw` (a bit: (byte, mask) in stRaw.BITS;
        `together`: the registers of the same block, whose raw values the decoder has)."""
        names = self.names
        member = self.scope.add(StIdentifier(reg.name), f"register {reg.name}", reg.pos)
        raw = f"stRaw.{member}"
        target = f"stValues.{member}"
        comment = names.register_comment(reg)
        if reg.scale_from is not None:
            available = self.scope.add(StIdentifier(reg.name, "available"), f"the availability flag of {reg.name}", reg.pos)
            why = f"FALSE: {reg.name} or {reg.scale_from} reads 'not available', {reg.scale_from} is not read yet or |sf| > 22"
            self.members += [Member(member, "LREAL", comment), Member(available, "BOOL", why)]
            return scaling.decode_statements(names, reg, raw, target, f"stValues.{available}", together)
        if reg.type.is_bool:
            assert bit is not None
            self.members.append(Member(member, "BOOL", comment))
            return [f"{target} := (stRaw.BITS[{bit[0]}] AND {st_hex(bit[1], 2)}) <> 0;"]
        if reg.type.is_string:
            return self._text(reg, member, raw, target, comment, locals_)
        natural = NATURAL[reg.type]
        lines: list[str] = []
        if reg.words == 2:
            lines += _combine(names.device, reg, raw)
            locals_["dw"] = "DWORD"
            value = f"DWORD_TO_{natural}(dw)"
        elif reg.words == 4:
            if reg.type.is_float:
                lines += halves64(reg, raw)
                locals_.update(nHigh="DWORD", nLow="DWORD")
            else:
                lines.append(assemble64(reg, raw))
                locals_["lw"] = "LWORD"
            value = f"LWORD_TO_{natural}(lw)"
        elif reg.type is DataType.F16:  # its bits, for the half's helper
            value = f"ROL({raw}, 8)" if swapped(reg) else raw
        elif swapped(reg):
            value = f"WORD_TO_{natural}(ROL({raw}, 8))"
        else:
            value = raw
        if reg.has_na or reg.name in self.factors:
            # The device's "not available" marker is no value: a flag beside the value, which is left as it was.
            available = self.scope.add(StIdentifier(reg.name, "available"), f"the availability flag of {reg.name}", reg.pos)
            marker = f"carries the device's 'not available' marker ({na_list(reg)})" if reg.has_na else ""
            marker += (" or " if marker else "") + ("is not read yet" if reg.name in self.factors else "")
            self.members.append(Member(available, "BOOL", f"FALSE: {reg.name} {marker}"))
            decode = self._value(reg, member, target, comment, locals_, value, natural, raw)
            return [
                *lines,
                f"stValues.{available} := {' AND '.join(_na_conditions(reg, value)) or 'TRUE'};",
                f"IF stValues.{available} THEN",
                *(f"    {line}" for line in decode),
                "END_IF;",
            ]
        return lines + self._value(reg, member, target, comment, locals_, value, natural, raw)

    def _value(
        self, reg: Register, member: str, target: str, comment: str, locals_: dict[str, str], value: str, natural: str, raw: str
    ) -> list[str]:
        """The statements that decode a numeric register whose raw value is `value` (words already combined)."""
        names = self.names
        lines: list[str] = []
        if reg.bitfields:
            word = "dw" if reg.words == 2 else ("lw" if reg.words == 4 else (f"ROL({raw}, 8)" if swapped(reg) else raw))
            self.members.append(Member(member, _word(reg), comment))
            lines.append(f"{target} := {word};")
            for b in reg.bitfields:
                field = self.scope.add(StIdentifier(reg.name, b.name), f"bitfield {b.name} of {reg.name}", b.pos)
                getter = f"{getter_name(names, reg, b)}({target})"
                if b.enum is not None:
                    self.members.append(Member(field, names.enum_type(b.enum), _bitfield_comment(b)))
                    decoder = StIdentifier("F", names.prefix, b.enum.name, "FROM_RAW")
                    lines += [
                        f"IF NOT {decoder}(nRaw := {getter_type(b)}_TO_DINT({getter}), eValue := stValues.{field}) THEN",
                        "    bOk := FALSE;",
                        "END_IF;",
                    ]
                else:
                    self.members.append(Member(field, getter_type(b), _bitfield_comment(b)))
                    lines.append(f"stValues.{field} := {getter};")
            return lines
        if reg.type.is_float:
            return lines + self._float(reg, member, target, comment, locals_, value)
        if reg.enum is not None:
            self.members.append(Member(member, names.enum_type(reg.enum), comment))
            decoder = StIdentifier("F", names.prefix, reg.enum.name, "FROM_RAW")
            as_dint = value if natural == "DINT" else f"{natural}_TO_DINT({value})"
            lines += [f"IF NOT {decoder}(nRaw := {as_dint}, eValue := {target}) THEN", "    bOk := FALSE;", "END_IF;"]
        elif reg.scaled or reg.offset_set:
            kind = value_type(reg)
            self.members.append(Member(member, kind, comment))
            expr = f"{natural}_TO_LREAL({value}) * {_ratio(reg)}{_offset(reg)}"
            lines.append(f"{target} := {expr};" if kind == "LREAL" else f"{target} := LREAL_TO_REAL({expr});")
        else:
            self.members.append(Member(member, natural, comment))
            lines.append(f"{target} := {value};")
        return lines

    def _float(self, reg: Register, member: str, target: str, comment: str, locals_: dict[str, str], value: str) -> list[str]:
        """An IEEE float: its bits through the device's helper (FALSE in plain IEC for infinity or NaN; for a half in both)."""
        kind = value_type(reg)
        self.members.append(Member(member, kind, comment))
        locals_["rValue"] = "LREAL"
        if reg.words == 1:
            self.used.add("f16")
            call = f"{self.helpers.f16_from_bits}(nBits := {value}, fValue := rValue)"
        elif reg.words == 2:
            self.used.add("f32")
            call = f"{self.helpers.f32_from_bits}(nBits := dw, fValue := rValue)"
        else:
            self.used.add("f64")
            call = f"{self.helpers.f64_from_bits}(nHigh := nHigh, nLow := nLow, fValue := rValue)"
        if reg.enum is not None:  # a setting coded as a float: a member when the float is that integer exactly
            self.members[-1] = Member(member, self.names.enum_type(reg.enum), comment)
            decoder = StIdentifier("F", self.names.prefix, reg.enum.name, "FROM_RAW")
            whole = "rValue >= -2147483648.0 AND rValue <= 2147483647.0 AND rValue = DINT_TO_LREAL(LREAL_TO_DINT(rValue))"
            return [
                f"IF {call} AND {whole} THEN",
                f"    IF NOT {decoder}(nRaw := LREAL_TO_DINT(rValue), eValue := {target}) THEN",
                "        bOk := FALSE;",
                "    END_IF;",
                "ELSE",
                "    bOk := FALSE;",
                "END_IF;",
            ]
        scaled = f"rValue * {_ratio(reg)}{_offset(reg)}" if reg.scaled or reg.offset_set else "rValue"
        store = f"{target} := {scaled};" if kind == "LREAL" else f"{target} := LREAL_TO_REAL({scaled});"
        return [f"IF {call} THEN", f"    {store}", "ELSE", "    bOk := FALSE;", "END_IF;"]

    def _text(self, reg: Register, member: str, raw: str, target: str, comment: str, locals_: dict[str, str]) -> list[str]:
        """Text: bytes in order (first character in the high byte), up to the first NUL; space padding removed."""
        self.used.add("char")
        self.members.append(TextMember(member, 2 * reg.words, comment))
        locals_.update(i="INT", nByte="BYTE", nWord="WORD")
        word = f"ROL({raw}[i / 2], 8)" if swapped(reg) else f"{raw}[i / 2]"
        lines = [
            f"{target} := '';",
            f"FOR i := 0 TO {2 * reg.words - 1} DO",
            f"    nWord := {word};",
            "    IF (i MOD 2) = 0 THEN",
            "        nByte := WORD_TO_BYTE(SHR(nWord, 8));",
            "    ELSE",
            "        nByte := WORD_TO_BYTE(nWord);",
            "    END_IF;",
            "    IF nByte = 0 THEN",
            "        EXIT;",
            "    END_IF;",
            f"    {target} := CONCAT({target}, {self.helpers.char}(nByte));",
            "END_FOR;",
        ]
        if reg.padding == "space":
            lines += [
                f"WHILE LEN({target}) > 0 DO",
                f"    IF RIGHT({target}, 1) <> ' ' THEN",
                "        EXIT;",
                "    END_IF;",
                f"    {target} := LEFT({target}, LEN({target}) - 1);",
                "END_WHILE;",
            ]
        return lines

    def struct(self, notation: Notation) -> StructView:
        """The struct in `notation`: one view for every notation when no member is text (its members' text made once)."""
        if self._struct is not None:
            return self._struct
        members = tuple([m if type(m) is Member else m.spelled(notation) for m in self.members])
        struct = StructView(self.type_name, "Decoded values of every readable register (the Python client's read_all()).", members)
        if all(map(operator.is_, members, self.members)):  # no text member: every notation spells them alike
            self._struct = struct
        return struct


def _na_conditions(reg: Register, value: str) -> list[str]:
    """ST conditions, all true when the raw value is none of the register's "not available" markers: a
    16-bit value compared as its type, a wider one by its bits (`dw`, `lw`, the halves of an f64)."""
    conditions: list[str] = []
    for mark, pattern in zip(reg.na, reg.na_bits, strict=True):
        if reg.type is DataType.F16:
            conditions.append(f"{value} <> {st_hex(pattern, 4)}")
        elif reg.words == 1:
            conditions.append(f"{value} <> {st_int(int(mark))}")
        elif reg.words == 2:
            conditions.append(f"dw <> {st_hex(pattern, 8)}")
        elif reg.type.is_float:
            conditions.append(f"(nHigh <> {st_hex(pattern >> 32, 8)} OR nLow <> {st_hex(pattern & 0xFFFFFFFF, 8)})")
        else:
            conditions.append(f"lw <> {st_hex(pattern, 16)}")
    if reg.na_nan and reg.words == 1:
        conditions.append(f"(({value} AND 16#7C00) <> 16#7C00 OR ({value} AND 16#03FF) = 0)")
    elif reg.na_nan and reg.words == 2:
        conditions.append("((dw AND 16#7F800000) <> 16#7F800000 OR (dw AND 16#007FFFFF) = 0)")
    elif reg.na_nan:
        conditions.append("((nHigh AND 16#7FF00000) <> 16#7FF00000 OR ((nHigh AND 16#000FFFFF) = 0 AND nLow = 0))")
    return conditions


def _ratio(reg: Register) -> str:
    return f"{st_real(reg.scale.numerator)} / {st_real(reg.scale.denominator)}"


def _offset(reg: Register) -> str:
    if not reg.offset_set:
        return ""
    sign = "-" if reg.offset < 0 else "+"
    return f" {sign} {st_real(abs(reg.offset.numerator))} / {st_real(reg.offset.denominator)}"


def getter_type(b: Bitfield) -> str:
    """What a bitfield's GET function returns: one bit is a BOOL, a wider field its UINT value."""
    return "BOOL" if b.width == 1 else "UINT"


def getter_name(names: Names, reg: Register, b: Bitfield) -> StIdentifier:
    return StIdentifier("F", names.prefix, owner(reg), "GET", b.name)


Planned = tuple[ReadBlock, PollClass, FirmwareGate | None, tuple[str, ...]]  # a block, its class, gate and variants (() all)


def _plan_key(reg: Register) -> tuple[str, str, str, tuple[str, ...]]:
    gate = (reg.firmware.first or "", reg.firmware.until or "") if reg.firmware else ("", "")
    return (reg.poll.value, *gate, reg.variants)


# By the device's identity (hashing a whole model would cost more than the work): each dialect and the poller ask. Each
# entry is dropped when its device is freed, as runtime_bridge's are, so a process that loads many maps keeps only the live ones'.
_PLANNED: dict[int, tuple[Planned, ...]] = {}


def plan_blocks(device: Device) -> list[Planned]:
    """The read plan split by poll class, firmware gate and variants (so a PLC polls each block at its class's
    rate, and a block never holds a register the connected firmware or variant may lack beside one it has), in
    address order per space. A block every variant reads bridges only words every variant answers. With one
    class, no gates and no variants (the seed maps) it is the Python client's read_all()."""
    key = id(device)
    cached = _PLANNED.get(key)
    if cached is not None:
        return list(cached)
    planned = _plan_blocks(device)
    _PLANNED[key] = tuple(planned)
    weakref.finalize(device, _PLANNED.pop, key, None)
    return planned


def _plan_blocks(device: Device) -> list[Planned]:
    readable = [r for r in device.registers if r.access.readable]
    every = tuple(v.name for v in device.info.variants)
    out: list[Planned] = []
    keys = sorted({_plan_key(r) for r in readable})
    for key in keys:
        poll, first, until, variants = key
        gate = FirmwareGate(first or None, until or None) if first or until else None
        if len(keys) == 1 and not (variants or every):
            # one class, gate and variant set for every readable register: read_all()'s plan, which the other back ends
            # ask for too and the runtime bridge makes once per device
            out += [(block, PollClass(poll), gate, variants) for block in read_plan(device)]
            continue
        chosen = [r for r in readable if _plan_key(r) == key]
        out += [(block, PollClass(poll), gate, variants) for block in read_plan(device, chosen, variants=variants or every)]
    order = {name: i for i, name in enumerate(SPACE_TAG)}
    out.sort(key=lambda item: (order[item[0].space], item[0].address))
    return out


def blocks(names: Names, values: Values) -> list[Block]:
    device = names.device
    out = []
    planned = plan_blocks(device)
    classes = {poll for _, poll, _, _ in planned}
    for index, (block, poll, gate, variants) in enumerate(planned):
        space = block.space
        bits = space in ("coil", "discrete_input")
        tag = "_".join(filter(None, (SPACE_TAG[space], f"{block.address:04X}")))
        what = f"read block {index} at {space} 0x{block.address:04X}"
        regs = tuple([device.register(spec.name) for spec in block.registers])
        scope = names.scope(f"a member of raw block {tag}")
        members: list[Member] = []
        if bits:
            count = (block.count + 7) // 8
            members.append(
                Member(
                    scope.add(StIdentifier("BITS"), "the bits"),
                    f"ARRAY[0..{count - 1}] OF BYTE",
                    f"{block.count} bits as the response packs them: address {st_hex(block.address)} + 8 * k + b is bit b of byte k",
                )
            )
        else:
            at_address = {r.address: r for r in regs}
            address = block.address
            end = block.address + block.count
            while address < end:
                reg = at_address.get(address)
                if reg is None:
                    pair = at_address.get(address + 1)
                    why = (
                        f"unused high word of {pair.label}"
                        if pair is not None and pair.paired
                        else "a word no register of the read describes"
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
        read_call, channel = SPACE_READ[space]
        info = regs[0].space_info
        request = (
            f"one Modbus {info.title} read, function 16#{info.read:02X}"
            if space != "holding"
            else "one Modbus read-holding-registers request"
        )
        unit = "bits" if bits else "words"
        struct = StructView(
            names.type("ST", "RAW", tag, what=what),
            f"Read block {index}: {block.count} {unit} from {st_hex(block.address)} in wire order ({request}).",
            tuple(members),
        )
        consts = [
            Const(names.const("BLOCK", tag, "ADDR", what=what), "UINT", st_hex(block.address)),
            Const(names.const("BLOCK", tag, "COUNT", what=what), "UINT", st_int(block.count), "bits" if bits else ""),
        ]
        if space != "holding":
            consts.append(Const(names.const("BLOCK", tag, "FUNCTION", what=what), "USINT", st_hex(info.read, 2), info.title))
        if classes != {PollClass.NORMAL}:
            consts.append(
                Const(names.const("BLOCK", tag, "POLL", what=what), "USINT", st_int(POLL_VALUE[poll]), f"poll class {poll.value}")
            )
        if gate is not None:
            consts += firmware_consts(names, f"BLOCK_{tag}", gate.first, gate.until, what, None)
        consts += variants_const(names, f"BLOCK_{tag}", variants, what, None)
        body = ["bOk := TRUE;"]
        local_types: dict[str, str] = {"bOk": "BOOL"}
        together = frozenset(r.name for r in regs)
        for reg in regs:
            bit = None
            if bits:
                offset = reg.address - block.address
                bit = (offset // 8, 1 << (offset % 8))
            body += values.add(reg, local_types, bit, together)
        name = names.function("DECODE", tag, what=what)
        body.append(f"{name} := bOk;")
        inputs = [Member("stRaw", struct.type_name)]
        if needs_order_input(device, regs):
            inputs.append(Member("bHighWordFirst", "BOOL", "the device's word-order parameter"))
        locals_ = tuple([Member(k, v) for k, v in local_types.items()])
        in_outs, statements = (Member("stValues", values.type_name),), tuple(body)
        union_comment, exact_comment = _decoder_comments(index, regs)
        with_unions = FunctionView(name, "BOOL", union_comment, tuple(inputs), in_outs, locals_, statements)
        exact = with_unions  # one view when the comments agree (a block without floats): the dialects print one text
        if exact_comment != union_comment:
            exact = FunctionView(name, "BOOL", exact_comment, tuple(inputs), in_outs, locals_, statements)
        out.append(
            Block(block.address, block.count, struct, regs, tuple(consts), with_unions, exact, space, bits, read_call, channel, info.read)
        )
    return out


def _decoder_comments(index: int, regs: tuple[Register, ...]) -> tuple[str, str]:
    """A block decoder's comment where floats go through a UNION, and where they are rebuilt exactly (which
    refuses infinity and NaN, as a half's helper does in both)."""
    why = "a register holds a value its enum does not list (that member keeps its old value)"
    no_value = ", or a float is infinity or NaN (plain IEC 61131-3 has no value for them)"
    head = f"Decode read block {index} into stValues; FALSE when {why}"
    with_unions = head + (no_value if any(r.type is DataType.F16 for r in regs) else "") + "."
    return with_unions, head + (no_value if any(r.type.is_float for r in regs) else "") + "."


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
        label = owner(reg)
        for b in reg.bitfields:
            # Literals, not the MASK / SHIFT constants: an IEC function cannot see global variables.
            mask = st_hex(b.mask, 4 * reg.words)
            shift = st_int(b.lsb)
            what = f"the accessors of bitfield {b.name} of {label}"
            get = names.globals.add(getter_name(names, reg, b), what, b.pos)
            put = names.function(label, "SET", b.name, what=what, pos=b.pos)
            to_uint = f"{word}_TO_UINT(SHR(nWord AND {mask}, {shift}))"
            get_body: tuple[str, ...]
            set_body: tuple[str, ...]
            returns = getter_type(b)
            if b.width == 1:
                get_body = (f"{get} := (nWord AND {mask}) <> 0;",)
                set_body = ("IF bValue THEN", f"    {put} := nWord OR {mask};", "ELSE", f"    {put} := nWord AND NOT {mask};", "END_IF;")
                value = Member("bValue", "BOOL")
            else:
                get_body = (f"{get} := {to_uint};",)
                set_body = (f"{put} := (nWord AND NOT {mask}) OR (SHL(UINT_TO_{word}(nValue), {shift}) AND {mask});",)
                value = Member("nValue", "UINT")
            functions.append(
                FunctionView(get, returns, f"Bits {b.bits_text} ({b.name}) of a {label} word.", (Member("nWord", word),), (), (), get_body)
            )
            functions.append(
                FunctionView(
                    put,
                    word,
                    f"The {label} word with bits {b.bits_text} ({b.name}) replaced; every other bit kept.",
                    (Member("nWord", word), value),
                    (),
                    (),
                    set_body,
                )
            )
    return functions
