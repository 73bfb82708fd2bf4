"""`regmap decode`: what a frame or a bus capture holds, named with the map's registers.

The words go through the runtime's codec (`words_to_raw`, `raw_to_value`), the same code that
decodes what the generated clients read. Every frame is read in its function's data space: a 0x02
request at 0x0001 names the discrete input at 0x0001, never the holding register there; the bit
functions (0x01/0x02/0x05/0x0F) carry bits (`carried`), a bit response as many as its request asked
for (`trim_bits`: the rest of its last byte is padding, which must be zero).
"""

from __future__ import annotations

import codecs
import dataclasses
import math
import re
import struct
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

from regmap.diagnostics import UsageError
from regmap.model import Device, Register
from regmap.runtime_bridge import documented_addresses
from regmap.tools.selectors import Registers
from regmap_runtime.codec import raw_to_value, words_to_raw
from regmap_runtime.rtu import STANDARD_EXCEPTIONS, Frame, FrameError, crc_ok, parse_frame, parse_hex, to_hex, unpack_bits
from regmap_runtime.spaces import COIL, DEFAULT_SPACE, DISCRETE_INPUT, HOLDING, INPUT, MAX_READ_BITS, MAX_WRITE_BITS, SPACES
from regmap_runtime.spec import Raw, RegisterSpec

# The Modbus names of the public function codes; the data spaces' codes come from the space table.
FUNCTION_NAMES = {
    COIL.read: "read coils",
    DISCRETE_INPUT.read: "read discrete inputs",
    HOLDING.read: "read holding registers",
    INPUT.read: "read input registers",
    COIL.write_single: "write single coil",
    HOLDING.write_single: "write single register",
    0x08: "diagnostics",
    COIL.write_multiple: "write multiple coils",
    HOLDING.write_multiple: "write multiple registers",
    0x17: "read/write multiple registers",
}

MODBUS_MAX_READ = 125  # registers per read (Modbus application protocol 6.3, 6.4)
MODBUS_MAX_WRITE = 123  # registers per write multiple (6.12)
CANDIDATES_SHOWN = 6
BIT_NAMES = {0: "off", 1: "on"}


def carried(frame: Frame) -> tuple[int, ...]:
    """The values a frame carries, one per address: register words, or in a bit space its bits."""
    return frame.bits if frame.space is not None and SPACES[frame.space].bits else frame.words


def trim_bits(frame: Frame, count: int) -> Frame:
    """A bit read response cut to the `count` bits its request asked for. A byte count other than
    ceil(count/8), or padding bits that are not zero (§6.1, §6.2 pad with zeros), is a problem."""
    if frame.kind != "read_response" or frame.space is None or not SPACES[frame.space].bits:
        return frame
    problems = list(frame.problems)
    need = (count + 7) // 8
    if frame.byte_count is not None and frame.byte_count != need:
        problems.append(f"{count} bits take {need} data byte(s), the byte count says {frame.byte_count}")
    if any(frame.bits[count:]):
        problems.append(f"the bits after the last of {count} are not zero (a response pads with zeros)")
    return dataclasses.replace(frame, bits=frame.bits[:count], problems=tuple(problems))


def _json_number(value: Any) -> Any:
    """JSON has no NaN or infinity: a float that is not finite becomes null (its text still says it)."""
    return None if isinstance(value, float) and not math.isfinite(value) else value


@dataclass
class DecodedValue:
    address: int
    register: str | None
    param: str | None
    raw: Raw | None  # an integer, a float, text, or 0/1 for a bit
    words: list[int]  # register words, or for a coil or discrete input its one bit
    value: Any = None  # engineering value: number, enum member name, text, True/False
    unit: str | None = None
    text: str = ""
    in_range: bool = True
    fields: dict[str, Any] | None = None  # a bitfield register's fields (enum fields by member name)
    space: str = DEFAULT_SPACE

    def as_json(self) -> dict[str, Any]:
        out: dict[str, Any] = {
            "address": self.address,
            "address_hex": f"0x{self.address:04X}",
            "space": self.space,
            "register": self.register,
            "param": self.param,
            "words": self.words,
            "raw": _json_number(self.raw),
            "value": _json_number(self.value),
            "unit": self.unit,
            "text": self.text,
            "in_range": self.in_range,
        }
        if self.fields is not None:
            out["fields"] = self.fields
        return out


@dataclass
class Decoded:
    frame: Frame
    direction: str
    function_name: str
    values: list[DecodedValue] = field(default_factory=list)
    exception: str | None = None
    notes: list[str] = field(default_factory=list)
    problems: list[str] = field(default_factory=list)  # beyond the frame's own (limits, junk)
    data_words: list[str] = field(default_factory=list)  # a read response without its request: every word (or byte of bits)
    source_line: int | None = None

    @property
    def ok(self) -> bool:
        return self.frame.crc_valid and not self.frame.problems and not self.problems

    def as_json(self) -> dict[str, Any]:
        f = self.frame
        return {
            "hex": to_hex(f.raw),
            "line": self.source_line,
            "slave": f.slave,
            "function": f.function,
            "function_name": self.function_name,
            "direction": self.direction,
            "kind": f.kind,
            "crc_valid": f.crc_valid,
            "crc": to_hex(f.raw[-2:]),
            "address": f.address,
            "address_hex": None if f.address is None else f"0x{f.address:04X}",
            "count": f.count,
            "byte_count": f.byte_count,
            "space": f.space,
            "words": list(f.words),
            "bits": list(f.bits),
            "exception_code": f.exception_code,
            "exception": self.exception,
            "values": [v.as_json() for v in self.values],
            "problems": [*f.problems, *self.problems],
            "notes": self.notes,
            "ok": self.ok,
        }


def number_text(value: int | float, data_type: str | None = None) -> str:
    """A number as people write it: integers as they are, floats in the fewest digits that give the
    same value back (an f32 in the fewest that give the same 32 bits: 0.1, not 0.10000000149011612)."""
    if not isinstance(value, float):
        return str(value)
    if not math.isfinite(value):
        return str(value)
    text = repr(value)
    if data_type == "f32":
        bits = struct.pack(">f", value)
        for digits in range(1, 10):
            short = f"{value:.{digits}g}"
            try:
                same = struct.pack(">f", float(short)) == bits
            except OverflowError:  # rounded past float32's largest value
                continue
            if same:
                text = repr(float(short))
                break
    if "e" in text:
        mantissa, _, exponent = text.partition("e")
        return f"{mantissa}e{int(exponent)}"
    return text[:-2] if text.endswith(".0") else text


def _eng_text(reg: Register, spec: RegisterSpec[Any], raw: int | float) -> str:
    number = raw_to_value(spec, raw)
    return number_text(number, None if reg.scaled or reg.offset_set else reg.type.value)


def describe_value(device: Device, reg: Register, raw: Raw, regs: Registers | None = None) -> tuple[Any, str, bool, dict[str, Any] | None]:
    """Engineering value, a human text (`2.2 A`, `save_ok (0x5555)`, `fault=0 enabled=1 ...`, `"PM-3000"`,
    `on`), whether the map's range and enum admit it, and a bitfield register's fields."""
    regs = regs or Registers(device)
    spec = regs.spec(reg)
    if isinstance(raw, str):
        readable = "\ufffd" not in raw
        quoted = '"' + raw.replace("\\", "\\\\").replace('"', '\\"') + '"'
        return raw, quoted + ("" if readable else f"  [NOT valid {reg.encoding}: unreadable bytes shown as U+FFFD]"), readable, None
    if reg.type.is_bool:
        return bool(raw), BIT_NAMES[1 if raw else 0], True, None
    if isinstance(raw, float) and math.isnan(raw):
        return raw, "NaN  [NOT a number: no value the map admits]", False, None
    in_range = reg.raw_min <= raw <= reg.raw_max
    outside = "" if in_range else f"  [OUTSIDE the map's range {_eng_text(reg, spec, reg.raw_min)}..{_eng_text(reg, spec, reg.raw_max)}]"
    if reg.bitfields and isinstance(raw, int):
        parts = []
        fields: dict[str, Any] = {}
        for b in reg.bitfields:
            field_value = (raw & b.mask) >> b.lsb
            member = b.enum.by_value(field_value) if b.enum else None
            if b.enum is not None and member is None:
                in_range = False
            shown: Any = member.name if member else field_value
            fields[b.name] = shown
            parts.append(f"{b.name}={shown}")
        return raw, f"0x{raw:04X}: " + " ".join(parts) + outside, in_range, fields
    if reg.enum is not None and isinstance(raw, int):
        member = reg.enum.by_value(raw)
        if member is None:
            return raw, f"{raw} = 0x{raw & 0xFFFFFFFF:X}  [NOT a value of {reg.enum.name}]", False, None
        return member.name, f"{member.name} ({raw} = 0x{raw & 0xFFFFFFFF:X})" + outside, in_range, None
    number = raw_to_value(spec, raw)
    unit = f" {reg.unit}" if reg.unit else ""
    scaled = reg.scaled or reg.offset_set
    shown_number = number_text(number, None if scaled else reg.type.value)
    raw_text = f" (raw {number_text(raw, reg.type.value)})" if scaled else ""
    return number, f"{shown_number}{unit}" + raw_text + outside, in_range, None


def decode_words(
    device: Device, start: int, words: Sequence[int], *, word_order: str | None = None, space: str = DEFAULT_SPACE
) -> list[DecodedValue]:
    """Split words read from (or written to) `start` of `space` into the registers they carry
    (for coils and discrete inputs: bits, one per address)."""
    out: list[DecodedValue] = []
    regs = Registers(device)
    address = start
    end = start + len(words)
    bits = SPACES[space].bits

    def one(text: str, reg: Register | None = None) -> None:
        word = words[address - start]
        shown = str(word) if bits else f"0x{word:04X}"
        name, param = (reg.name, reg.param) if reg is not None else (None, None)
        out.append(DecodedValue(address, name, param, None, [word], text=f"{shown}, {text}", space=space))

    while address < end:
        reg = device.covering(address, space)
        if reg is None:
            one("not documented in the map" if space == DEFAULT_SPACE else f"not documented in the map's {SPACES[space].title}")
            address += 1
            continue
        if reg.paired and address == reg.first_address:
            one(f"the unused high word of {reg.label}", reg)
            address += 1
            continue
        own = list(range(reg.address, reg.last_address + 1))
        if own[0] < start or own[-1] >= end:
            one(f"part of {reg.label} (not all of its words are here)", reg)
            address += 1
            continue
        own_words = [words[a - start] for a in own]
        try:
            raw = words_to_raw(regs.spec(reg).in_word_order(word_order), own_words)
        except ValueError as exc:  # a bit that is neither 0 nor 1: the frame is wrong, not the decoder
            one(f"not a value of {reg.label} ({exc})", reg)
            address = reg.last_address + 1
            continue
        value, text, in_range, fields = describe_value(device, reg, raw, regs)
        out.append(DecodedValue(reg.address, reg.name, reg.param, raw, own_words, value, reg.unit, text, in_range, fields, space))
        address = reg.last_address + 1
    return out


def _read_limit(space: str) -> int:
    return MAX_READ_BITS if SPACES[space].bits else MODBUS_MAX_READ


def _plausible(frame: Frame) -> bool:
    if frame.problems and any("CRC" not in p for p in frame.problems):
        return False
    if frame.kind == "read_request":
        return frame.count is not None and 1 <= frame.count <= _read_limit(frame.space or DEFAULT_SPACE)
    return frame.kind != "unknown"


def _parse(frame_bytes: bytes, direction: str | None) -> tuple[Frame, list[str]]:
    """Parse, settling the direction by CRC and plausibility, and spotting junk after a valid CRC."""
    extra: list[str] = []
    if not crc_ok(frame_bytes):
        for junk in (1, 2, 3):
            head = frame_bytes[:-junk]
            if len(head) >= 4 and crc_ok(head):
                frame = parse_frame(head, direction) if direction else _best(head)
                if _plausible(frame):
                    extra.append(f"{junk} byte(s) after the frame's CRC: {to_hex(frame_bytes[-junk:])} (trailing junk)")
                    return frame, extra
    if direction:
        return parse_frame(frame_bytes, direction), extra
    return _best(frame_bytes), extra


def _best(frame_bytes: bytes) -> Frame:
    first = parse_frame(frame_bytes, None)
    if first.kind in ("read_request", "read_response", "write_multiple_request", "write_multiple_response") and not _plausible(first):
        other = parse_frame(frame_bytes, "response" if first.kind.endswith("request") else "request")
        if _plausible(other):
            return other
    return first


def _limits(device: Device, frame: Frame) -> list[str]:
    t = device.transport
    space = SPACES[frame.space or DEFAULT_SPACE]
    unit = "bit" if space.bits else "register"
    most_read = MAX_READ_BITS if space.bits else MODBUS_MAX_READ
    map_read = t.max_read_coils if space.bits else t.max_read_registers
    out = []
    if frame.kind == "read_request" and frame.count is not None:
        if not 1 <= frame.count <= most_read:
            out.append(f"{unit} count {frame.count} is outside Modbus's 1..{most_read}")
        elif frame.count > map_read:
            out.append(f"{unit} count {frame.count} is over {device.info.model}'s limit of {map_read} per read")
    if frame.kind == "read_response" and not space.bits and len(frame.words) > t.max_read_registers:
        out.append(f"{len(frame.words)} registers is over {device.info.model}'s limit of {t.max_read_registers} per read")
    if frame.kind == "write_multiple_request" and frame.count is not None:
        most_write = MAX_WRITE_BITS if space.bits else MODBUS_MAX_WRITE
        map_write = t.max_write_coils if space.bits else t.max_write_registers
        if not 1 <= frame.count <= most_write:
            out.append(f"{unit} count {frame.count} is outside Modbus's 1..{most_write}")
        elif frame.count > map_write:
            out.append(f"{unit} count {frame.count} is over {device.info.model}'s limit of {map_write} per write")
    if t.max_message_bytes is not None and len(frame.raw) > t.max_message_bytes:
        out.append(f"{len(frame.raw)} bytes is over {device.info.model}'s message limit of {t.max_message_bytes}")
    return out


def _candidates(device: Device, count: int, space: str) -> list[str]:
    """Registers a read of `count` words from `space` could have started at: whole registers, no undocumented gap."""
    documented = documented_addresses(device)
    registers = [r for r in device.registers if r.space == space]
    starts = sorted({r.first_address for r in registers if r.access.readable} | {r.address for r in registers})
    ranked: list[tuple[int, str]] = []
    for start in starts:
        span = range(start, start + count)
        if not all((space, a) in documented or device.transport.tolerates_gaps for a in span):
            continue
        first, last = device.covering(start, space), device.covering(start + count - 1, space)
        if first is None or last is None or start not in (first.first_address, first.address) or start + count - 1 != last.last_address:
            continue
        # Likeliest first: one register of exactly this many words, then one paired register, then runs.
        rank = 0 if last is first and first.words == count else 1 if last is first else 2
        ranked.append((rank, f"0x{start:04X} {first.label}" + (f" .. {last.label}" if last is not first else "")))
    return [text for _, text in sorted(ranked, key=lambda r: r[0])]


def _word_table(words: Sequence[int]) -> list[str]:
    return [f"word {i}: 0x{w:04X} = {w} unsigned, {w - 0x10000 if w & 0x8000 else w} signed" for i, w in enumerate(words)]


def _bit_table(frame: Frame) -> list[str]:
    """A bit read response without its request: each data byte and its bits, the first bit first."""
    data = frame.raw[3:-2]
    return [f"byte {i}: 0x{b:02X} = bits {i * 8}..{i * 8 + 7}: {','.join(map(str, unpack_bits(bytes([b]))))}" for i, b in enumerate(data)]


def _space_note(device: Device, space: str) -> list[str]:
    """A request to a space the map documents nothing in (`function_codes` may still list it)."""
    if space == DEFAULT_SPACE or any(r.space == space for r in device.registers):
        return []
    return [f"{device.info.model} has no {SPACES[space].title} in its map"]


def decode_frame(
    device: Device, frame_bytes: bytes, *, direction: str | None = None, request: Frame | None = None, word_order: str | None = None
) -> Decoded:
    try:
        frame, problems = _parse(frame_bytes, direction)
    except FrameError as exc:
        raise UsageError(str(exc)) from None
    base_function = frame.function & 0x7F
    name = FUNCTION_NAMES.get(base_function, f"function 0x{base_function:02X}")
    if frame.kind == "read_response" and request is not None and request.kind == "read_request" and request.count is not None:
        frame = trim_bits(frame, request.count)  # the bits after the requested count are padding
    kind_direction = {
        "read_request": "request",
        "read_response": "response",
        "write_multiple_request": "request",
        "write_multiple_response": "response",
        "exception": "response",
    }.get(frame.kind, direction or "request or response")
    decoded = Decoded(frame=frame, direction=kind_direction, function_name=name, problems=problems + _limits(device, frame))
    space = frame.space or DEFAULT_SPACE
    bits = SPACES[space].bits
    unit = "bits" if bits else "registers"
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
        absent = _space_note(device, space)
        decoded.notes += absent
        if not absent:  # a space without registers: one note, not a line per address
            decoded.values = _registers_in(device, frame.address, min(frame.count, _read_limit(space)), space)
        if bits and direction is None and len(frame.raw) == 8 and frame.raw[2] == 3:
            decoded.notes.append("it reads alike as a response carrying 3 bytes of bits: --direction response decodes it so")
    elif frame.kind in ("write_single", "write_multiple_request") and frame.address is not None:
        decoded.values = decode_words(device, frame.address, carried(frame), word_order=word_order, space=space)
    elif frame.kind == "read_response":
        if request is not None and request.kind == "read_request" and request.address is not None:
            came = len(carried(frame))
            if request.space is not None and request.space != frame.space:
                decoded.problems.append(f"a {name} response answers a request of function 0x{request.function:02X}")
            elif not bits and request.count is not None and request.count != came:
                decoded.problems.append(f"the request asked for {request.count} registers, the response carries {came}")
            elif bits and request.count is not None and came < request.count:
                decoded.problems.append(f"the request asked for {request.count} bits, the response carries {came}")
            decoded.values = decode_words(device, request.address, carried(frame), word_order=word_order, space=space)
        elif bits:
            decoded.data_words = _bit_table(frame)
            decoded.notes.append(
                f"{len(frame.raw) - 5} byte(s) carry up to {8 * (len(frame.raw) - 5)} bits, the first in the lowest bit; "
                "give the request (--request, or pair them in --file) to name the bits and cut off the padding"
            )
        else:
            decoded.data_words = _word_table(frame.words)
            could = _candidates(device, len(frame.words), space) if frame.words and not frame.problems else []
            if could:
                shown = ", ".join(could[:CANDIDATES_SHOWN]) + (
                    f" and {len(could) - CANDIDATES_SHOWN} more" if len(could) > CANDIDATES_SHOWN else ""
                )
                decoded.notes.append(f"{len(frame.words)} word(s) could be a read from {shown}")
            decoded.notes.append(
                "a read response does not carry the address; give the request (--request, or pair them in --file) to name the registers"
            )
    elif frame.kind == "write_multiple_response" and request is not None and request.count is not None and request.count != frame.count:
        decoded.problems.append(f"the request wrote {request.count} {unit}, the response echoes {frame.count}")
    if base_function not in device.transport.function_codes and frame.kind != "exception":
        decoded.notes.append(f"function 0x{base_function:02X} is not supported by {device.info.model}")
    if request is not None and request.slave != frame.slave:
        decoded.problems.append(f"answer from slave {frame.slave} to a request for slave {request.slave}")
    return decoded


def decode_answer(device: Device, frame_bytes: bytes, request_bytes: bytes, *, word_order: str | None = None) -> Decoded:
    """A response decoded against the request given beside it (`--request`). A damaged or malformed
    request names the wrong registers, so what is wrong with it is a problem of the answer too."""
    try:
        request = parse_frame(request_bytes, "request")
    except FrameError as exc:
        raise UsageError(f"--request: {exc}") from None
    decoded = decode_frame(device, frame_bytes, direction="response", request=request, word_order=word_order)
    problems = list(request.problems)
    if request.kind in ("exception", "unknown"):
        problems.append(f"function 0x{request.function:02X} is no request")
    decoded.problems[:0] = [f"--request {to_hex(request.raw)}: {problem}" for problem in problems]
    return decoded


def _registers_in(device: Device, start: int, count: int, space: str) -> list[DecodedValue]:
    out = []
    seen: set[str] = set()
    undocumented = "not documented in the map" if space == DEFAULT_SPACE else f"not documented in the map's {SPACES[space].title}"
    for address in range(start, start + count):
        reg = device.covering(address, space)
        if reg is None:
            out.append(DecodedValue(address, None, None, None, [], text=undocumented, space=space))
        elif reg.name not in seen:
            seen.add(reg.name)
            out.append(DecodedValue(reg.address, reg.name, reg.param, None, [], unit=reg.unit, text=reg.title, space=space))
    return out


def render_text(decoded: Decoded) -> str:
    f = decoded.frame
    crc = "ok" if f.crc_valid else "MISMATCH"
    where = f"line {decoded.source_line}: " if decoded.source_line is not None else ""
    lines = [
        where + to_hex(f.raw),
        f"  slave {f.slave}, function 0x{f.function:02X} {decoded.function_name} ({decoded.direction}), CRC {to_hex(f.raw[-2:])} {crc}",
    ]
    bits = f.space is not None and SPACES[f.space].bits
    if f.address is not None:
        lines.append(
            f"  address 0x{f.address:04X}"
            + (f", count {f.count}" if f.count is not None else "")
            + (f", byte count {f.byte_count}" if f.byte_count is not None else "")
        )
    elif f.byte_count is not None:
        lines.append(f"  byte count {f.byte_count}, " + (f"{8 * (len(f.raw) - 5)} bits" if bits else f"{len(f.words)} words"))
    if decoded.exception:
        lines.append(f"  exception {decoded.exception}")
    lines.extend(f"  {row}" for row in decoded.data_words)
    for v in decoded.values:
        label = " ".join(x for x in (v.param, v.register) if x) or "-"
        value = f" = {v.text}" if v.raw is not None else f": {v.text}"
        lines.append(f"  0x{v.address:04X} {label}{value}")
    for problem in [*f.problems, *decoded.problems]:
        lines.append(f"  problem: {problem}")
    for note in decoded.notes:
        lines.append(f"  note: {note}")
    return "\n".join(lines)


_DIRECTION_TAGS = {"tx": "request", ">": "request", "->": "request", "rx": "response", "<": "response", "<-": "response"}
# A timestamp before the tag: `12:00:00.001`, `[2024-05-01 12:00:00.001]`, `2024-05-01T12:00:00Z`, `1714557600.123`.
_TIMESTAMP = re.compile(
    r"^\s*(?:\[[^\]]*\]|\d{4}-\d{2}-\d{2}[T ]\d{1,2}:\d{2}(?::\d{2}(?:[.,]\d+)?)?(?:Z|[+-]\d{2}:?\d{2})?|\d{1,2}:\d{2}:\d{2}(?:[.,]\d+)?|\d{9,}\.\d+)\s*"
)
_LIBMODBUS = re.compile(r"^(?:(?:\[[0-9A-Fa-f]{2}\])+|(?:<[0-9A-Fa-f]{2}>)+)$")
_TAG = re.compile(r"^(tx|rx|->|<-|>|<)\s*[:>]?\s*", re.I)
# pymodbus's frame logging, after its log prefix: `send: 0x1 0x3 0x1 0x91 ...`, `recv: 0x1 0x3 ... extra data: `
# (2.x: SEND:/RECV:), and `Processing: 0x1 0x3 ...` for the bytes it received (a response on a client).
_PYMODBUS = re.compile(r"\b(send|recv|processing):\s*((?:0x[0-9a-f]{1,2}\b\s*)+)", re.I)
_PYMODBUS_DIRECTIONS = {"send": "request", "recv": "response", "processing": None}


@dataclass(frozen=True)
class CaptureLine:
    number: int
    text: str
    not_utf8: tuple[int, int] | None = None  # (file offset, byte) of the first byte that is not UTF-8 text


@dataclass(frozen=True)
class CaptureError:
    line: int | None  # None: the capture as a whole (no frames at all)
    text: str
    message: str
    source: str

    def __str__(self) -> str:
        return f"{self.source}:{self.line}: {self.message}" if self.line is not None else f"{self.source}: {self.message}"

    def as_json(self) -> dict[str, Any]:
        return {"line": self.line, "text": self.text, "error": self.message, "ok": False}


@dataclass
class CaptureResult:
    frames: list[Decoded]
    errors: list[CaptureError]

    def entries(self) -> list[Decoded | CaptureError]:
        """Every frame and every line that is none, in the capture's order."""
        found: list[Decoded | CaptureError] = [*self.frames, *self.errors]
        return sorted(found, key=lambda entry: (entry.source_line if isinstance(entry, Decoded) else entry.line) or 0)


# A capture with a NUL byte is not text (UTF-16 without a BOM, a pcap, a logic analyser's own format).
BINARY_HINT = "decode wants text, one frame a line in hex, as serial monitors and `mbpoll -v` print them"


def capture_lines(data: bytes, source: str) -> list[CaptureLine]:
    """The lines of a capture file as serial monitors, mbpoll and Windows tools write them: UTF-8 (a BOM
    allowed), UTF-16 with its BOM (PowerShell's `>`), CRLF or LF. A line that is not UTF-8 (a comment in
    a Windows code page) is read byte for byte, so its hex is still decoded; a binary file is refused."""
    if data.startswith((codecs.BOM_UTF16_LE, codecs.BOM_UTF16_BE)):
        try:
            text = data.decode("utf-16")
        except UnicodeDecodeError as exc:
            raise UsageError(f"{source}: not UTF-16 text at byte offset {exc.start}, although it starts with a UTF-16 BOM") from None
        return [CaptureLine(n, line) for n, line in enumerate(text.splitlines(), 1)]
    nul = data.find(b"\0")
    if nul >= 0:
        raise UsageError(f"{source}: a binary file, not a text capture (byte offset {nul} is 0x00); {BINARY_HINT}")
    offset = len(codecs.BOM_UTF8) if data.startswith(codecs.BOM_UTF8) else 0
    out = []
    for number, raw_line in enumerate(data[offset:].split(b"\n"), 1):
        try:
            out.append(CaptureLine(number, raw_line.decode("utf-8").rstrip("\r")))
        except UnicodeDecodeError as exc:
            where = (offset + exc.start, raw_line[exc.start])
            out.append(CaptureLine(number, raw_line.decode("latin-1").rstrip("\r"), where))
        offset += len(raw_line) + 1
    return out


def split_capture_line(line: str) -> tuple[str | None, str]:
    """(direction or None, the hex text) of one capture line, without timestamp and comment."""
    text = line.split("#", 1)[0].strip()
    if _LIBMODBUS.match(text):  # libmodbus's debug output (mbpoll -v): [01][03]... sent, <01><03>... received
        direction = "request" if text.startswith("[") else "response"
        return direction, " ".join(re.findall(r"[0-9A-Fa-f]{2}", text))
    pymodbus = _PYMODBUS.search(text)
    if pymodbus is not None:
        return _PYMODBUS_DIRECTIONS[pymodbus.group(1).lower()], " ".join(f"{int(t, 16):02X}" for t in pymodbus.group(2).split())
    text = _TIMESTAMP.sub("", text, count=1)
    match = _TAG.match(text)
    if match is None:
        return None, text
    return _DIRECTION_TAGS[match.group(1).lower()], text[match.end() :]


def decode_capture(device: Device, lines: Sequence[CaptureLine], source: str, *, word_order: str | None = None) -> CaptureResult:
    """Decode a log of frames, one per line, pairing each response with the request before it.

    A line may start with a timestamp and a direction tag (TX/RX, TX>, > or <), or be a frame line of
    mbpoll -v or of pymodbus's log; `#` starts a comment.
    A line that is not a frame is reported with its number and the rest is still decoded; a capture
    without a single frame is reported too.
    """
    out: list[Decoded] = []
    errors: list[CaptureError] = []
    pending: Frame | None = None
    for line in lines:
        direction, text = split_capture_line(line.text)
        if not text:
            continue
        try:
            frame_bytes = parse_hex(text)
            if direction is None:
                direction = "response" if pending is not None else None
            decoded = decode_frame(
                device, frame_bytes, direction=direction, request=pending if direction == "response" else None, word_order=word_order
            )
        except (FrameError, UsageError) as exc:
            message = str(exc)
            if line.not_utf8 is not None:
                at, byte = line.not_utf8
                message = f"not UTF-8 text: byte 0x{byte:02X} at byte offset {at}"
            errors.append(CaptureError(line.number, line.text.strip(), message, source))
            pending = None
            continue
        decoded.source_line = line.number
        out.append(decoded)
        pending = decoded.frame if decoded.direction == "request" else None
    if not out and not errors:
        errors.append(CaptureError(None, "", "no frames", source))
    return CaptureResult(out, errors)
