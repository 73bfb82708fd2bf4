"""What the client makes of the line: pymodbus's settings and method names, the bytes it saw, the
typed error of a failed request, which requests may be sent again, and the masks of a mask write.

pymodbus is created with no retries of its own: it would send a lost command again. The client
repeats a request only where repeating cannot act twice: a read, or a write that covers nothing but
settings (registers the map does not mark as triggers). A write sent once whose answer is lost is
an `OutcomeUnknown`: the device may or may not have carried it out. Also here: the answers of
report server id (0x11) and read device identification (0x2B/0x0E) as the client returns them.
"""

from __future__ import annotations

import dataclasses
import re
from collections.abc import Mapping, Sequence
from typing import Any

from pymodbus.exceptions import ConnectionException, ModbusIOException

from .codec import RangeError, enum_names
from .errors import ConnectionLost, CrcError, DeviceTimeout, OutcomeUnknown, ProtocolError, RegmapError, WrongSlave
from .rtu import crc_ok, to_hex
from .spaces import COIL, DISCRETE_INPUT, HOLDING, INPUT
from .spec import HIGH_FIRST, DeviceSpec, RegisterSpec
from .types import swap_bytes

PARITY = {"none": "N", "even": "E", "odd": "O"}
# pymodbus's spelling of each space's reads and writes: (read, write single, write multiple); None where the space is read-only.
PYMODBUS_METHODS: dict[str, tuple[str, str | None, str | None]] = {
    HOLDING.name: ("read_holding_registers", "write_register", "write_registers"),
    INPUT.name: ("read_input_registers", None, None),
    COIL.name: ("read_coils", "write_coil", "write_coils"),  # write_coil(True) sends FF 00, as 0x05 requires
    DISCRETE_INPUT.name: ("read_discrete_inputs", None, None),
}


def serial_settings(device: DeviceSpec, baud: int | None, parity: str | None, stop_bits: int | None) -> dict[str, Any]:
    """pymodbus's serial settings: the map's where None is given (0 is no baud rate: termios's B0 hangs the line up)."""
    if baud is not None and baud <= 0:
        raise ValueError(f"baud {baud} is not a baud rate")
    return {
        "baudrate": device.baud if baud is None else baud,
        "parity": PARITY[device.parity if parity is None else parity],
        "bytesize": device.data_bits,
        "stopbits": device.stop_bits if stop_bits is None else stop_bits,
    }


class LineWatch:
    """pymodbus's packet hook: keeps the bytes of the latest answer (bounded) so an unusable answer
    can be named (bad CRC, another slave, garbage) rather than reported as silence, and counts the
    requests that went out. Changes nothing."""

    def __init__(self, rtu_framing: bool) -> None:
        self.rtu_framing = rtu_framing
        self.received = b""
        self.packets_sent = 0

    def __call__(self, sending: bool, data: bytes) -> bytes:
        if sending:
            self.packets_sent += 1
        self.received = b"" if sending else bytes(data[-260:])
        return data


def transport_error(line: Any, slave: int, exc: Exception) -> RegmapError:
    """A typed error saying what happened on the line, in regmap's words (pymodbus's texts name its own
    internals): silence, a lost connection, a bad CRC, another slave, or garbage."""
    seen: bytes = line.received
    text = str(exc)
    if isinstance(exc, ConnectionException):
        if "unexpectedly closed" in text:
            return ConnectionLost("the connection closed before the answer was complete")
        return ConnectionLost("the connection could not be opened" if "connect" in text.lower() else "the connection was lost")
    if not isinstance(exc, ModbusIOException):
        return ProtocolError(f"unusable answer: {to_hex(seen)}" if seen else "unusable answer")
    other = re.search(r"device id\S* but received (\d+)", text)
    if other:
        return WrongSlave(f"asked slave {slave}, the answer came from slave {other.group(1)}")
    if not seen:
        return DeviceTimeout(f"no answer from slave {slave}")
    # Where the answer's unit id is: RTU's first byte, the 7th of a Modbus TCP header.
    unit, shortest = (0, 4) if line.rtu_framing else (6, 8)
    if len(seen) >= shortest and seen[unit] != slave:
        return WrongSlave(f"asked slave {slave}, the answer came from slave {seen[unit]}: {to_hex(seen)}")
    if line.rtu_framing and len(seen) >= 4 and not crc_ok(seen):
        return CrcError(f"the answer's CRC does not match: {to_hex(seen)}")
    return ProtocolError(f"unusable answer: {to_hex(seen)}")


def may_repeat(registers: Sequence[RegisterSpec[Any]], space: str, address: int, words: Sequence[int]) -> bool:
    """Whether a write of `words` (bits) at `address` of `space` may be sent again when its answer is
    lost: only when every address belongs to a register of the map and none of them is a trigger."""
    count = len(words)
    covered = set(range(address, address + count))
    claimed: set[int] = set()
    for spec in registers:
        if spec.space != space or spec.first_address >= address + count or spec.address + spec.words <= address:
            continue
        if spec.trigger:
            return False
        claimed.update(range(spec.first_address, spec.address + spec.words))
    return covered <= claimed


def outcome_unknown(
    registers: Sequence[RegisterSpec[Any]], space: str, address: int, words: Sequence[int], cause: RegmapError
) -> OutcomeUnknown:
    """The error of a write sent once whose answer was lost: what was written, why the outcome is not
    known, and what to read before deciding to send it again."""
    touched = [s for s in registers if s.space == space and s.first_address < address + len(words) and s.address + s.words > address]
    target = ", ".join(s.label for s in touched) or "an address the map does not describe"
    shown = " ".join(f"0x{w:04X}" for w in words)
    readable = [s.label for s in touched if s.readable]
    check = (
        f"read {', '.join(readable)} back (and the device's status) before sending it again"
        if readable
        else "check the device's state before sending it again (the map gives no way to read this back)"
    )
    message = (
        f"the write of {shown} to {target} (0x{address:04X}) went out once and no usable answer came"
        f" ({type(cause).__name__}: {cause}): the device may or may not have carried it out;"
        f" it was not sent again; {check}"
    )
    return OutcomeUnknown(message, cause, tuple(s.name for s in touched))


def mask_write_masks(spec: RegisterSpec[Any], fields: Mapping[str, Any]) -> tuple[int, int]:
    """The AND and OR masks of a mask write (0x16) that sets the named fields of a one-word bitfield register
    and leaves every other bit as the device holds it; each named field checked (its width, its enum)."""
    if spec.bitfield_type is None:
        raise TypeError(f"{spec.label} has no bitfields")
    raw = int(dataclasses.replace(spec.bitfield_type.from_raw(0), **fields).to_raw())  # unknown names and widths refused
    named = 0
    for field in spec.bitfields:
        if field.name in fields:
            named |= field.mask
            value = (raw & field.mask) >> field.lsb
            if field.enum is not None and value not in field.enum._value2member_map_:
                raise RangeError(f"{spec.label}.{field.name}: {value} is not one of {enum_names(field.enum)}")
    and_mask, or_mask = ~named & 0xFFFF, raw & named
    if spec.byte_order != HIGH_FIRST:  # the device applies the masks to the word as it travels
        and_mask, or_mask = swap_bytes([and_mask, or_mask])
    return and_mask, or_mask


@dataclasses.dataclass(frozen=True)
class ServerIdReport:
    """What report server id (0x11) answered: every byte after the byte count (MBAP §6.13: the
    server id, the run indicator 0x00 OFF / 0xFF ON, additional data). The id's length is the device's
    own; `split` cuts the data where the map says the id ends."""

    data: bytes

    def split(self, id_length: int) -> tuple[bytes, bool | None, bytes]:
        """(server id, running: True ON, False OFF, None neither; additional data)."""
        if len(self.data) <= id_length:
            return self.data, None, b""
        run = self.data[id_length]
        return self.data[:id_length], True if run == 0xFF else False if run == 0x00 else None, self.data[id_length + 1 :]


def server_id_report(line: LineWatch, response: Any) -> ServerIdReport:
    """The report's data from the answer's own bytes (pymodbus takes the last byte for the run
    indicator, which is wrong when additional data follows it); pymodbus's fields where the bytes are not kept."""
    seen = line.received
    pdu = (seen[1:-2] if line.rtu_framing else seen[7:]) if seen else b""
    if len(pdu) >= 2 and pdu[0] == 0x11 and len(pdu) == 2 + pdu[1]:
        return ServerIdReport(bytes(pdu[2:]))
    identifier = bytes(getattr(response, "identifier", b""))
    return ServerIdReport(identifier + bytes([0xFF if getattr(response, "status", False) else 0x00]))


def identification_objects(answers: Sequence[Any]) -> dict[int, str]:
    """The objects of a read device identification stream, in object id order, from its answers."""
    objects: dict[int, str] = {}
    for answer in answers:
        for object_id, value in dict(getattr(answer, "information", {})).items():
            parts = value if isinstance(value, list) else [value]
            objects[int(object_id)] = b"".join(bytes(p) for p in parts).decode("ascii", "replace")
    return dict(sorted(objects.items()))


def next_identification_object(answer: Any, asked: int) -> int | None:
    """The object id the next request of a stream starts at, or None when the stream is complete;
    an answer that says more follows but does not move forward is a ProtocolError."""
    if int(getattr(answer, "more_follows", 0)) != 0xFF:
        return None
    following = int(getattr(answer, "next_object_id", 0))
    if following <= asked:
        raise ProtocolError(f"read device identification: more follows, but from object 0x{following:02X} after 0x{asked:02X}")
    return following
