"""The Python back end's docstrings of a register: its constant's (every fact of it) and its methods' (one line)."""

from __future__ import annotations

from regmap.core.text import eng, na_list, titled, zone_text
from regmap.model import ByteOrder, PollClass, Register, WordOrder
from regmap.render import py_doc
from regmap_runtime.spaces import DEFAULT_SPACE


def sources(source: tuple[str, ...]) -> str:
    return f". Manual section {', '.join(source)}." if source else "."


def wire_order(reg: Register) -> str:
    """The register's bytes on the wire, A the most significant: ABCD, CDAB (words low first), BADC
    (bytes swapped), DCBA (both), and the same for four words (ABCDEFGH ...)."""
    letters = "ABCDEFGH"[: 2 * reg.words]
    pairs = [letters[i : i + 2] for i in range(0, len(letters), 2)]
    if reg.byte_order is ByteOrder.LOW_FIRST:
        pairs = [pair[::-1] for pair in pairs]
    if reg.wide and reg.word_order is WordOrder.LOW_FIRST:
        pairs = pairs[::-1]
    return "".join(pairs)


def _layout_facts(reg: Register) -> list[str]:
    """Where the map goes beyond 16/32-bit holding registers: the byte order of floats, 64-bit and
    byte-swapped values, a string's length, encoding and padding (seed maps' docstrings stay as they were)."""
    if reg.type.is_string:
        swapped = ", bytes swapped in each word" if reg.byte_order is ByteOrder.LOW_FIRST else ""
        return [
            f"{reg.words} words ({2 * reg.words} bytes of {reg.encoding}, {reg.padding.upper() if reg.padding == 'nul' else reg.padding} padded{swapped})"
        ]
    if reg.type.is_bool:
        return []
    if reg.byte_order is ByteOrder.LOW_FIRST or reg.type.is_float or reg.type.words > 2:
        return [f"byte order {wire_order(reg)}"]
    return []


def register_doc(reg: Register) -> str:
    kind = reg.type
    parts = [titled(reg.title, reg.title_zh) + "."]
    facts = [f"Parameter {reg.param}"] if reg.param else []
    if reg.space != DEFAULT_SPACE:
        facts.append(reg.space_info.title[:-1])  # "input register", "coil", "discrete input"
    facts.append(f"address 0x{reg.address:04X}" + (" (low word of a 32-bit pair)" if reg.paired else ""))
    facts.append(kind._value_ + (f" ({zone_text(reg)})" if reg.zone else ""))
    if kind.is_string or kind.is_float or kind.words > 2 or reg.byte_order is ByteOrder.LOW_FIRST:  # else _layout_facts has none
        facts += _layout_facts(reg)
    if reg.unit:
        facts.append(f"unit {reg.unit}")
    facts += [f"value = raw x 10^{reg.scale_from} (read with it; not available (None) when {reg.scale_from} is)"] if reg.scale_from else []
    # eng() of an int of a register neither scaled, offset, a bit nor a timestamp is its str(): most ranges and defaults
    exact = not (reg.scaled or reg.offset_set or kind.is_bool or reg.zone is not None)
    if reg.min is not None or reg.max is not None:
        low, high = reg.raw_min, reg.raw_max
        shown = f"{low}..{high}" if exact and type(low) is int and type(high) is int else f"{eng(reg, low)}..{eng(reg, high)}"
        facts.append(f"{'raw ' if reg.scale_from else ''}range {shown}")
    if reg.default is not None:
        default = reg.default
        facts.append(f"{'raw ' if reg.scale_from else ''}default {default if exact and type(default) is int else eng(reg, default)}")
    if reg.takes_effect:
        facts.append(f"takes effect {reg.takes_effect.replace('_', ' ')}")
    if reg.firmware is not None:
        facts.append(f"exists with {reg.firmware.text}")
    if reg.poll is not PollClass.NORMAL:
        facts.append(f"poll {reg.poll.value}")
    if reg.variants:
        facts.append(f"only on the variant(s) {', '.join(reg.variants)} (a client made with variant= refuses it on another)")
    if reg.has_na:
        facts.append(f"not available (read as None): {na_list(reg)}")
    parts.append(", ".join(facts) + sources(reg.source))
    if reg.description:
        parts.append(reg.description)
    return py_doc(" ".join(parts))


def method_docs(reg: Register, constant: str) -> tuple[str, str]:
    """The read and write methods' docstrings: what help() needs to pick the method; the rest at `constant`.
    The title is cleaned once for both (what precedes it, a verb and a constant, holds no quote, space run or escape)."""
    tail = py_doc(f"{titled(reg.title, reg.title_zh)}; documented at the constant.")
    return f"Read {constant}: {tail}", f"Write {constant}: {tail}"
