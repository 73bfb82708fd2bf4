"""How Structured Text holds each data type, and the statements that move a value between its wire
words and its ST type: word and byte order, IEEE floats, text and bits.

Floats: CODESYS / TwinCAT reinterpret the bits through a UNION (`U_<DEV>_F32` / `U_<DEV>_F64`), which
both define. Plain IEC 61131-3 has neither a UNION nor a bit cast (and whether DWORD_TO_REAL converts
the number or the bits differs between tools), so the `iec/` helpers rebuild the value from its fields
with exact LREAL arithmetic (mantissa x a power of two, both exact in IEEE 754 double) and split a value
into its fields by halving or doubling it to [1, 2). Plain IEC has no literal for infinity or NaN: its
decoder returns FALSE for them (CODESYS returns the REAL as the device sent it, as the Python client
does); both encoders refuse them, as the Python client refuses NaN and values outside the range.

Text: ST strings are bytes; a byte becomes a one-character STRING through MID of three tables of `$hh`
escapes (85 bytes each), and a character its code through FIND in the same tables, in both dialects (plain IEC
has no CHAR/BYTE conversion). Text bytes are kept as the device sends them (no transcoding).
"""

from __future__ import annotations

from regmap.backends.st.names import StIdentifier
from regmap.model import ByteOrder, DataType, Register, WordOrder
from regmap.records import dataclass

# The ST type of a register's raw value (strings: STRING of its bytes, see `st_type`).
NATURAL = {
    DataType.U16: "UINT",
    DataType.S16: "INT",
    DataType.U32: "UDINT",
    DataType.S32: "DINT",
    DataType.U64: "ULINT",
    DataType.S64: "LINT",
    DataType.F16: "REAL",  # every half is a REAL exactly
    DataType.F32: "REAL",
    DataType.F64: "LREAL",
    DataType.BOOL: "BOOL",
    DataType.TIMESTAMP: "UDINT",
}

# Bit string of the same width: the word a register's words are assembled into.
BITS = {1: "WORD", 2: "DWORD", 4: "LWORD"}

# Every byte 1..255 in order, in three strings of 85: MID(table k, 1, b - 85 k) is the character b, and
# FIND(table k, c) + 85 k the code of c. One table of 255 would not fit matiec's STRING (126 bytes).
BYTE_TABLE_LENGTH = 85
BYTE_TABLES = tuple(
    (start - 1, "'" + "".join(f"${b:02X}" for b in range(start, start + BYTE_TABLE_LENGTH)) + "'")
    for start in range(1, 256, BYTE_TABLE_LENGTH)
)


def char_body(name: str) -> list[str]:
    """F_<DEV>_CHAR(nByte : BYTE) : STRING, the one-character string of a byte 1..255."""
    lines = []
    for k, (before, table) in enumerate(BYTE_TABLES):
        test = "IF" if k == 0 else "ELSIF"
        if k < len(BYTE_TABLES) - 1:
            lines.append(f"{test} nByte <= {before + BYTE_TABLE_LENGTH} THEN")
        else:
            lines.append("ELSE")
        lines.append(f"    {name} := MID({table}, 1, BYTE_TO_INT(nByte) - {before});")
    return [*lines, "END_IF;"]


def char_code_body(name: str) -> list[str]:
    """F_<DEV>_CHAR_CODE(sChar : STRING) : BYTE, the byte of a one-character string (0: the empty one)."""
    lines = [f"{name} := 0;", "IF LEN(sChar) = 0 THEN", "    RETURN;", "END_IF;"]
    for before, table in BYTE_TABLES:
        lines += [
            f"nAt := FIND({table}, sChar);",
            "IF nAt > 0 THEN",
            f"    {name} := INT_TO_BYTE(nAt + {before});",
            "    RETURN;",
            "END_IF;",
        ]
    return lines


@dataclass(frozen=True)
class Notation:
    """How a dialect writes enums and text: every view but the float helpers reads the dialect only through it,
    so dialects that share a notation share those views."""

    enum_base: bool  # `(A := 1, ...) UINT;`: CODESYS' enum values and base type; plain `(A, ...)` otherwise
    qualifier: str  # `E_X.MEMBER` (CODESYS qualified_only) or `E_X#MEMBER` (the standard's typed enum value)
    sized_strings: bool  # `STRING(16)`; matiec reads no length in a STRUCT member or a VAR_INPUT: plain `STRING`

    def string(self, size: int) -> str:
        """The text type of `size` bytes (plain IEC: matiec's STRING, 126 bytes; the encoders check the length)."""
        return f"STRING({size})" if self.sized_strings else "STRING"

    def member(self, type_name: str, member: str) -> str:
        """An enum value, always qualified: two enums of a map may share a member name (`NONE`)."""
        return f"{type_name}{self.qualifier}{member}"


@dataclass(frozen=True)
class Dialect:
    """What differs between CODESYS / TwinCAT and plain IEC 61131-3 (OpenPLC / matiec)."""

    name: str
    title: str
    pragmas: tuple[str, ...]  # before every enum type
    notation: Notation
    unions: bool  # floats' bits through a UNION (CODESYS / TwinCAT); otherwise exact LREAL arithmetic

    @property
    def enum_base(self) -> bool:
        return self.notation.enum_base

    def string(self, size: int) -> str:
        return self.notation.string(size)


CODESYS_NOTATION = Notation(enum_base=True, qualifier=".", sized_strings=True)
CODESYS = Dialect("codesys", "CODESYS / TwinCAT 3", ("{attribute 'qualified_only'}", "{attribute 'strict'}"), CODESYS_NOTATION, True)
# matiec implements edition 2: no enum values (the FROM_RAW / TO_RAW CASEs carry the numbers), no string lengths.
IEC = Dialect("iec", "IEC 61131-3 (OpenPLC / matiec)", (), Notation(enum_base=False, qualifier="#", sized_strings=False), False)
DIALECTS = (CODESYS, IEC)
# The PLCopen XML project (TwinCAT 3 / CODESYS import): CODESYS' text, but TC6 XML has no UNION.
PLCOPEN = Dialect("plcopen", "PLCopen XML (TwinCAT 3 / CODESYS)", (), CODESYS_NOTATION, False)


def st_type(reg: Register, notation: Notation) -> str:
    if reg.type.is_string:
        return notation.string(2 * reg.words)
    return NATURAL[reg.type]


def swapped(reg: Register) -> bool:
    """The device sends this register's words with their two bytes exchanged."""
    return reg.byte_order is ByteOrder.LOW_FIRST and not reg.type.is_bool


def value_type(reg: Register) -> str:
    """The decoded value's ST type of a number: scaled (or offset) ones become REAL, 64-bit ones LREAL."""
    if reg.type.numeric and (reg.scaled or reg.offset_set):
        return "LREAL" if reg.type.words == 4 else "REAL"
    return NATURAL[reg.type]


def wire_word(reg: Register, index: int, words: str) -> str:
    """The expression of value word `index` (0 = most significant) from the wire words array `words`."""
    n = reg.words
    at = index if reg.word_order is WordOrder.HIGH_FIRST or n == 1 else n - 1 - index
    expr = f"{words}[{at}]"
    return f"ROL({expr}, 8)" if swapped(reg) else expr


def put_word(reg: Register, index: int, output: str, value: str) -> str:
    """The statement that stores value word `index` (0 = most significant) into the wire words `output`."""
    n = reg.words
    at = index if reg.word_order is WordOrder.HIGH_FIRST or n == 1 else n - 1 - index
    return f"{output}[{at}] := {f'ROL({value}, 8)' if swapped(reg) else value};"


def assemble64(reg: Register, words: str, target: str = "lw") -> str:
    parts = [f"SHL(WORD_TO_LWORD({wire_word(reg, i, words)}), {48 - 16 * i})" for i in range(3)]
    return f"{target} := {' OR '.join(parts)} OR WORD_TO_LWORD({wire_word(reg, 3, words)});"


def halves64(reg: Register, words: str) -> list[str]:
    """nHigh / nLow (DWORD) of a 64-bit value from its wire words."""
    w = [wire_word(reg, i, words) for i in range(4)]
    return [
        f"nHigh := SHL(WORD_TO_DWORD({w[0]}), 16) OR WORD_TO_DWORD({w[1]});",
        f"nLow := SHL(WORD_TO_DWORD({w[2]}), 16) OR WORD_TO_DWORD({w[3]});",
    ]


def put_halves64(reg: Register, output: str) -> list[str]:
    """The wire words of a 64-bit value from nHigh / nLow."""
    return [
        put_word(reg, 0, output, "DWORD_TO_WORD(SHR(nHigh, 16))"),
        put_word(reg, 1, output, "DWORD_TO_WORD(nHigh)"),
        put_word(reg, 2, output, "DWORD_TO_WORD(SHR(nLow, 16))"),
        put_word(reg, 3, output, "DWORD_TO_WORD(nLow)"),
    ]


# -- the per-device helper functions (floats and text) ------------------------------------------


@dataclass(frozen=True)
class Helpers:
    """Names of one device's float and text helpers (declared only when its registers need them)."""

    f32_from_bits: StIdentifier
    f32_to_bits: StIdentifier
    f16_from_bits: StIdentifier
    f16_to_bits: StIdentifier
    f64_from_bits: StIdentifier
    f64_to_bits: StIdentifier
    char: StIdentifier
    code: StIdentifier
    union32: StIdentifier
    union64: StIdentifier


def helper_names(prefix: str) -> Helpers:
    return Helpers(
        StIdentifier("F", prefix, "F32", "FROM", "BITS"),
        StIdentifier("F", prefix, "F32", "TO", "BITS"),
        StIdentifier("F", prefix, "F16", "FROM", "BITS"),
        StIdentifier("F", prefix, "F16", "TO", "BITS"),
        StIdentifier("F", prefix, "F64", "FROM", "BITS"),
        StIdentifier("F", prefix, "F64", "TO", "BITS"),
        StIdentifier("F", prefix, "CHAR"),
        StIdentifier("F", prefix, "CHAR", "CODE"),
        StIdentifier("U", prefix, "F32"),
        StIdentifier("U", prefix, "F64"),
    )


TWO_POWER_32 = "4294967296.0"


def f32_from_bits_body(h: Helpers, union: bool) -> tuple[list[tuple[str, str]], list[str]]:
    """(locals, statements) of F32_FROM_BITS(nBits : DWORD; fValue : LREAL in-out) : BOOL."""
    name = h.f32_from_bits
    if union:
        return [("uBits", h.union32)], ["uBits.nBits := nBits;", "fValue := REAL_TO_LREAL(uBits.fValue);", f"{name} := TRUE;"]
    return [("nExp", "DINT"), ("fMant", "LREAL"), ("fTwo", "LREAL")], [
        "fTwo := 2.0;",
        "nExp := DWORD_TO_DINT(SHR(nBits, 23) AND 16#000000FF);",
        "fMant := UDINT_TO_LREAL(DWORD_TO_UDINT(nBits AND 16#007FFFFF));",
        "IF nExp = 255 THEN",
        f"    {name} := FALSE; (* infinity or NaN: plain IEC 61131-3 has no value for them *)",
        "    RETURN;",
        "END_IF;",
        "IF nExp = 0 THEN",
        "    fValue := fMant * EXPT(fTwo, -149);",
        "ELSE",
        "    fValue := (fMant + 8388608.0) * EXPT(fTwo, nExp - 150);",
        "END_IF;",
        "IF (nBits AND 16#80000000) <> 0 THEN",
        "    fValue := -fValue;",
        "END_IF;",
        f"{name} := TRUE;",
    ]


def f64_from_bits_body(h: Helpers, union: bool) -> tuple[list[tuple[str, str]], list[str]]:
    """(locals, statements) of F64_FROM_BITS(nHigh, nLow : DWORD; fValue : LREAL in-out) : BOOL."""
    name = h.f64_from_bits
    if union:
        return [("uBits", h.union64)], [
            "uBits.nBits := SHL(DWORD_TO_LWORD(nHigh), 32) OR DWORD_TO_LWORD(nLow);",
            "fValue := uBits.fValue;",
            f"{name} := TRUE;",
        ]
    return [("nExp", "DINT"), ("fMant", "LREAL"), ("fTwo", "LREAL")], [
        "fTwo := 2.0;",
        "nExp := DWORD_TO_DINT(SHR(nHigh, 20) AND 16#000007FF);",
        f"fMant := UDINT_TO_LREAL(DWORD_TO_UDINT(nHigh AND 16#000FFFFF)) * {TWO_POWER_32} + UDINT_TO_LREAL(DWORD_TO_UDINT(nLow));",
        "IF nExp = 2047 THEN",
        f"    {name} := FALSE; (* infinity or NaN: plain IEC 61131-3 has no value for them *)",
        "    RETURN;",
        "END_IF;",
        "IF nExp = 0 THEN",
        "    fValue := fMant * EXPT(fTwo, -1074);",
        "ELSE",
        "    fValue := (fMant + 4503599627370496.0) * EXPT(fTwo, nExp - 1075);",
        "END_IF;",
        "IF (nHigh AND 16#80000000) <> 0 THEN",
        "    fValue := -fValue;",
        "END_IF;",
        f"{name} := TRUE;",
    ]


def _normalise() -> list[str]:
    """Statements that bring fAbs (non-zero) to [1, 2) while counting the power of two in nExp; infinity and
    NaN return (x - x is NaN for both). No literal bound: matiec reads every real literal as a REAL."""
    return [
        "IF NOT (fAbs - fAbs = 0.0) THEN",
        "    RETURN; (* infinity or NaN *)",
        "END_IF;",
        "nExp := 0;",
        "WHILE fAbs >= 2.0 DO",
        "    fAbs := fAbs * 0.5;",
        "    nExp := nExp + 1;",
        "END_WHILE;",
        "WHILE fAbs < 1.0 DO",
        "    fAbs := fAbs * 2.0;",
        "    nExp := nExp - 1;",
        "END_WHILE;",
    ]


def f32_to_bits_body(h: Helpers, union: bool) -> tuple[list[tuple[str, str]], list[str]]:
    """(locals, statements) of F32_TO_BITS(fValue : REAL; nBits : DWORD in-out) : BOOL (FALSE: infinity or NaN)."""
    name = h.f32_to_bits
    if union:
        return [("uBits", h.union32)], [
            "IF NOT (ABS(fValue) <= 3.4028234663852886e38) THEN",
            f"    {name} := FALSE;",
            "    RETURN;",
            "END_IF;",
            "uBits.fValue := fValue;",
            "nBits := uBits.nBits;",
            f"{name} := TRUE;",
        ]
    return [("nExp", "DINT"), ("fAbs", "LREAL"), ("fTwo", "LREAL")], [
        f"{name} := FALSE;",
        "fTwo := 2.0;",
        "fAbs := ABS(REAL_TO_LREAL(fValue));",
        "IF fAbs = 0.0 THEN",
        "    nBits := 16#00000000;",
        f"    {name} := TRUE;",
        "    RETURN;",
        "END_IF;",
        *_normalise(),
        "IF nExp < -126 THEN",
        "    nBits := UDINT_TO_DWORD(LREAL_TO_UDINT(fAbs * EXPT(fTwo, nExp + 149)));",
        "ELSE",
        "    nBits := SHL(DINT_TO_DWORD(nExp + 127), 23) OR UDINT_TO_DWORD(LREAL_TO_UDINT((fAbs - 1.0) * 8388608.0));",
        "END_IF;",
        "IF fValue < 0.0 THEN",
        "    nBits := nBits OR 16#80000000;",
        "END_IF;",
        f"{name} := TRUE;",
    ]


def f64_to_bits_body(h: Helpers, union: bool) -> tuple[list[tuple[str, str]], list[str]]:
    """(locals, statements) of F64_TO_BITS(fValue : LREAL; nHigh, nLow : DWORD in-out) : BOOL."""
    name = h.f64_to_bits
    if union:
        return [("uBits", h.union64)], [
            "IF NOT (ABS(fValue) <= 1.7976931348623157e308) THEN",
            f"    {name} := FALSE;",
            "    RETURN;",
            "END_IF;",
            "uBits.fValue := fValue;",
            "nHigh := LWORD_TO_DWORD(SHR(uBits.nBits, 32));",
            "nLow := LWORD_TO_DWORD(uBits.nBits);",
            f"{name} := TRUE;",
        ]
    return [("nExp", "DINT"), ("fAbs", "LREAL"), ("fTwo", "LREAL"), ("fMant", "LREAL"), ("nUpper", "UDINT")], [
        f"{name} := FALSE;",
        "fTwo := 2.0;",
        "fAbs := ABS(fValue);",
        "IF fAbs = 0.0 THEN",
        "    nHigh := 16#00000000;",
        "    nLow := 16#00000000;",
        f"    {name} := TRUE;",
        "    RETURN;",
        "END_IF;",
        *_normalise(),
        "IF nExp < -1022 THEN",
        "    fMant := fAbs * EXPT(fTwo, nExp + 1074);",
        "    nExp := -1023;",
        "ELSE",
        "    fMant := (fAbs - 1.0) * 4503599627370496.0;",
        "END_IF;",
        "(* the mantissa's upper 20 bits: the quotient rounded down (a conversion rounds to nearest) *)",
        f"nUpper := LREAL_TO_UDINT(fMant / {TWO_POWER_32});",
        f"IF UDINT_TO_LREAL(nUpper) * {TWO_POWER_32} > fMant THEN",
        "    nUpper := nUpper - 1;",
        "END_IF;",
        "nHigh := SHL(DINT_TO_DWORD(nExp + 1023), 20) OR UDINT_TO_DWORD(nUpper);",
        f"nLow := UDINT_TO_DWORD(LREAL_TO_UDINT(fMant - UDINT_TO_LREAL(nUpper) * {TWO_POWER_32}));",
        "IF fValue < 0.0 THEN",
        "    nHigh := nHigh OR 16#80000000;",
        "END_IF;",
        f"{name} := TRUE;",
    ]
