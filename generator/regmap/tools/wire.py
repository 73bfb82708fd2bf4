"""Frames of every data space on the wire: the runtime's register frames plus the bit functions.

Registers (0x03/0x04 reads, 0x06/0x10 writes) are built and parsed by `regmap_runtime.rtu`; the bit
functions are here, per the Modbus Application Protocol v1.1b3: 0x01/0x02 read coils and discrete
inputs (§6.1, §6.2: a byte count of ceil(n/8), bits packed LSB first, padding bits zero), 0x05
write single coil (§6.5: FF 00 on, 00 00 off, nothing else), 0x0F write multiple coils (§6.11).

A parsed bit frame is a runtime `Frame` whose `words` are bits (0 or 1, one per address), the
convention of the runtime's codec for coils; `bit_padding` holds the padding bits of a response.
The frame tools (`frame`, `decode`, the docs' annotation) and the simulator build and read bits
through these functions only.
"""

from __future__ import annotations

import dataclasses
import struct
from collections.abc import Sequence

from regmap_runtime.rtu import (
    EXCEPTION_FLAG,
    Frame,
    FrameError,
    build_read,
    build_write_multiple,
    build_write_single,
    crc_bytes,
    crc_ok,
    to_hex,
    with_crc,
)
from regmap_runtime.rtu import parse_frame as parse_register_frame
from regmap_runtime.spaces import BY_FUNCTION, COIL_OFF, COIL_ON, DEFAULT_SPACE, MAX_READ_BITS, MAX_WRITE_BITS, SPACES

BIT_READS = {s.read: s for s in SPACES.values() if s.bits}
BIT_WRITE_SINGLE = {s.write_single: s for s in SPACES.values() if s.bits and s.write_single is not None}
BIT_WRITE_MULTIPLE = {s.write_multiple: s for s in SPACES.values() if s.bits and s.write_multiple is not None}
BIT_FUNCTIONS = frozenset((*BIT_READS, *BIT_WRITE_SINGLE, *BIT_WRITE_MULTIPLE))


def byte_count(bits: int) -> int:
    """Bytes that carry `bits` packed bits: ceil(n/8)."""
    return (bits + 7) // 8


def pack_bits(bits: Sequence[int]) -> bytes:
    """Bits packed eight to a byte, the first bit in the least significant bit of the first byte;
    the bits after the last are zero."""
    out = bytearray(byte_count(len(bits)))
    for i, bit in enumerate(bits):
        if bit not in (0, 1):
            raise FrameError(f"a bit is 0 or 1, not {bit!r}")
        if bit:
            out[i // 8] |= 1 << (i % 8)
    return bytes(out)


def unpack_bits(data: bytes, count: int | None = None) -> list[int]:
    """The bits of packed bytes, LSB first: `count` of them, or every bit of every byte."""
    bits = [(byte >> i) & 1 for byte in data for i in range(8)]
    return bits if count is None else bits[:count]


def coil_word(bit: int) -> int:
    """What 0x05 carries for a coil state: FF 00 on, 00 00 off (§6.5)."""
    return COIL_ON if bit else COIL_OFF


def _check(slave: int, address: int) -> None:
    if not 0 <= slave <= 255:
        raise FrameError(f"slave id {slave} is outside 0..255")
    if not 0 <= address <= 0xFFFF:
        raise FrameError(f"address {address} is outside 0..0xFFFF")


def build_read_frame(slave: int, address: int, count: int, space: str = DEFAULT_SPACE) -> bytes:
    """The read request of `space`: 0x01/0x02 for bits (1..2000), 0x03/0x04 for registers (1..125)."""
    facts = SPACES[space]
    if not facts.bits:
        return build_read(slave, address, count, space=space)
    _check(slave, address)
    if not 1 <= count <= MAX_READ_BITS:
        raise FrameError(f"bit count {count} is outside 1..{MAX_READ_BITS}")
    return with_crc(struct.pack(">BBHH", slave, facts.read, address, count))


def build_write_frame(slave: int, address: int, values: Sequence[int], single: bool, space: str = DEFAULT_SPACE) -> bytes:
    """A write request of `space`: one value with the single-write function (0x05 for a coil: FF 00
    or 00 00; 0x06 for a register), or several with 0x0F (packed bits) / 0x10 (words)."""
    facts = SPACES[space]
    if not facts.bits:
        return (
            build_write_single(slave, address, values[0], space=space)
            if single
            else build_write_multiple(slave, address, list(values), space=space)
        )
    if facts.write_single is None or facts.write_multiple is None:
        raise FrameError(f"{facts.title} cannot be written")
    _check(slave, address)
    if single:
        if len(values) != 1 or values[0] not in (0, 1):
            raise FrameError(f"write single coil takes one bit (0 or 1), not {list(values)}")
        return with_crc(struct.pack(">BBHH", slave, facts.write_single, address, coil_word(values[0])))
    if not 1 <= len(values) <= MAX_WRITE_BITS:
        raise FrameError(f"coil count {len(values)} is outside 1..{MAX_WRITE_BITS}")
    data = pack_bits(values)
    return with_crc(struct.pack(">BBHHB", slave, facts.write_multiple, address, len(values), len(data)) + data)


def build_bits_response(slave: int, function: int, bits: Sequence[int]) -> bytes:
    """A read coils / read discrete inputs response (padding bits zero)."""
    data = pack_bits(bits)
    return with_crc(bytes([slave, function, len(data)]) + data)


@dataclasses.dataclass(frozen=True)
class BitFrame(Frame):
    """A parsed frame of a bit function: `words` are its bits, `bit_padding` the bits after the last
    one a response's byte count carries (the whole last byte's rest, before a request trims them)."""

    bit_padding: tuple[int, ...] = ()


def parse_frame(frame: bytes, direction: str | None = None) -> Frame:
    """`regmap_runtime.rtu.parse_frame`, and the bit functions parsed as bits (a response carries
    every bit of its bytes: `trim_bits` cuts them to the request's count)."""
    if len(frame) < 4:
        raise FrameError(f"frame too short: {len(frame)} bytes, a Modbus RTU frame has at least 4")
    function = frame[1]
    if function & EXCEPTION_FLAG or function not in BIT_FUNCTIONS:
        return parse_register_frame(frame, direction)
    slave, body = frame[0], frame[2:-2]
    valid = crc_ok(frame)
    space = BY_FUNCTION[function][0]
    problems: list[str] = []
    if not valid:
        problems.append(f"CRC mismatch: frame carries {to_hex(frame[-2:])}, expected {to_hex(crc_bytes(frame[:-2]))}")

    def done(
        kind: str,
        address: int | None = None,
        count: int | None = None,
        byte_count: int | None = None,
        words: tuple[int, ...] = (),
        bit_padding: tuple[int, ...] = (),
    ) -> Frame:
        return BitFrame(
            raw=frame,
            slave=slave,
            function=function,
            kind=kind,
            crc_valid=valid,
            address=address,
            count=count,
            byte_count=byte_count,
            words=words,
            problems=tuple(problems),
            space=space.name,
            bit_padding=bit_padding,
        )

    if function in BIT_READS:
        as_request = direction == "request" or (direction is None and len(body) == 4 and not _reads_as_response(body))
        if as_request:
            if len(body) != 4:
                problems.append(f"read request carries {len(body)} data bytes, expected 4")
                return done("read_request")
            address, count = struct.unpack(">HH", body)
            return done("read_request", address=address, count=count)
        if not body:
            problems.append("read response has no byte count")
            return done("read_response")
        count_byte, data = body[0], body[1:]
        if count_byte != len(data):
            problems.append(f"byte count says {count_byte} but {len(data)} data bytes follow")
        return done("read_response", byte_count=count_byte, words=tuple(unpack_bits(data)))
    if function in BIT_WRITE_SINGLE:
        if len(body) != 4:
            problems.append(f"write-single-coil frame carries {len(body)} data bytes, expected 4")
            return done("write_single")
        address, value = struct.unpack(">HH", body)
        if value not in (COIL_ON, COIL_OFF):
            problems.append(f"write single coil takes FF 00 (on) or 00 00 (off), not {value >> 8:02X} {value & 0xFF:02X}")
            return done("write_single", address=address, count=1)
        return done("write_single", address=address, count=1, words=(1 if value == COIL_ON else 0,))
    if direction == "response" or (direction is None and len(body) == 4):
        if len(body) != 4:
            problems.append(f"write-multiple-coils response carries {len(body)} data bytes, expected 4")
            return done("write_multiple_response")
        address, count = struct.unpack(">HH", body)
        return done("write_multiple_response", address=address, count=count)
    if len(body) < 5:
        problems.append(f"write-multiple-coils request carries only {len(body)} data bytes")
        return done("write_multiple_request")
    address, count, count_byte = struct.unpack(">HHB", body[:5])
    data = body[5:]
    if count_byte != len(data):
        problems.append(f"byte count says {count_byte} but {len(data)} data bytes follow")
    if count_byte != byte_count(count):
        problems.append(f"{count} coils take {byte_count(count)} data byte(s), the byte count says {count_byte}")
    bits = unpack_bits(data)
    return done(
        "write_multiple_request",
        address=address,
        count=count,
        byte_count=count_byte,
        words=tuple(bits[:count]),
        bit_padding=tuple(bits[count:]),
    )


def _reads_as_response(body: bytes) -> bool:
    """A 4-byte body of 0x01/0x02 is a request unless its quantity cannot be one (0 or over 2000)."""
    count = int.from_bytes(body[2:4], "big")
    return not 1 <= count <= MAX_READ_BITS and body[0] == 3


def trim_bits(frame: Frame, count: int) -> Frame:
    """A bit read response cut to the `count` bits the request asked for: the rest become its padding
    (which §6.1/§6.2 want zero), and a byte count other than ceil(count/8) is a problem."""
    if not isinstance(frame, BitFrame) or frame.kind != "read_response":
        return frame
    problems = list(frame.problems)
    if frame.byte_count is not None and frame.byte_count != byte_count(count):
        problems.append(f"{count} bits take {byte_count(count)} data byte(s), the byte count says {frame.byte_count}")
    padding = frame.words[count:]
    if any(padding):
        problems.append(f"the bits after the last of {count} are not zero (a response pads with zeros)")
    return dataclasses.replace(frame, words=frame.words[:count], bit_padding=padding, problems=tuple(problems))
