"""`replaced`: `dataclasses.replace` for the model's records, without a call of their `__init__`.

An array's elements after its first, and a register given errata, are copies of a register with a few fields changed.
`dataclasses.replace` reads the 45 fields of a `Register` one `Field` at a time and hands them to `__init__` as
keywords; this builds the new instance's `__dict__` as that `__init__` would (every init field, in field order) and
leaves out what a read of the old one cached there (a `cached_property`'s value belongs to the old fields).
"""

from __future__ import annotations

import dataclasses
from typing import Any, TypeVar

Record = TypeVar("Record")

_INIT_FIELDS: dict[type, tuple[tuple[str, ...], frozenset[str]]] = {}  # keyed by class: a class's fields never change


def replaced(record: Record, **changes: Any) -> Record:
    """A copy of `record` (a frozen `regmap.records.dataclass` without default factories) with `changes` made."""
    cls = type(record)
    known = _INIT_FIELDS.get(cls)
    if known is None:
        names = tuple(field.name for field in dataclasses.fields(cls) if field.init)  # type: ignore[arg-type]
        known = _INIT_FIELDS[cls] = (names, frozenset(names))
    names, allowed = known
    if not allowed.issuperset(changes):
        unknown = ", ".join(sorted(set(changes) - allowed))
        raise TypeError(f"{cls.__name__} has no init field {unknown}")
    old = record.__dict__
    fields = {name: old[name] for name in names}
    fields.update(changes)
    copy: Record = object.__new__(cls)
    copy.__dict__.update(fields)
    return copy
