"""Pairing the items of two maps: by each key in turn, so a renamed or moved item is one change."""

from __future__ import annotations

from collections.abc import Callable, Hashable, Iterable, Sequence
from typing import TypeVar

T = TypeVar("T")
Key = Callable[[T], Hashable | None]


def _match(
    old: Iterable[T], new: Iterable[T], keys: Sequence[Key[T]], accept: Callable[[T, T], bool] | None = None
) -> tuple[list[tuple[T, T, int]], list[T], list[T]]:
    """Pair items by each key in turn (a key pairs only values unique on both sides, and never None).
    Returns (old, new, index of the key that paired them), the unpaired old and the unpaired new."""
    rest_old, rest_new = list(old), list(new)
    pairs: list[tuple[T, T, int]] = []
    for k, key in enumerate(keys):
        by_old: dict[Hashable, list[T]] = {}
        by_new: dict[Hashable, list[T]] = {}
        for item in rest_old:
            if (value := key(item)) is not None:
                by_old.setdefault(value, []).append(item)
        for item in rest_new:
            if (value := key(item)) is not None:
                by_new.setdefault(value, []).append(item)
        paired_old: set[int] = set()
        paired_new: set[int] = set()
        for value, olds in by_old.items():
            news = by_new.get(value, [])
            if len(olds) == 1 and len(news) == 1 and (k == 0 or accept is None or accept(olds[0], news[0])):
                pairs.append((olds[0], news[0], k))
                paired_old.add(id(olds[0]))
                paired_new.add(id(news[0]))
        rest_old = [i for i in rest_old if id(i) not in paired_old]
        rest_new = [i for i in rest_new if id(i) not in paired_new]
    return pairs, rest_old, rest_new
