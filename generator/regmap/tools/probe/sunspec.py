"""The SunSpec chain of a device: the `SunS` marker at 40000, 50000 or 0, then model ID + length pairs until
the end marker (ID 0xFFFF). Reads only: two registers for the marker, two per model."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from regmap.model import Device

from .bus import ProbeBus
from .report import Note

MARKER = [0x5375, 0x6E53]  # "SunS"
BASES = (40000, 50000, 0)
END_ID = 0xFFFF
MAX_MODELS = 256  # a chain longer than this is a device that does not end it


@dataclass
class Chain:
    base: int | None = None
    models: list[tuple[int, int, int]] = field(default_factory=list)  # (model id, address of its ID, length L)
    ended: bool = False
    problem: str | None = None

    def as_json(self) -> Any:
        return {
            "base": self.base,
            "models": [{"id": mid, "address": address, "length": length} for mid, address, length in self.models],
            "ended": self.ended,
            "problem": self.problem,
        }


def walk(bus: ProbeBus, device: Device) -> tuple[Chain, list[Note]]:
    """Find the marker, walk the models, and compare them with the map's model ID registers (their defaults)."""
    chain = Chain()
    for base in BASES:
        answer = bus.read(base, 2)
        if answer.ok and answer.words == MARKER:
            chain.base = base
            break
    if chain.base is None:
        return chain, [Note("sunspec", "transport", "no_marker", f"no SunS marker at {', '.join(map(str, BASES))}", True)]
    address = chain.base + 2
    while len(chain.models) < MAX_MODELS and address + 1 <= 0xFFFF:
        answer = bus.read(address, 2)
        if not answer.ok or answer.words is None:
            chain.problem = f"the model header at {address} did not answer ({answer.text})"
            break
        mid, length = answer.words
        if mid == END_ID:
            chain.ended = True
            break
        chain.models.append((mid, address, length))
        address += 2 + length
    else:
        chain.problem = "the chain does not end (no model ID 0xFFFF)"
    listed = ", ".join(f"{mid} at {addr} (L {length})" for mid, addr, length in chain.models)
    notes = [Note("sunspec", "transport", "chain", f"SunSpec chain at {chain.base}: models {listed or 'none'}", chain.problem is not None)]
    if chain.problem is not None:
        notes.append(Note("sunspec", "transport", "chain_broken", chain.problem, True))
    expected = {
        reg.address: reg.default
        for reg in device.registers
        if reg.name.endswith("_id") and isinstance(reg.default, int) and reg.address >= chain.base
    }
    for mid, addr, _ in chain.models:
        if addr in expected and expected[addr] != mid:
            notes.append(Note("sunspec", f"{addr}", "model", f"model {mid} at {addr}, where the map has model {expected[addr]}", True))
    return chain, notes
