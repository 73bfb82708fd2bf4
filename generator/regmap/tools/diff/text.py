"""Display helpers: map text and values as short plain text (before/after cells) and as JSON values."""

from __future__ import annotations

import enum
import re
import unicodedata
from collections.abc import Mapping, Sequence
from fractions import Fraction
from typing import Any

from regmap.model import Access, ArrayDef, FirmwareGate, Register
from regmap.render import hex4


def _plain(text: str) -> str:
    """Map text on one line, without control characters (terminals) or runs of whitespace."""
    cleaned = "".join(" " if unicodedata.category(ch) in ("Cc", "Zl", "Zp") else ch for ch in text)
    return " ".join(cleaned.split())


def _clip(text: str, limit: int = 60) -> str:
    return text if len(text) <= limit else text[: limit - 1] + "…"


def _val(value: int) -> str:
    """An enum or command value as the maps write them: hex from 10 up."""
    return f"0x{value:02X}" if value >= 10 else str(value)


def _show(value: Any) -> str:
    if value is None:
        return "none"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, str):
        return f'"{_clip(_plain(value))}"'
    if isinstance(value, (tuple, list)):
        return "[" + ", ".join(_show(v) for v in value) + "]"
    if isinstance(value, Fraction):
        return _fraction(value)
    if isinstance(value, enum.Enum):
        return str(value.value)
    return _clip(_plain(str(value)))


def _pair(a: Any, b: Any, limit: int = 60) -> tuple[str, str]:
    """Two values for a before/after pair; long texts are shown around their first difference."""
    if not (isinstance(a, str) and isinstance(b, str)):
        return _show(a), _show(b)
    a, b = _plain(a), _plain(b)
    if len(a) <= limit and len(b) <= limit:
        return f'"{a}"', f'"{b}"'
    same = next((i for i, (x, y) in enumerate(zip(a, b, strict=False)) if x != y), min(len(a), len(b)))
    start = max(0, same - limit // 3)

    def window(text: str) -> str:
        part = text[start : start + limit]
        return ("…" if start else "") + part + ("…" if start + limit < len(text) else "")

    return f'"{window(a)}"', f'"{window(b)}"'


def _fields(diffs: Sequence[tuple[str, Any, Any]]) -> tuple[str, str]:
    """`field value; field value` before and after, for the fields that differ."""
    pairs = [(f, *_pair(a, b)) for f, a, b in diffs]
    return "; ".join(f"{f} {a}" for f, a, _ in pairs), "; ".join(f"{f} {b}" for f, _, b in pairs)


def _fraction(value: Fraction) -> str:
    if value.denominator == 1:
        return str(value.numerator)
    as_float = float(value)
    return repr(as_float) if Fraction(repr(as_float)) == value else f"{value.numerator}/{value.denominator}"


def _json(value: Any) -> Any:
    if isinstance(value, (tuple, list)):
        return [_json(v) for v in value]
    if isinstance(value, Fraction):
        return value.numerator if value.denominator == 1 else float(value)
    if isinstance(value, enum.Enum):
        return value.value
    if isinstance(value, bytes):
        return value.hex(" ").upper()
    if isinstance(value, Mapping):
        return {str(k): _json(v) for k, v in value.items()}
    return value


def _range(lo: int | float | None, hi: int | float | None) -> str:
    if lo is not None and hi is not None:
        return f"{lo}..{hi}"
    if lo is not None:
        return f">= {lo}"
    if hi is not None:
        return f"<= {hi}"
    return "not given"


ACCESS = {Access.READ: "R", Access.READ_WRITE: "RW", Access.WRITE: "W"}


def _register_summary(r: Register) -> str:
    """`Pr5.00 0x0191 u16 RW A, "Peak current"`; a register outside the holding registers names its
    space (`0x0000 input f32 R V`), a gated one its firmware (`..., firmware >= 2.0`)."""
    kind = r.type.value + (f" x{r.words}" if r.type.is_string else "")
    parts = [hex4(r.address), kind, ACCESS[r.access]]
    if r.space != "holding":
        parts.insert(1, r.space)
    if r.param:
        parts.insert(0, r.param)
    if r.unit:
        parts.append(_plain(r.unit))
    gate = f", {r.firmware.text}" if r.firmware is not None else ""
    return " ".join(parts) + f', "{_clip(_plain(r.title))}"' + gate


def _gate(gate: FirmwareGate | None) -> str:
    """A firmware gate as diff prints it: `firmware >= 2.0`, `2.1 <= firmware < 3.0`, or `every firmware`."""
    return "every firmware" if gate is None else gate.text


def _array_summary(a: ArrayDef) -> str:
    members = ", ".join(m.name for m in a.members)
    return f"{a.count} x {a.stride} words at {hex4(a.base)} ({members})"


def _layout(name: str, value: int) -> str:
    return f"{name} {hex4(value) if name == 'base' else value}"


def _effect(effect: tuple[Any, ...] | None) -> str:
    if effect is None:
        return "none"
    kind, register, value, after_read = effect
    parts = [kind, *([register] if register else []), *([f"value {_val(value)}"] if value else [])]
    return " ".join(parts + ([f"then {_val(after_read)} after a read"] if after_read is not None else []))


def _indices(indices: Sequence[int]) -> str:
    """`[0, 1, 2, 5]` -> `0..2,5`."""
    runs: list[list[int]] = []
    for i in sorted(indices):
        if runs and i == runs[-1][-1] + 1:
            runs[-1].append(i)
        else:
            runs.append([i])
    return ",".join(str(r[0]) if len(r) == 1 else f"{r[0]}..{r[-1]}" for r in runs)


def _natural(text: str) -> list[Any]:
    return [int(t) if t.isdigit() else t for t in re.split(r"(\d+)", text)]
