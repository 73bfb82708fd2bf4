"""`dataclass`: the standard library's, with `__repr__`, `__eq__` and `__hash__` built from the class's fields instead
of compiled from source for each class. Python 3.11 compiles six functions for each frozen dataclass (about 0.9 ms a
class); half of them go this way. The methods answer as the generated ones do: the same text, the same comparisons,
the same hashes (tests/project/test_records.py compares them). mypy sees the standard decorator itself.

A class that writes one of the three methods itself, or asks for another option than `frozen`, is left to the
standard decorator whole.
"""

from __future__ import annotations

import dataclasses
import operator
import reprlib
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

_BUILT_HERE = ("__repr__", "__eq__", "__hash__")

if TYPE_CHECKING:
    from dataclasses import dataclass as dataclass
else:

    def dataclass(cls: type | None = None, /, **options: Any) -> Any:
        def made(cls: type) -> type:
            if set(options) - {"frozen"} or any(name in cls.__dict__ for name in _BUILT_HERE):
                return dataclasses.dataclass(cls, **options)
            return _with_methods(dataclasses.dataclass(cls, repr=False, eq=False, **options), options.get("frozen", False))

        return made if cls is None else made(cls)


def _with_methods(cls: type, frozen: bool) -> type:
    fields = dataclasses.fields(cls)
    compared = _values([field.name for field in fields if field.compare])
    hashed = _values([field.name for field in fields if (field.compare if field.hash is None else field.hash)])
    shown = [field.name for field in fields if field.repr]

    @reprlib.recursive_repr()
    def __repr__(self: Any) -> str:
        return f"{self.__class__.__qualname__}({', '.join(f'{name}={getattr(self, name)!r}' for name in shown)})"

    def __eq__(self: Any, other: Any) -> Any:
        if other.__class__ is self.__class__:
            return compared(self) == compared(other)
        return NotImplemented

    def __hash__(self: Any) -> int:
        return hash(hashed(self))

    # As the standard decorator does: a frozen class hashes its compared fields, a mutable one is unhashable.
    methods = {"__repr__": __repr__, "__eq__": __eq__, "__hash__": __hash__ if frozen else None}
    for name, method in methods.items():
        if method is not None:
            method.__qualname__ = f"{cls.__qualname__}.{name}"
        setattr(cls, name, method)
    return cls


def _values(names: list[str]) -> Callable[[Any], tuple[Any, ...]]:
    """The tuple of those attributes (the generated methods compare and hash tuples, even of one field or none)."""
    if len(names) >= 2:
        return operator.attrgetter(*names)
    if names:
        [name] = names
        return lambda record: (getattr(record, name),)
    return lambda record: ()
