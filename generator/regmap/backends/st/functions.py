"""The statements of one device's Structured Text: the raw read-plan blocks and their decoders, bitfield
accessors, encoders that refuse what the Python client refuses, and command helpers."""

from __future__ import annotations

from dataclasses import dataclass

from regmap.backends.st.names import StIdentifier, st_hex, st_int, st_real
from regmap.backends.st.views import (
    NATURAL,
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
    needs_order_input,
    owner,
    sentences,
)
from regmap.backends.text import eng
from regmap.model import Bitfield, Command, Device, Register, WordOrder
from regmap.runtime_bridge import read_plan


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
