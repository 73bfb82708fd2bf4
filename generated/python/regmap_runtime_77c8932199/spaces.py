"""The one table of Modbus register spaces: which function codes read and write each.

Registers, read plans, documented addresses and register owners are keyed on (space, address);
frame builders, parsers, the client and the simulator take their function codes from here.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Space:
    """One register space. A read-only space (input registers, discrete inputs) has no write codes."""

    name: str
    title: str
    read: int
    write_single: int | None = None
    write_multiple: int | None = None

    @property
    def codes(self) -> dict[str, int]:
        """The space's function codes by operation: read, write_single, write_multiple."""
        codes = {"read": self.read, "write_single": self.write_single, "write_multiple": self.write_multiple}
        return {operation: code for operation, code in codes.items() if code is not None}


# Modbus Application Protocol v1.1b3 §6.3, §6.6, §6.12.
HOLDING = Space("holding", "holding registers", read=0x03, write_single=0x06, write_multiple=0x10)

SPACES: dict[str, Space] = {s.name: s for s in (HOLDING,)}
DEFAULT_SPACE = HOLDING.name
