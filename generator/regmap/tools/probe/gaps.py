"""Reads across undocumented addresses: the requests a gap-spanning plan would send, tried one by one;
and the opt-in scan of the undocumented addresses inside the map's address ranges (one register per
read, at most SCAN_LIMIT addresses)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from regmap.model import Device
from regmap.runtime_bridge import documented_addresses, runtime_specs
from regmap_runtime.plan import plan_reads
from regmap_runtime.profile import ranges
from regmap_runtime.spaces import DEFAULT_SPACE

from .bus import ProbeBus
from .report import Note

SCAN_LIMIT = 2048


@dataclass
class Gaps:
    map_tolerates: bool
    tried: list[tuple[int, int, str]] = field(default_factory=list)  # (address, count, answer)

    @property
    def answered(self) -> int:
        return sum(1 for *_, what in self.tried if what == "answered")

    def as_json(self) -> dict[str, Any]:
        return {
            "map_says": "tolerate" if self.map_tolerates else "reject",
            "tried": len(self.tried),
            "answered": self.answered,
            "reads": [{"address": a, "count": n, "answer": what} for a, n, what in self.tried],
        }


def holding_addresses(device: Device) -> set[int]:
    """The documented holding-register addresses: read limits, gap reads and the scan are learned for
    holding registers, where the drives' quirks are (and what a device profile records)."""
    return {address for space, address in documented_addresses(device) if space == DEFAULT_SPACE}


def spanning_reads(device: Device, limit: int) -> list[tuple[int, int]]:
    """The requests of the gap-spanning plan that cross an undocumented address."""
    documented = holding_addresses(device)
    blocks = plan_reads([s for s in runtime_specs(device) if s.space == DEFAULT_SPACE], limit, None)
    return [(b.address, b.count) for b in blocks if any(a not in documented for a in range(b.address, b.address + b.count))]


def try_gaps(bus: ProbeBus, device: Device, limit: int, progress: Callable[[str], None] | None = None) -> tuple[Gaps, list[Note]]:
    result = Gaps(device.transport.tolerates_gaps)
    reads = spanning_reads(device, limit)
    for number, (address, count) in enumerate(reads, 1):
        if progress is not None:
            progress(f"gaps: request {number} of {len(reads)}")
        result.tried.append((address, count, bus.read(address, count).text))
    return result, _notes(result)


def _notes(r: Gaps) -> list[Note]:
    tried, answered = len(r.tried), r.answered
    if not tried:
        return [Note("gaps", "transport", "gap_reads", "no read of the map's registers would span an undocumented address", False)]
    if r.map_tolerates:
        agrees = answered == tried
        return [Note("gaps", "transport", "gap_reads", f"answered {answered} of {tried} reads spanning undocumented addresses", not agrees)]
    if answered:
        text = f"answered {answered} of {tried} reads spanning undocumented addresses; the map says it rejects them"
        return [Note("gaps", "transport", "gap_reads", text, True)]
    refusals = sorted({what for *_, what in r.tried})
    return [
        Note("gaps", "transport", "gap_reads", f"refused all {tried} reads spanning undocumented addresses ({', '.join(refusals)})", False)
    ]


@dataclass
class Scan:
    scanned: int = 0
    left: int = 0  # beyond SCAN_LIMIT, or not reached
    answering: list[int] = field(default_factory=list)

    def as_json(self) -> dict[str, Any]:
        return {
            "scanned": self.scanned,
            "not_scanned": self.left,
            "answering": [[first, last] for first, last in ranges(set(self.answering))],
        }


def undocumented_in_ranges(device: Device) -> list[int]:
    """Undocumented addresses between the first and last register of each group (the map's address ranges)."""
    documented = holding_addresses(device)
    out: set[int] = set()
    for group in device.groups:
        regs = [r for r in device.registers if r.group == group.id and r.space == DEFAULT_SPACE]
        if regs:
            first, last = min(r.first_address for r in regs), max(r.last_address for r in regs)
            out.update(a for a in range(first, last + 1) if a not in documented)
    return sorted(out)


def scan(bus: ProbeBus, device: Device, progress: Callable[[str], None] | None = None) -> tuple[Scan, list[Note]]:
    addresses = [a for a in undocumented_in_ranges(device) if a not in bus.observed]
    result = Scan(left=len(addresses))
    for address in addresses[:SCAN_LIMIT]:
        if progress is not None and result.scanned % 64 == 0:
            progress(f"scan: {result.scanned} of {min(len(addresses), SCAN_LIMIT)} addresses")
        answer = bus.read(address, 1)
        result.scanned += 1
        result.left -= 1
        if answer.ok:
            result.answering.append(address)
    shown = ", ".join(f"0x{a:04X}" if a == b else f"0x{a:04X}-0x{b:04X}" for a, b in ranges(set(result.answering))[:8])
    more = f" (and {result.left} not scanned)" if result.left else ""
    if result.answering and not device.transport.tolerates_gaps:
        text = f"{len(result.answering)} of {result.scanned} undocumented addresses answer: {shown}{more}; the map says they do not"
        return result, [Note("scan", "transport", "undocumented_answers", text, True)]
    return result, [
        Note("scan", "transport", "undocumented_answers", f"none of {result.scanned} undocumented addresses answers{more}", False)
    ]
