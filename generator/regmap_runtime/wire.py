"""What the client makes of the line: the bytes it saw, the typed error of a failed request, and
which requests may be sent again.

pymodbus is created with no retries of its own: it would send a lost command again. The client
repeats a request only where repeating cannot act twice: a read, or a write that covers nothing but
settings (registers the map does not mark as triggers). A write sent once whose answer is lost is
an `OutcomeUnknown`: the device may or may not have carried it out.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from typing import Any

from pymodbus.exceptions import ConnectionException, ModbusIOException

from .errors import ConnectionLost, CrcError, DeviceTimeout, OutcomeUnknown, ProtocolError, RegmapError, WrongSlave
from .rtu import crc_ok, to_hex
from .spec import RegisterSpec


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
