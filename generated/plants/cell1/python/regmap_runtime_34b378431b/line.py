"""Several devices on one line: the order a plant polls them in, and the line's timing kept between frames.

RTU is half duplex: one request, one answer, then the line is quiet for 3.5 characters before the next
request, and a device needs its turnaround (the time its manual gives from a request to being ready for
the next) before it is addressed again. `interleave` is the poll order every back end prints (the C and ST
poll tables, the plant page) and the plant client runs; `PacedLine` keeps the timing on a serial line.
Neither touches a bus: the clock and the sleep are injected, so the schedule is testable without one.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Mapping, Sequence
from typing import TypeVar

from .wire import LineWatch

T = TypeVar("T")


def interleave(plans: Sequence[Sequence[T]]) -> list[tuple[int, T]]:
    """Round robin over the devices, block by block: (device index, block) in line order. A device whose
    plan is longer keeps its turn after the others are done, so no device waits for all of another's reads."""
    order: list[tuple[int, T]] = []
    for turn in range(max((len(plan) for plan in plans), default=0)):
        for index, plan in enumerate(plans):
            if turn < len(plan):
                order.append((index, plan[turn]))
    return order


def frame_s(frame_bytes: int, character_bits: int, baud: int) -> float:
    """How long a frame of `frame_bytes` characters takes on the wire."""
    return frame_bytes * character_bits / baud


class PacedLine(LineWatch):
    """pymodbus's packet hook for a serial line shared by several slaves: before a frame goes out it waits
    until the line is free, that is until both the inter-frame silence after the last byte seen (the answer,
    or the request when none came) and the turnaround of the device last addressed, counted from the end of
    its request, have passed. It changes no byte; `waited_s` is the time it held requests back."""

    def __init__(
        self,
        silence_s: float,
        turnaround_s: Mapping[int, float],
        *,
        character_bits: int,
        baud: int,
        clock: Callable[[], float] = time.monotonic,
        sleep: Callable[[float], None] = time.sleep,
    ) -> None:
        super().__init__(rtu_framing=True)
        self.silence_s = silence_s
        self.turnaround_s = dict(turnaround_s)
        self.character_bits = character_bits
        self.baud = baud
        self.clock = clock
        self.sleep = sleep
        self.free_at = float("-inf")
        self.waited_s = 0.0

    def __call__(self, sending: bool, data: bytes) -> bytes:
        now = self.clock()
        if sending:
            while now < self.free_at:
                self.sleep(self.free_at - now)
                self.waited_s += self.free_at - now
                now = self.clock()
            request_end = now + frame_s(len(data), self.character_bits, self.baud)
            slave = data[0] if data else 0
            # A broadcast or a silent slave leaves only the request on the line: both rules count from it.
            self.free_at = max(request_end + self.silence_s, request_end + self.turnaround_s.get(slave, 0.0))
        else:
            self.free_at = max(self.free_at, now + self.silence_s)
        return super().__call__(sending, data)
