# Copied by regmap from generator/regmap_runtime/errors.py - do not edit; regenerate with `regmap generate`.
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
    """No (valid) answer within the timeout after all retries."""


class ConnectionLost(RegmapError):
    """The port or socket could not be opened or was lost."""


class ProtocolError(RegmapError):
    """The answer was malformed or did not match the request."""
