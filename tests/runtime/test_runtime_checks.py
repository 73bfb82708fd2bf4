"""Every check the runtime makes, with a case that trips it and a case at its edge that passes."""

from __future__ import annotations

import dataclasses
from typing import Any

import pytest
from pymodbus.client import ModbusTcpClient

from regmap.model import PollClass
from regmap_runtime.client import SyncClient
from regmap_runtime.codec import RangeError, check_raw, merge_fields, parse_fields, value_to_raw, words_to_raw
from regmap_runtime.errors import AccessError, FirmwareError, ProtocolError
from regmap_runtime.plan import ReadBlock, plan_writes
from regmap_runtime.spec import HIGH_FIRST, LOW_FIRST, POLL_CLASSES, BitfieldSpec, DeviceSpec, RegisterSpec, Writable, poll_class

from conftest import ROOT, SimulatorFactory, generated_runtime
from support.clients import client_module


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
    """Independent cases beside tests/tools/simulator/test_simulator_clients.py's peak current and run status."""
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


# -- issue #19: firmware versions, gates, poll classes, bit spaces, access ------------------------


def device_spec(**kwargs: object) -> DeviceSpec:
    base = DeviceSpec(
        id="d",
        map_version="1",
        fingerprint="f",
        registers=(),
        baud=9600,
        parity="none",
        data_bits=8,
        stop_bits=1,
        max_read_registers=125,
        max_write_registers=123,
        word_order=HIGH_FIRST,
        broadcast_id=0,
        function_codes=(0x01, 0x03, 0x05, 0x06, 0x0F, 0x10),
        tolerates_gaps=False,
    )
    return dataclasses.replace(base, **kwargs)  # type: ignore[arg-type]


@pytest.mark.parametrize(
    ("form", "decimals", "raw", "version", "text"),
    [
        ("decimal", 2, 125, (1, 25), "1.25"),
        ("decimal", 2, 105, (1, 5), "1.05"),  # 1.05 < 1.20: the minor part is a number, not a digit string
        ("decimal", 1, 20, (2, 0), "2.0"),
        ("decimal", 0, 7, (7,), "7"),
        ("major_minor", 0, 0x020A, (2, 10), "2.10"),
        ("major_minor", 0, 0x0203, (2, 3), "2.3"),
        ("string", 0, "V2.10 build 7", (2, 10), "V2.10 build 7"),
        ("string", 0, " 3.1.4 ", (3, 1, 4), "3.1.4"),
    ],
)
def test_firmware_versions_and_their_text(form: str, decimals: int, raw: int | str, version: tuple[int, ...], text: str) -> None:
    device = device_spec(firmware_register="fw", firmware_format=form, firmware_decimals=decimals)
    assert device.firmware_version(raw) == version
    assert device.firmware_text(raw) == text


def test_a_version_string_without_a_number_is_refused() -> None:
    with pytest.raises(ValueError, match="no version number"):
        device_spec(firmware_format="string").firmware_version("unknown")


def test_firmware_gates_at_their_edges() -> None:
    gated = spec("u16", firmware_from="2.0", firmware_until="3.0")
    assert [gated.exists_in(v) for v in ((1, 99), (2, 0), (2, 10), (3, 0), (3, 0, 1))] == [False, True, True, False, False]
    assert gated.firmware_text == "2.0 <= firmware < 3.0"
    assert spec("u16").exists_in((0,)) and spec("u16").firmware_text is None


def test_documented_addresses_follow_the_firmware() -> None:
    old: RegisterSpec[int] = RegisterSpec(name="old", address=0x10, data_type="u32", access="r", firmware_until="2.0")
    new: RegisterSpec[int] = RegisterSpec(name="new", address=0x12, data_type="u16", access="r", firmware_from="2.0")
    device = device_spec(registers=(old, new))
    assert device.documented == frozenset(("holding", a) for a in (0x10, 0x11, 0x12))
    assert device.documented_in((1, 0)) == frozenset({("holding", 0x10), ("holding", 0x11)})
    assert device.documented_in((2, 0)) == frozenset({("holding", 0x12)})
    assert device_spec(registers=(old, new), tolerates_gaps=True).documented_in((1, 0)) is None


def test_poll_classes_are_named_or_refused() -> None:
    assert [poll_class(p) for p in ("static", "fast", "normal", "slow")] == list(POLL_CLASSES)
    assert poll_class(PollClass.FAST) == "fast"
    for bad in ("often", "", None, 1):
        with pytest.raises(ValueError, match="unknown poll class"):
            poll_class(bad)


class _Bits:
    def __init__(self, bits: list[bool]) -> None:
        self.bits = bits


def _offline(device: DeviceSpec) -> SyncClient:
    cls: type[SyncClient] = type("Offline", (SyncClient,), {"DEVICE": device})
    return cls(ModbusTcpClient("127.0.0.1", port=1))


def test_bit_answers_are_trimmed_to_the_count_and_checked() -> None:
    client = _offline(device_spec())
    block = ReadBlock(0x13, 10, (), "coil")
    assert client.read_words(_Bits([True, False] * 8), block) == [1, 0] * 5  # pymodbus pads to whole bytes
    with pytest.raises(ProtocolError, match="asked for 10 bits at 0x0013, got 8"):
        client.read_words(_Bits([True] * 8), block)


def test_a_coil_is_written_as_a_bit_and_nothing_else() -> None:
    client = _offline(device_spec())
    assert client.write_args("coil", 0xAC, [1], True) == (0xAC, True)
    assert client.write_args("coil", 0x13, [1, 0, 1], False) == (0x13, [True, False, True])
    assert client.write_args("holding", 0x10, [0xFF00], True) == (0x10, 0xFF00)
    with pytest.raises(ValueError, match="a coil is written as 0 or 1"):
        client.write_args("coil", 0xAC, [0xFF00], True)


def test_writes_are_planned_per_space_with_the_devices_codes_and_limits() -> None:
    coils: list[Writable[Any]] = [Writable(name=f"c{a}", address=a, data_type="bool", access="rw", space="coil") for a in range(6)]
    regs: list[Writable[Any]] = [Writable(name=f"h{a}", address=a, data_type="u16", access="rw") for a in range(3)]
    values: dict[Writable[Any], Any] = {**dict.fromkeys(coils, True), **dict.fromkeys(regs, 7)}
    client = _offline(device_spec(registers=(*coils, *regs), max_write_coils=4, max_write_registers=2))
    assert [(b.space, b.address, b.words) for b in client.plan_writes(values)] == [
        ("holding", 0, (7, 7)),
        ("holding", 2, (7,)),
        ("coil", 0, (1, 1, 1, 1)),
        ("coil", 4, (1, 1)),
    ]
    single = _offline(device_spec(function_codes=(0x01, 0x03, 0x05, 0x06, 0x10)))  # no 0x0F: one coil a request
    assert [b.words for b in single.plan_writes(dict.fromkeys(coils[:3], False))] == [(0,), (0,), (0,)]
    only_multiple = _offline(device_spec(function_codes=(0x01, 0x03, 0x0F, 0x10)))
    assert only_multiple.writer("coil", True)[0] == 0x0F and only_multiple.writer("holding", True)[0] == 0x10
    assert single.writer("coil", True)[0] == 0x05


def test_read_only_spaces_and_registers_are_refused_as_access_errors() -> None:
    client = _offline(device_spec())
    targets: tuple[RegisterSpec[Any], ...] = (
        RegisterSpec(name="i", address=1, data_type="u16", access="r", space="input"),
        RegisterSpec(name="d", address=1, data_type="bool", access="r", space="discrete_input"),
        RegisterSpec(name="h", address=1, data_type="u16", access="r"),
    )
    for target in targets:
        with pytest.raises(AccessError, match="is read-only"):
            client.encode(target, 1)
        with pytest.raises(TypeError):
            client.encode_raw(target, 1)
    with pytest.raises(AccessError, match="is write-only"):
        client.plan_reads([RegisterSpec(name="w", address=1, data_type="u16", access="w")])
    assert client.requests_sent == 0


def test_check_firmware_refuses_a_version_it_cannot_read() -> None:
    fw: RegisterSpec[str] = RegisterSpec(name="fw", address=0, data_type="string", access="r", string_words=2)
    cls: type[SyncClient] = type(
        "Offline", (SyncClient,), {"DEVICE": device_spec(registers=(fw,), firmware_register="fw", firmware_format="string")}
    )
    client = cls(ModbusTcpClient("127.0.0.1", port=1), check_firmware=True)
    assert client.firmware_pending
    with pytest.raises(FirmwareError, match="the firmware register fw holds 'none', which is not a version") as info:
        client.learn_firmware([0x6E6F, 0x6E65])
    assert info.value.found == "none" and info.value.register is None
    assert client.learn_firmware([0x3235, 0x2E31]) == (25, 1) and client.firmware_text == "25.1"
    assert not client.firmware_pending
