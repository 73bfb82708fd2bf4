"""The one table of Modbus data spaces: which function codes read and write each, and whether it
holds 16-bit registers or single bits.

Registers, read plans, documented addresses and register owners are keyed on (space, address);
frame builders, parsers, the client and the simulator take their function codes from here.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Space:
    """One data space. A read-only space (input registers, discrete inputs) has no write codes."""

    name: str
    title: str
    read: int
    write_single: int | None = None
    write_multiple: int | None = None
    bits: bool = False  # coils and discrete inputs: one bit per address, packed eight to a byte

    @property
    def codes(self) -> dict[str, int]:
        """The space's function codes by operation: read, write_single, write_multiple."""
        codes = {"read": self.read, "write_single": self.write_single, "write_multiple": self.write_multiple}
        return {operation: code for operation, code in codes.items() if code is not None}

    @property
    def writable(self) -> bool:
        return self.write_single is not None or self.write_multiple is not None

    @property
    def unit(self) -> str:
        """What one address holds, for messages: "register" or "bit"."""
        return "bit" if self.bits else "register"


# Modbus Application Protocol v1.1b3 §6.1-§6.12; the request limits are its quantity ranges.
HOLDING = Space("holding", "holding registers", read=0x03, write_single=0x06, write_multiple=0x10)
INPUT = Space("input", "input registers", read=0x04)
COIL = Space("coil", "coils", read=0x01, write_single=0x05, write_multiple=0x0F, bits=True)
DISCRETE_INPUT = Space("discrete_input", "discrete inputs", read=0x02, bits=True)

SPACES: dict[str, Space] = {s.name: s for s in (HOLDING, INPUT, COIL, DISCRETE_INPUT)}
DEFAULT_SPACE = HOLDING.name

BY_FUNCTION: dict[int, tuple[Space, str]] = {code: (s, op) for s in SPACES.values() for op, code in s.codes.items()}
"""Function code -> (its space, the operation: read, write_single or write_multiple)."""

MAX_READ_REGISTERS = 125  # §6.3/§6.4
MAX_WRITE_REGISTERS = 123  # §6.12
MAX_READ_BITS = 2000  # §6.1/§6.2
MAX_WRITE_BITS = 1968  # §6.11
MASK_WRITE_REGISTER = 0x16  # §6.16: one holding register, (current AND and_mask) OR (or_mask AND NOT and_mask)
COIL_ON, COIL_OFF = 0xFF00, 0x0000  # §6.5: the only two values 0x05 accepts
