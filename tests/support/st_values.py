"""What the executed-ST tests share: a register's words at its edges (from the Python runtime's own
encoding), a read block's words, and the comparison of a value the compiled ST printed with the Python
client's reading of the same words."""

from __future__ import annotations

import math
import struct
from collections.abc import Iterator
from typing import Any

from regmap.backends.st.functions import Block
from regmap.backends.st.names import StIdentifier
from regmap.core.decoding import DecodedValue, carried, trim_bits
from regmap.model import Device, Register, WordOrder
from regmap.runtime_bridge import runtime_specs
from regmap_runtime.codec import _wire_order, raw_to_words
from regmap_runtime.rtu import parse_frame
from regmap_runtime.spec import RegisterSpec


def register_spec(device: Device, reg: Register) -> RegisterSpec[Any]:
    return next(s for s in runtime_specs(device) if s.name == reg.name)


def as_f32(value: float) -> float:
    return float(struct.unpack("<f", struct.pack("<f", value))[0])


def value_members(reg: Register) -> list[str]:
    if reg.bitfields:
        return [StIdentifier(reg.name), *(StIdentifier(reg.name, b.name) for b in reg.bitfields)]
    flagged = reg.has_na or reg.scale_from is not None  # a scaled point: also FALSE for its factor's marker
    return [StIdentifier(reg.name), *([StIdentifier(reg.name, "available")] if flagged else [])]


def edge_words(specs: dict[str, RegisterSpec[Any]], kind: str) -> dict[str, list[int]]:
    """Each register's words (wire order) for an edge, from the runtime's own encoding of the raw value."""
    out: dict[str, list[int]] = {}
    for name, spec in specs.items():
        info = spec.type_info
        if info.is_string:
            text = {"min": "", "max": "Z" * (2 * spec.words), "w8000": "A b"[: 2 * spec.words]}.get(kind, "Ab")
            out[name] = raw_to_words(spec, text)
        elif info.is_bool:
            out[name] = [0 if kind == "min" else 1]
        elif kind.startswith("member"):
            if spec.enum is None or spec.bitfields:
                continue
            k = int(kind.removeprefix("member"))
            members = sorted(int(m) for m in spec.enum)
            if k < len(members):
                out[name] = raw_to_words(spec, members[k])
            else:  # a value no member has
                missing = next(v for v in range(int(spec.raw_min), int(spec.raw_max) + 2) if v not in members)
                if missing <= info.raw_max:
                    out[name] = raw_to_words(spec, missing)
        elif kind in ("infinity", "nan"):
            if info.is_float:  # no raw value the runtime encodes: its words, put in wire order as it reads them
                out[name] = _wire_order(spec, list(info.to_words(math.inf if kind == "infinity" else math.nan)))
        elif kind == "w8000":
            out[name] = [0x8000] + [0] * (spec.words - 1)
        elif kind == "half":
            if spec.enum is not None and info.is_float:  # a setting coded as a float: half-way between two members
                out[name] = raw_to_words(spec, min(int(m) for m in spec.enum) + 0.5)
        elif kind == "na":
            if spec.na:  # the last "not available" marker (min and max often are the first)
                out[name] = raw_to_words(spec, spec.na[-1])
        else:
            out[name] = raw_to_words(spec, spec.raw_min if kind == "min" else spec.raw_max)
    return out


def block_words(block: Block, by_register: dict[str, list[int]]) -> list[int]:
    """The block's words: each register's own words where given, else a pattern of distinct words."""
    words = [(0x1234 + 0x0111 * k) & 0xFFFF if not block.bits else k % 2 for k in range(block.count)]
    for reg in block.registers:
        own = by_register.get(reg.name)
        if own is not None:
            for k, word in enumerate(own):
                words[reg.address - block.address + k] = word
    return words


def order_flag(device: Device, high_word_first: bool | None) -> bool:
    return device.transport.word_order is WordOrder.HIGH_FIRST if high_word_first is None else high_word_first


def compare_value(reg: Register, value: DecodedValue, got: dict[str, str], kind: str) -> tuple[bool, list[str]]:
    """(whether the Python client reads a valid value, what the ST got wrong); `kind`: the ST member's type."""
    name = StIdentifier(reg.name)
    st = got[name]
    if reg.type.is_bool:
        return True, [] if int(st) == int(bool(value.value)) else [f"ST {st}, Python {value.value}"]
    if reg.type.is_string:
        text = bytes.fromhex(st.rstrip("-")).decode(reg.encoding or "ascii", errors="replace")
        return True, [] if text == value.value else [f"ST {text!r}, Python {value.value!r}"]
    if reg.has_na or reg.scale_from is not None:
        available = int(got[StIdentifier(reg.name, "available")])
        if value.value is None:  # the device's "not available" marker: the flag says so, the value is left alone
            return True, [] if available == 0 else [f"ST available for the marker {value.raw!r}, Python None"]
        if available != 1:
            return True, [f"ST not available, Python {value.value!r}"]
    if reg.bitfields:
        wrong = [] if int(st) == value.raw else [f"word: ST {st}, Python {value.raw}"]
        valid = True
        for b in reg.bitfields:
            shown = (value.fields or {})[b.name]
            field = got[StIdentifier(reg.name, b.name)]
            if b.enum is not None:
                if isinstance(shown, int):  # no member: the ST keeps the old value and returns FALSE
                    valid = False
                    continue
                field = b.enum.members[int(field)].name
            elif b.width == 1:
                shown = int(shown)
            if str(field) != str(shown):
                wrong.append(f"{b.name}: ST {field}, Python {shown}")
        return valid, wrong
    if reg.enum is not None:
        if not isinstance(value.value, str):
            return False, []
        member = reg.enum.members[int(st)].name
        return True, [] if member == value.value else [f"ST {member}, Python {value.value}"]
    if isinstance(value.value, float) and not math.isfinite(value.value):
        return False, []  # plain IEC has no infinity or NaN: the decoder says FALSE
    if kind in ("REAL", "LREAL"):
        expected, shown = float(value.value), float(st)
        if kind == "REAL":  # printed with 9 digits, which read back to the same single
            expected, shown = as_f32(expected), as_f32(shown)
        return True, [] if shown == expected else [f"ST {st}, Python {value.value!r}"]
    return True, [] if int(st) == value.value else [f"ST {st}, Python {value.value!r}"]


def example_data(device: Device) -> Iterator[tuple[str, str, str, int, list[int]]]:
    """(example id, kind, space, start address, words or bits) of every example frame that carries values."""
    by_id = {ex.id: ex for ex in device.examples}
    for ex in device.examples:
        frame = parse_frame(ex.wire_frame, ex.direction)
        if frame.kind in ("write_single", "write_multiple_request") and frame.address is not None and frame.space:
            yield ex.id, "write", frame.space, frame.address, list(carried(frame))
        elif frame.kind == "read_response" and ex.request in by_id and frame.space:
            request = parse_frame(by_id[str(ex.request)].wire_frame, "request")
            if request.address is not None and request.count is not None:
                yield ex.id, "read", frame.space, request.address, list(carried(trim_bits(frame, request.count)))
