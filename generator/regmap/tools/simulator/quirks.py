"""Where a simulated drive departs from its map: the devices `regmap probe` has to recognise.

A real drive may answer reads across undocumented addresses, refuse reads shorter than the map's
limit (or take longer ones), lay 32-bit values in the other word order, or run another firmware (whose gated registers are
absent, and whose firmware register reports it).
Each quirk is off by default: the simulator then plays the map exactly.
"""

from __future__ import annotations

from dataclasses import dataclass

WORD_ORDERS = ("high_first", "low_first")


@dataclass(frozen=True)
class Quirks:
    max_read: int | None = None  # registers per read the drive takes (the map's max_read_registers when None), at most 125
    answer_gaps: bool = False  # reads over undocumented addresses return 0 for them instead of exception 0x02
    word_order: str | None = (
        None  # the drive's 32-bit word order at start-up (on a map with a word-order register: that register's setting)
    )
    firmware: str | None = None  # the firmware version played: the map's firmware register reports it, registers it lacks answer 0x02
    variant: str | None = None  # the device variant played (device.variants): registers it lacks answer 0x02

    def __post_init__(self) -> None:
        if self.max_read is not None and not 1 <= self.max_read <= 125:
            raise ValueError(f"max_read {self.max_read} is outside 1..125")
        if self.word_order is not None and self.word_order not in WORD_ORDERS:
            raise ValueError(f"word_order must be one of {', '.join(WORD_ORDERS)}")
