"""Plain-text spellings every back end shares: a title with its Chinese title, numbers, engineering values.

Each back end escapes the result for its own target (`py_doc`, `c_comment`, `md_text`) and keeps its
own spelling where the targets truly differ (C number literals, the manual-section sentence ...).
"""

from __future__ import annotations

from fractions import Fraction

from regmap.model import Register


def titled(title: str, title_zh: str | None) -> str:
    """`Peak current (峰值电流)`: the manual's title, with the Chinese one when the map gives it."""
    return f"{title} ({title_zh})" if title_zh else title


def number(value: Fraction | int | float) -> str:
    """A number as the docs and comments print it: integers exactly, anything else to 10 significant digits
    (an exact decimal of more digits in full)."""
    if isinstance(value, Fraction) and value.denominator == 1:
        return str(value.numerator)
    if isinstance(value, int):
        return str(value)
    if isinstance(value, Fraction):
        places = _decimal_places(value.denominator)
        exact = _decimal_text(value, places) if places is not None else ""
        if len(exact.lstrip("-0").replace(".", "")) > 10:
            return exact  # an exact decimal of more digits than 10 (a counter x 0.001): 123456789.012, not 123456789
    return f"{float(value):.10g}"


def _decimal_text(value: Fraction, places: int) -> str:
    digits = str(abs(value.numerator * 10**places // value.denominator)).rjust(places + 1, "0")
    sign = "-" if value < 0 else ""
    return sign + (f"{digits[:-places]}.{digits[-places:]}" if places else digits)


def _decimal_places(denominator: int) -> int | None:
    """How many decimals write 1/denominator exactly (2**a * 5**b needs max(a, b)), or None when no finite decimal does."""
    twos = fives = 0
    while denominator % 2 == 0:
        denominator, twos = denominator // 2, twos + 1
    while denominator % 5 == 0:
        denominator, fives = denominator // 5, fives + 1
    return max(twos, fives) if denominator == 1 else None


def eng(reg: Register, raw: int | float | str) -> str:
    """The engineering value of a raw register value (raw x scale + offset); text as a quoted
    string, a coil as on/off. A float raw is scaled as a float (it is no exact fraction)."""
    if isinstance(raw, str):
        return '"' + raw + '"'
    if reg.type.is_bool:
        return "on" if raw else "off"
    if isinstance(raw, float):
        return number(raw * float(reg.scale) + float(reg.offset))
    return number(raw * reg.scale + reg.offset)
