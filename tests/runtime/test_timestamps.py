"""A timestamp register (`type: timestamp`): seconds since 1970 in an unsigned 32-bit value, read as a
datetime (aware in UTC for zone utc, naive for local), written from one of its own kind only."""

from __future__ import annotations

from datetime import UTC, datetime, timedelta, timezone

import pytest

from regmap_runtime.codec import RangeError, decode_value, raw_to_words, value_to_raw, words_to_raw
from regmap_runtime.spec import HIGH_FIRST, LOW_FIRST, RegisterSpec

LAST = (1 << 32) - 1


def _spec(zone: str, word_order: str = HIGH_FIRST, **extra: object) -> RegisterSpec[datetime]:
    return RegisterSpec(name="clock", address=0x0108, data_type="timestamp", access="rw", word_order=word_order, zone=zone, **extra)  # type: ignore[arg-type]


@pytest.mark.parametrize("order", [HIGH_FIRST, LOW_FIRST])
@pytest.mark.parametrize(
    ("seconds", "words_high_first", "utc_text"),
    [
        (0, [0x0000, 0x0000], "1970-01-01T00:00:00+00:00"),
        (1, [0x0000, 0x0001], "1970-01-01T00:00:01+00:00"),
        (0x65920080, [0x6592, 0x0080], "2024-01-01T00:00:00+00:00"),
        (0x80000000, [0x8000, 0x0000], "2038-01-19T03:14:08+00:00"),  # past the signed 32-bit end: read unsigned
        (LAST, [0xFFFF, 0xFFFF], "2106-02-07T06:28:15+00:00"),
    ],
)
def test_words_decode_to_the_time_and_back_in_both_word_orders(
    order: str, seconds: int, words_high_first: list[int], utc_text: str
) -> None:
    words = words_high_first if order == HIGH_FIRST else words_high_first[::-1]
    utc, local = _spec("utc", order), _spec("local", order)
    when = decode_value(utc, words_to_raw(utc, words))
    assert when == datetime.fromisoformat(utc_text)
    assert when.tzinfo is not None and when.utcoffset() == timedelta(0)
    naive = decode_value(local, words_to_raw(local, words))
    assert naive.tzinfo is None and naive == when.replace(tzinfo=None)  # the same count on a clock with no zone
    assert raw_to_words(utc, value_to_raw(utc, when)) == words
    assert raw_to_words(local, value_to_raw(local, naive)) == words


def test_an_aware_time_in_another_zone_is_the_same_instant_on_a_utc_register() -> None:
    utc = _spec("utc")
    berlin = datetime(2024, 1, 1, 1, 0, tzinfo=timezone(timedelta(hours=1)))
    assert value_to_raw(utc, berlin) == 0x65920080
    assert value_to_raw(utc, "2024-01-01T00:00:00Z") == 0x65920080
    assert value_to_raw(utc, "1704067200") == 0x65920080  # the seconds themselves
    assert value_to_raw(_spec("local"), "2024-01-01 00:00:00") == 0x65920080


@pytest.mark.parametrize(
    ("zone", "value", "why"),
    [
        ("utc", datetime(2024, 1, 1), "has no zone"),  # a naive time on a UTC clock would be a guess
        ("utc", "2024-01-01T00:00:00", "has no zone"),
        ("local", datetime(2024, 1, 1, tzinfo=UTC), "has a zone"),  # the device's clock has none to convert to
        ("local", "2024-01-01T00:00:00+01:00", "has a zone"),
        ("utc", datetime(1969, 12, 31, 23, 59, 59, tzinfo=UTC), "is outside 1970-01-01T00:00:00Z..2106-02-07T06:28:15Z"),
        ("utc", datetime(2106, 2, 7, 6, 28, 16, tzinfo=UTC), "2106-02-07T06:28:16Z is outside 1970-01-01T00:00:00Z..2106-02-07T06:28:15Z"),
        ("local", datetime(2024, 1, 1, 0, 0, 0, 500000), "not a whole second"),
        ("local", 1 << 32, "outside 0..4294967295"),
        ("local", -1, "outside 0..4294967295"),
        ("local", 1.0, "is not a time"),
        ("local", True, "is not a time"),
        ("local", "noon", "not an ISO 8601 time"),
    ],
)
def test_a_write_refuses_what_is_no_time_of_the_registers_clock(zone: str, value: object, why: str) -> None:
    with pytest.raises(RangeError, match=why):
        value_to_raw(_spec(zone), value)  # type: ignore[arg-type]


def test_the_not_available_marker_reads_as_none_and_is_never_written() -> None:
    spec = _spec("utc", na=(0,))
    assert decode_value(spec, 0) is None
    assert decode_value(spec, 1) == datetime(1970, 1, 1, 0, 0, 1, tzinfo=UTC)
    with pytest.raises(RangeError, match="not available"):
        value_to_raw(spec, datetime(1970, 1, 1, tzinfo=UTC))
