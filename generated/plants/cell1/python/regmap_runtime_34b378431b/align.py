"""Read alignment: a device (a float energy meter) that answers a read only when it starts on a multiple of
`words` and covers a multiple of `words` registers (`transport.read_alignment` in its map)."""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass


@dataclass(frozen=True)
class Alignment:
    """Reads of `spaces` start on a multiple of `words` and cover a multiple of `words`; `exempt` lists the
    reads (space, address, count) the manual allows although they break the rule; `exception` is what the
    device answers a misaligned read with (None: the map does not say)."""

    words: int
    spaces: tuple[str, ...]
    exempt: tuple[tuple[str, int, int], ...] = ()
    exception: int | None = None

    def applies(self, space: str) -> bool:
        return space in self.spaces

    def aligned(self, space: str, address: int, count: int) -> bool:
        """The read keeps the rule (or the rule does not cover its space)."""
        return not self.applies(space) or (address % self.words == 0 and count % self.words == 0)

    def allows(self, space: str, address: int, count: int) -> bool:
        """The device answers the read: it keeps the rule, or the manual exempts it."""
        return self.aligned(space, address, count) or (space, address, count) in self.exempt

    def extent(self, space: str, start: int, end: int) -> tuple[int, int]:
        """[start, end) widened to whole aligned units, in a space the rule covers."""
        if not self.applies(space):
            return start, end
        return start - start % self.words, end + (-end) % self.words

    def limit(self, space: str, limit: int) -> int:
        """The most words an aligned read may cover within `limit` (125 becomes 124 for pairs)."""
        return limit - limit % self.words if self.applies(space) else limit

    def refusal(self, space: str, address: int, count: int) -> str | None:
        """Why the device refuses this read (None: it does not): one line for the user."""
        if self.allows(space, address, count):
            return None
        answer = f"exception 0x{self.exception:02X}" if self.exception is not None else "an exception"
        return (
            f"a read of {count} word(s) at 0x{address:04X} breaks the device's read alignment: reads of {space} registers start on a"
            f" multiple of {self.words} and cover a multiple of {self.words} words (the device answers {answer})"
        )


def padded(
    alignment: Alignment | None, space: str, start: int, end: int, readable: Callable[[Iterable[int]], bool]
) -> tuple[int, int] | None:
    """[start, end) widened to the alignment, or None when a padding word is not readable."""
    if alignment is None:
        return start, end
    low, high = alignment.extent(space, start, end)
    return (low, high) if readable([*range(low, start), *range(end, high)]) else None
