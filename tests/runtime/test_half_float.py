"""f16: IEEE 754 half precision in one register (Home Assistant's `float16`, struct's "e"), through the
runtime's codec: every bit pattern decodes as struct does, a written value is rounded to the nearest half
(ties to even) and refused when the rounding leaves the register's range or overflows to infinity."""

from __future__ import annotations

import math
import struct
from typing import Any

import pytest

from regmap_runtime.codec import RangeError, decode_value, raw_to_value, raw_to_words, value_to_raw, words_to_raw
from regmap_runtime.spec import RegisterSpec
from regmap_runtime.types import TYPES


def _half(**kwargs: Any) -> RegisterSpec[Any]:
    return RegisterSpec(name="level", address=0x0010, data_type="f16", access="rw", **kwargs)


def _bits(value: float) -> int:
    return int(struct.unpack(">H", struct.pack(">e", value))[0])


def test_the_type_is_one_signed_word_of_half_precision() -> None:
    info = TYPES["f16"]
    assert (info.words, info.bits, info.kind, info.wide, info.codec) == (1, 16, "float", False, "e")
    assert (info.raw_min, info.raw_max) == (-65504.0, 65504.0)


def test_every_bit_pattern_decodes_as_struct_e_does() -> None:
    spec, swapped = _half(), _half(byte_order="low_first")
    for bits in range(0x10000):
        expected = struct.unpack(">e", bits.to_bytes(2, "big"))[0]
        got = float(words_to_raw(spec, [bits]))
        also = float(words_to_raw(swapped, [((bits & 0xFF) << 8) | (bits >> 8)]))
        if math.isnan(expected):
            assert math.isnan(got) and math.isnan(also), hex(bits)
        else:
            assert got == also == expected and math.copysign(1, got) == math.copysign(1, expected), hex(bits)


@pytest.mark.parametrize(
    ("value", "bits"),
    [
        (1.5, 0x3E00),
        (-2.0, 0xC000),
        (0.1, 0x2E66),  # 0.0999755859375: the nearest half
        (65504.0, 0x7BFF),  # the largest finite half
        (6.103515625e-05, 0x0400),  # the smallest normal
        (5.960464477539063e-08, 0x0001),  # the smallest subnormal
        (2049.0, 0x6800),  # halfway between 2048 and 2050: ties to even (2048)
        (2051.0, 0x6802),  # halfway between 2050 and 2052: ties to even (2052)
        (1.0 + 2.0**-11, 0x3C00),  # halfway above 1.0: to even (1.0)
    ],
)
def test_a_written_value_is_rounded_to_the_nearest_half_ties_to_even(value: float, bits: int) -> None:
    spec = _half()
    raw = value_to_raw(spec, value)
    assert raw_to_words(spec, raw) == [bits] == [_bits(value)]
    assert raw == struct.unpack(">e", bits.to_bytes(2, "big"))[0]  # the raw is what the register holds


@pytest.mark.parametrize("value", [65520.0, 65536.0, 1e6, -65520.0, math.inf, "inf", "nan"])
def test_a_value_that_would_be_infinity_or_nan_is_refused(value: float | str) -> None:
    with pytest.raises(RangeError):
        value_to_raw(_half(), value)


def test_rounding_never_carries_a_value_past_the_maps_range() -> None:
    # max 1.0006: 1.0006 is inside, but the nearest half is 1.0009765625, beyond it.
    spec = _half(max=1.0006)
    with pytest.raises(RangeError, match="outside"):
        value_to_raw(spec, 1.0006)
    assert value_to_raw(spec, 1.0004) == 1.0  # rounds down: inside


def test_a_scaled_half_reads_and_writes_through_the_scale() -> None:
    spec = _half(scale_num=1, scale_den=10)
    assert raw_to_value(spec, float(words_to_raw(spec, [0x4B00]))) == pytest.approx(1.4)  # raw 14.0
    assert raw_to_words(spec, value_to_raw(spec, 1.4)) == [0x4B00]


def test_the_nan_marker_reads_as_not_available_and_is_never_written() -> None:
    spec = _half(na_nan=True)
    assert spec.is_na(words_to_raw(spec, [0x7E00]))
    assert spec.is_na(words_to_raw(spec, [0xFE01]))  # any NaN
    assert not spec.is_na(words_to_raw(spec, [0x7C00]))  # infinity is no NaN
    assert decode_value(spec, words_to_raw(spec, [0x7E00])) is None  # NaN is its only marker: no `na` list
    assert decode_value(spec, words_to_raw(spec, [0x7C00])) == math.inf
    with pytest.raises(RangeError):
        value_to_raw(spec, float("nan"))
