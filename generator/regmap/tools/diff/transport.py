"""Changes of the transport settings: one row per setting."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

from regmap.model import Transport
from regmap.tools.diff.kinds import MAJOR, MINOR, PATCH, Bump, Changes
from regmap.tools.diff.text import _pair, _range, _show


def transport_changes(o: Transport, n: Transport, rename: Callable[[str], str]) -> Changes:
    """One change per transport setting that differs; `rename` maps an old register name to the new one."""
    out = Changes()

    def setting(name: str, bump: Bump, a: Any, b: Any, show: Callable[[Any], str] = _show, note: str = "") -> None:
        out.add("transport_changed", name, bump, show(a), show(b), a, b, note)

    def grew_or_shrank(name: str, a: Sequence[int], b: Sequence[int], show: Callable[[Any], str] = _show) -> None:
        if tuple(a) == tuple(b):
            return
        lost, gained = sorted(set(a) - set(b)), sorted(set(b) - set(a))
        note = "; ".join(p for p in (f"removed {show(lost)}" if lost else "", f"added {show(gained)}" if gained else "") if p)
        setting(name, MAJOR if lost else MINOR if gained else PATCH, list(a), list(b), show, note)

    def limit(name: str, a: int | None, b: int | None) -> None:
        if a != b:
            smaller = a is not None and b is not None and b < a
            setting(name, MAJOR if smaller else PATCH, a, b, note="smaller: old requests may be refused" if smaller else "")

    notes = {
        "word_order": "applies to every 32-bit register without its own word order",
        "byte_order": "applies to every register without its own byte order",
    }
    for name in ("baud", "parity", "data_bits", "stop_bits", "word_order", "byte_order", "crc_byte_order"):
        a, b = getattr(o, name), getattr(n, name)
        if a != b:
            setting(name, MAJOR, a, b, note=notes.get(name, "an old client uses the old setting by default"))
    grew_or_shrank("baud_rates", o.baud_rates, n.baud_rates)
    if (o.slave_min, o.slave_max) != (n.slave_min, n.slave_max):
        narrowed = n.slave_min > o.slave_min or n.slave_max < o.slave_max
        out.add(
            "transport_changed",
            "slave_ids",
            MAJOR if narrowed else MINOR,
            _range(o.slave_min, o.slave_max),
            _range(n.slave_min, n.slave_max),
            {"min": o.slave_min, "max": o.slave_max},
            {"min": n.slave_min, "max": n.slave_max},
            "narrowed" if narrowed else "widened",
        )
    if o.broadcast_id != n.broadcast_id:
        setting("broadcast_id", MINOR if o.broadcast_id is None else MAJOR, o.broadcast_id, n.broadcast_id)
    grew_or_shrank(
        "function_codes",
        o.function_codes,
        n.function_codes,
        lambda v: _show([f"0x{c:02X}" for c in v]) if isinstance(v, list) else _show(v),
    )
    limit("max_read_registers", o.max_read_registers, n.max_read_registers)
    limit("max_write_registers", o.max_write_registers, n.max_write_registers)
    limit("max_message_bytes", o.max_message_bytes, n.max_message_bytes)
    limit("max_read_coils", o.max_read_coils, n.max_read_coils)
    limit("max_write_coils", o.max_write_coils, n.max_write_coils)

    def wor(t: Transport) -> dict[str, Any] | None:
        w = t.word_order_register
        if w is None:
            return None
        name = rename(w.register.name) if t is o else w.register.name
        if w.swap_value is not None:
            return {"register": name, "swap_value": w.swap_value}
        return {"register": name, "high_first": w.high_first, "low_first": w.low_first}

    a_wor, b_wor = wor(o), wor(n)
    if a_wor != b_wor:
        show = lambda v: "none" if v is None else f"{v['register']} ({_order_values(v)})"  # noqa: E731
        setting("word_order_register", MINOR if a_wor is None else MAJOR, a_wor, b_wor, show)
    a_align, b_align = _alignment(o), _alignment(n)
    if a_align != b_align:
        note = "old read plans may break the new alignment" if b_align is not None else ""
        setting("read_alignment", MAJOR if b_align is not None else MINOR, a_align, b_align, note=note)
    if o.undocumented_addresses != n.undocumented_addresses:
        stricter = n.undocumented_addresses == "reject"
        note = "old read plans that bridge gaps are refused now" if stricter else ""
        setting("undocumented_addresses", MAJOR if stricter else PATCH, o.undocumented_addresses, n.undocumented_addresses, note=note)
    if o.response_delay_ms != n.response_delay_ms:
        setting("response_delay_ms", PATCH, o.response_delay_ms, n.response_delay_ms)
    for name, a, b in (
        ("timing", [vars(t) for t in o.timing], [vars(t) for t in n.timing]),
        (
            "exceptions",
            [(e.code, e.name, e.title, e.title_zh, e.source) for e in o.exceptions],
            [(e.code, e.name, e.title, e.title_zh, e.source) for e in n.exceptions],
        ),
    ):
        if a != b:
            codes = name == "exceptions"
            show = (lambda v: _show([f"0x{e[0]:02X} {e[1]}" for e in v])) if codes else (lambda v: f"{len(v)} rows")
            setting(name, PATCH, a, b, show)
    for name in ("source", "notes"):
        a, b = getattr(o, name), getattr(n, name)
        if a != b:
            out.add("transport_changed", name, PATCH, *_pair(a, b), a, b)

    return out


def _order_values(v: dict[str, Any]) -> str:
    if "swap_value" in v:
        return f"writing {v['swap_value']} swaps the order"
    return f"high first {v['high_first']}, low first {v['low_first']}"


def _alignment(t: Transport) -> str | None:
    a = t.read_alignment
    if a is None:
        return None
    exempt = f", exempt {', '.join(r.name for r in a.exempt)}" if a.exempt else ""
    return f"{a.words} words in {', '.join(a.spaces)}{exempt}"
