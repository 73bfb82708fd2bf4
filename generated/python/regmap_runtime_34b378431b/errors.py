"""Errors a generated client raises. Catch `RegmapError` for all of them."""

from __future__ import annotations


class RegmapError(Exception):
    """Base of every error raised by a regmap client."""


class DeviceException(RegmapError):
    """The device answered with a Modbus exception response."""

    def __init__(self, function: int, code: int, meaning: str, name: str | None = None) -> None:
        self.function = function
        self.code = code
        self.meaning = meaning
        self.name = name
        super().__init__(f"device answered exception 0x{code:02X} ({meaning}) to function 0x{function:02X}")


class DeviceTimeout(RegmapError):
    """No answer at all within the timeout, after every try the request was allowed (the line stayed silent)."""


class ConnectionLost(RegmapError):
    """The port or socket could not be opened or was lost."""


class ProtocolError(RegmapError):
    """The answer was malformed or did not match the request."""


class CrcError(ProtocolError):
    """An answer came, but its CRC does not match (noise, wrong baud or parity, two masters)."""


class WrongSlave(ProtocolError):
    """An answer came from another slave id than the one asked (two drives with one id, or a wrong --slave)."""


class AccessError(RegmapError, TypeError):
    """A write to a read-only register or space (input registers, discrete inputs), or a read of a
    write-only register: refused before anything was sent."""


class FirmwareError(RegmapError):
    """The connected device's firmware lacks the register (its map gates it by firmware version), or
    the firmware version could not be read or understood; for a refused register nothing was sent.

    `register` names the register (None when the version itself is the problem), `gate` is its gate
    as people read it (`firmware >= 2.00`), `found` the version the device reported (None if unknown)."""

    def __init__(self, message: str, register: str | None = None, gate: str | None = None, found: str | None = None) -> None:
        self.register = register
        self.gate = gate
        self.found = found
        super().__init__(message)


class OutcomeUnknown(RegmapError):
    """A write that must not be repeated (a command, a trigger) went out once and no usable answer came:
    the device may or may not have carried it out, and it was not sent again. Read its state back
    before deciding to send it again.

    `cause` is the error of the lost answer (DeviceTimeout, CrcError ...), `registers` the names of the
    registers the write covered."""

    def __init__(self, message: str, cause: RegmapError, registers: tuple[str, ...] = ()) -> None:
        self.cause = cause
        self.registers = registers
        super().__init__(message)
