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
    """No answer at all within the timeout, after all retries (the line stayed silent)."""


class ConnectionLost(RegmapError):
    """The port or socket could not be opened or was lost."""


class ProtocolError(RegmapError):
    """The answer was malformed or did not match the request."""


class CrcError(ProtocolError):
    """An answer came, but its CRC does not match (noise, wrong baud or parity, two masters)."""


class WrongSlave(ProtocolError):
    """An answer came from another slave id than the one asked (two drives with one id, or a wrong --slave)."""
