"""The largest read the drive takes: a binary search from the map's limit, down to 1 or up to the
Modbus limit of 125, about 8 requests.

A read is tried at the start of the longest run of addresses known to answer. Exception 0x03 (or
silence) means the quantity was refused; data means it was answered; 0x02 means the quantity was
taken and an address refused (Modbus §6 checks the quantity first), which counts as taken for the
limit but proves no address. A profile lowers the limit only to a quantity seen taken with the next
one refused, and raises it only to a quantity seen answered with data.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from regmap.model import Device

from .bus import ProbeBus
from .report import Note

SPEC_MAX_READ = 125
ILLEGAL_ADDRESS = 0x02


@dataclass
class Limit:
    map_limit: int
    start: int = 0
    accepted: int | None = None  # the largest quantity taken (None: not even 1)
    refused: int | None = None  # the smallest quantity refused (None: none up to 125)
    answered: int = 0  # the largest quantity answered with data
    tries: dict[int, str] = field(default_factory=dict)

    @property
    def profile_limit(self) -> int | None:
        """What a profile may set: never past what was observed."""
        if self.refused is not None and self.refused <= self.map_limit and self.accepted:
            return self.accepted
        if self.answered > self.map_limit:
            return self.answered
        return None

    def as_json(self) -> dict[str, Any]:
        return {
            "map": self.map_limit,
            "start_address": self.start,
            "largest_taken": self.accepted,
            "smallest_refused": self.refused,
            "largest_answered": self.answered,
            "tries": {str(n): what for n, what in sorted(self.tries.items())},
        }


def longest_run(addresses: set[int]) -> tuple[int, int]:
    """(start, length) of the longest run of consecutive addresses."""
    best, start, length = (0, 0), None, 0
    for address in sorted(addresses):
        if start is not None and address == start + length:
            length += 1
        else:
            start, length = address, 1
        if length > best[1]:
            best = (start, length)
    return best


def search(bus: ProbeBus, device: Device, known: set[int]) -> tuple[Limit, list[Note]]:
    result = Limit(device.transport.max_read_registers)
    result.start = longest_run(known)[0]

    def taken(count: int) -> bool:
        address = min(result.start, 0x10000 - count)
        answer = bus.read(address, count)
        result.tries[count] = answer.text
        if answer.ok:
            result.answered = max(result.answered, count)
            return True
        return answer.exception == ILLEGAL_ADDRESS

    low, high = 0, SPEC_MAX_READ + 1  # low is taken (0 trivially), high refused (126 by the spec)
    first = min(result.map_limit, SPEC_MAX_READ)
    if taken(first):
        low = first
    else:
        high = first
    while high - low > 1:
        middle = (low + high) // 2
        if taken(middle):
            low = middle
        else:
            high = middle
    result.accepted = low or None
    result.refused = high if high <= SPEC_MAX_READ else None
    return result, _notes(result)


def _notes(r: Limit) -> list[Note]:
    if r.accepted is None:
        return [Note("limits", "transport", "read_limit", f"the drive took no read at 0x{r.start:04X}, not even of 1 register", True)]
    if r.accepted < r.map_limit:
        text = f"the drive refuses reads of more than {r.accepted} registers ({r.tries.get(r.accepted + 1, 'refused')}); the map says {r.map_limit}"
        return [Note("limits", "transport", "read_limit", text, True)]
    if r.accepted > r.map_limit:
        proven = f"answered {r.answered}" if r.answered > r.map_limit else "took the quantity, refusing an address"
        text = f"the drive takes reads of up to {r.accepted} registers ({proven}); the map says {r.map_limit}"
        return [Note("limits", "transport", "read_limit", text, True)]
    return [Note("limits", "transport", "read_limit", f"reads of up to {r.accepted} registers, as the map says", False)]
