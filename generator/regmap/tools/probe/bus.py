"""Every request the probe sends goes through `ProbeBus`: a time budget, a rate limit, and a stop when
the device stops making sense (several requests in a row without a usable answer)."""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TypeVar

from regmap_runtime.client import SyncClient
from regmap_runtime.errors import ConnectionLost, DeviceException, RegmapError
from regmap_runtime.spaces import DEFAULT_SPACE

T = TypeVar("T")
CONFUSED_AFTER = 3  # requests in a row with no usable answer


class Stop(Exception):
    """The probe must stop now; the message says why. What was learned so far is still reported."""


@dataclass(frozen=True)
class Answer:
    words: list[int] | None = None  # a read that was answered
    exception: int | None = None  # a Modbus exception code
    failure: str | None = None  # no answer, or an unusable one

    @property
    def ok(self) -> bool:
        return self.exception is None and self.failure is None

    @property
    def text(self) -> str:
        if self.exception is not None:
            return f"exception 0x{self.exception:02X}"
        return self.failure or "answered"


class ProbeBus:
    def __init__(
        self,
        client: SyncClient,
        *,
        budget_s: float,
        rate: float | None = None,
        clock: Callable[[], float] = time.monotonic,
        sleep: Callable[[float], None] = time.sleep,
    ) -> None:
        self.client = client
        self.budget_s = budget_s
        self.interval_s = 1.0 / rate if rate else 0.0
        self.clock = clock
        self.sleep = sleep
        self.started = clock()
        self.next_at = self.started
        self.requests = 0
        self.silent = 0
        self.observed: set[int] = set()  # every address a read was answered for

    @property
    def elapsed_s(self) -> float:
        return self.clock() - self.started

    def _pace(self) -> None:
        now = self.clock()
        wait = max(0.0, self.next_at - now)
        if now + wait - self.started > self.budget_s:
            raise Stop(f"the time budget of {self.budget_s:g} s is spent")
        if wait:
            self.sleep(wait)
        self.next_at = max(now, self.next_at) + self.interval_s
        self.requests += 1

    def _send(self, send: Callable[[], list[int] | None]) -> Answer:
        self._pace()
        try:
            words = send()
        except DeviceException as exc:
            self.silent = 0
            return Answer(exception=exc.code)
        except ConnectionLost as exc:
            raise Stop(f"the connection was lost: {exc}") from None
        except RegmapError as exc:
            self.silent += 1
            if self.silent >= CONFUSED_AFTER:
                raise Stop(f"{self.silent} requests in a row got no usable answer (the last: {exc}): the device looks confused") from None
            return Answer(failure=f"{type(exc).__name__}: {exc}")
        self.silent = 0
        return Answer(words=words)

    def call(self, ask: Callable[[], T]) -> tuple[T | None, Answer]:
        """Any other request (identification, server id): what `ask` returned, and how the device answered."""
        got: list[T] = []

        def send() -> list[int] | None:
            got.append(ask())
            return None

        answer = self._send(send)
        return (got[0] if got else None), answer

    def read(self, address: int, count: int, space: str = DEFAULT_SPACE) -> Answer:
        answer = self._send(lambda: self.client.read_raw(address, count, space=space))
        if answer.ok and space == DEFAULT_SPACE:
            # Limits, gaps and the profile are learned for holding registers, where the drives' quirks are.
            self.observed.update(range(address, address + count))
        return answer

    def write(self, address: int, words: Sequence[int], space: str = DEFAULT_SPACE) -> Answer:
        def send() -> list[int] | None:
            self.client.write_raw(address, list(words), multiple=len(words) > 1, space=space)
            return None

        return self._send(send)
