"""Scale factors in Structured Text (`scale_from`, SunSpec's sunssf): value = raw x 10^sf, sf the signed raw value
of another (s16) register the device reports and may change at run time.

Per scaled register, `F_<DEV>_SCALED_<R>` takes the register's words and the sf's raw INT and gives the value as an
LREAL (a u32 counter has 10 digits, and a step of 10^-n is no binary fraction: REAL's 24 bits would lose the last
digits); FALSE, the value unchanged, for either register's "not available" marker. `F_<DEV>_ENCODE_<R>` takes the
value, the sf and whether the sf is known, and refuses what the Python client refuses (regmap_runtime.scaling):
an sf not known, a value that is no whole multiple of 10^sf, a raw value outside the register's range.

10^|sf| is built by multiplying by 10.0, which is exact up to 10^22; beyond that (|sf| > 22: no device in the
SunSpec range of -10..10) the value is reported as not available and a write is refused, rather than shown
approximately. With |sf| <= 22 the quotient raw / 10^-sf and the product raw x 10^sf are correctly rounded,
as the Python client's (64-bit raws beyond 2^53 are rounded to an LREAL first: within one unit in the last place).
"""

from __future__ import annotations

from regmap.backends.st.codec import NATURAL, assemble64, swapped
from regmap.backends.st.names import StIdentifier, st_int, st_real
from regmap.backends.st.view_types import FunctionView, Member
from regmap.backends.st.views import Names, configurable
from regmap.model import Register

EXACT_POWER = 22  # 10^22 is the largest power of ten an LREAL (IEEE double) holds exactly
EXACT_INTEGER = 2**53  # every integer up to here is an LREAL exactly


def power_name(names: Names) -> StIdentifier:
    return StIdentifier("F", names.prefix, "POW10")


def scaled_name(reg: Register, names: Names) -> StIdentifier:
    return StIdentifier("F", names.prefix, "SCALED", reg.name)


def power_function(names: Names) -> FunctionView:
    """`F_<DEV>_POW10`: 10^|nExp| exactly, or FALSE when it is no LREAL exactly (|nExp| > 22)."""
    name = names.function("POW10", what="the power-of-ten helper of the scale factors")
    body = (
        f"IF nExp < {-EXACT_POWER} OR nExp > {EXACT_POWER} THEN",
        f"    {name} := FALSE; (* 10^{EXACT_POWER + 1} and beyond are no LREAL exactly *)",
        "    RETURN;",
        "END_IF;",
        "fPow := 1.0;",
        "i := ABS(nExp);",
        "WHILE i > 0 DO  (* not FOR i := 1 TO ...: matiec 6bb2c33 runs FOR 1 TO 1 no time *)",
        "    fPow := fPow * 10.0;",
        "    i := i - 1;",
        "END_WHILE;",
        f"{name} := TRUE;",
    )
    comment = f"10^|nExp| (a scale factor's power of ten), exact; FALSE when |nExp| > {EXACT_POWER}, which no LREAL holds exactly."
    return FunctionView(name, "BOOL", comment, (Member("nExp", "INT"),), (Member("fPow", "LREAL"),), (Member("i", "INT"),), body)


def _word_names(reg: Register) -> list[str]:
    """The inputs of a scaled register's words: `nWord`, or one per word in wire order (matiec passes no array
    member of a struct to an array parameter)."""
    return ["nWord"] if reg.words == 1 else [f"nWord{k}" for k in range(reg.words)]


def _raw_from_words(names: Names, reg: Register) -> tuple[list[str], list[Member]]:
    """Statements that set `nRaw` from the register's words, and the locals they need."""
    natural = NATURAL[reg.type]
    if reg.words == 1:
        word = "ROL(nWord, 8)" if swapped(reg) else "nWord"
        return [f"nRaw := WORD_TO_{natural}({word});"], []
    gather = [f"aWords[{k}] := {word};" for k, word in enumerate(_word_names(reg))]
    words = Member("aWords", f"ARRAY[0..{reg.words - 1}] OF WORD")
    if reg.words == 4:
        return [*gather, assemble64(reg, "aWords"), f"nRaw := LWORD_TO_{natural}(lw);"], [words, Member("lw", "LWORD")]
    from regmap.backends.st.functions import _combine  # functions imports this module

    return [*gather, *_combine(names.device, reg, "aWords"), f"nRaw := DWORD_TO_{natural}(dw);"], [words, Member("dw", "DWORD")]


def _refuse(name: str, test: str, why: str) -> list[str]:
    return [f"IF {test} THEN", f"    {name} := FALSE; (* {why} *)", "    RETURN;", "END_IF;"]


def _sf_refusals(names: Names, reg: Register, name: str) -> list[str]:
    """FALSE for the sf's "not available" markers, and for an sf whose power of ten is no exact LREAL."""
    sf = names.device.register(reg.scale_from or "")
    lines: list[str] = []
    for mark in sf.na:
        lines += _refuse(name, f"nSf = {st_int(int(mark))}", f"{sf.name} reads its 'not available' marker")
    return lines + _refuse(name, f"NOT {power_name(names)}(nExp := nSf, fPow := rPow)", f"|sf| > {EXACT_POWER}")


def _scale(natural: str, target: str) -> list[str]:
    """`target` := nRaw x 10^nSf, with rPow = 10^|nSf|: a division for a negative sf (correctly rounded, as Python)."""
    return [
        "IF nSf < 0 THEN",
        f"    {target} := {natural}_TO_LREAL(nRaw) / rPow;",
        "ELSE",
        f"    {target} := {natural}_TO_LREAL(nRaw) * rPow;",
        "END_IF;",
    ]


def scaled_function(names: Names, reg: Register) -> FunctionView:
    """`F_<DEV>_SCALED_<R>`: the value of R from its words and its sf's raw value; FALSE (fValue unchanged) when
    either reads "not available" or |sf| > 22."""
    from regmap.backends.st.functions import _na_conditions  # functions imports this module

    sf = names.device.register(reg.scale_from or "")
    name = names.function("SCALED", reg.name, what=f"the scaled value of {reg.name}", pos=reg.pos)
    natural = NATURAL[reg.type]
    combine, wide_locals = _raw_from_words(names, reg)
    body = list(combine)
    marks = _na_conditions(reg, "nRaw")
    if marks:
        body += _refuse(name, f"NOT ({' AND '.join(marks)})", f"{reg.name} reads its 'not available' marker")
    body += _sf_refusals(names, reg, name)
    body += [*_scale(natural, "fValue"), f"{name} := TRUE;"]
    inputs = [
        Member(word, "WORD", f"{reg.name} as read" + (f", word {k} on the wire" if reg.words > 1 else ""))
        for k, word in enumerate(_word_names(reg))
    ]
    if configurable(names.device, reg):
        inputs.append(Member("bHighWordFirst", "BOOL", "the device's word-order parameter"))
    inputs.append(Member("nSf", "INT", f"the raw value of {sf.name}, read with it"))
    comment = (
        f"The value of {reg.name} = raw x 10^{sf.name}{f' in {reg.unit}' if reg.unit else ''}; "
        f"FALSE, fValue unchanged, when {reg.name} or {sf.name} reads 'not available' or |{sf.name}| > {EXACT_POWER}."
    )
    local = (Member("nRaw", natural), Member("rPow", "LREAL"), *wide_locals)
    return FunctionView(name, "BOOL", comment, tuple(inputs), (Member("fValue", "LREAL"),), local, tuple(body))


def decode_statements(names: Names, reg: Register, raw: str, target: str, available: str, together: frozenset[str]) -> list[str]:
    """The block decoder's statements for scaled register R (`raw`: its raw member): with the sf of the same read
    when the block holds it, else the sf its own block decoded last (none yet: not available)."""
    sf = names.device.register(reg.scale_from or "")
    same_read = sf.name in together
    words = [raw] if reg.words == 1 else [f"{raw}[{k}]" for k in range(reg.words)]
    args = [f"{name} := {word}" for name, word in zip(_word_names(reg), words, strict=True)]
    if configurable(names.device, reg):
        args.append("bHighWordFirst := bHighWordFirst")
    if same_read:
        sf_raw = f"stRaw.{StIdentifier(sf.name)}"
        args.append(f"nSf := {f'WORD_TO_INT(ROL({sf_raw}, 8))' if swapped(sf) else sf_raw}")
    else:
        args.append(f"nSf := stValues.{StIdentifier(sf.name)}")
    call = f"{available} := {scaled_name(reg, names)}({', '.join(args)}, fValue := {target});"
    if same_read:
        return [call]
    return [f"IF stValues.{StIdentifier(sf.name, 'available')} THEN", f"    {call}", "ELSE", f"    {available} := FALSE;", "END_IF;"]


def encoder(names: Names, reg: Register, label: str, put_words: list[str], refuse_more: list[str]) -> FunctionView:
    """`F_<DEV>_ENCODE_<R>`: the words of value fValue at scale factor nSf; FALSE, the words unchanged, when the sf is
    not known (bSfAvailable FALSE, its marker, |sf| > 22), when fValue is no whole multiple of 10^sf, or when the raw
    value is outside the register's range. Whole multiple, exactly: the value the decoder shows for the nearest raw
    integer must be fValue itself (no tolerance). For raws below 10^15 that is the Python client's rule (the value's
    shortest decimal x 10^-sf is an integer); a raw beyond 2^53, which no LREAL holds exactly, is refused."""
    sf = names.device.register(reg.scale_from or "")
    name = names.function("ENCODE", label, what=f"the encoder of {label}", pos=reg.pos)
    raw_type = "ULINT" if reg.type.value == "u64" else "LINT"
    low, high = max(reg.raw_min, -EXACT_INTEGER), min(reg.raw_max, EXACT_INTEGER)
    body = _refuse(name, "NOT bSfAvailable", f"{sf.name} is not known")
    body += _sf_refusals(names, reg, name)
    body += [
        "IF nSf < 0 THEN",
        "    rRaw := fValue * rPow;",
        "ELSE",
        "    rRaw := fValue / rPow;",
        "END_IF;",
        *_refuse(name, f"NOT (rRaw > {st_real(low - 1)} AND rRaw < {st_real(high + 1)})", "out of range, or NaN"),
        f"nRaw := LREAL_TO_{raw_type}(rRaw); (* the nearest integer *)",
        *_scale(raw_type, "rBack"),
        *_refuse(name, "rBack <> fValue", f"not a whole multiple of 10^{sf.name}"),
        *_refuse(name, f"nRaw < {reg.raw_min} OR nRaw > {reg.raw_max}", "outside the raw range"),
        *refuse_more,
        *put_words,
        f"{name} := TRUE;",
    ]
    inputs = [
        Member("fValue", "LREAL", f"in {reg.unit}" if reg.unit else "engineering value"),
        Member("nSf", "INT", f"the raw value of {sf.name}, read just now"),
        Member("bSfAvailable", "BOOL", f"{sf.name} was read and is available (stValues.{StIdentifier(sf.name, 'available')})"),
    ]
    if configurable(names.device, reg):
        inputs.append(Member("bHighWordFirst", "BOOL", "the device's word-order parameter"))
    output = (Member("nWord", "WORD"),) if reg.words == 1 and not reg.paired else (Member("aWords", f"ARRAY[0..{reg.span - 1}] OF WORD"),)
    local = [Member("nRaw", raw_type), Member("rPow", "LREAL"), Member("rRaw", "LREAL"), Member("rBack", "LREAL")]
    if reg.words == 2:
        local.append(Member("dw", "DWORD"))
    if reg.words == 4:
        local += [Member("lw", "LWORD"), Member("nHigh", "DWORD"), Member("nLow", "DWORD")]
    comment = (
        f"The word{'s' if reg.words > 1 or reg.paired else ''} to write to {label} for value fValue = raw x 10^{sf.name} "
        f"(raw {reg.raw_min}..{reg.raw_max}); FALSE, the words unchanged, when {sf.name} is not known, fValue is no whole "
        "multiple of 10^sf, or the raw value is out of range: the Python client's rule."
    )
    return FunctionView(name, "BOOL", comment, tuple(inputs), output, tuple(local), tuple(body))
