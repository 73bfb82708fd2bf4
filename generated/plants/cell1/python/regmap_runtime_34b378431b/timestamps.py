"""A timestamp register: seconds since 1970-01-01T00:00 in an unsigned 32-bit value, on one of two clocks.

`utc`: the seconds count UTC, a read is an aware `datetime` in UTC and a write takes an aware one (any
zone: the instant is what is sent). `local`: the device counts its own wall clock and knows no zone, a
read is a naive `datetime` and a write takes a naive one. Neither is ever turned into the other: no zone
is guessed (not the host's, not UTC).
"""

from __future__ import annotations

from datetime import UTC, datetime, timedelta

UTC_ZONE = "utc"
LOCAL_ZONE = "local"
ZONES = (UTC_ZONE, LOCAL_ZONE)

SECONDS_MAX = (1 << 32) - 1
"""The last second an unsigned 32-bit count holds: 2106-02-07T06:28:15."""

_EPOCH_NAIVE = datetime(1970, 1, 1)
_EPOCH_UTC = datetime(1970, 1, 1, tzinfo=UTC)


class TimestampError(ValueError):
    """A value that is not a time of the register's clock (naive for utc, aware for local), not a whole
    second, or outside 1970-01-01T00:00:00 .. 2106-02-07T06:28:15."""


def seconds_to_datetime(seconds: int, zone: str) -> datetime:
    """The time `seconds` after the epoch of `zone`'s clock: aware in UTC for utc, naive for local."""
    if zone == UTC_ZONE:
        return _EPOCH_UTC + timedelta(seconds=seconds)
    return _EPOCH_NAIVE + timedelta(seconds=seconds)


def datetime_to_seconds(value: datetime, zone: str) -> int:
    """The raw seconds of `value` on `zone`'s clock; TimestampError for the other clock's kind of time,
    a fraction of a second, or a time the 32-bit count cannot hold."""
    aware = value.utcoffset() is not None
    if zone == UTC_ZONE and not aware:
        raise TimestampError(f"{_shown(value)} has no zone; the register counts UTC (give the time with its zone: Z, +00:00, tzinfo=UTC)")
    if zone == LOCAL_ZONE and aware:
        raise TimestampError(
            f"{_shown(value)} has a zone; the register counts the device's local clock, which has none (give the time without one)"
        )
    delta = value - (_EPOCH_UTC if aware else _EPOCH_NAIVE)
    if delta.microseconds:
        raise TimestampError(f"{_shown(value)} is not a whole second; the register counts seconds")
    seconds = delta.days * 86400 + delta.seconds
    if not 0 <= seconds <= SECONDS_MAX:
        raise TimestampError(
            f"{_shown(value)} is outside {time_text(0, zone)}..{time_text(SECONDS_MAX, zone)} (an unsigned 32-bit count of seconds)"
        )
    return seconds


def parse_time(text: str, zone: str) -> datetime:
    """ISO 8601 text (`2024-03-01T12:00:00Z`, `2024-03-01 12:00:00`) as a datetime; TimestampError if it is none."""
    try:
        return datetime.fromisoformat(text.strip())
    except ValueError:
        example = "2024-03-01T12:00:00Z" if zone == UTC_ZONE else "2024-03-01T12:00:00"
        raise TimestampError(f"{text!r} is not an ISO 8601 time ({example})") from None


def timestamp_seconds(value: object, zone: str) -> int:
    """The raw seconds of a value written to a timestamp register: a datetime of its clock, ISO text, or
    the seconds themselves (an int)."""
    if isinstance(value, str):
        text = value.strip()
        value = int(text) if text.isdigit() else parse_time(text, zone)
    if isinstance(value, datetime):
        return datetime_to_seconds(value, zone)
    if isinstance(value, int) and not isinstance(value, bool):
        if not 0 <= value <= SECONDS_MAX:
            raise TimestampError(f"{value} seconds is outside 0..{SECONDS_MAX} (an unsigned 32-bit count)")
        return value
    raise TimestampError(f"{value!r} is not a time (a datetime, ISO 8601 text or seconds since 1970)")


def time_text(seconds: int, zone: str) -> str:
    """How docs and tools print a timestamp: ISO 8601, `Z` for utc, no zone for local."""
    return _shown(seconds_to_datetime(seconds, zone))


def _shown(value: datetime) -> str:
    text = value.isoformat()
    return text[:-6] + "Z" if text.endswith("+00:00") else text
