"""A timestamp register's checks: its clock (`zone`), the keys a time has no use for, its default as seconds."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from regmap.kinds import DataType
from regmap_runtime.timestamps import ZONES, TimestampError, timestamp_seconds

NOT_FOR_TIME = ("scale", "offset", "unit", "min", "max", "enum", "bitfields")
"""Keys of a number that a time has no use for: it is seconds since 1970, read as a date and time."""


def timestamp_facts(r: dict[str, Any], dtype: DataType, inherited: set[str], problem: Callable[[str, str], None]) -> tuple[str | None, Any]:
    """(the register's zone, its default as raw seconds) for a timestamp; (None, the default as given) for
    any other type. `problem(key, message)` reports a zone on another type, a timestamp without one, a key a
    time has no use for, and a default that is no time of its clock or does not fit 32 bits."""
    zone, default = r.get("zone"), r.get("default")
    if not dtype.is_timestamp:
        if zone is not None and "zone" not in inherited:
            problem("zone", f"`zone` is the clock of a timestamp register; a {dtype.value} register has none")
        return None, default
    if zone not in ZONES:
        problem("type", "a timestamp needs `zone`: utc or local, as the manual says (it is never guessed)")
        return None, None
    for key in NOT_FOR_TIME:
        if r.get(key) is not None and key not in inherited:
            problem(key, f"`{key}` is for a number; a timestamp is seconds since 1970, read as a {zone} date and time")
    if default is None:
        return zone, None
    if isinstance(default, bool | float):
        problem("default", f"the default of a timestamp is ISO 8601 text or whole seconds since 1970, not {default!r}")
        return zone, None
    try:
        return zone, timestamp_seconds(default, zone)
    except TimestampError as exc:
        problem("default", f"default: {exc}")
        return zone, None
