"""One frame decoded: its function, its problems (Modbus's limits and the map's), the values it carries.

Every frame is read in its function's data space: a 0x02 request at 0x0001 names the discrete input
at 0x0001, never the holding register there. The direction, when not given, is settled by CRC and
plausibility.
"""

from __future__ import annotations

import struct
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

from regmap.core.decoding import FUNCTION_NAMES, DecodedValue, carried, decode_words, trim_bits
from regmap.diagnostics import UsageError
from regmap.model import Device
from regmap.runtime_bridge import documented_addresses
from regmap_runtime.rtu import STANDARD_EXCEPTIONS, Frame, FrameError, crc_ok, parse_frame, to_hex, unpack_bits, with_crc
from regmap_runtime.spaces import DEFAULT_SPACE, MAX_READ_BITS, MAX_READ_REGISTERS, MAX_WRITE_BITS, MAX_WRITE_REGISTERS, SPACES

CANDIDATES_SHOWN = 6


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
    mbap: tuple[bytes, int, int] | None = None  # a Modbus TCP ADU: (its bytes, transaction, unit); the frame is then its PDU with a CRC

    @property
    def ok(self) -> bool:
        return self.frame.crc_valid and not self.frame.problems and not self.problems

    def as_json(self) -> dict[str, Any]:
        f = self.frame
        return {
            "hex": to_hex(f.raw if self.mbap is None else self.mbap[0]),
            "mbap": None if self.mbap is None else {"transaction": self.mbap[1], "unit": self.mbap[2]},
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


def _read_limit(space: str) -> int:
    return MAX_READ_BITS if SPACES[space].bits else MAX_READ_REGISTERS


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
    most_read = MAX_READ_BITS if space.bits else MAX_READ_REGISTERS
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
        most_write = MAX_WRITE_BITS if space.bits else MAX_WRITE_REGISTERS
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
        "read_write_request": "request",
        "read_write_response": "response",
        "server_id_request": "request",
        "server_id_response": "response",
        "device_id_request": "request",
        "device_id_response": "response",
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
    elif frame.kind in _OTHER_KINDS:
        _other(device, decoded, request, word_order)
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


_OTHER_KINDS = (
    "mask_write",
    "read_write_request",
    "read_write_response",
    "diagnostics",
    "server_id_response",
    "device_id_request",
    "device_id_response",
)
_DEVICE_ID_READS = {1: "basic stream", 2: "regular stream", 3: "extended stream", 4: "one object"}


def _other(device: Device, decoded: Decoded, request: Frame | None, word_order: str | None) -> None:
    """0x16, 0x17, 0x08, 0x11 and 0x2B/0x0E: the registers they touch, the data they carry, against the map."""
    frame = decoded.frame
    t = device.transport
    if frame.kind == "mask_write" and frame.address is not None and len(frame.words) == 2:
        and_mask, or_mask = frame.words
        reg = device.covering(frame.address, DEFAULT_SPACE)
        target = reg.label if reg is not None else "an address the map does not document"
        kept, set_, cleared = and_mask, or_mask & ~and_mask & 0xFFFF, ~and_mask & ~or_mask & 0xFFFF
        decoded.notes.append(
            f"{target}: keeps bits 0x{kept:04X}, sets 0x{set_:04X}, clears 0x{cleared:04X} (AND 0x{and_mask:04X}, OR 0x{or_mask:04X})"
        )
    elif frame.kind == "read_write_request" and frame.write_address is not None and frame.address is not None:
        decoded.values = decode_words(device, frame.write_address, frame.words, word_order=word_order, space=DEFAULT_SPACE)
        if frame.count is not None:
            read = ", ".join(
                v.register or f"0x{v.address:04X}"
                for v in _registers_in(device, frame.address, min(frame.count, MAX_READ_REGISTERS), DEFAULT_SPACE)
            )
            decoded.notes.append(f"then reads {frame.count} register(s) from 0x{frame.address:04X}: {read}")
    elif frame.kind == "read_write_response":
        if request is not None and request.kind == "read_write_request" and request.address is not None:
            if request.count is not None and request.count != len(frame.words):
                decoded.problems.append(f"the request asked for {request.count} registers, the response carries {len(frame.words)}")
            decoded.values = decode_words(device, request.address, frame.words, word_order=word_order, space=DEFAULT_SPACE)
        else:
            decoded.data_words = _word_table(frame.words)
            decoded.notes.append("a read/write response does not carry the read address; give the request to name the registers")
    elif frame.kind == "diagnostics":
        if frame.count == 0x0000:
            decoded.notes.append(f"sub-function 0x0000 return query data, data {to_hex(frame.data) or '(none)'}: the answer echoes it")
        else:
            decoded.notes.append(f"sub-function 0x{frame.count or 0:04X}: regmap serves only 0x0000 (return query data)")
    elif frame.kind == "server_id_response":
        decoded.notes.append(f"report {to_hex(frame.data)} ({frame.data.decode('ascii', 'replace')!r})")
        s = t.server_id
        if s is not None:
            expected = s.id + bytes([0xFF if s.running else 0x00]) + s.additional_data.encode("ascii")
            if frame.data != expected:
                decoded.notes.append(f"the map says {to_hex(expected)}: server id {to_hex(s.id)}, run indicator, {s.additional_data!r}")
    elif frame.kind == "device_id_request" and frame.device_id is not None:
        code, object_id = frame.device_id[:2]
        decoded.notes.append(f"read device id code {code} ({_DEVICE_ID_READS.get(code, 'not one of 1..4')}), object 0x{object_id:02X}")
    elif frame.kind == "device_id_response" and frame.device_id is not None:
        _code, level, more, following = frame.device_id
        mapped = dict(t.identification.objects) if t.identification is not None else {}
        for object_id, text in frame.objects:
            differs = object_id in mapped and mapped[object_id] != text
            decoded.notes.append(f"object 0x{object_id:02X} = {text!r}" + (f" (the map says {mapped[object_id]!r})" if differs else ""))
        decoded.notes.append(f"conformity level 0x{level:02X}" + (f"; more follows from object 0x{following:02X}" if more == 0xFF else ""))


def mbap_to_rtu(adu: bytes, what: str = "frame") -> tuple[bytes, int]:
    """The RTU frame with the same unit and PDU as a Modbus TCP ADU (the CRC computed), and its transaction id."""
    if len(adu) < 8:
        raise UsageError(f"{what}: {len(adu)} bytes is no Modbus TCP ADU (an MBAP header is 7 bytes, a PDU at least 1)")
    transaction, protocol, length = struct.unpack(">HHH", adu[:6])
    if protocol != 0:
        raise UsageError(f"{what}: MBAP protocol id {protocol} (Modbus is 0)")
    if length != len(adu) - 6:
        raise UsageError(f"{what}: the MBAP length says {length} bytes follow, {len(adu) - 6} do")
    return with_crc(adu[6:]), transaction


def decode_mbap(
    device: Device, adu: bytes, *, direction: str | None = None, request: bytes | None = None, word_order: str | None = None
) -> Decoded:
    """A Modbus TCP ADU decoded as the RTU frame with its unit and PDU; `request` the ADU it answers."""
    frame, transaction = mbap_to_rtu(adu)
    if request is not None:
        decoded = decode_answer(device, frame, mbap_to_rtu(request, "--request")[0], word_order=word_order)
    else:
        decoded = decode_frame(device, frame, direction=direction, word_order=word_order)
    decoded.mbap = (adu, transaction, adu[6])
    return decoded
