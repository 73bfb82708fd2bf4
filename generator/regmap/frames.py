"""Frame building and decoding for field engineers: `regmap frame` and `regmap decode`.

Everything goes through the runtime's planner and codec, so a frame printed here is byte for
byte the frame the generated client sends.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

from regmap.backends.common import read_plan, runtime_specs
from regmap.diagnostics import UsageError
from regmap.model import Device, Register
from regmap_runtime.codec import RangeError, check_raw, raw_to_value, raw_to_words, value_to_raw, words_to_raw
from regmap_runtime.plan import WriteBlock, plan_writes
from regmap_runtime.rtu import (
    STANDARD_EXCEPTIONS,
    Frame,
    FrameError,
    build_read,
    build_write_multiple,
    build_write_single,
    parse_frame,
    parse_hex,
    to_hex,
)
from regmap_runtime.spec import RegisterSpec

FUNCTION_NAMES = {
    0x01: "read coils",
    0x02: "read discrete inputs",
    0x03: "read holding registers",
    0x04: "read input registers",
    0x05: "write single coil",
    0x06: "write single register",
    0x0F: "write multiple coils",
    0x10: "write multiple registers",
}


class Registers:
    """Look-ups by selector and by address over one device's registers."""

    def __init__(self, device: Device) -> None:
        self.device = device
        self.specs: dict[str, RegisterSpec[Any]] = {s.name: s for s in runtime_specs(device)}
        self.by_name = {r.name: r for r in device.registers}
        self.by_param = {r.param: r for r in device.registers if r.param}
        self.by_param_folded = {r.param.lower(): r for r in device.registers if r.param}
        self.by_address = {r.address: r for r in device.registers}

    def find(self, selector: str) -> Register | None:
        """A register by name, manual parameter id, or address (0x0191 or decimal 401)."""
        text = selector.strip()
        if text in self.by_name:
            return self.by_name[text]
        if text in self.by_param:
            return self.by_param[text]
        if text.lower() in self.by_param_folded:
            return self.by_param_folded[text.lower()]
        address = parse_address(text)
        if address is not None:
            return self.by_address.get(address)
        return None

    def resolve(self, selector: str) -> Register:
        reg = self.find(selector)
        if reg is None:
            hint = ""
            address = parse_address(selector)
            if address is not None:
                owner = self.device.covering(address)
                hint = (
                    f" (0x{address:04X} lies inside {owner.label})"
                    if owner
                    else f" (no register at 0x{address:04X}; --raw writes any address)"
                )
            raise UsageError(f"unknown register {selector!r}{hint}")
        return reg

    def spec(self, reg: Register) -> RegisterSpec[Any]:
        return self.specs[reg.name]


def parse_address(text: str) -> int | None:
    text = text.strip()
    try:
        value = int(text, 16) if text.lower().startswith("0x") else int(text, 10) if re.fullmatch(r"[0-9]+", text) else None
    except ValueError:
        return None
    if value is None or not 0 <= value <= 0xFFFF:
        return None
    return value


def parse_int(text: str, what: str) -> int:
    try:
        return int(text, 0)
    except ValueError:
        raise UsageError(f"{what}: {text!r} is not an integer") from None


def check_slave(device: Device, slave: int) -> None:
    t = device.transport
    if slave == t.broadcast_id or t.slave_min <= slave <= t.slave_max:
        return
    broadcast = f", or {t.broadcast_id} to broadcast" if t.broadcast_id is not None else ""
    raise UsageError(f"slave id {slave} is outside {t.slave_min}..{t.slave_max}{broadcast} for {device.info.model}")


# -- building ----------------------------------------------------------------------------


def read_frames(device: Device, selector: str, count: int | None, slave: int) -> list[bytes]:
    """Read one register, or `count` consecutive registers from it, with the fewest requests."""
    check_slave(device, slave)
    regs = Registers(device)
    reg = regs.find(selector)
    if reg is None:
        address = parse_address(selector)
        if address is None:
            regs.resolve(selector)  # raises with the explanation
            raise AssertionError("unreachable")
        return [build_read(slave, address, count or 1)]
    if not reg.access.readable:
        raise UsageError(f"{reg.label} is write-only")
    if count is None or count == 1:
        chosen = [reg]
    else:
        readable = [r for r in sorted(device.registers, key=lambda r: r.address) if r.access.readable and r.address >= reg.address]
        chosen = readable[:count]
        if len(chosen) < count:
            raise UsageError(f"only {len(chosen)} readable registers from {reg.label} onwards, asked for {count}")
    blocks = read_plan(device, chosen)
    return [build_read(slave, b.address, b.count) for b in blocks]


@dataclass
class Assignments:
    """Parsed SELECTOR=VALUE items: checked register values, and raw writes to any address."""

    values: list[tuple[RegisterSpec[Any], int]] = field(default_factory=list)
    raw_writes: list[tuple[int, list[int]]] = field(default_factory=list)
    registers: list[Register] = field(default_factory=list)


def parse_assignments(device: Device, assignments: Sequence[str], raw: bool) -> Assignments:
    regs = Registers(device)
    out = Assignments()
    for item in assignments:
        selector, sep, value_text = item.partition("=")
        if not sep or not selector or not value_text:
            raise UsageError(f"write wants SELECTOR=VALUE, got {item!r}")
        reg = regs.find(selector)
        if reg is None:
            address = parse_address(selector)
            if address is None or not raw:
                regs.resolve(selector)
            assert address is not None
            words = [parse_int(w, selector) for w in value_text.split(",")]
            if any(not 0 <= w <= 0xFFFF for w in words):
                raise UsageError(f"{selector}: raw words are 0..0xFFFF")
            out.raw_writes.append((address, words))
            continue
        if not reg.access.writable:
            raise UsageError(f"{reg.label} is read-only")
        spec = regs.spec(reg)
        try:
            symbolic = None if raw else symbolic_raw(reg, value_text)
            if raw:
                number = parse_int(value_text, reg.label)
            elif symbolic is not None:
                number = symbolic
            else:
                number = value_to_raw(spec, value_text)
            check_raw(spec, number)
        except RangeError as exc:
            raise UsageError(str(exc)) from None
        out.values.append((spec, number))
        out.registers.append(reg)
    return out


def write_blocks(device: Device, values: list[tuple[RegisterSpec[Any], int]]) -> list[WriteBlock]:
    try:
        return plan_writes(values, device.transport.max_write_registers, 0x10 in device.transport.function_codes)
    except ValueError as exc:
        raise UsageError(str(exc)) from None


def write_frames(device: Device, assignments: Sequence[str], slave: int, raw: bool) -> list[bytes]:
    """Frames for SELECTOR=VALUE assignments; contiguous registers share one 0x10 frame."""
    check_slave(device, slave)
    parsed = parse_assignments(device, assignments, raw)
    frames = [build_write_single(slave, a, w[0]) if len(w) == 1 else build_write_multiple(slave, a, w) for a, w in parsed.raw_writes]
    for block in write_blocks(device, parsed.values):
        frames.append(
            build_write_single(slave, block.address, block.words[0])
            if block.single
            else build_write_multiple(slave, block.address, list(block.words))
        )
    return frames


def symbolic_raw(reg: Register, text: str) -> int | None:
    """Raw value of an enum member name (`save_all_parameters`) or of bitfields written
    `field:value,field:value` (`function:addr0,normally_closed:1`); None when `text` is neither."""
    if reg.enum is not None:
        member = reg.enum.member(text.strip().lower())
        if member is not None:
            return member.value
    if not reg.bitfields or ":" not in text:
        return None
    fields = {b.name: b for b in reg.bitfields}
    raw = 0
    for part in text.split(","):
        name, _, value_text = part.partition(":")
        field_spec = fields.get(name.strip())
        if field_spec is None:
            raise UsageError(f"{reg.label} has no bitfield {name.strip()!r} (fields: {', '.join(fields)})")
        member = field_spec.enum.member(value_text.strip().lower()) if field_spec.enum else None
        value = member.value if member is not None else parse_int(value_text.strip(), f"{reg.label}.{field_spec.name}")
        if not 0 <= value <= field_spec.max_value:
            raise UsageError(f"{reg.label}.{field_spec.name}: {value} does not fit in {field_spec.width} bit(s)")
        raw |= value << field_spec.lsb
    return raw


def command_frames(device: Device, name: str, argument: str | None, slave: int) -> list[bytes]:
    check_slave(device, slave)
    command = next((c for c in device.commands if c.name == name), None)
    if command is None:
        known = ", ".join(c.name for c in device.commands) or "none"
        raise UsageError(f"unknown command {name!r} (commands: {known})")
    try:
        raw = command.raw_value(None if argument is None else parse_int(argument, command.name))
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    spec = Registers(device).spec(command.register)
    words = raw_to_words(spec, raw)
    if len(words) == 1:
        return [build_write_single(slave, command.register.address, words[0])]
    return [build_write_multiple(slave, command.register.address, words)]


# -- decoding ----------------------------------------------------------------------------


@dataclass
class DecodedValue:
    address: int
    register: str | None
    param: str | None
    raw: int | None
    words: list[int]
    value: Any = None
    unit: str | None = None
    text: str = ""

    def as_json(self) -> dict[str, Any]:
        return {
            "address": self.address,
            "register": self.register,
            "param": self.param,
            "words": self.words,
            "raw": self.raw,
            "value": self.value,
            "unit": self.unit,
            "text": self.text,
        }


@dataclass
class Decoded:
    frame: Frame
    direction: str
    function_name: str
    values: list[DecodedValue] = field(default_factory=list)
    exception: str | None = None
    notes: list[str] = field(default_factory=list)

    @property
    def ok(self) -> bool:
        return self.frame.crc_valid and not self.frame.problems

    def as_json(self) -> dict[str, Any]:
        f = self.frame
        return {
            "hex": to_hex(f.raw),
            "slave": f.slave,
            "function": f.function,
            "function_name": self.function_name,
            "direction": self.direction,
            "kind": f.kind,
            "crc_valid": f.crc_valid,
            "crc": to_hex(f.raw[-2:]),
            "address": f.address,
            "count": f.count,
            "byte_count": f.byte_count,
            "words": list(f.words),
            "exception_code": f.exception_code,
            "exception": self.exception,
            "values": [v.as_json() for v in self.values],
            "problems": list(f.problems),
            "notes": self.notes,
        }


def describe_value(device: Device, reg: Register, raw: int) -> tuple[Any, str]:
    """Engineering value and a human text: `2.2 A`, `save_ok (0x5555)`, `fault=0 enabled=1 ...`."""
    spec = Registers(device).spec(reg)
    if reg.bitfields:
        parts = []
        for b in reg.bitfields:
            field_value = (raw & b.mask) >> b.lsb
            member = b.enum.by_value(field_value) if b.enum else None
            parts.append(f"{b.name}={member.name if member else field_value}")
        return {b.name: (raw & b.mask) >> b.lsb for b in reg.bitfields}, f"0x{raw:04X}: " + " ".join(parts)
    if reg.enum is not None:
        member = reg.enum.by_value(raw)
        label = member.name if member else "value not in the manual's table"
        return (member.name if member else raw), f"{label} ({raw} = 0x{raw & 0xFFFFFFFF:X})"
    number = raw_to_value(spec, raw)
    unit = f" {reg.unit}" if reg.unit else ""
    shown = f"{number:g}" if isinstance(number, float) else str(number)
    return number, f"{shown}{unit}" + (f" (raw {raw})" if reg.scaled else "")


def decode_words(device: Device, start: int, words: Sequence[int]) -> list[DecodedValue]:
    """Split words read from (or written to) `start` into the registers they carry."""
    out: list[DecodedValue] = []
    regs = Registers(device)
    address = start
    end = start + len(words)
    while address < end:
        reg = device.covering(address)
        if reg is None:
            out.append(
                DecodedValue(address, None, None, words[address - start], [words[address - start]], text="not documented in the map")
            )
            address += 1
            continue
        if reg.paired and address == reg.first_address:
            word = words[address - start]
            out.append(DecodedValue(address, reg.name, reg.param, None, [word], text=f"0x{word:04X}, the unused high word of {reg.label}"))
            address += 1
            continue
        own = list(range(reg.address, reg.last_address + 1))
        if own[0] < start or own[-1] >= end:
            word = words[address - start]
            out.append(
                DecodedValue(
                    address, reg.name, reg.param, None, [word], text=f"part of {reg.label} (not all of its words are in this frame)"
                )
            )
            address += 1
            continue
        own_words = [words[a - start] for a in own]
        raw = words_to_raw(regs.spec(reg), own_words)
        value, text = describe_value(device, reg, raw)
        out.append(DecodedValue(reg.address, reg.name, reg.param, raw, own_words, value, reg.unit, text))
        address = reg.last_address + 1
    return out


def decode_frame(device: Device, frame_bytes: bytes, *, direction: str | None = None, request: Frame | None = None) -> Decoded:
    try:
        frame = parse_frame(frame_bytes, direction)
    except FrameError as exc:
        raise UsageError(str(exc)) from None
    base_function = frame.function & 0x7F
    name = FUNCTION_NAMES.get(base_function, f"function 0x{base_function:02X}")
    kind_direction = {
        "read_request": "request",
        "read_response": "response",
        "write_multiple_request": "request",
        "write_multiple_response": "response",
        "exception": "response",
    }.get(frame.kind, direction or "request or response")
    decoded = Decoded(frame=frame, direction=kind_direction, function_name=name)
    if frame.kind == "exception":
        code = frame.exception_code
        known = device.transport.exception(code) if code is not None else None
        meaning = (
            known.title + (f" ({known.title_zh})" if known and known.title_zh else "")
            if known
            else STANDARD_EXCEPTIONS.get(code or 0, "unknown exception code")
        )
        decoded.exception = f"0x{code:02X}: {meaning}" if code is not None else "missing exception code"
    elif frame.kind == "read_request" and frame.address is not None and frame.count is not None:
        decoded.values = _registers_in(device, frame.address, frame.count)
    elif frame.kind in ("write_single", "write_multiple_request") and frame.address is not None:
        decoded.values = decode_words(device, frame.address, frame.words)
    elif frame.kind == "read_response":
        if request is not None and request.kind == "read_request" and request.address is not None:
            if request.count is not None and request.count != len(frame.words):
                decoded.notes.append(f"the request asked for {request.count} registers, the response carries {len(frame.words)}")
            decoded.values = decode_words(device, request.address, frame.words)
        else:
            decoded.notes.append("a read response does not carry the address; give the request (--file pairs them) to name the registers")
    elif frame.kind == "write_multiple_response" and request is not None and request.count is not None and request.count != frame.count:
        decoded.notes.append(f"the request wrote {request.count} registers, the response echoes {frame.count}")
    if base_function not in device.transport.function_codes and frame.kind != "exception":
        decoded.notes.append(f"function 0x{base_function:02X} is not supported by {device.info.model}")
    if request is not None and request.slave != frame.slave:
        decoded.notes.append(f"answer from slave {frame.slave} to a request for slave {request.slave}")
    return decoded


def _registers_in(device: Device, start: int, count: int) -> list[DecodedValue]:
    out = []
    seen: set[str] = set()
    for address in range(start, start + count):
        reg = device.covering(address)
        if reg is None:
            out.append(DecodedValue(address, None, None, None, [], text="not documented in the map"))
        elif reg.name not in seen:
            seen.add(reg.name)
            out.append(DecodedValue(reg.address, reg.name, reg.param, None, [], unit=reg.unit, text=reg.title))
    return out


def render_text(decoded: Decoded) -> str:
    f = decoded.frame
    crc = "ok" if f.crc_valid else "MISMATCH"
    lines = [
        to_hex(f.raw),
        f"  slave {f.slave}, function 0x{f.function:02X} {decoded.function_name} ({decoded.direction}), CRC {to_hex(f.raw[-2:])} {crc}",
    ]
    if f.address is not None:
        lines.append(
            f"  address 0x{f.address:04X}"
            + (f", count {f.count}" if f.count is not None else "")
            + (f", byte count {f.byte_count}" if f.byte_count is not None else "")
        )
    elif f.byte_count is not None:
        lines.append(f"  byte count {f.byte_count}, {len(f.words)} words")
    if decoded.exception:
        lines.append(f"  exception {decoded.exception}")
    for v in decoded.values:
        label = " ".join(x for x in (v.param, v.register) if x) or "-"
        value = f" = {v.text}" if v.raw is not None else f": {v.text}"
        lines.append(f"  0x{v.address:04X} {label}{value}")
    for problem in f.problems:
        lines.append(f"  problem: {problem}")
    for note in decoded.notes:
        lines.append(f"  note: {note}")
    return "\n".join(lines)


_DIRECTION_TAGS = {"tx": "request", ">": "request", "->": "request", "rx": "response", "<": "response", "<-": "response"}


def decode_capture(device: Device, lines: Sequence[str], source: str) -> list[Decoded]:
    """Decode a log of frames, one per line, pairing each response with the request before it.

    A line may start with a direction tag (TX/RX, > or <); `#` starts a comment.
    """
    out: list[Decoded] = []
    pending: Frame | None = None
    for number, line in enumerate(lines, 1):
        text = line.split("#", 1)[0].strip()
        if not text:
            continue
        direction: str | None = None
        first, _, rest = text.partition(" ")
        tag = first.rstrip(":").lower()
        if tag in _DIRECTION_TAGS:
            direction, text = _DIRECTION_TAGS[tag], rest
        try:
            frame_bytes = parse_hex(text)
        except FrameError as exc:
            raise UsageError(f"{source}:{number}: {exc}") from None
        if direction is None:
            direction = "response" if pending is not None else "request"
        try:
            decoded = decode_frame(device, frame_bytes, direction=direction, request=pending if direction == "response" else None)
        except UsageError as exc:
            raise UsageError(f"{source}:{number}: {exc}") from None
        out.append(decoded)
        pending = decoded.frame if decoded.direction == "request" else None
    return out
