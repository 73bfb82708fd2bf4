"""YAML text for values, written the way the maps write them (hex addresses, flow lists, quoted when needed)."""

from __future__ import annotations

import json
import re
from fractions import Fraction
from typing import Any

_PLAIN = re.compile(r"^[A-Za-z\u4e00-\u9fff][\w\u4e00-\u9fff .()/+%°Ω·-]*$")
_RESERVED = {"null", "true", "false", "yes", "no", "on", "off", "y", "n", "~"}


def scalar(value: Any, key: str = "") -> str:
    if value is None:
        return "null"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, Fraction):
        return str(value.numerator) if value.denominator == 1 else repr(float(value))
    if isinstance(value, int):
        return f"0x{value:04X}" if key == "address" or (key == "na" and value >= 0) else str(value)
    if isinstance(value, float):
        text = repr(value)  # 1e-07: YAML 1.1 reads a float only with a dot and a signed exponent
        mantissa, e, exponent = text.partition("e")
        if e and "." not in mantissa:
            mantissa += ".0"
        return mantissa + (("e" + (exponent if exponent[0] in "+-" else "+" + exponent)) if e else "")
    text = str(value)
    if _PLAIN.match(text) and text.lower() not in _RESERVED and not text.endswith((" ", ":")) and ": " not in text and " #" not in text:
        return text
    return json.dumps(text, ensure_ascii=False)  # a JSON string is a YAML double-quoted scalar


def flow(value: Any, key: str = "") -> str:
    """A value on one line: scalars, `[a, b]`, `{k: v}`."""
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(flow(v, key if key == "na" else "") for v in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k}: {flow(v, k)}" for k, v in value.items()) + "}"
    return scalar(value, key)


def block(mapping: dict[str, Any], indent: int, first: str = "") -> list[str]:
    """A mapping as block lines at `indent`; `first` prefixes the first line (`- ` for a list item)."""
    lines = []
    pad = " " * indent
    for i, (key, value) in enumerate(mapping.items()):
        lead = (pad[: -len(first)] + first) if i == 0 and first else pad
        if isinstance(value, list) and value and isinstance(value[0], dict):
            lines.append(f"{lead}{key}:")
            lines += [f"{pad}  - {flow(v)}" for v in value]
        else:
            lines.append(f"{lead}{key}: {flow(value, key)}")
    return lines
