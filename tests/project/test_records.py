"""regmap.records.dataclass makes classes that answer as the standard decorator's do: the same repr (recursion
included), the same equality (NaN, other classes, subclasses), the same hashes, unhashable when mutable, frozen
when frozen; and a class it cannot serve (its own __eq__, another option) is the standard decorator's alone."""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from typing import Any

import pytest

from regmap import records

Decorator = Callable[..., Any]


def _shapes(decorate: Decorator) -> dict[str, type]:
    """The same class bodies, made by `decorate`."""

    @decorate(frozen=True)
    class Point:
        x: int
        y: float = 0.0
        label: str = dataclasses.field(default="", compare=False)
        note: str = dataclasses.field(default="", repr=False)
        weight: int = dataclasses.field(default=0, compare=False, hash=True)

    @decorate(frozen=True)
    class Single:
        value: Any

    @decorate(frozen=True)
    class Empty:
        pass

    @decorate
    class Mutable:
        items: list[Any] = dataclasses.field(default_factory=list)

    @decorate(frozen=True)
    class Child(Point):
        extra: tuple[int, ...] = ()

    return {"Point": Point, "Single": Single, "Empty": Empty, "Mutable": Mutable, "Child": Child}


STANDARD = _shapes(dataclasses.dataclass)
OURS = _shapes(records.dataclass)


def _samples(shapes: dict[str, type]) -> list[Any]:
    nan = math.nan
    point, single, empty, mutable, child = (shapes[n] for n in ("Point", "Single", "Empty", "Mutable", "Child"))
    return [
        point(1, 2.5, "a", "hidden", 3),
        point(1, 2.5, "b", "other", 3),  # differs only in a field that is not compared
        point(1, 2.5, "a", "hidden", 4),  # differs only in a hashed, uncompared field
        point(2),
        single(nan),
        single(nan),
        single((1, "x")),
        empty(),
        empty(),
        mutable([1, 2]),
        mutable([1, 2]),
        child(1, 2.5, "a", "hidden", 3),
        child(1, 2.5, "a", "hidden", 3, (7,)),
    ]


def _answers(shapes: dict[str, type]) -> dict[str, Any]:
    samples = _samples(shapes)
    shared_nan = shapes["Single"](math.nan)
    return {
        "repr": [repr(sample) for sample in samples],
        "eq": [[a == b for b in samples] for a in samples],
        "ne": [[a != b for b in samples] for a in samples],
        "eq_other_class": [sample == (1, 2.5) for sample in samples],
        "hash": [hash(sample) if sample.__class__.__hash__ is not None else "unhashable" for sample in samples],
        "same_nan": shared_nan == shared_nan,
        "fields": {name: [f.name for f in dataclasses.fields(cls)] for name, cls in shapes.items()},
        "doc": {name: cls.__doc__ for name, cls in shapes.items()},
        "qualname": {name: cls.__repr__.__qualname__.split(".")[-2:] for name, cls in shapes.items()},
    }


def test_the_methods_answer_as_the_standard_ones() -> None:
    assert _answers(OURS) == _answers(STANDARD)


def test_a_frozen_record_stays_frozen_and_a_recursive_one_prints() -> None:
    point = OURS["Point"](1)
    with pytest.raises(dataclasses.FrozenInstanceError):
        point.x = 2
    looped = OURS["Mutable"]()
    looped.items.append(looped)
    standard = STANDARD["Mutable"]()
    standard.items.append(standard)
    assert repr(looped) == repr(standard) == "_shapes.<locals>.Mutable(items=[...])"
    assert dataclasses.replace(point, y=4.0) == OURS["Point"](1, 4.0)


def test_a_class_with_its_own_eq_or_another_option_is_the_standard_decorators() -> None:
    @records.dataclass(frozen=True)
    class OwnEq:
        x: int

        def __eq__(self, other: object) -> bool:
            return True

        __hash__ = object.__hash__

    @records.dataclass(frozen=True, order=True)
    class Ordered:
        x: int

    assert OwnEq(1) == OwnEq(2)  # its own __eq__ kept
    assert Ordered(1) < Ordered(2)  # order=True needs the standard decorator's __eq__ (with eq=False it refuses)
