"""The statements of one device's Structured Text: the raw read-plan blocks and their decoders, bitfield
accessors, encoders that refuse what the Python client refuses, and command helpers."""

from __future__ import annotations

from dataclasses import dataclass

from regmap.backends.st.codec import (
    NATURAL,
    Helpers,
    assemble64,
    halves64,
    put_halves64,
    put_word,
    st_type,
    swapped,
    value_type,
)
from regmap.backends.st.names import StIdentifier, st_hex, st_int, st_real
from regmap.backends.st.views import (
    POLL_VALUE,
    Const,
    Dialect,
    FunctionView,
    Member,
    Names,
    StructView,
    _bitfield_comment,
    _register_comment,
    _word,
    configurable,
    firmware_consts,
    needs_order_input,
    owner,
    sentences,
)
from regmap.backends.text import eng
from regmap.model import Bitfield, Command, Device, FirmwareGate, PollClass, Register, WordOrder
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
    decode: FunctionView
    space: str = "holding"
    bits: bool = False
    read_call: str = "ReadRegs"
    channel: str = "Read Holding Registers"
    function: int = 0x03


def _raw_member_type(reg: Register) -> str:
    if reg.words > 1:
        return f"ARRAY[0..{reg.words - 1}] OF WORD"
    return "WORD" if reg.bitfields or swapped(reg) else NATURAL[reg.type]


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

    def __init__(self, names: Names, dialect: Dialect, helpers: Helpers) -> None:
        self.names = names
        self.dialect = dialect
        self.helpers = helpers
        self.scope = names.scope("a member of the values struct")
        self.members: list[Member] = []
        self.type_name = names.type("ST", "VALUES", what="the values struct")
        self.used: set[str] = set()  # helpers the decoders call: f32, f64, char

    def add(self, reg: Register, locals_: dict[str, str], bit: tuple[int, int] | None = None) -> list[str]:
        """Declare the register's members; the statements that decode it from `stRaw` (a bit: (byte, mask) in stRaw.BITS)."""
        names = self.names
        member = self.scope.add(StIdentifier(reg.name), f"register {reg.name}", reg.pos)
        raw = f"stRaw.{member}"
        target = f"stValues.{member}"
        comment = _register_comment(reg)
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
        elif swapped(reg):
            value = f"WORD_TO_{natural}(ROL({raw}, 8))"
        else:
            value = raw
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
                        f"IF NOT {decoder}(nRaw := UINT_TO_DINT({getter}), eValue := stValues.{field}) THEN",
                        "    bOk := FALSE;",
                        "END_IF;",
                    ]
                else:
                    self.members.append(Member(field, "BOOL" if b.width == 1 else "UINT", _bitfield_comment(b)))
                    lines.append(f"stValues.{field} := {getter};")
            return lines
        if reg.type.is_float:
            return lines + self._float(reg, member, target, comment, locals_)
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

    def _float(self, reg: Register, member: str, target: str, comment: str, locals_: dict[str, str]) -> list[str]:
        """An IEEE float: its bits through the device's helper (FALSE in plain IEC for infinity or NaN)."""
        kind = value_type(reg)
        self.members.append(Member(member, kind, comment))
        locals_["rValue"] = "LREAL"
        if reg.words == 2:
            self.used.add("f32")
            call = f"{self.helpers.f32_from_bits}(nBits := dw, fValue := rValue)"
        else:
            self.used.add("f64")
            call = f"{self.helpers.f64_from_bits}(nHigh := nHigh, nLow := nLow, fValue := rValue)"
        scaled = f"rValue * {_ratio(reg)}{_offset(reg)}" if reg.scaled or reg.offset_set else "rValue"
        store = f"{target} := {scaled};" if kind == "LREAL" else f"{target} := LREAL_TO_REAL({scaled});"
        return [f"IF {call} THEN", f"    {store}", "ELSE", "    bOk := FALSE;", "END_IF;"]

    def _text(self, reg: Register, member: str, raw: str, target: str, comment: str, locals_: dict[str, str]) -> list[str]:
        """Text: bytes in order (first character in the high byte), up to the first NUL; space padding removed."""
        self.used.add("char")
        self.members.append(Member(member, st_type(reg), comment))
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

    def struct(self) -> StructView:
        return StructView(
            self.type_name, "Decoded values of every readable register (the Python client's read_all()).", tuple(self.members)
        )


def _ratio(reg: Register) -> str:
    return f"{st_real(reg.scale.numerator)} / {st_real(reg.scale.denominator)}"


def _offset(reg: Register) -> str:
    if not reg.offset_set:
        return ""
    sign = "-" if reg.offset < 0 else "+"
    return f" {sign} {st_real(abs(reg.offset.numerator))} / {st_real(reg.offset.denominator)}"


def getter_name(names: Names, reg: Register, b: Bitfield) -> StIdentifier:
    return StIdentifier("F", names.prefix, owner(reg), "GET", b.name)


def plan_blocks(device: Device) -> list[tuple[ReadBlock, PollClass, FirmwareGate | None]]:
    """The read plan split by poll class and firmware gate (so a PLC polls each block at its class's rate,
    and a block never holds a register the connected firmware may lack beside one it has), in address
    order per space. With one class and no gates (the seed maps) it is the Python client's read_all()."""
    readable = [r for r in device.registers if r.access.readable]
    keys = sorted(
        {(r.poll.value, r.firmware.first or "", r.firmware.until or "") if r.firmware else (r.poll.value, "", "") for r in readable}
    )
    out: list[tuple[ReadBlock, PollClass, FirmwareGate | None]] = []
    for poll, first, until in keys:
        chosen = [
            r
            for r in readable
            if r.poll.value == poll and ((r.firmware.first or "", r.firmware.until or "") if r.firmware else ("", "")) == (first, until)
        ]
        gate = FirmwareGate(first or None, until or None) if first or until else None
        out += [(block, PollClass(poll), gate) for block in read_plan(device, chosen)]
    order = {name: i for i, name in enumerate(SPACE_TAG)}
    out.sort(key=lambda item: (order[item[0].space], item[0].address))
    return out


def blocks(names: Names, values: Values) -> list[Block]:
    device = names.device
    out = []
    planned = plan_blocks(device)
    classes = {poll for _, poll, _ in planned}
    for index, (block, poll, gate) in enumerate(planned):
        space = block.space
        bits = space in ("coil", "discrete_input")
        tag = "_".join(filter(None, (SPACE_TAG[space], f"{block.address:04X}")))
        what = f"read block {index} at {space} 0x{block.address:04X}"
        regs = tuple(device.register(spec.name) for spec in block.registers)
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
        body = ["bOk := TRUE;"]
        local_types: dict[str, str] = {"bOk": "BOOL"}
        for reg in regs:
            bit = None
            if bits:
                offset = reg.address - block.address
                bit = (offset // 8, 1 << (offset % 8))
            body += values.add(reg, local_types, bit)
        name = names.function("DECODE", tag, what=what)
        body.append(f"{name} := bOk;")
        inputs = [Member("stRaw", struct.type_name)]
        if needs_order_input(device, regs):
            inputs.append(Member("bHighWordFirst", "BOOL", "the device's word-order parameter"))
        why = "a register holds a value its enum does not list (that member keeps its old value)"
        if any(r.type.is_float for r in regs) and not names.dialect.enum_base:
            why += ", or a float is infinity or NaN (plain IEC 61131-3 has no value for them)"
        decode = FunctionView(
            name,
            "BOOL",
            f"Decode read block {index} into stValues; FALSE when {why}.",
            tuple(inputs),
            (Member("stValues", values.type_name),),
            tuple(Member(k, v) for k, v in local_types.items()),
            tuple(body),
        )
        out.append(Block(block.address, block.count, struct, regs, tuple(consts), decode, space, bits, read_call, channel, info.read))
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


def _range_lines(name: str, lo: int | float, hi: int | float) -> list[str]:
    return [f"IF nRaw < {lo} OR nRaw > {hi} THEN", f"    {name} := FALSE;", "    RETURN;", "END_IF;"]


def _put_words(device: Device, reg: Register, output: str) -> list[str]:
    natural = NATURAL[reg.type]
    if reg.words == 1:
        word = f"{natural}_TO_WORD(LINT_TO_{natural}(nRaw))"
        if swapped(reg):
            word = f"ROL({word}, 8)"
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
    if reg.words == 4:
        return [
            f"lw := {natural}_TO_LWORD(nRaw);",
            "nHigh := LWORD_TO_DWORD(SHR(lw, 32));",
            "nLow := LWORD_TO_DWORD(lw);",
            *put_halves64(reg, output),
        ]
    lines = [f"dw := {natural}_TO_DWORD(LINT_TO_{natural}(nRaw));"]
    return lines + _put_dword(device, reg, output)


def _put_dword(device: Device, reg: Register, output: str) -> list[str]:
    """The two wire words of `dw` (a 32-bit value) in the register's word and byte order."""
    if swapped(reg):
        high = [put_word(reg, 0, output, "DWORD_TO_WORD(SHR(dw, 16))"), put_word(reg, 1, output, "DWORD_TO_WORD(dw)")]
        return high
    high = [f"{output}[0] := DWORD_TO_WORD(SHR(dw, 16));", f"{output}[1] := DWORD_TO_WORD(dw);"]
    low = [f"{output}[0] := DWORD_TO_WORD(dw);", f"{output}[1] := DWORD_TO_WORD(SHR(dw, 16));"]
    if configurable(device, reg):
        return ["IF bHighWordFirst THEN", *("    " + s for s in high), "ELSE", *("    " + s for s in low), "END_IF;"]
    return high if reg.word_order is WordOrder.HIGH_FIRST else low


def encoders(names: Names, helpers: Helpers, used: set[str]) -> list[FunctionView]:
    """An encoder per writable register (one per array member when its elements share the range):
    the value into the words to write, or FALSE (words unchanged) when the Python client would
    refuse it (out of range, not a multiple of the resolution, not a member of the enum, NaN,
    text too long or not in the register's encoding)."""
    device = names.device
    functions = []
    for regs in owners(device):
        reg = regs[0]
        if not reg.access.writable:
            continue
        uniform = len({(r.raw_min, r.raw_max) for r in regs}) == 1
        for r in [reg] if uniform else regs:
            label = owner(r) if uniform else r.name
            if r.type.is_string:
                used.add("code")
                functions.append(_text_encoder(names, helpers, r, label))
            elif r.type.is_bool:
                functions.append(_bit_encoder(names, r, label))
            elif r.type.is_float:
                used.add("f32" if r.words == 2 else "f64")
                functions.append(_float_encoder(names, helpers, r, label))
            else:
                functions.append(_encoder(names, r, label))
    return functions


def _less_offset(reg: Register) -> str:
    """The engineering value less the register's offset (fValue itself without one)."""
    if not reg.offset_set:
        return "fValue"
    sign = "+" if reg.offset < 0 else "-"
    return f"(fValue {sign} {st_real(abs(reg.offset))})"


def _output(reg: Register) -> tuple[str, str]:
    if reg.words == 1 and not reg.paired:
        return "nWord", "WORD"
    return "aWords", f"ARRAY[0..{reg.span - 1}] OF WORD"


def _encoder_comment(reg: Register, label: str, output: str) -> str:
    where = "FIRST_ADDR (the pair's unused high word first)" if reg.paired else "ADDR"
    if reg.type.is_string:
        what = f"at most {2 * reg.words} bytes of {reg.encoding} text"
    else:
        what = f"range {eng(reg, reg.raw_min)}..{eng(reg, reg.raw_max)}{f' {reg.unit}' if reg.unit else ''}"
    return sentences(
        f"The word{'s' if output == 'aWords' else ''} to write to {label} (at its {where})",
        what,
        "FALSE, the words unchanged, when the Python client would refuse the value",
    )


def _bit_encoder(names: Names, reg: Register, label: str) -> FunctionView:
    """A coil: the value function 16#05 writes (16#FF00 on, 16#0000 off); 16#0F takes the bit itself."""
    name = names.function("ENCODE", label, what=f"the encoder of {label}", pos=reg.pos)
    body = ("IF bValue THEN", "    nWord := 16#FF00;", "ELSE", "    nWord := 16#0000;", "END_IF;", f"{name} := TRUE;")
    comment = sentences(
        f"The value function 16#05 writes to {label} (16#FF00 on, 16#0000 off); function 16#0F takes the bit itself",
        "always TRUE: a coil takes either state",
    )
    return FunctionView(name, "BOOL", comment, (Member("bValue", "BOOL"),), (Member("nWord", "WORD"),), (), body)


def _float_encoder(names: Names, helpers: Helpers, reg: Register, label: str) -> FunctionView:
    name = names.function("ENCODE", label, what=f"the encoder of {label}", pos=reg.pos)
    output, out_type = _output(reg)
    natural = NATURAL[reg.type]
    local = [Member("rRaw", "LREAL")]
    body: list[str] = []
    if reg.scaled or reg.offset_set:
        inputs = [Member("fValue", "LREAL", f"in {reg.unit}" if reg.unit else "engineering value")]
        body.append(f"rRaw := {_less_offset(reg)} * {st_real(reg.scale.denominator)} / {st_real(reg.scale.numerator)};")
    else:
        inputs = [Member("fValue", natural, f"in {reg.unit}" if reg.unit else "")]
        body.append("rRaw := REAL_TO_LREAL(fValue);" if natural == "REAL" else "rRaw := fValue;")
    body += [
        f"IF NOT (rRaw >= {st_real(reg.raw_min)} AND rRaw <= {st_real(reg.raw_max)}) THEN",  # NaN fails too
        f"    {name} := FALSE;",
        "    RETURN;",
        "END_IF;",
    ]
    if reg.words == 2:
        local.append(Member("dw", "DWORD"))
        body += [
            f"IF NOT {helpers.f32_to_bits}(fValue := LREAL_TO_REAL(rRaw), nBits := dw) THEN",
            f"    {name} := FALSE;",
            "    RETURN;",
            "END_IF;",
            *_put_dword(names.device, reg, output),
        ]
    else:
        local += [Member("nHigh", "DWORD"), Member("nLow", "DWORD")]
        body += [
            f"IF NOT {helpers.f64_to_bits}(fValue := rRaw, nHigh := nHigh, nLow := nLow) THEN",
            f"    {name} := FALSE;",
            "    RETURN;",
            "END_IF;",
            *put_halves64(reg, output),
        ]
    if configurable(names.device, reg):
        inputs.append(Member("bHighWordFirst", "BOOL", "the device's word-order parameter"))
    body.append(f"{name} := TRUE;")
    return FunctionView(
        name, "BOOL", _encoder_comment(reg, label, output), tuple(inputs), (Member(output, out_type),), tuple(local), tuple(body)
    )


def _text_encoder(names: Names, helpers: Helpers, reg: Register, label: str) -> FunctionView:
    """Text into words: its bytes, first character in the high byte, padded; FALSE when too long or,
    for ascii, a byte above 16#7F (bytes are taken as they are: no transcoding)."""
    name = names.function("ENCODE", label, what=f"the encoder of {label}", pos=reg.pos)
    size = 2 * reg.words
    pad = "16#20" if reg.padding == "space" else "16#00"
    body = [
        "nLen := LEN(sValue);",
        f"IF nLen > {size} THEN",
        f"    {name} := FALSE;",
        "    RETURN;",
        "END_IF;",
        f"FOR i := 0 TO {size - 1} DO",
        f"    nByte := {pad};",
        "    IF i < nLen THEN",
        f"        nByte := {helpers.code}(MID(sValue, 1, i + 1));",
    ]
    if reg.encoding == "ascii":
        body += ["        IF nByte > 16#7F THEN", f"            {name} := FALSE;", "            RETURN;", "        END_IF;"]
    body += [
        "    END_IF;",
        "    aBytes[i] := nByte;",
        "END_FOR;",
        f"FOR i := 0 TO {reg.words - 1} DO",
        "    nWord := SHL(BYTE_TO_WORD(aBytes[2 * i]), 8) OR BYTE_TO_WORD(aBytes[2 * i + 1]);",
        f"    aWords[i] := {'ROL(nWord, 8)' if swapped(reg) else 'nWord'};",
        "END_FOR;",
        f"{name} := TRUE;",
    ]
    local = (
        Member("nLen", "INT"),
        Member("i", "INT"),
        Member("nByte", "BYTE"),
        Member("nWord", "WORD"),
        Member("aBytes", f"ARRAY[0..{size - 1}] OF BYTE"),
    )
    return FunctionView(
        name,
        "BOOL",
        _encoder_comment(reg, label, "aWords"),
        (Member("sValue", st_type(reg)),),
        (Member("aWords", f"ARRAY[0..{reg.words - 1}] OF WORD"),),
        local,
        tuple(body),
    )


def _encoder(names: Names, reg: Register, label: str) -> FunctionView:
    device = names.device
    name = names.function("ENCODE", label, what=f"the encoder of {label}", pos=reg.pos)
    natural = NATURAL[reg.type]
    raw_type = "ULINT" if reg.type.value == "u64" else "LINT"
    inputs: list[Member] = []
    local = [Member("nRaw", raw_type)]
    body: list[str] = []
    checked = (reg.raw_min, reg.raw_max) != (reg.type.raw_min, reg.type.raw_max)
    if reg.bitfields:
        inputs.append(Member("nValue", _word(reg), "the whole word; build it with the SET functions"))
        as_natural = f"{_word(reg)}_TO_{natural}(nValue)"
        body.append(f"nRaw := {as_natural};" if natural == raw_type else f"nRaw := {natural}_TO_{raw_type}({as_natural});")
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
    elif reg.scaled or reg.offset_set:
        inputs.append(Member("fValue", "LREAL", f"in {reg.unit}" if reg.unit else "engineering value"))
        local.append(Member("rRaw", "LREAL"))
        ratio = f"{st_real(reg.scale.denominator)} / {st_real(reg.scale.numerator)}"
        body.append(f"rRaw := {_less_offset(reg)} * {ratio};")
        if reg.words == 4:  # the bounds of a 64-bit raw value are no exact LREALs: stay half a step inside
            bounds = f"rRaw >= {st_real(reg.raw_min)} - 0.5 AND rRaw < {st_real(reg.raw_max)} + 0.5"
        else:
            bounds = f"rRaw >= {st_real(reg.raw_min - 1)} AND rRaw <= {st_real(reg.raw_max + 1)}"
        body += [
            f"IF NOT ({bounds}) THEN",  # NaN fails too
            f"    {name} := FALSE;",
            "    RETURN;",
            "END_IF;",
            f"nRaw := LREAL_TO_{raw_type}(rRaw);",
            f"IF ABS(rRaw - {raw_type}_TO_LREAL(nRaw)) > 0.001 THEN",
            f"    {name} := FALSE;",
            "    RETURN;",
            "END_IF;",
        ]
        checked = True
    else:
        inputs.append(Member("nValue", natural))
        body.append(f"nRaw := {natural}_TO_{raw_type}(nValue)" + ";" if raw_type != natural else "nRaw := nValue;")
    if checked:
        body += _range_lines(name, reg.raw_min, reg.raw_max)
    if configurable(device, reg):
        inputs.append(Member("bHighWordFirst", "BOOL", "the device's word-order parameter"))
    if reg.words == 2:
        local.append(Member("dw", "DWORD"))
    if reg.words == 4:
        local += [Member("lw", "LWORD"), Member("nHigh", "DWORD"), Member("nLow", "DWORD")]
    output, out_type = _output(reg)
    body += _put_words(device, reg, output)
    body.append(f"{name} := TRUE;")
    return FunctionView(
        name, "BOOL", _encoder_comment(reg, label, output), tuple(inputs), (Member(output, out_type),), tuple(local), tuple(body)
    )


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
