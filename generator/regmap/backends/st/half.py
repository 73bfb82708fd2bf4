"""The half-float (f16) helpers of a device's Structured Text: a WORD's sign, exponent and mantissa to an LREAL
and back, with exact LREAL arithmetic in both dialects (CODESYS / TwinCAT have no 16-bit float to put in a
UNION). Every literal is a power of two or a small integer, so matiec reading it as a REAL changes nothing."""

from __future__ import annotations

from regmap.backends.st.codec import Helpers

SMALLEST_NORMAL = "0.00006103515625"  # 2^-14
TWO_POWER_24 = "16777216.0"


def f16_from_bits_body(h: Helpers) -> tuple[list[tuple[str, str]], list[str]]:
    """(locals, statements) of F16_FROM_BITS(nBits : WORD; fValue : LREAL in-out) : BOOL (FALSE: infinity or NaN)."""
    name = h.f16_from_bits
    return [("nExp", "DINT"), ("fMant", "LREAL"), ("fTwo", "LREAL")], [
        "fTwo := 2.0;",
        "nExp := WORD_TO_DINT(SHR(nBits, 10) AND 16#001F);",
        "fMant := UINT_TO_LREAL(WORD_TO_UINT(nBits AND 16#03FF));",
        "IF nExp = 31 THEN",
        f"    {name} := FALSE; (* infinity or NaN: no value *)",
        "    RETURN;",
        "END_IF;",
        "IF nExp = 0 THEN",
        "    fValue := fMant * EXPT(fTwo, -24);",
        "ELSE",
        "    fValue := (fMant + 1024.0) * EXPT(fTwo, nExp - 25);",
        "END_IF;",
        "IF (nBits AND 16#8000) <> 0 THEN",
        "    fValue := -fValue;",
        "END_IF;",
        f"{name} := TRUE;",
    ]


def f16_to_bits_body(h: Helpers) -> tuple[list[tuple[str, str]], list[str]]:
    """(locals, statements) of F16_TO_BITS(fValue : LREAL; nBits : WORD in-out) : BOOL: the nearest half, ties
    to even; FALSE for infinity, NaN and what rounds to infinity (65520 and beyond)."""
    name = h.f16_to_bits
    return [("nExp", "DINT"), ("nMant", "DINT"), ("nStep", "DINT"), ("fAbs", "LREAL"), ("fStep", "LREAL"), ("i", "INT")], [
        f"{name} := FALSE;",
        "fAbs := ABS(fValue);",
        "IF NOT (fAbs - fAbs = 0.0) THEN",
        "    RETURN; (* infinity or NaN *)",
        "END_IF;",
        "IF fAbs >= 65520.0 THEN",
        "    RETURN; (* rounds to infinity *)",
        "END_IF;",
        f"IF fAbs < {SMALLEST_NORMAL} THEN",
        f"    fAbs := fAbs * {TWO_POWER_24}; (* a subnormal: in units of 2^-24 *)",
        "    nExp := 0;",
        "ELSE",
        "    nExp := 15;",
        "    WHILE fAbs >= 2.0 DO",
        "        fAbs := fAbs * 0.5;",
        "        nExp := nExp + 1;",
        "    END_WHILE;",
        "    WHILE fAbs < 1.0 DO",
        "        fAbs := fAbs * 2.0;",
        "        nExp := nExp - 1;",
        "    END_WHILE;",
        "    fAbs := (fAbs - 1.0) * 1024.0; (* the mantissa, in units of its last bit *)",
        "END_IF;",
        "(* fAbs < 1024: its whole part bit by bit (exact; no conversion that might round), the rest below 1 *)",
        "nMant := 0;",
        "fStep := 512.0;",
        "nStep := 512;",
        "FOR i := 1 TO 10 DO",
        "    IF fAbs >= fStep THEN",
        "        fAbs := fAbs - fStep;",
        "        nMant := nMant + nStep;",
        "    END_IF;",
        "    fStep := fStep * 0.5;",
        "    nStep := nStep / 2;",
        "END_FOR;",
        "IF fAbs > 0.5 OR (fAbs = 0.5 AND (nMant MOD 2) = 1) THEN",
        "    nMant := nMant + 1; (* to nearest, ties to even; a carry moves into the exponent *)",
        "END_IF;",
        "nBits := DINT_TO_WORD(nExp * 1024 + nMant);",
        "IF fValue < 0.0 THEN",
        "    nBits := nBits OR 16#8000;",
        "END_IF;",
        f"{name} := TRUE;",
    ]
