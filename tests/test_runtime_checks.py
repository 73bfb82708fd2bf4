"""Every check the runtime makes, with a case that trips it and a case at its edge that passes."""

from __future__ import annotations

import dataclasses

import pytest

from regmap_runtime.codec import RangeError, check_raw, merge_fields, parse_fields, value_to_raw, words_to_raw
from regmap_runtime.plan import plan_writes
from regmap_runtime.spec import HIGH_FIRST, LOW_FIRST, BitfieldSpec, RegisterSpec

from conftest import ROOT, SimulatorFactory, generated_runtime
from test_python_client import client_module


def spec(data_type: str, **kwargs: object) -> RegisterSpec[int]:
    return RegisterSpec(name="r", address=0x10, data_type=data_type, access="rw", **kwargs)  # type: ignore[arg-type]


@pytest.mark.parametrize(
    ("data_type", "low", "high"),
    [("u16", 0, 0xFFFF), ("s16", -0x8000, 0x7FFF), ("u32", 0, 0xFFFFFFFF), ("s32", -0x80000000, 0x7FFFFFFF)],
)
def test_the_type_range_is_checked_at_both_ends(data_type: str, low: int, high: int) -> None:
    s = spec(data_type)
    check_raw(s, low)
    check_raw(s, high)
    for outside in (low - 1, high + 1):
        with pytest.raises(RangeError):
            check_raw(s, outside)


def test_the_map_range_is_checked_at_both_ends() -> None:
    s = spec("s16", min=-10, max=10)
    check_raw(s, -10)
    check_raw(s, 10)
    for outside in (-11, 11):
        with pytest.raises(RangeError, match=r"outside -10\.\.10"):
            check_raw(s, outside)


@pytest.mark.parametrize(
    ("data_type", "words", "order", "raw"),
    [
        ("s16", [0x8000], HIGH_FIRST, -32768),
        ("s16", [0x7FFF], HIGH_FIRST, 32767),
        ("s16", [0xFFFF], HIGH_FIRST, -1),
        ("u16", [0x8000], HIGH_FIRST, 0x8000),
        ("s32", [0x8000, 0x0000], HIGH_FIRST, -(1 << 31)),
        ("s32", [0x0000, 0x8000], LOW_FIRST, -(1 << 31)),
        ("s32", [0xFFFF, 0x7FFF], LOW_FIRST, 0x7FFFFFFF),
        ("u32", [0xFFFF, 0xFFFF], HIGH_FIRST, 0xFFFFFFFF),
    ],
)
def test_sign_extension_and_word_order_at_the_edges(data_type: str, words: list[int], order: str, raw: int) -> None:
    assert words_to_raw(spec(data_type, word_order=order), words) == raw


def test_resolution_is_checked() -> None:
    s = spec("u16", scale_num=1, scale_den=10, max=80)
    assert value_to_raw(s, 8.0) == 80
    assert value_to_raw(s, "0.1") == 1
    with pytest.raises(RangeError, match="resolution"):
        value_to_raw(s, 0.15)
    with pytest.raises(RangeError, match="outside"):
        value_to_raw(s, 8.1)


def test_a_bitfield_value_one_bit_too_wide_is_refused() -> None:
    idm = client_module("idm_rs")
    widest = idm.Di3FunctionBits(function=127, normally_closed=False)
    assert widest.to_raw() == 0x7F
    with pytest.raises(ValueError, match="does not fit in 7 bit"):
        idm.Di3FunctionBits(function=128, normally_closed=False).to_raw()
    with pytest.raises(ValueError, match="does not fit in 1 bit"):
        dataclasses.replace(widest, normally_closed=2).to_raw()


FIELDS = (BitfieldSpec("low", 0, 4), BitfieldSpec("flag", 7, 1))


def test_field_text_is_checked_and_merged() -> None:
    s = spec("u16", bitfields=FIELDS)
    assert parse_fields(s, "LOW:15,flag:true") == (None, {"low": 15, "flag": 1})
    assert parse_fields(s, "0xFF00,low:1") == (0xFF00, {"low": 1})
    assert merge_fields(s, 0xFFFF, {"low": 0}) == 0xFFF0
    assert merge_fields(s, 0x0000, {"flag": 1}) == 0x0080
    for bad, message in (
        ("low:16", "does not fit in 4 bit"),
        ("flag:2", "does not fit in 1 bit"),
        ("nope:1", "no bitfield 'nope'"),
        ("low:1,low:2", "given twice"),
        ("low:1,0xFF", "a base word may only come first"),
        ("low:x", "not a number"),
    ):
        with pytest.raises(RangeError, match=message):
            parse_fields(s, bad)


def test_a_bitfield_enum_field_given_as_a_number_is_checked_against_its_enum() -> None:
    import enum

    class Mode(enum.IntEnum):
        OFF = 0
        ON = 3

    s = spec("u16", bitfields=(BitfieldSpec("mode", 0, 2, Mode),))
    assert parse_fields(s, "mode:3") == (None, {"mode": 3})
    assert parse_fields(s, "mode:on") == (None, {"mode": 3})
    with pytest.raises(RangeError, match="2 is not one of off=0, on=3"):
        parse_fields(s, "mode:2")


def test_the_same_register_twice_in_one_write_is_refused() -> None:
    s = spec("u16")
    with pytest.raises(ValueError, match="twice"):
        plan_writes([(s, 1), (s, 2)], 10)


def test_the_simulator_refuses_a_second_read_only_and_out_of_range_write(simulator: SimulatorFactory) -> None:
    """Independent cases beside tests/test_simulator.py's peak current and run status."""
    DeviceException = generated_runtime("errors").DeviceException  # what the generated client raises

    sim = simulator(ROOT / "maps" / "c630s.yaml")
    assert sim.port is not None
    c630s = client_module("c630s")
    with c630s.C630s.tcp("127.0.0.1", sim.port, timeout=2) as drive:
        read_only = next(r for r in c630s.DEVICE.registers if r.access == "r" and r.words == 1)
        with pytest.raises(DeviceException) as info:
            drive.write_raw(read_only.address, [1])
        assert info.value.code == 0x03
        target = c630s.PULSES_PER_REVOLUTION
        assert target.max is not None
        high = target.max + 1
        with pytest.raises(DeviceException) as info:
            drive.write_raw(target.address, [high & 0xFFFF, high >> 16])  # low word first, as the map says
        assert info.value.code == 0x03
        with pytest.raises(DeviceException) as info:
            drive.write_raw(target.address, [1])  # half of the 32-bit value
        assert info.value.code == 0x02
        assert drive.read_pulses_per_revolution() == 10000
