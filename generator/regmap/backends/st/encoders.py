"""The encoders of one device's Structured Text: engineering value -> register words, refusing (FALSE)
what the Python client refuses: out of range, not a member, NaN, text that does not fit."""

from __future__ import annotations

from collections.abc import Sequence

from regmap.backends.st import scaling
from regmap.backends.st.codec import (
    NATURAL,
    Helpers,
    Notation,
    put_halves64,
    put_word,
    st_type,
    swapped,
)
from regmap.backends.st.functions import getter_name, getter_type, owners
from regmap.backends.st.names import StIdentifier, st_real
from regmap.backends.st.view_types import FunctionView, Member
from regmap.backends.st.views import Names, _word, configurable, owner
from regmap.core.text import eng, sentences
from regmap.model import Command, Device, EnumType, Register, WordOrder


def _range_lines(name: str, lo: int | float, hi: int | float) -> list[str]:
    return [f"IF nRaw < {lo} OR nRaw > {hi} THEN", f"    {name} := FALSE;", "    RETURN;", "END_IF;"]


def _refuse_reported(names: Names, notation: Notation, name: str, variable: str, enum: EnumType) -> list[str]:
    """FALSE for a member the device only reports (access r): a state, never a value to write."""
    reported = [m for m in enum.members if not m.writable]
    if not reported:
        return []
    type_name = names.enum_type(enum)
    labels = [f"    {notation.member(type_name, StIdentifier(m.name))}" for m in reported]
    return [
        f"CASE {variable} OF",
        *(label + ("," if i < len(labels) - 1 else ":") for i, label in enumerate(labels)),
        f"        {name} := FALSE; (* a state the device only reports *)",
        "        RETURN;",
        "END_CASE;",
    ]


def _refuse_destructive(device: Device, reg: Register, name: str) -> list[str]:
    """FALSE for what a destructive command writes: the program sends that command's constants by name, deliberately."""
    lines = []
    for command in device.destructive_commands(reg):
        first, last = command.raw_values
        test = f"nRaw = {first}" if first == last else f"nRaw >= {first} AND nRaw <= {last}"
        lines += [f"IF {test} THEN", f"    {name} := FALSE; (* {command.name}: destructive *)", "    RETURN;", "END_IF;"]
    return lines


def _refuse_na(reg: Register, name: str, raw: str) -> list[str]:
    """FALSE for the device's "not available" marker: it is never a value to write (NaN fails the range test already)."""
    lines = []
    for mark in reg.na:
        literal = st_real(mark) if reg.type.is_float else str(mark)
        lines += [f"IF {raw} = {literal} THEN", f"    {name} := FALSE; (* the device's 'not available' marker *)", "    RETURN;", "END_IF;"]
    return lines


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


def encoder_targets(device: Device) -> list[tuple[str, list[Register]]]:
    """(label, registers) of each encoder: one per writable register, one per array member whose
    elements share the range (label: the member's name, registers: its elements), else one per element."""
    out: list[tuple[str, list[Register]]] = []
    for regs in owners(device):
        reg = regs[0]
        if not reg.access.writable:
            continue
        if len({(r.raw_min, r.raw_max) for r in regs}) == 1:
            out.append((owner(reg), regs))
        else:
            out += [(r.name, [r]) for r in regs]
    return out


def encoders(
    names: Names,
    targets: Sequence[tuple[str, list[Register]]],
    notation: Notation,
    helpers: Helpers,
    used: set[str],
    other: Sequence[FunctionView] = (),
) -> list[FunctionView]:
    """An encoder per target of `encoder_targets` (one per writable register, one per array member when its elements
    share the range): the value into the words to write, or FALSE (words unchanged) when the Python client would
    refuse it (out of range, not a multiple of the resolution, not a member of the enum, NaN,
    text too long or not in the register's encoding). `other`: the same encoders in another
    notation, taken as they are where `differs_by_notation` says the notation changes nothing."""
    functions = []
    for index, (label, regs) in enumerate(targets):
        r = regs[0]
        if other and not differs_by_notation(r):
            functions.append(other[index])
        elif r.type.is_string:
            used.add("code")
            functions.append(_text_encoder(names, notation, helpers, r, label))
        elif r.type.is_bool:
            functions.append(_bit_encoder(names, r, label))
        elif r.scale_from is not None:
            put = _put_words(names.device, r, _output(r)[0])
            name = StIdentifier("F", names.prefix, "ENCODE", label)
            functions.append(
                scaling.encoder(names, r, label, put, _refuse_destructive(names.device, r, name) + _refuse_na(r, name, "nRaw"))
            )
        elif r.type.is_float:
            used.add({1: "f16", 2: "f32"}.get(r.words, "f64"))
            functions.append(_float_encoder(names, notation, helpers, r, label))
        else:
            functions.append(_encoder(names, notation, r, label))
    return functions


def differs_by_notation(reg: Register) -> bool:
    """Whether the notation changes the encoder of `reg`: text (its STRING input), or an enum with a member the
    device only reports (`_refuse_reported` names it)."""
    enums = [reg.enum, *(b.enum for b in reg.bitfields)]
    return reg.type.is_string or any(e is not None and any(not m.writable for m in e.members) for e in enums)


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


def _float_encoder(names: Names, notation: Notation, helpers: Helpers, reg: Register, label: str) -> FunctionView:
    name = names.function("ENCODE", label, what=f"the encoder of {label}", pos=reg.pos)
    output, out_type = _output(reg)
    natural = NATURAL[reg.type]
    local = [Member("rRaw", "LREAL")]
    body: list[str] = []
    if reg.enum is not None:  # a setting coded as a float: the member's value, as a float
        inputs = [Member("eValue", names.enum_type(reg.enum))]
        body += _refuse_reported(names, notation, name, "eValue", reg.enum)
        body.append(f"rRaw := DINT_TO_LREAL({StIdentifier('F', names.prefix, reg.enum.name, 'TO_RAW')}(eValue));")
    elif reg.scaled or reg.offset_set:
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
        *_refuse_na(reg, name, "rRaw"),
    ]
    if reg.words == 1:  # the nearest half; the half it becomes is checked as the Python client checks it
        local += [Member("nBits", "WORD"), Member("rHeld", "LREAL")]
        body += [
            f"IF NOT ({helpers.f16_to_bits}(fValue := rRaw, nBits := nBits) AND {helpers.f16_from_bits}(nBits := nBits, fValue := rHeld)) THEN",
            f"    {name} := FALSE;",
            "    RETURN;",
            "END_IF;",
            f"IF NOT (rHeld >= {st_real(reg.raw_min)} AND rHeld <= {st_real(reg.raw_max)}) THEN",
            f"    {name} := FALSE;",
            "    RETURN;",
            "END_IF;",
            *_refuse_na(reg, name, "rHeld"),
            f"{output} := {'ROL(nBits, 8)' if swapped(reg) else 'nBits'};",
        ]
    elif reg.words == 2:
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


def _text_encoder(names: Names, notation: Notation, helpers: Helpers, reg: Register, label: str) -> FunctionView:
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
        "i := 0;",
        f"WHILE i < {reg.words} DO  (* not FOR i := 0 TO {reg.words - 1}: matiec 6bb2c33 runs FOR 0 TO 0 no time *)",
        "    nWord := SHL(BYTE_TO_WORD(aBytes[2 * i]), 8) OR BYTE_TO_WORD(aBytes[2 * i + 1]);",
        f"    aWords[i] := {'ROL(nWord, 8)' if swapped(reg) else 'nWord'};",
        "    i := i + 1;",
        "END_WHILE;",
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
        (Member("sValue", st_type(reg, notation)),),
        (Member("aWords", f"ARRAY[0..{reg.words - 1}] OF WORD"),),
        local,
        tuple(body),
    )


def _encoder(names: Names, notation: Notation, reg: Register, label: str) -> FunctionView:
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
                    f"IF NOT {decoder}(nRaw := {getter_type(b)}_TO_DINT({getter_name(names, reg, b)}(nValue)), eValue := {local_name}) THEN",
                    f"    {name} := FALSE;",
                    "    RETURN;",
                    "END_IF;",
                    *_refuse_reported(names, notation, name, local_name, b.enum),
                ]
    elif reg.enum is not None:
        inputs.append(Member("eValue", names.enum_type(reg.enum)))
        body += _refuse_reported(names, notation, name, "eValue", reg.enum)
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
    body += _refuse_destructive(device, reg, name)
    body += _refuse_na(reg, name, "nRaw")
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
