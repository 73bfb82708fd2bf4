"""regmap.records.dataclass makes classes that answer as the standard decorator's do: the same repr (recursion
included), the same equality (NaN, other classes, subclasses), the same hashes, unhashable when mutable, frozen
when frozen, the same __init__ (signature, defaults, factories, errors); and a class it cannot serve (its own __eq__,
another option) is the standard decorator's alone."""

from __future__ import annotations

import dataclasses
import functools
import inspect
import math
import operator
import os
import shutil
import subprocess
import sys
import types
import typing
from collections.abc import Callable
from pathlib import Path
from typing import Any, ClassVar, NamedTuple

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

    @decorate(frozen=True)
    class Made:
        """Fields the __init__ does not take, or fills from a factory."""

        items: tuple[int, ...] = dataclasses.field(default_factory=tuple)
        hidden: int = dataclasses.field(default=5, init=False)
        made: list[int] = dataclasses.field(default_factory=list, init=False, compare=False)
        shared: ClassVar[int] = 3

    class Plain(Point):  # no dataclass itself: may have attributes of its own, not set the fields
        pass

    @decorate(frozen=True)
    class Checked:
        value: int

        def __post_init__(self) -> None:
            if self.value < 0:
                raise ValueError(f"negative: {self.value}")

    # annotations that are objects, not text (a module without `from __future__ import annotations`)
    typed = decorate(frozen=True)(type("Typed", (), {"__annotations__": {"count": int, "items": list[int], "kind": Any}, "kind": None}))

    return {
        "Typed": typed,
        "Point": Point,
        "Single": Single,
        "Empty": Empty,
        "Mutable": Mutable,
        "Child": Child,
        "Made": Made,
        "Plain": Plain,
        "Checked": Checked,
    }


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
        shapes["Made"](),
        shapes["Made"]((1, 2)),
        shapes["Plain"](1),
    ]


def _outcome(action: Callable[[], object]) -> str:
    """What an action answers, or the exception it raises (its class and words)."""
    try:
        return repr(action())
    except Exception as exc:
        return f"{type(exc).__name__}: {exc}"


def _given_another_attribute(instance: object) -> dict[str, Any]:
    instance.other = 2  # type: ignore[attr-defined]
    return vars(instance)


def _own(shapes: dict[str, type], method: str) -> dict[str, Any]:
    """The method each class defines itself."""
    return {name: vars(cls)[method] for name, cls in shapes.items() if method in vars(cls)}


def _instances(shapes: dict[str, type]) -> dict[str, Any]:
    """How the classes are made and how their instances take changes."""
    point, plain, mutable, made = (shapes[n] for n in ("Point", "Plain", "Mutable", "Made"))
    attempts: dict[str, Callable[[], object]] = {
        "no argument": lambda: point(),
        "too many": lambda: point(1, 2.0, "", "", 0, 9),
        "unknown keyword": lambda: point(1, z=2),
        "not taken": lambda: made(hidden=1),
        "set a field": lambda: setattr(point(1), "x", 2),
        "set another attribute": lambda: setattr(point(1), "other", 2),
        "delete a field": lambda: delattr(point(1), "x"),
        "plain: set a field": lambda: setattr(plain(1), "x", 2),
        "plain: delete a field": lambda: delattr(plain(1), "x"),
        "plain: set its own": lambda: _given_another_attribute(plain(1)),
        "mutable: set a field": lambda: setattr(mutable(), "items", [3]),
        "made: defaults": lambda: (made().items, made().hidden, made().made),
        "made: own list each": lambda: made().made is made().made,
        "mutable: own list each": lambda: mutable().items is mutable().items,
        "replace": lambda: dataclasses.replace(point(1, 2.0), label="b"),
        "post init": lambda: shapes["Checked"](-1),
    }
    return {
        "signature": {name: str(inspect.signature(cls)) for name, cls in shapes.items()},
        "init": {name: (init.__qualname__.split(".")[-2:], init.__module__) for name, init in _own(shapes, "__init__").items()},
        "setattr": {name: method.__qualname__.split(".")[-2:] for name, method in _own(shapes, "__setattr__").items()},
        "frozen": {name: cls.__dataclass_params__.frozen for name, cls in shapes.items()},  # type: ignore[attr-defined]
        "outcomes": {name: _outcome(action) for name, action in attempts.items()},
    }


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


def test_the_init_and_the_frozen_methods_answer_as_the_standard_ones() -> None:
    assert _instances(OURS) == _instances(STANDARD)


def test_a_subclass_made_by_the_standard_decorator_is_frozen_only_as_its_base_is() -> None:
    for base in (OURS["Point"], OURS["Mutable"]):
        frozen = base.__dataclass_params__.frozen  # type: ignore[attr-defined]
        standard: Any = dataclasses.dataclass(frozen=frozen)(type("Sub", (base,), {"__annotations__": {"more": "int"}, "more": 0}))
        assert standard(1).more == 0 if frozen else standard().more == 0
        with pytest.raises(TypeError, match="cannot inherit"):
            dataclasses.dataclass(frozen=not frozen)(type("Wrong", (base,), {}))


def test_a_field_without_a_default_after_one_with_a_default_is_refused_as_the_standard_decorator_refuses_it() -> None:
    def shape(decorate: Decorator) -> str:
        return _outcome(lambda: decorate(type("Bad", (), {"__annotations__": {"a": "int", "b": "int"}, "a": 0})))

    assert shape(records.dataclass).startswith("TypeError: non-default argument 'b'")
    assert shape(records.dataclass) == shape(dataclasses.dataclass)


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

    @records.dataclass(frozen=True, slots=True)
    class Slotted:
        x: int

    assert OwnEq(1) == OwnEq(2)  # its own __eq__ kept
    assert Slotted.__slots__ == ("x",)
    assert not hasattr(Slotted(1), "__dict__")


def test_an_ordered_record_compares_as_the_standard_ones() -> None:
    def answers(decorate: Decorator) -> list[str]:
        class Version:
            major: int
            minor: int
            note: str = dataclasses.field(default="", compare=False)

        ordered: Any = decorate(frozen=True, order=True)(Version)
        versions = [ordered(1, 2, "b"), ordered(1, 2, "a"), ordered(1, 10), ordered(0, 99), ordered(2, 0)]
        tests = (operator.lt, operator.le, operator.gt, operator.ge)
        return [
            repr(sorted(versions)),
            *(_outcome(functools.partial(test, a, b)) for a in versions for b in versions for test in tests),
            *(_outcome(functools.partial(test, versions[0], (1, 2))) for test in tests),
            *(vars(ordered)[name].__name__ for name in ("__lt__", "__ge__")),
        ]

    assert answers(records.dataclass) == answers(dataclasses.dataclass)


def _tuples(base: Any) -> dict[str, Any]:
    """The same NamedTuple bodies, made on `base` (typing's NamedTuple or regmap.records')."""

    class Point(base):  # type: ignore[misc]
        """A point on the plane."""

        x: int
        y: float = 0.0
        label: str = "origin"

        def norm(self) -> float:
            return abs(self.x) + abs(self.y)

        @property
        def text(self) -> str:
            return f"{self.x},{self.y}"

    class Bare(base):  # type: ignore[misc]
        items: tuple[int, ...]

    return {"Point": Point, "Bare": Bare}


def _text(annotation: Any) -> Any:
    """An annotation as the class body wrote it: typing's NamedTuple makes a ForwardRef of it, regmap.records' keeps it."""
    return getattr(annotation, "__forward_arg__", annotation)


def _tuple_answers(shapes: dict[str, Any]) -> dict[str, Any]:
    point, bare = shapes["Point"], shapes["Bare"]
    made = point(3, -1.5)

    answers: dict[str, Any] = {
        "fields": {name: (cls._fields, cls._field_defaults) for name, cls in shapes.items()},
        "names": {name: (cls.__name__, cls.__qualname__.split(".")[-1], cls.__module__, cls.__doc__) for name, cls in shapes.items()},
        "annotations": {
            name: {key: getattr(kind, "__forward_arg__", kind) for key, kind in cls.__annotations__.items()} for name, cls in shapes.items()
        },
        "signature": {
            name: [(p.name, p.default, _text(p.annotation)) for p in inspect.signature(cls).parameters.values()]
            for name, cls in shapes.items()
        },
        "instance": [
            repr(made),
            made.norm(),
            made.text,
            made._asdict(),
            made._replace(y=2.0),
            tuple(made),
            hash(made) == hash((3, -1.5, "origin")),
        ],
        "equal": [made == (3, -1.5, "origin"), made == point(3, -1.5), bare((1,)) == ((1,),)],
        "outcomes": {
            "missing": _outcome(lambda: point()),
            "too many": _outcome(lambda: point(1, 2.0, "a", "b")),
            "set": _outcome(lambda: setattr(made, "x", 1)),
        },
    }
    return answers


def test_a_records_named_tuple_answers_as_typings() -> None:
    assert _tuple_answers(_tuples(records.NamedTuple)) == _tuple_answers(_tuples(NamedTuple))
    assert typing.get_type_hints(_tuples(records.NamedTuple)["Point"]) == typing.get_type_hints(_tuples(NamedTuple)["Point"])


def test_a_records_named_tuple_refuses_what_typings_refuses() -> None:
    def made(base: Any, namespace: dict[str, Any]) -> str:
        return _outcome(lambda: types.new_class("Wrong", (base,), exec_body=lambda body: body.update(namespace, __module__=__name__)))

    refused: list[dict[str, Any]] = [
        {"__annotations__": {"a": "int", "b": "int", "c": "int"}, "a": 0, "b": 1},  # a field without a default after two with
        {"__annotations__": {"a": "int"}, "_replace": None},
        {"__annotations__": {"a": "int"}, "__init__": None},
    ]
    for namespace in refused:
        assert made(records.NamedTuple, namespace) == made(NamedTuple, namespace)
        assert made(records.NamedTuple, namespace).split(":")[0] in ("TypeError", "AttributeError")


def test_a_cached_property_is_worked_out_once_per_instance() -> None:
    worked_out: list[int] = []

    @records.dataclass(frozen=True)
    class Square:
        side: int

        @records.cached_property
        def area(self) -> int:
            """The side squared."""
            worked_out.append(self.side)
            return self.side * self.side

    small, large = Square(2), Square(3)
    assert (small.area, small.area, large.area, large.area) == (4, 4, 9, 9)
    assert worked_out == [2, 3]
    assert Square.__dict__["area"].__doc__ == "The side squared."


def test_records_of_the_same_number_of_fields_keep_their_own_names() -> None:
    """The code of an `__init__` or a named tuple's `__new__` is shared by the classes of as many fields: each class's
    parameters are still its own fields, in order, with its own defaults."""

    @records.dataclass(frozen=True)
    class First:
        a: int
        b: int = 1

    @records.dataclass(frozen=True)
    class Second:
        y: str
        x: str = "x"

    class Pair(records.NamedTuple):
        left: int
        right: int = 2

    class Other(records.NamedTuple):
        up: str
        down: str = "d"

    assert (vars(First(5)), vars(Second(y="z")), Pair(1)._asdict(), Other(up="u")._asdict()) == (
        {"a": 5, "b": 1},
        {"y": "z", "x": "x"},
        {"left": 1, "right": 2},
        {"up": "u", "down": "d"},
    )
    assert [str(inspect.signature(cls)) for cls in (First, Second, Pair, Other)] == [
        "(a: 'int', b: 'int' = 1) -> None",
        "(y: 'str', x: 'str' = 'x') -> None",
        "(left: 'int', right: 'int' = 2)",
        "(up: 'str', down: 'str' = 'd')",
    ]
    missing_y = _outcome(lambda: Second(x="q"))  # type: ignore[call-arg]
    missing_up = _outcome(lambda: Other(down="q"))  # type: ignore[call-arg]
    assert missing_y.endswith(".Second.__init__() missing 1 required positional argument: 'y'")
    assert missing_up == "TypeError: Other.__new__() missing 1 required positional argument: 'up'"


def _field_facts(cls: type) -> dict[str, Any]:
    """What the standard decorator records of a class's fields, and leaves on the class itself."""
    fields: dict[str, Any] = cls.__dataclass_fields__  # type: ignore[attr-defined]
    return {
        "fields": [
            (f.name, f.type, f.default, f.default_factory, f.init, f.repr, f.hash, f.compare, f.kw_only, f._field_type.name)
            for f in fields.values()
        ],
        "match_args": getattr(cls, "__match_args__", None),
        "class attributes": {name: vars(cls).get(name, "absent") for name in fields},
    }


def test_a_records_fields_are_the_standard_decorators() -> None:
    standard, ours = (
        {name: _field_facts(cls) for name, cls in shapes.items() if "__dataclass_fields__" in vars(cls)} for shapes in (STANDARD, OURS)
    )
    assert ours == standard

    def hidden(decorate: Decorator) -> dict[str, Any]:
        @decorate(frozen=True)
        class Hidden:
            shown: int = 0
            kept: int = dataclasses.field(default=5, init=False)

        return _field_facts(Hidden)

    assert hidden(records.dataclass) == hidden(dataclasses.dataclass)

    def refusal(decorate: Decorator, namespace: dict[str, Any]) -> str:
        return _outcome(lambda: decorate(frozen=True)(type("Bad", (), namespace)))

    for namespace in (
        {"__annotations__": {"items": "list[int]"}, "items": []},  # a mutable default
        {"__annotations__": {"x": "int"}, "y": dataclasses.field(default=1)},  # a field without an annotation
    ):
        assert refusal(records.dataclass, dict(namespace)) == refusal(dataclasses.dataclass, dict(namespace))


_ON_ANOTHER_PYTHON = """\
import dataclasses
from regmap import records

@records.dataclass(frozen=True)
class Point:
    x: int
    y: float = 0.0
    items: tuple[int, ...] = dataclasses.field(default_factory=tuple)

@dataclasses.dataclass(frozen=True)
class Standard:
    x: int
    y: float = 0.0
    items: tuple[int, ...] = dataclasses.field(default_factory=tuple)

class Pair(records.NamedTuple):
    a: int
    b: str = ""

made, standard = Point(1, items=(2,)), Standard(1, items=(2,))
assert repr(made) == repr(standard).replace("Standard", "Point"), repr(made)
assert dataclasses.astuple(made) == dataclasses.astuple(standard) and hash(made) == hash(Point(1, items=(2,)))
assert Pair(1)._replace(b="x") == (1, "x") and repr(Pair(1)) == "Pair(a=1, b='')"
print("records ok")
"""


def _pythons() -> list[str]:
    """This interpreter, and every other CPython >= 3.11 found on PATH or under pyenv (records copies 3.11's private
    parts and must fall back to the standard library's own elsewhere: a newer dataclasses once refused regmap at
    import). A candidate that does not run (a pyenv shim of a version not selected) is left out."""
    candidates = {shutil.which(f"python3.{minor}") for minor in range(11, 16)}
    candidates |= {str(p) for p in (Path(os.environ.get("PYENV_ROOT", Path.home() / ".pyenv")) / "versions").glob("3.1*/bin/python3")}
    found = {sys.executable}
    for path in sorted(c for c in candidates if c is not None):
        check = "import sys; print(sys.implementation.name == 'cpython' and sys.version_info >= (3, 11))"
        if subprocess.run([path, "-c", check], capture_output=True, text=True, check=False).stdout == "True\n":
            found.add(path)
    return sorted(found)


@pytest.mark.parametrize("python", _pythons())
def test_records_builds_classes_on_every_python_found(python: str) -> None:
    source = str(Path(records.__file__).parents[1])
    done = subprocess.run(
        [python, "-c", _ON_ANOTHER_PYTHON], env={**os.environ, "PYTHONPATH": source}, capture_output=True, text=True, check=False
    )
    assert done.returncode == 0 and done.stdout == "records ok\n", done.stderr
