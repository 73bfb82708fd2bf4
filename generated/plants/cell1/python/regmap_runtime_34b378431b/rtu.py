"""Modbus RTU framing: CRC-16, request building and frame parsing. Pure Python, no I/O."""

from __future__ import annotations

import re
import struct
from dataclasses import dataclass
from typing import Any

from .spaces import (
    COIL_OFF,
    COIL_ON,
    DEFAULT_SPACE,
    MASK_WRITE_REGISTER,
    MAX_READ_BITS,
    MAX_READ_REGISTERS,
    MAX_WRITE_BITS,
    MAX_WRITE_REGISTERS,
    SPACES,
    Space,
)

EXCEPTION_FLAG = 0x80
# Which space and which operation each function code of the space table is.
READS = {s.read: s for s in SPACES.values()}
WRITES_SINGLE = {s.write_single: s for s in SPACES.values() if s.write_single is not None}
WRITES_MULTIPLE = {s.write_multiple: s for s in SPACES.values() if s.write_multiple is not None}
DIAGNOSTICS = 0x08  # sub-function 0x0000, return query data
REPORT_SERVER_ID = 0x11
READ_WRITE_MULTIPLE = 0x17
ENCAPSULATED_INTERFACE = 0x2B  # with MEI type 0x0E: read device identification
READ_DEVICE_ID = 0x0E
# Every function a map may list: what the simulator serves and the tools build and decode.
SERVED_FUNCTIONS = frozenset(
    {
        *READS,
        *WRITES_SINGLE,
        *WRITES_MULTIPLE,
        MASK_WRITE_REGISTER,
        DIAGNOSTICS,
        REPORT_SERVER_ID,
        READ_WRITE_MULTIPLE,
        ENCAPSULATED_INTERFACE,
    }
)

STANDARD_EXCEPTIONS = {
    0x01: "illegal function",
    0x02: "illegal data address",
    0x03: "illegal data value",
    0x04: "server device failure",
    0x05: "acknowledge",
    0x06: "server device busy",
    0x08: "memory parity error",
    0x0A: "gateway path unavailable",
    0x0B: "gateway target failed to respond",
}


class FrameError(ValueError):
    """A frame that cannot be built or parsed; the message says what is wrong."""


def crc16(data: bytes) -> int:
    """Modbus CRC-16 (polynomial 0xA001 reflected, initial value 0xFFFF)."""
    crc = 0xFFFF
    for byte in data:
        crc ^= byte
        for _ in range(8):
            crc = (crc >> 1) ^ 0xA001 if crc & 1 else crc >> 1
    return crc


def crc_bytes(data: bytes) -> bytes:
    """The two CRC bytes as they go on the wire: low byte first."""
    return struct.pack("<H", crc16(data))


def with_crc(body: bytes) -> bytes:
    return body + crc_bytes(body)


def crc_ok(frame: bytes) -> bool:
    return len(frame) >= 4 and crc_bytes(frame[:-2]) == frame[-2:]


_HEX_TOKEN = re.compile(r"^(?:0x)?((?:[0-9a-fA-F]{2})+)h?$")


def parse_hex(text: str) -> bytes:
    """Parse hex bytes as people write them: `01 03 00 01`, `01030001`, `0x01 0x03`, `01H 03H`,
    or grouped words as some manuals print them (`01 06 1801 2211`)."""
    out = bytearray()
    for token in text.replace(",", " ").split():
        match = _HEX_TOKEN.match(token)
        if not match:
            raise FrameError(f"not hex bytes: {token!r} (write bytes as two hex digits each)")
        out.extend(bytes.fromhex(match.group(1)))
    if not out:
        raise FrameError("no bytes given")
    return bytes(out)


def to_hex(frame: bytes) -> str:
    return " ".join(f"{b:02X}" for b in frame)


def _check_slave(slave: int) -> None:
    if not 0 <= slave <= 255:
        raise FrameError(f"slave id {slave} is outside 0..255")


def _check_address(address: int) -> None:
    if not 0 <= address <= 0xFFFF:
        raise FrameError(f"address {address} is outside 0..0xFFFF")


def _check_word(word: int) -> None:
    if not 0 <= word <= 0xFFFF:
        raise FrameError(f"register word {word} is outside 0..0xFFFF")


def _write_function(space: str, multiple: bool) -> int:
    facts = SPACES[space]
    function = facts.write_multiple if multiple else facts.write_single
    if function is None:
        raise FrameError(f"{facts.title} cannot be written")
    return function


def _check_bit(bit: int) -> None:
    if bit not in (0, 1):
        raise FrameError(f"a bit is 0 or 1, not {bit}")


def pack_bits(bits: list[int] | tuple[int, ...]) -> bytes:
    """Bits as a 0x01/0x02 response or a 0x0F request carries them: the first bit in the lowest bit of
    the first byte, eight to a byte, the last byte padded with zeros (Modbus Application Protocol §6.1)."""
    for bit in bits:
        _check_bit(bit)
    return sum(bit << i for i, bit in enumerate(bits)).to_bytes((len(bits) + 7) // 8, "little")


def unpack_bits(data: bytes, count: int | None = None) -> tuple[int, ...]:
    """The bits of `data`, first bit from the lowest bit of the first byte; `count` keeps only the first ones."""
    bits = tuple((byte >> i) & 1 for byte in data for i in range(8))
    return bits if count is None else bits[:count]


def build_read(slave: int, address: int, count: int, *, space: str = DEFAULT_SPACE) -> bytes:
    """A read request: `count` registers (0x03/0x04, at most 125) or bits (0x01/0x02, at most 2000)."""
    _check_slave(slave)
    _check_address(address)
    facts = SPACES[space]
    limit = MAX_READ_BITS if facts.bits else MAX_READ_REGISTERS
    if not 1 <= count <= limit:
        raise FrameError(f"{facts.unit} count {count} is outside 1..{limit}")
    return with_crc(struct.pack(">BBHH", slave, facts.read, address, count))


def build_write_single(slave: int, address: int, word: int, *, space: str = DEFAULT_SPACE) -> bytes:
    """A write-single request: one register word (0x06), or one coil given as its bit 0/1 and sent as
    FF00 (on) or 0000 (off), the only two values 0x05 carries (§6.5)."""
    function = _write_function(space, multiple=False)
    _check_slave(slave)
    _check_address(address)
    if SPACES[space].bits:
        _check_bit(word)
        word = COIL_ON if word else COIL_OFF
    _check_word(word)
    return with_crc(struct.pack(">BBHH", slave, function, address, word))


def build_write_multiple(slave: int, address: int, words: list[int] | tuple[int, ...], *, space: str = DEFAULT_SPACE) -> bytes:
    """A write-multiple request: register words (0x10, at most 123) or coil bits 0/1 (0x0F, at most 1968, packed as §6.11 says)."""
    function = _write_function(space, multiple=True)
    _check_slave(slave)
    _check_address(address)
    facts = SPACES[space]
    limit = MAX_WRITE_BITS if facts.bits else MAX_WRITE_REGISTERS
    if not 1 <= len(words) <= limit:
        raise FrameError(f"{facts.unit} count {len(words)} is outside 1..{limit}")
    if facts.bits:
        data = pack_bits(words)
    else:
        for word in words:
            _check_word(word)
        data = b"".join(struct.pack(">H", w) for w in words)
    body = struct.pack(">BBHHB", slave, function, address, len(words), len(data))
    return with_crc(body + data)


MAX_READ_WRITE_REGISTERS = 121  # §6.17: the write part of read/write multiple registers
RETURN_QUERY_DATA = 0x0000  # §6.8.1: the diagnostics sub-function regmap sends and serves
DEVICE_ID_CODES = {"basic": 0x01, "regular": 0x02, "extended": 0x03, "individual": 0x04}  # §6.21


def build_mask_write(slave: int, address: int, and_mask: int, or_mask: int) -> bytes:
    """Mask write register (0x16, §6.16): the register becomes (current AND and_mask) OR (or_mask AND NOT and_mask)."""
    _check_slave(slave)
    _check_address(address)
    _check_word(and_mask)
    _check_word(or_mask)
    return with_crc(struct.pack(">BBHHH", slave, MASK_WRITE_REGISTER, address, and_mask, or_mask))


def build_read_write(slave: int, read_address: int, read_count: int, write_address: int, words: list[int] | tuple[int, ...]) -> bytes:
    """Read/write multiple registers (0x17, §6.17): write `words` at `write_address`, then read `read_count` from `read_address`."""
    _check_slave(slave)
    _check_address(read_address)
    _check_address(write_address)
    if not 1 <= read_count <= MAX_READ_REGISTERS:
        raise FrameError(f"read count {read_count} is outside 1..{MAX_READ_REGISTERS}")
    if not 1 <= len(words) <= MAX_READ_WRITE_REGISTERS:
        raise FrameError(f"write count {len(words)} is outside 1..{MAX_READ_WRITE_REGISTERS}")
    for word in words:
        _check_word(word)
    head = struct.pack(">BBHHHHB", slave, READ_WRITE_MULTIPLE, read_address, read_count, write_address, len(words), 2 * len(words))
    return with_crc(head + struct.pack(f">{len(words)}H", *words))


def build_echo(slave: int, word: int) -> bytes:
    """Diagnostics (0x08) sub-function 0x0000, return query data: the device echoes the request."""
    _check_slave(slave)
    _check_word(word)
    return with_crc(struct.pack(">BBHH", slave, DIAGNOSTICS, RETURN_QUERY_DATA, word))


def build_report_server_id(slave: int) -> bytes:
    """Report server id (0x11, §6.13): no data."""
    _check_slave(slave)
    return with_crc(bytes([slave, REPORT_SERVER_ID]))


def build_read_device_id(slave: int, code: int, object_id: int = 0) -> bytes:
    """Read device identification (0x2B/0x0E, §6.21): read code 1 basic, 2 regular, 3 extended, 4 one object."""
    _check_slave(slave)
    if code not in DEVICE_ID_CODES.values():
        raise FrameError(f"read device id code {code} is not one of 1 (basic), 2 (regular), 3 (extended), 4 (one object)")
    if not 0 <= object_id <= 0xFF:
        raise FrameError(f"object id {object_id} is outside 0..255")
    return with_crc(bytes([slave, ENCAPSULATED_INTERFACE, READ_DEVICE_ID, code, object_id]))


def build_read_response(slave: int, words: list[int] | tuple[int, ...], *, space: str = DEFAULT_SPACE) -> bytes:
    """A read response: register words, or (coils, discrete inputs) bits 0/1, packed."""
    if SPACES[space].bits:
        data = pack_bits(words)
    else:
        for word in words:
            _check_word(word)
        data = b"".join(struct.pack(">H", w) for w in words)
    return with_crc(struct.pack(">BBB", slave, SPACES[space].read, len(data)) + data)


def build_write_multiple_response(slave: int, address: int, count: int, *, space: str = DEFAULT_SPACE) -> bytes:
    return with_crc(struct.pack(">BBHH", slave, _write_function(space, multiple=True), address, count))


@dataclass(frozen=True)
class Frame:
    """A parsed RTU frame. `kind` says which of the optional fields are set."""

    raw: bytes
    slave: int
    function: int
    kind: str  # read_request, read_response, write_single, write_multiple_request, write_multiple_response, exception, unknown
    crc_valid: bool
    address: int | None = None
    count: int | None = None
    byte_count: int | None = None
    words: tuple[int, ...] = ()
    exception_code: int | None = None
    problems: tuple[str, ...] = ()
    space: str | None = None  # the register space the function addresses (None: exception, unknown)
    bits: tuple[int, ...] = ()  # coils, discrete inputs: the bits carried (a read response: every bit of its bytes)
    write_address: int | None = None  # 0x17: where the write goes (address/count are the read's)
    write_count: int | None = None
    data: bytes = b""  # 0x08: the query data; 0x11: the report after its byte count
    objects: tuple[tuple[int, str], ...] = ()  # 0x2B/0x0E response: (object id, text)
    device_id: tuple[int, int, int, int] | None = (
        None  # 0x2B/0x0E: (read code, conformity level, more follows, next object id); a request: (code, object id, 0, 0)
    )


def _words(data: bytes) -> tuple[int, ...]:
    return tuple(int.from_bytes(data[i : i + 2], "big") for i in range(0, len(data) - 1, 2))


def parse_frame(frame: bytes, direction: str | None = None) -> Frame:
    """Parse one frame. `direction` ("request"/"response") settles the frames that read alike both ways.

    Raises FrameError only when the bytes cannot be a frame at all (too short); everything else
    that is wrong (CRC, byte count, length) is reported in `problems` so a decoder can still show it.
    """
    if len(frame) < 4:
        raise FrameError(f"frame too short: {len(frame)} bytes, a Modbus RTU frame has at least 4")
    slave, function = frame[0], frame[1]
    body = frame[2:-2]
    valid = crc_ok(frame)
    problems: list[str] = []
    if not valid:
        problems.append(f"CRC mismatch: frame carries {to_hex(frame[-2:])}, expected {to_hex(crc_bytes(frame[:-2]))}")
    space = READS.get(function) or WRITES_SINGLE.get(function) or WRITES_MULTIPLE.get(function)
    if function in OTHER_FUNCTIONS:
        space = SPACES[DEFAULT_SPACE] if function in (MASK_WRITE_REGISTER, READ_WRITE_MULTIPLE) else None
    if function & EXCEPTION_FLAG:
        if len(body) != 1:
            problems.append(f"exception frame carries {len(body)} data bytes, expected 1")
        fields: dict[str, Any] = {"kind": "exception", "exception_code": body[0] if body else None}
    elif function in OTHER_FUNCTIONS:
        fields = OTHER_FUNCTIONS[function](body, direction, problems)
    elif space is None:
        fields = {"kind": "unknown", "words": _words(body)}
    elif function in READS:
        fields = _read_fields(space, body, direction, problems)
    elif function in WRITES_SINGLE:
        fields = _write_single_fields(space, body, problems)
    else:
        fields = _write_multiple_fields(space, body, direction, problems)
    return Frame(
        raw=frame,
        slave=slave,
        function=function,
        crc_valid=valid,
        problems=tuple(problems),
        space=space.name if space is not None else None,
        **fields,
    )


def _read_fields(space: Space, body: bytes, direction: str | None, problems: list[str]) -> dict[str, Any]:
    """A read request (0x01-0x04) or its response; what is wrong goes to `problems`."""
    # A read request body is 4 bytes; a register response body is 1 + 2n bytes, always odd. A bit
    # response may be 4 bytes too (3 bytes of bits): it is one when its byte count says so and the
    # same bytes would ask for more bits than a request may.
    looks_like_request = len(body) == 4 and not (space.bits and body[0] == 3 and not 1 <= int.from_bytes(body[2:4], "big") <= MAX_READ_BITS)
    if direction == "request" or (direction is None and looks_like_request):
        if len(body) != 4:
            problems.append(f"read request carries {len(body)} data bytes, expected 4")
            return {"kind": "read_request"}
        address, count = struct.unpack(">HH", body)
        return {"kind": "read_request", "address": address, "count": count}
    if not body:
        problems.append("read response has no byte count")
        return {"kind": "read_response"}
    byte_count = body[0]
    data = body[1:]
    if byte_count != len(data):
        problems.append(f"byte count says {byte_count} but {len(data)} data bytes follow")
    if space.bits:
        return {"kind": "read_response", "byte_count": byte_count, "bits": unpack_bits(data)}
    if len(data) % 2:
        problems.append("odd number of data bytes")
    return {"kind": "read_response", "byte_count": byte_count, "words": _words(data)}


def _write_single_fields(space: Space, body: bytes, problems: list[str]) -> dict[str, Any]:
    """A write-single frame (0x05/0x06: the request and its echo read alike)."""
    if len(body) != 4:
        problems.append(f"write-single frame carries {len(body)} data bytes, expected 4")
        return {"kind": "write_single"}
    address, word = struct.unpack(">HH", body)
    fields: dict[str, Any] = {"kind": "write_single", "address": address, "count": 1, "words": (word,)}
    if not space.bits:
        return fields
    if word not in (COIL_ON, COIL_OFF):
        problems.append(f"a coil write carries FF 00 (on) or 00 00 (off), not {word >> 8:02X} {word & 0xFF:02X}")
        return fields
    return {**fields, "bits": (1 if word == COIL_ON else 0,)}


def _write_multiple_fields(space: Space, body: bytes, direction: str | None, problems: list[str]) -> dict[str, Any]:
    """A write-multiple request (0x0F/0x10) or its response."""
    if direction == "response" or (direction is None and len(body) == 4):
        if len(body) != 4:
            problems.append(f"write-multiple response carries {len(body)} data bytes, expected 4")
            return {"kind": "write_multiple_response"}
        address, count = struct.unpack(">HH", body)
        return {"kind": "write_multiple_response", "address": address, "count": count}
    if len(body) < 5:
        problems.append(f"write-multiple request carries only {len(body)} data bytes")
        return {"kind": "write_multiple_request"}
    address, count, byte_count = struct.unpack(">HHB", body[:5])
    data = body[5:]
    if byte_count != len(data):
        problems.append(f"byte count says {byte_count} but {len(data)} data bytes follow")
    fields: dict[str, Any] = {"kind": "write_multiple_request", "address": address, "count": count, "byte_count": byte_count}
    if space.bits:
        if (count + 7) // 8 != len(data):
            problems.append(f"coil count says {count} but {len(data)} data bytes follow")
        return {**fields, "bits": unpack_bits(data, count)}
    if count * 2 != len(data):
        problems.append(f"register count says {count} but {len(data)} data bytes follow")
    return {**fields, "words": _words(data)}


def _mask_write_fields(body: bytes, _direction: str | None, problems: list[str]) -> dict[str, Any]:
    """0x16: the request and its echo read alike (address, AND mask, OR mask)."""
    if len(body) != 6:
        problems.append(f"mask write frame carries {len(body)} data bytes, expected 6")
        return {"kind": "mask_write"}
    address, and_mask, or_mask = struct.unpack(">HHH", body)
    return {"kind": "mask_write", "address": address, "count": 1, "words": (and_mask, or_mask)}


def _read_write_fields(body: bytes, direction: str | None, problems: list[str]) -> dict[str, Any]:
    """0x17: the request (read address and count, write address, count, byte count, words) or its response (the words read)."""
    if direction == "response" or (direction is None and (len(body) < 9 or body[0] == len(body) - 1)):
        if not body:
            problems.append("read/write response has no byte count")
            return {"kind": "read_write_response"}
        if body[0] != len(body) - 1:
            problems.append(f"byte count says {body[0]} but {len(body) - 1} data bytes follow")
        if (len(body) - 1) % 2:
            problems.append("odd number of data bytes")
        return {"kind": "read_write_response", "byte_count": body[0], "words": _words(body[1:])}
    if len(body) < 9:
        problems.append(f"read/write request carries only {len(body)} data bytes")
        return {"kind": "read_write_request"}
    read_at, read_count, write_at, write_count, byte_count = struct.unpack(">HHHHB", body[:9])
    data = body[9:]
    if byte_count != len(data):
        problems.append(f"byte count says {byte_count} but {len(data)} data bytes follow")
    if write_count * 2 != len(data):
        problems.append(f"write count says {write_count} but {len(data)} data bytes follow")
    if not 1 <= read_count <= MAX_READ_REGISTERS:
        problems.append(f"read count {read_count} is outside 1..{MAX_READ_REGISTERS}")
    if not 1 <= write_count <= MAX_READ_WRITE_REGISTERS:
        problems.append(f"write count {write_count} is outside 1..{MAX_READ_WRITE_REGISTERS}")
    return {
        "kind": "read_write_request",
        "address": read_at,
        "count": read_count,
        "write_address": write_at,
        "write_count": write_count,
        "byte_count": byte_count,
        "words": _words(data),
    }


def _diagnostics_fields(body: bytes, _direction: str | None, problems: list[str]) -> dict[str, Any]:
    """0x08: sub-function and data (the request and a return-query-data echo read alike)."""
    if len(body) < 2:
        problems.append(f"diagnostics frame carries {len(body)} data bytes, expected a sub-function and data")
        return {"kind": "diagnostics"}
    sub_function = int.from_bytes(body[:2], "big")
    return {"kind": "diagnostics", "count": sub_function, "data": bytes(body[2:])}


def _server_id_fields(body: bytes, direction: str | None, problems: list[str]) -> dict[str, Any]:
    """0x11: an empty request, or the byte count and the report."""
    if direction == "request" or (direction is None and not body):
        if body:
            problems.append(f"report server id request carries {len(body)} data bytes, expected none")
        return {"kind": "server_id_request"}
    if not body:
        problems.append("report server id response has no byte count")
        return {"kind": "server_id_response"}
    if body[0] != len(body) - 1:
        problems.append(f"byte count says {body[0]} but {len(body) - 1} data bytes follow")
    return {"kind": "server_id_response", "byte_count": body[0], "data": bytes(body[1:])}


def _device_id_fields(body: bytes, direction: str | None, problems: list[str]) -> dict[str, Any]:
    """0x2B/0x0E: the request (read code, object id) or the response (its header and objects)."""
    if not body or body[0] != READ_DEVICE_ID:
        problems.append(f"MEI type {body[0]:#04x} is not read device identification (0x0E)" if body else "no MEI type")
        return {"kind": "unknown"}
    if direction == "request" or (direction is None and len(body) == 3):
        if len(body) != 3:
            problems.append(f"read device identification request carries {len(body)} data bytes, expected 3")
            return {"kind": "device_id_request"}
        if body[1] not in DEVICE_ID_CODES.values():
            problems.append(f"read device id code {body[1]} is not 1..4")
        return {"kind": "device_id_request", "device_id": (body[1], body[2], 0, 0)}
    if len(body) < 6:
        problems.append(f"read device identification response carries only {len(body)} data bytes")
        return {"kind": "device_id_response"}
    code, level, more, following, count = body[1:6]
    objects: list[tuple[int, str]] = []
    at = 6
    while at + 2 <= len(body):
        object_id, length = body[at], body[at + 1]
        value = body[at + 2 : at + 2 + length]
        if len(value) != length:
            problems.append(f"object 0x{object_id:02X} says {length} bytes, {len(value)} follow")
        objects.append((object_id, value.decode("ascii", "replace")))
        at += 2 + length
    if at != len(body):
        problems.append(f"{len(body) - at} byte(s) after the last object")
    if count != len(objects):
        problems.append(f"the response says {count} objects and carries {len(objects)}")
    if more not in (0x00, 0xFF):
        problems.append(f"more follows is 0x{more:02X}, not 00 or FF")
    return {"kind": "device_id_response", "count": count, "objects": tuple(objects), "device_id": (code, level, more, following)}


OTHER_FUNCTIONS = {
    MASK_WRITE_REGISTER: _mask_write_fields,
    READ_WRITE_MULTIPLE: _read_write_fields,
    DIAGNOSTICS: _diagnostics_fields,
    REPORT_SERVER_ID: _server_id_fields,
    ENCAPSULATED_INTERFACE: _device_id_fields,
}
"""Functions beyond the spaces' reads and writes: function code -> the fields of its frame."""
