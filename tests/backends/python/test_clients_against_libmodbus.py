"""Issue #19's fixture maps through the Python client, against a libmodbus server (not regmap's).

Each case runs twice: with the client built from the map at run time (`regmap_runtime`, as `regmap
read` builds it) and with the generated module (its vendored runtime). The server's tables are
filled by independent encoders (struct, libmodbus's own float setters, pymodbus's
convert_to_registers) and what the client reads must be what they encoded; what the client writes
must be, in the server's final tables, what they encode. Frames the client sends are recorded by
pymodbus's packet hook, so "nothing was sent" is checked on the wire, not only by a counter.
"""

from __future__ import annotations

import asyncio
import dataclasses
import importlib
import math
import struct
import sys
from pathlib import Path
from typing import Any

import pytest
from pymodbus.client import ModbusTcpClient
from pymodbus.client.mixin import ModbusClientMixin

from regmap.model import PollClass
from regmap.runtime_bridge import runtime_device
from regmap_runtime.client import SyncClient
from regmap_runtime.spec import DeviceSpec, ReadOnly, ReadWrite, RegisterSpec

from conftest import mypy_strict
from support import docstrings
from support.fixture_clients import (
    DEVICES,
    FLAVOURS,
    POWER,
    REMOTE,
    SWAPPED,
    Recorder,
    flavour,
    generated_python,
    read,
    write,
)
from support.libmodbus_ref import LibmodbusRef, LibmodbusServerFactory, Tables, libmodbus_ref_fixture, libmodbus_server_fixture  # noqa: F401

DATATYPE = ModbusClientMixin.DATATYPE


# -- independent encoders ----------------------------------------------------------------------


def be_words(data: bytes) -> list[int]:
    """Register words of bytes as they go on the wire (each word's first byte is its high byte)."""
    return list(struct.unpack(f">{len(data) // 2}H", data))


def text_words(text: str, words: int, encoding: str = "ascii", pad: bytes = b"\0") -> list[int]:
    return be_words(text.encode(encoding).ljust(2 * words, pad))


def at(address: int, words: list[int] | tuple[int, ...]) -> dict[int, int]:
    return {address + i: w for i, w in enumerate(words)}


@pytest.fixture(params=FLAVOURS)
def kind(request: pytest.FixtureRequest) -> str:
    name: str = request.param
    return name


def test_the_generated_fixture_clients_pass_mypy_strict() -> None:
    python = generated_python()
    runtime = next(p.name for p in python.iterdir() if p.name.startswith("regmap_runtime_"))
    result = mypy_strict(*(f"-p{d}" for d in DEVICES), f"-p{runtime}", cwd=python)
    assert result.returncode == 0, result.stdout + result.stderr


# -- the power meter: input registers, f32 in two word orders, scale + offset, 64-bit, strings ----

F32_PF = struct.unpack(">f", struct.pack(">f", 0.1))[0]  # 0.1 as the device's float32 holds it


def power_tables(ref: LibmodbusRef, firmware: int = 200, *, thd: bool = True) -> Tables:
    """The meter's tables by independent encoders; `thd=False` leaves 0x0040 out of the input table
    (so a read of it is refused, as an old firmware would)."""
    energy = ModbusClientMixin.convert_to_registers(123456789012, DATATYPE.UINT64)
    assert energy == be_words(struct.pack(">Q", 123456789012))
    inputs = {
        **at(0x0000, ref.set_float("abcd", 230.5)),
        **at(0x0002, ref.set_float("cdab", 12.25)),
        0x0004: 5002,
        0x0006: be_words(struct.pack(">h", -123))[0],
        **at(0x0008, ref.set_float("abcd", 0.1)),
        **at(0x0010, energy),
        **at(0x0014, be_words(struct.pack(">q", -987654321012345))),
        **at(0x0018, be_words(struct.pack(">d", 12345.678))),
    }
    if thd:
        inputs.update(at(0x0040, ref.set_float("abcd", 3.5)))
    holding = {
        **at(0x0100, text_words("PM-3000", 8)),
        **at(0x0108, text_words("SN 4711", 6, pad=b" ")),
        0x0110: firmware,
        0x0120: 5,
        **at(0x0122, ref.set_float("abcd", 900.0)),
        **at(0x0124, ref.set_float("cdab", 253.5)),
        **at(0x0126, text_words("Zähl", 4, "utf-8")),
    }
    return {"input": inputs, "holding": holding}


POWER_VALUES: dict[str, tuple[type, Any]] = {
    "voltage_l1": (float, 230.5),
    "current_l1": (float, 12.25),
    "frequency": (float, pytest.approx(50.02)),
    "temperature": (float, pytest.approx(-123 * 0.1 - 40)),
    "power_factor": (float, F32_PF),
    "active_energy": (float, pytest.approx(123456789.012)),
    "reactive_energy": (int, -987654321012345),
    "energy_total": (float, 12345.678),
    "thd_voltage_l1": (float, 3.5),
    "model_name": (str, "PM-3000"),
    "serial_number": (str, "SN 4711"),
    "firmware_version": (int, 200),
    "ct_ratio": (int, 5),
    "demand_period": (float, 900.0),
    "voltage_alarm": (float, 253.5),
    "meter_label": (str, "Zähl"),
}


def check_values(values: dict[str, Any], expected: dict[str, tuple[type, Any]]) -> None:
    for name, (kind_of, value) in expected.items():
        got = values[name]
        assert type(got) is kind_of, f"{name}: {got!r} is {type(got).__name__}, not {kind_of.__name__}"
        assert got == value, f"{name}: read {got!r}, the encoder put {value!r}"


def test_power_meter_reads_every_type(kind: str, libmodbus_ref: LibmodbusRef, libmodbus_server: LibmodbusServerFactory) -> None:
    f = flavour(kind, POWER)
    port, _ = libmodbus_server(power_tables(libmodbus_ref))
    client, recorder = f.client(port)
    with client:
        check_values({name: read(f, client, name) for name in POWER_VALUES}, POWER_VALUES)
        assert [pdu[0] for pdu in recorder.pdus()] == [0x04] * 9 + [0x03] * 7  # input registers by 0x04, holding by 0x03
        before = len(recorder.sent)
        values = client.read_all()
        check_values(values, POWER_VALUES)
        assert set(values) == {r.name for r in f.device.registers if r.access.readable}
        plan = [(pdu[0], int.from_bytes(pdu[1:3], "big"), int.from_bytes(pdu[3:5], "big")) for pdu in recorder.pdus()[before:]]
    # Space by space (holding first), never across an address the map does not document (0x05, 0x07, 0x10E, 0x121).
    assert plan == [
        (0x03, 0x100, 14),
        (0x03, 0x110, 1),
        (0x03, 0x120, 1),
        (0x03, 0x122, 8),
        (0x04, 0x00, 5),
        (0x04, 0x06, 1),
        (0x04, 0x08, 2),
        (0x04, 0x10, 12),
        (0x04, 0x40, 2),
    ]
    if f.module is not None:
        assert len(plan) == f.module.READ_PLAN_REQUESTS


def test_power_meter_writes_land_as_the_encoders_say(
    kind: str, libmodbus_ref: LibmodbusRef, libmodbus_server: LibmodbusServerFactory
) -> None:
    f = flavour(kind, POWER)
    port, finish = libmodbus_server(power_tables(libmodbus_ref))
    client, recorder = f.client(port)
    with client:
        write(f, client, "ct_ratio", 10000)
        write(f, client, "demand_period", 1.5)
        write(f, client, "voltage_alarm", 230.1)  # not a float32: rounded to the nearest, as libmodbus rounds
        write(f, client, "meter_label", "Zähl")
        write(f, client, "meter_label", "ab")  # the rest is NUL padding again
        assert read(f, client, "voltage_alarm") == struct.unpack(">f", struct.pack(">f", 230.1))[0]
        assert read(f, client, "meter_label") == "ab"
        before = len(recorder.sent)
        client.write_many({f.spec("demand_period"): 3600.0, f.spec("voltage_alarm"): 0.0})
        assert [pdu[:6] for pdu in recorder.pdus()[before:]] == [bytes.fromhex("10 0122 0004 08")]  # one 0x10 for both floats
    holding = finish()["holding"]
    assert [holding[0x120]] == [10000]
    assert [holding[0x122], holding[0x123]] == list(libmodbus_ref.set_float("abcd", 3600.0))
    assert [holding[0x124], holding[0x125]] == list(libmodbus_ref.set_float("cdab", 0.0))
    assert [holding[a] for a in range(0x126, 0x12A)] == text_words("ab", 4, "utf-8")
    functions = [pdu[0] for pdu in recorder.pdus() if pdu[0] in (0x06, 0x10)]
    assert functions == [0x06, 0x10, 0x10, 0x10, 0x10, 0x10]  # a u16 by 0x06; floats and strings are several words


def test_power_meter_float_writes_match_libmodbus(libmodbus_ref: LibmodbusRef, libmodbus_server: LibmodbusServerFactory) -> None:
    """Several floats, both word orders, checked against libmodbus's setters (rounding to float32 included)."""
    f = flavour("runtime", POWER)
    port, finish = libmodbus_server(power_tables(libmodbus_ref))
    client, _ = f.client(port)
    values = [1.0, 1.1, 33.333, 999.999, 3599.9999]
    got: list[tuple[list[int], list[int]]] = []
    with client:
        for value in values:
            client.write_many({f.spec("demand_period"): value, f.spec("voltage_alarm"): min(value, 1000.0)})
            words = client.read_raw(0x122, 4)
            got.append((words[:2], words[2:]))
    finish()
    for value, (period, alarm) in zip(values, got, strict=True):
        assert period == list(libmodbus_ref.set_float("abcd", value))
        assert alarm == list(libmodbus_ref.set_float("cdab", min(value, 1000.0)))


@pytest.mark.parametrize(
    ("name", "value", "message"),
    [
        ("meter_label", "Zählerstand", "is 12 bytes in utf-8; the register holds 8"),
        ("meter_label", "a\ud800", "cannot be written in utf-8"),
        ("meter_label", "a\0b", "may not contain NUL"),
        ("demand_period", math.nan, "NaN"),
        ("demand_period", math.inf, "not a finite number|outside"),
        ("demand_period", 0.5, r"outside 1\.\.3600"),
        ("demand_period", 3600.5, r"outside 1\.\.3600"),
        ("voltage_alarm", -0.1, r"outside 0\.\.1000"),
        ("ct_ratio", 0, r"outside 1\.\.10000"),
        ("ct_ratio", 10001, r"outside 1\.\.10000"),
        ("ct_ratio", 1.5, "resolution"),
    ],
)
def test_power_meter_refuses_bad_values_before_sending(
    kind: str, name: str, value: Any, message: str, libmodbus_ref: LibmodbusRef, libmodbus_server: LibmodbusServerFactory
) -> None:
    f = flavour(kind, POWER)
    port, finish = libmodbus_server(power_tables(libmodbus_ref))
    client, recorder = f.client(port)
    with client:
        with pytest.raises(ValueError, match=message):
            write(f, client, name, value)
        assert recorder.sent == []
        write(f, client, "demand_period", 3600.0)  # the edge itself is accepted
    assert [finish()["holding"][a] for a in (0x122, 0x123)] == list(libmodbus_ref.set_float("abcd", 3600.0))


def test_a_write_to_an_input_register_is_refused_without_traffic(
    kind: str, libmodbus_ref: LibmodbusRef, libmodbus_server: LibmodbusServerFactory
) -> None:
    f = flavour(kind, POWER)
    port, finish = libmodbus_server(power_tables(libmodbus_ref))
    client, recorder = f.client(port)
    with client:
        if f.module is not None:
            assert not hasattr(client, "write_voltage_l1") and hasattr(client, "read_voltage_l1")
        for name in ("voltage_l1", "model_name"):  # an input register; a read-only holding register
            with pytest.raises(f.errors.AccessError, match=f"{name} is read-only"):
                client.write(f.spec(name), 1.0 if name == "voltage_l1" else "x")
            with pytest.raises(TypeError):  # AccessError is a TypeError too, as the client's refusals were
                client.write_many({f.spec(name): 1}, raw=True)
        with pytest.raises(f.errors.AccessError, match="input registers cannot be written"):
            client.write_raw(0x0000, [1], space="input")
        assert recorder.sent == []
    assert finish()["input"][0x0000] == libmodbus_ref.set_float("abcd", 230.5)[0]


# -- firmware gates ----------------------------------------------------------------------------


def reads_of(recorder: Recorder, start: int = 0) -> list[tuple[int, int, int]]:
    """(function, address, count) of the read requests sent."""
    return [
        (pdu[0], int.from_bytes(pdu[1:3], "big"), int.from_bytes(pdu[3:5], "big"))
        for pdu in recorder.pdus()[start:]
        if pdu[0] in (0x01, 0x02, 0x03, 0x04)
    ]


def test_check_firmware_reads_the_version_on_connect_and_refuses_what_it_lacks(
    kind: str, libmodbus_ref: LibmodbusRef, libmodbus_server: LibmodbusServerFactory
) -> None:
    f = flavour(kind, POWER)
    port, finish = libmodbus_server(power_tables(libmodbus_ref, firmware=125, thd=False))  # 1.25: no power quality
    client, recorder = f.client(port, check_firmware=True)
    unread = client.firmware
    assert unread is None
    with client:
        assert (client.firmware, client.firmware_text) == ((1, 25), "1.25")
        assert reads_of(recorder) == [(0x03, 0x0110, 1)]  # the firmware register, on connect
        with pytest.raises(f.errors.FirmwareError) as info:
            read(f, client, "thd_voltage_l1")
        assert (info.value.register, info.value.gate, info.value.found) == ("thd_voltage_l1", "firmware >= 2.00", "1.25")
        assert "thd_voltage_l1 exists only with firmware >= 2.00; the device reports firmware 1.25" in str(info.value)
        assert len(recorder.sent) == 1  # refused before sending
        assert read(f, client, "demand_period") == 900.0  # from 1.20: 1.25 has it
        before = len(recorder.sent)
        values = client.read_all()  # the input table ends at 0x1B: a read of 0x40 would be refused by the server
        assert "thd_voltage_l1" not in values
        assert set(values) == {r.name for r in f.device.registers if r.access.readable} - {"thd_voltage_l1"}
        assert all(address < 0x40 for function, address, _ in reads_of(recorder, before) if function == 0x04)
    finish()


def test_an_older_firmware_refuses_writes_too(kind: str, libmodbus_ref: LibmodbusRef, libmodbus_server: LibmodbusServerFactory) -> None:
    f = flavour(kind, POWER)
    port, finish = libmodbus_server(power_tables(libmodbus_ref, firmware=115, thd=False))  # 1.15: no demand period
    client, recorder = f.client(port, check_firmware=True)
    with client:
        assert client.firmware == (1, 15) and client.firmware_text == "1.15"
        with pytest.raises(
            f.errors.FirmwareError, match=r"demand_period exists only with firmware >= 1\.20; the device reports firmware 1\.15"
        ):
            write(f, client, "demand_period", 60.0)
        with pytest.raises(f.errors.FirmwareError):
            client.write_many({f.spec("ct_ratio"): 2, f.spec("demand_period"): 60.0})  # nothing of the batch is sent
        assert len(recorder.sent) == 1
        assert "demand_period" not in client.read_all()
    assert finish()["holding"][0x120] == 5


def test_a_new_firmware_reads_the_gated_registers(kind: str, libmodbus_ref: LibmodbusRef, libmodbus_server: LibmodbusServerFactory) -> None:
    f = flavour(kind, POWER)
    port, _ = libmodbus_server(power_tables(libmodbus_ref, firmware=200))
    client, _ = f.client(port, check_firmware=True)
    with client:
        assert client.firmware == (2, 0) and client.firmware_text == "2.00"
        assert read(f, client, "thd_voltage_l1") == 3.5
        assert client.read_all()["thd_voltage_l1"] == 3.5


def test_without_check_firmware_nothing_changes(kind: str, libmodbus_ref: LibmodbusRef, libmodbus_server: LibmodbusServerFactory) -> None:
    f = flavour(kind, POWER)
    port, _ = libmodbus_server(power_tables(libmodbus_ref, firmware=125, thd=False))
    client, recorder = f.client(port)
    with client:
        assert recorder.sent == [] and client.firmware is None
        with pytest.raises(f.errors.DeviceException) as info:  # sent, and the device refused it
            read(f, client, "thd_voltage_l1")
        assert info.value.code == 0x02 and reads_of(recorder) == [(0x04, 0x40, 2)]


def test_check_firmware_without_connect_reads_the_version_first(
    kind: str, libmodbus_ref: LibmodbusRef, libmodbus_server: LibmodbusServerFactory
) -> None:
    f = flavour(kind, POWER)
    port, _ = libmodbus_server(power_tables(libmodbus_ref, firmware=125, thd=False))
    client, recorder = f.client(port, check_firmware=True)  # pymodbus connects on the first request
    try:
        assert read(f, client, "frequency") == pytest.approx(50.02)
        assert reads_of(recorder) == [(0x03, 0x0110, 1), (0x04, 0x0004, 1)]
        assert client.firmware == (1, 25)
    finally:
        client.close()


def test_check_firmware_needs_a_firmware_register(kind: str) -> None:
    f = flavour(kind, REMOTE)
    with pytest.raises(f.errors.FirmwareError, match="fixture_remote_io: check_firmware=True, but the map names no firmware register"):
        f.client(1, check_firmware=True)
    with pytest.raises(f.errors.FirmwareError, match="a broadcast"):
        flavour(kind, POWER).sync_class(ModbusTcpClient("127.0.0.1", port=1), 0, check_firmware=True)


def swapped_tables(firmware: int) -> Tables:
    """The byte-swapped drive (bytes low first, words low first: little-endian on the wire) by struct."""

    def le(fmt: str, value: Any) -> list[int]:
        return be_words(struct.pack("<" + fmt, value))

    holding = {
        0x0000: le("H", firmware)[0],
        0x0001: le("H", 0x0201)[0],  # ready, mode = position
        0x0002: le("h", -1234)[0],
        **at(0x0003, le("i", 305419896)),
        **at(0x0005, ModbusClientMixin.convert_to_registers(2.5, DATATYPE.FLOAT32, word_order="little")),  # CDAB
        **at(0x0007, [le("H", w)[0] for w in text_words("AXIS-01", 4)]),
        0x0010: le("H", 150)[0],
        0x0011: le("H", 2)[0],
        **at(0x0020, le("d", 12345.25)),
        **at(0x0024, le("I", 7)),
    }
    return {"holding": holding}


def test_major_minor_firmware_on_a_byte_swapped_drive(kind: str, libmodbus_server: LibmodbusServerFactory) -> None:
    f = flavour(kind, SWAPPED)
    port, _ = libmodbus_server(swapped_tables(0x0203))
    client, recorder = f.client(port, check_firmware=True)
    with client:
        assert (client.firmware, client.firmware_text) == ((2, 3), "2.3")
        assert read(f, client, "torque_limit") == 150  # from 2.0
        for name, gate in (("legacy_mode", "firmware < 2.0"), ("runtime_hours", "firmware >= 2.5"), ("fault_count", "firmware >= 2.5")):
            with pytest.raises(f.errors.FirmwareError) as info:
                read(f, client, name)
            assert (info.value.register, info.value.gate, info.value.found) == (name, gate, "2.3")
        before = len(recorder.sent)
        values = client.read_all()
        assert set(values) == {"firmware", "status", "speed", "position", "gain", "label", "torque_limit"}
        spans = [(address, address + count) for _, address, count in reads_of(recorder, before)]
        assert not any(start <= 0x11 < end for start, end in spans)  # the plan leaves out what 2.3 lacks
        assert values["position"] == 305419896 and values["gain"] == 2.5 and values["label"] == "AXIS-01"
        assert values["speed"] == pytest.approx(-123.4)
        status = values["status"]
        if f.module is None:  # a client built at run time has no bitfield classes: the word itself
            assert status == 0x0201
        else:
            assert (status.ready, status.fault, status.mode, status.raw) == (True, False, f.module.DriveMode.POSITION, 0x0201)


@pytest.mark.parametrize(
    ("firmware", "present", "absent"), [(0x0105, "legacy_mode", "torque_limit"), (0x0205, "runtime_hours", "legacy_mode")]
)
def test_other_firmware_versions_of_the_drive(
    kind: str, firmware: int, present: str, absent: str, libmodbus_server: LibmodbusServerFactory
) -> None:
    f = flavour(kind, SWAPPED)
    port, _ = libmodbus_server(swapped_tables(firmware))
    client, _ = f.client(port, check_firmware=True)
    with client:
        assert client.firmware == (firmware >> 8, firmware & 0xFF)
        values = client.read_all()
        assert present in values and absent not in values
        value = read(f, client, present)
        assert value == (12345.25 if present == "runtime_hours" else 2)
        if present == "legacy_mode":
            assert type(value).__name__ == "DriveMode"
        with pytest.raises(f.errors.FirmwareError):
            read(f, client, absent)


def test_the_async_client_checks_firmware_and_poll_classes(
    kind: str, libmodbus_ref: LibmodbusRef, libmodbus_server: LibmodbusServerFactory
) -> None:
    f = flavour(kind, POWER)
    port, finish = libmodbus_server(power_tables(libmodbus_ref, firmware=125, thd=False))
    recorders: list[Recorder] = []

    async def main() -> None:
        client, recorder = f.async_client(port, check_firmware=True)  # pymodbus's async client wants the running loop
        recorders.append(recorder)
        async with client:
            assert client.firmware == (1, 25)
            fast = await client.read_all(poll="fast")
            assert set(fast) == {"voltage_l1", "current_l1", "frequency"} and fast["current_l1"] == 12.25
            with pytest.raises(f.errors.FirmwareError):
                await client.read(f.spec("thd_voltage_l1"))
            if f.module is not None:
                await client.write_voltage_alarm(240.0)
                assert await client.read_voltage_alarm() == 240.0
            else:
                await client.write(f.spec("voltage_alarm"), 240.0)
            assert "thd_voltage_l1" not in await client.read_all()

    asyncio.run(main())
    assert reads_of(recorders[0])[:2] == [(0x03, 0x0110, 1), (0x04, 0x0000, 5)]
    assert [finish()["holding"][a] for a in (0x124, 0x125)] == list(libmodbus_ref.set_float("cdab", 240.0))


# -- poll classes ------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("poll", "names", "requests"),
    [
        ("static", {"model_name", "serial_number", "firmware_version"}, [(0x03, 0x100, 14), (0x03, 0x110, 1)]),
        ("fast", {"voltage_l1", "current_l1", "frequency"}, [(0x04, 0x00, 5)]),
        (PollClass.SLOW, {"temperature", "active_energy", "reactive_energy", "energy_total"}, [(0x04, 0x06, 1), (0x04, 0x10, 12)]),
        (
            "normal",
            {"power_factor", "thd_voltage_l1", "ct_ratio", "demand_period", "voltage_alarm", "meter_label"},
            [(0x03, 0x120, 1), (0x03, 0x122, 8), (0x04, 0x08, 2), (0x04, 0x40, 2)],
        ),
    ],
)
def test_read_all_reads_one_poll_class(
    kind: str,
    poll: Any,
    names: set[str],
    requests: list[tuple[int, int, int]],
    libmodbus_ref: LibmodbusRef,
    libmodbus_server: LibmodbusServerFactory,
) -> None:
    f = flavour(kind, POWER)
    port, _ = libmodbus_server(power_tables(libmodbus_ref))
    client, recorder = f.client(port)
    with client:
        values = client.read_all(poll=poll)
    assert set(values) == names
    assert reads_of(recorder) == requests
    check_values(values, {name: POWER_VALUES[name] for name in names})


def test_an_unknown_poll_class_is_refused_before_sending(
    kind: str, libmodbus_ref: LibmodbusRef, libmodbus_server: LibmodbusServerFactory
) -> None:
    f = flavour(kind, POWER)
    port, _ = libmodbus_server(power_tables(libmodbus_ref))
    client, recorder = f.client(port, check_firmware=True)
    try:
        with pytest.raises(ValueError, match="unknown poll class 'often': one of static, fast, normal, slow"):
            client.read_all(poll="often")
        assert recorder.sent == []  # not even the firmware register
    finally:
        client.close()


# -- the remote IO module: coils, discrete inputs, an input register (the Modbus spec's examples) -

SPEC_COILS = bytes.fromhex("CD 6B 05")  # §6.1: coils 20..38 (27-20, 35-28, 38-36)
SPEC_INPUTS = bytes.fromhex("AC DB 35")  # §6.2: inputs 197..218


def remote_tables(ref: LibmodbusRef) -> Tables:
    """The tables of MBAP §6.1-§6.4's examples; the bits unpacked by libmodbus's modbus_set_bits_from_bytes."""
    return {
        "coil": {**at(0x13, ref.unpack_bits(19, SPEC_COILS)), 0xAC: 0},
        "discrete_input": at(0xC4, ref.unpack_bits(22, SPEC_INPUTS)),
        "input": {0x08: 10},
        "holding": {0x6B: 0x022B, 0x6C: 0x0000, 0x6D: 0x0064},  # §6.3
    }


def test_remote_io_reads_coils_and_discrete_inputs(
    kind: str, libmodbus_ref: LibmodbusRef, libmodbus_server: LibmodbusServerFactory
) -> None:
    f = flavour(kind, REMOTE)
    port, _ = libmodbus_server(remote_tables(libmodbus_ref))
    coils, inputs = libmodbus_ref.unpack_bits(19, SPEC_COILS), libmodbus_ref.unpack_bits(22, SPEC_INPUTS)
    client, recorder = f.client(port)
    with client:
        relays = [read(f, client, f"relay_{n}_on") for n in range(20, 39)]
        assert relays == [bool(b) for b in coils] and all(type(v) is bool for v in relays)
        digital = [read(f, client, f"input_{n}_active") for n in range(197, 219)]
        assert digital == [bool(b) for b in inputs] and all(type(v) is bool for v in digital)
        assert read(f, client, "analog_in_9") == 10 and read(f, client, "alarm_output") is False
        assert read(f, client, "config_108") == 0x022B
        assert client.read_raw(0x13, 19, space="coil") == coils  # 19 bits, not the 24 of the answer's three bytes
        assert client.read_raw(0xC4, 22, space="discrete_input") == inputs
        before = len(recorder.sent)
        values = client.read_all()
    assert [values[f"relay_{n}_on"] for n in range(20, 39)] == relays
    assert [values[f"input_{n}_active"] for n in range(197, 219)] == digital
    # The spec's own requests: §6.3 (3 registers from 108), §6.4, §6.1 (19 coils from 20), §6.2 (22 inputs from 197).
    assert [pdu.hex(" ").upper() for pdu in recorder.pdus()[before:]] == [
        "03 00 6B 00 03",
        "04 00 08 00 01",
        "01 00 13 00 13",
        "01 00 AC 00 01",
        "02 00 C4 00 16",
    ]
    if f.module is not None:
        assert f.module.READ_PLAN_REQUESTS == 5


def test_a_coil_write_sends_ff00_and_lands(kind: str, libmodbus_ref: LibmodbusRef, libmodbus_server: LibmodbusServerFactory) -> None:
    f = flavour(kind, REMOTE)
    port, finish = libmodbus_server(remote_tables(libmodbus_ref))
    client, recorder = f.client(port)
    with client:
        write(f, client, "alarm_output", True)
        assert recorder.pdus()[-1] == bytes.fromhex("05 00 AC FF 00")  # §6.5: on is FF 00
        assert read(f, client, "alarm_output") is True
        write(f, client, "relay_21_on", True)
        write(f, client, "relay_20_on", False)
        assert recorder.pdus()[-1] == bytes.fromhex("05 00 13 00 00")  # off is 00 00
        with pytest.raises(ValueError, match="on or off"):
            write(f, client, "relay_22_on", 2)
    tables = finish()["coil"]
    assert (tables[0xAC], tables[0x13], tables[0x14]) == (1, 0, 1)


def test_write_many_coils_is_the_specs_0x0f_example(
    kind: str, libmodbus_ref: LibmodbusRef, libmodbus_server: LibmodbusServerFactory
) -> None:
    f = flavour(kind, REMOTE)
    port, finish = libmodbus_server(remote_tables(libmodbus_ref))
    bits = libmodbus_ref.unpack_bits(10, bytes.fromhex("CD 01"))  # §6.11: coils 20..29
    client, recorder = f.client(port)
    with client:
        client.write_many({f.spec(f"relay_{20 + i}_on"): bool(bit) for i, bit in enumerate(bits)})
    assert recorder.pdus() == [bytes.fromhex("0F 00 13 00 0A 02 CD 01")]
    tables = finish()["coil"]
    assert [tables[0x13 + i] for i in range(10)] == bits
    assert [tables[0x13 + i] for i in range(10, 19)] == libmodbus_ref.unpack_bits(19, SPEC_COILS)[10:]  # untouched


def test_read_only_bit_and_register_spaces_are_refused(
    kind: str, libmodbus_ref: LibmodbusRef, libmodbus_server: LibmodbusServerFactory
) -> None:
    f = flavour(kind, REMOTE)
    port, finish = libmodbus_server(remote_tables(libmodbus_ref))
    client, recorder = f.client(port)
    with client:
        if f.module is not None:
            element = client.input(197)
            assert hasattr(element, "read_active") and not hasattr(element, "write_active")
            assert not hasattr(client, "write_analog_in_9") and hasattr(client.relay(20), "write_on")
        for name, value in (("input_197_active", True), ("analog_in_9", 1)):
            with pytest.raises(f.errors.AccessError, match="read-only"):
                client.write(f.spec(name), value)
        with pytest.raises(f.errors.AccessError, match="discrete inputs cannot be written"):
            client.write_raw(0xC4, [1], space="discrete_input")
    assert recorder.sent == []
    assert finish()["discrete_input"][0xC4] == 0


def test_coil_function_codes_follow_the_device(kind: str, libmodbus_ref: LibmodbusRef, libmodbus_server: LibmodbusServerFactory) -> None:
    """0x05 vs 0x0F follows the device's function_codes, as 0x06 vs 0x10 does."""
    f = flavour(kind, REMOTE)
    port, finish = libmodbus_server(remote_tables(libmodbus_ref))
    spec = f.spec_device
    no_multiple = dataclasses.replace(spec, function_codes=tuple(c for c in spec.function_codes if c != 0x0F))
    client, recorder = f.client(port, device=no_multiple)
    with client:
        client.write_many({f.spec("relay_20_on"): True, f.spec("relay_21_on"): True, f.spec("relay_22_on"): False})
    assert [pdu.hex(" ").upper() for pdu in recorder.pdus()] == ["05 00 13 FF 00", "05 00 14 FF 00", "05 00 15 00 00"]
    no_single = dataclasses.replace(spec, function_codes=tuple(c for c in spec.function_codes if c != 0x05))
    client, recorder = f.client(port, device=no_single)
    with client:
        client.write(f.spec("alarm_output"), True)
    assert recorder.pdus() == [bytes.fromhex("0F 00 AC 00 01 01 01")]
    tables = finish()["coil"]
    assert (tables[0x13], tables[0x14], tables[0x15], tables[0xAC]) == (1, 1, 0, 1)


def test_coil_limits_per_request_are_the_devices(kind: str, libmodbus_ref: LibmodbusRef, libmodbus_server: LibmodbusServerFactory) -> None:
    f = flavour(kind, REMOTE)
    port, finish = libmodbus_server(remote_tables(libmodbus_ref))
    small = dataclasses.replace(f.spec_device, max_read_coils=8, max_write_coils=4, max_read_registers=2)
    client, recorder = f.client(port, device=small)
    with client:
        values = client.read_all()
        assert reads_of(recorder) == [
            (0x03, 0x6B, 2),
            (0x03, 0x6D, 1),
            (0x04, 0x08, 1),
            (0x01, 0x13, 8),
            (0x01, 0x1B, 8),
            (0x01, 0x23, 3),
            (0x01, 0xAC, 1),
            (0x02, 0xC4, 8),
            (0x02, 0xCC, 8),
            (0x02, 0xD4, 6),
        ]
        assert [values[f"relay_{n}_on"] for n in range(20, 39)] == [bool(b) for b in libmodbus_ref.unpack_bits(19, SPEC_COILS)]
        before = len(recorder.sent)
        client.write_many({f.spec(f"relay_{n}_on"): n % 3 == 0 for n in range(20, 30)})
        writes = [(pdu[0], int.from_bytes(pdu[1:3], "big"), int.from_bytes(pdu[3:5], "big")) for pdu in recorder.pdus()[before:]]
    assert writes == [(0x0F, 0x13, 4), (0x0F, 0x17, 4), (0x0F, 0x1B, 2)]
    tables = finish()["coil"]
    assert [tables[0x13 + i] for i in range(10)] == [int((20 + i) % 3 == 0) for i in range(10)]


# -- every type in every byte and word order, holding and input registers -------------------------

ORDERS = {  # libmodbus's name of the order -> (byte_order, word_order)
    "abcd": ("high_first", "high_first"),
    "badc": ("low_first", "high_first"),
    "cdab": ("high_first", "low_first"),
    "dcba": ("low_first", "low_first"),
}
MATRIX_VALUES: dict[str, tuple[str, Any]] = {  # type -> (struct format, value)
    "u16": ("H", 0x1234),
    "s16": ("h", -2),
    "u32": ("I", 0x12345678),
    "s32": ("i", -123456789),
    "u64": ("Q", 0x0123456789ABCDEF),
    "s64": ("q", -0x0123456789ABCDEF),
    "f32": ("f", 230.5),
    "f64": ("d", -1234.5678e10),
    "string": ("", "AXIS-01"),
}
PYMODBUS_TYPES = {
    "u32": DATATYPE.UINT32,
    "s32": DATATYPE.INT32,
    "u64": DATATYPE.UINT64,
    "s64": DATATYPE.INT64,
    "f32": DATATYPE.FLOAT32,
    "f64": DATATYPE.FLOAT64,
}


def matrix_words(data_type: str, order: str) -> list[int]:
    """The wire words of MATRIX_VALUES[data_type] in `order`, from struct's big-endian bytes: each word's
    two bytes exchanged for bytes low first, the words reversed for words low first (wide values only)."""
    fmt, value = MATRIX_VALUES[data_type]
    data = value.encode("ascii").ljust(8, b"\0") if data_type == "string" else struct.pack(">" + fmt, value)
    byte_order, word_order = ORDERS[order]
    pairs = [data[i : i + 2] for i in range(0, len(data), 2)]
    if byte_order == "low_first":
        pairs = [pair[::-1] for pair in pairs]
    if word_order == "low_first" and len(pairs) > 1 and data_type != "string":
        pairs = pairs[::-1]
    return be_words(b"".join(pairs))


def matrix_device() -> DeviceSpec:
    """Every type x every order, as holding (rw) and input (r) registers, 8 addresses apart."""
    registers: list[RegisterSpec[Any]] = []
    address = 0
    for data_type in MATRIX_VALUES:
        for order, (byte_order, word_order) in ORDERS.items():
            if data_type == "string" and word_order == "low_first":
                continue  # text has no word order
            for space in ("holding", "input"):
                extra: dict[str, Any] = {"string_words": 4} if data_type == "string" else {}
                spec_class = ReadWrite if space == "holding" else ReadOnly
                registers.append(
                    spec_class(
                        name=f"{space}_{data_type}_{order}",
                        address=address,
                        data_type=data_type,
                        access="rw" if space == "holding" else "r",
                        space=space,
                        byte_order=byte_order,
                        word_order=word_order,
                        follows_device_order=False,  # the order is the register's own, not the device's
                        **extra,
                    )
                )
            address += 8
    base = runtime_device(DEVICES[POWER])
    return dataclasses.replace(
        base, id="matrix", registers=tuple(registers), tolerates_gaps=True, firmware_register=None, max_read_registers=125
    )


def test_matrix_is_anchored_on_libmodbus_and_pymodbus(libmodbus_ref: LibmodbusRef) -> None:
    """The test's own layout against libmodbus's float setters (every order) and pymodbus's word orders."""
    for order in ORDERS:
        assert matrix_words("f32", order) == list(libmodbus_ref.set_float(order, 230.5))
    for data_type, pymodbus_type in PYMODBUS_TYPES.items():
        value = MATRIX_VALUES[data_type][1]
        assert matrix_words(data_type, "abcd") == ModbusClientMixin.convert_to_registers(value, pymodbus_type)
        assert matrix_words(data_type, "cdab") == ModbusClientMixin.convert_to_registers(value, pymodbus_type, word_order="little")
    assert matrix_words("string", "abcd")[:4] == ModbusClientMixin.convert_to_registers("AXIS-01", DATATYPE.STRING)


def test_every_type_in_every_order_reads_and_writes(libmodbus_server: LibmodbusServerFactory) -> None:
    device = matrix_device()
    tables: Tables = {"holding": {}, "input": {}}
    for spec in device.registers:
        tables[spec.space].update(at(spec.address, matrix_words(spec.data_type, spec.name.split("_")[-1])))
    port, finish = libmodbus_server(tables)
    cls: type[SyncClient] = type("Matrix", (SyncClient,), {"DEVICE": device})
    with cls.tcp("127.0.0.1", port, timeout=3, retries=0) as client:
        values = client.read_all()
        assert client.requests_sent == 6  # 34 registers 8 apart in each space, across the gaps (tolerated): 3 x 125 words or fewer
        for spec in device.registers:
            expected = MATRIX_VALUES[spec.data_type][1]
            assert values[spec.name] == expected, spec.name
            assert type(values[spec.name]) is type(expected), spec.name
        holding = [s for s in device.registers if isinstance(s, ReadWrite)]
        client.write_many({spec: 0 if spec.data_type != "string" else "" for spec in holding})
        assert set(client.read_many(*holding).values()) == {0, ""}
        for spec in holding:
            client.write(spec, MATRIX_VALUES[spec.data_type][1])
    final = finish()
    for spec in holding:
        order = spec.name.split("_")[-1]
        assert [final["holding"][spec.address + i] for i in range(spec.words)] == matrix_words(spec.data_type, order), spec.name


# -- the generated modules' surface ------------------------------------------------------------


def test_generated_accessors_are_typed_per_type_and_space() -> None:
    generated_python()
    power, remote, swapped = (importlib.import_module(d) for d in (POWER, REMOTE, SWAPPED))
    returns = {
        (power.FixturePowerMeter, "read_voltage_l1"): "float",  # f32
        (power.FixturePowerMeter, "read_frequency"): "float",  # u16 with a scale
        (power.FixturePowerMeter, "read_temperature"): "float",  # s16 with scale and offset
        (power.FixturePowerMeter, "read_reactive_energy"): "int",  # s64
        (power.FixturePowerMeter, "read_model_name"): "str",
        (power.FixturePowerMeter, "read_firmware_version"): "int",
        (remote.FixtureRemoteIo, "read_alarm_output"): "bool",  # a coil
        (remote.InputElement, "read_active"): "bool",  # a discrete input
        (remote.FixtureRemoteIo, "read_analog_in_9"): "int",  # an input register
        (swapped.FixtureSwappedDrive, "read_legacy_mode"): "DriveMode | Unlisted",  # a value the enum does not list is Unlisted
        (swapped.FixtureSwappedDrive, "read_status"): "StatusBits",
        (swapped.FixtureSwappedDrive, "read_runtime_hours"): "float",  # f64
    }
    for (cls, method), annotation in returns.items():
        assert getattr(cls, method).__annotations__["return"] == annotation, (cls.__name__, method)
    writes = {
        (power.FixturePowerMeter, "write_meter_label"): "str",
        (power.FixturePowerMeter, "write_demand_period"): "float",
        (remote.FixtureRemoteIo, "write_alarm_output"): "bool",
        (remote.RelayElement, "write_on"): "bool",
        (swapped.FixtureSwappedDrive, "write_legacy_mode"): "DriveMode | Literal['idle', 'speed', 'position']",
    }
    for (cls, method), annotation in writes.items():
        assert getattr(cls, method).__annotations__["value"] == annotation, (cls.__name__, method)
    for cls, method in (
        (power.FixturePowerMeter, "write_voltage_l1"),  # input register
        (power.FixturePowerMeter, "write_model_name"),  # read-only
        (remote.FixtureRemoteIo, "write_analog_in_9"),
        (remote.InputElement, "write_active"),  # discrete input
        (power.AsyncFixturePowerMeter, "write_voltage_l1"),
    ):
        assert not hasattr(cls, method), (cls.__name__, method)
    assert type(power.VOLTAGE_L1).__name__ == "ReadOnly" and type(remote.ALARM_OUTPUT).__name__ == "ReadWrite"


def test_generated_docstrings_say_space_order_gate_and_poll() -> None:
    """A register is documented once, under its constant; each of its methods names the constant and the title."""
    generated_python()
    power, remote, swapped = (importlib.import_module(d) for d in (POWER, REMOTE, SWAPPED))
    docs = {
        (power.FixturePowerMeter.read_current_l1, "CURRENT_L1"): ("input register, address 0x0002", "f32, byte order CDAB", "poll fast"),
        (power.FixturePowerMeter.read_thd_voltage_l1, "THD_VOLTAGE_L1"): ("byte order ABCD", "exists with firmware >= 2.00"),
        (power.FixturePowerMeter.read_active_energy, "ACTIVE_ENERGY"): ("u64, byte order ABCDEFGH", "poll slow"),
        (power.FixturePowerMeter.read_serial_number, "SERIAL_NUMBER"): ("6 words (12 bytes of ascii, space padded)", "poll static"),
        (remote.FixtureRemoteIo.read_alarm_output, "ALARM_OUTPUT"): ("coil, address 0x00AC",),
        (remote.InputElement.read_active, "INPUT[n].active"): ("discrete input",),
        (swapped.FixtureSwappedDrive.read_position, "POSITION"): ("s32, byte order DCBA",),
        (swapped.FixtureSwappedDrive.read_gain, "GAIN"): ("f32, byte order CDAB",),
        (swapped.FixtureSwappedDrive.read_speed, "SPEED"): ("s16, byte order BA",),
        (swapped.FixtureSwappedDrive.read_label, "LABEL"): ("bytes swapped in each word",),
        (swapped.FixtureSwappedDrive.read_legacy_mode, "LEGACY_MODE"): ("exists with firmware < 2.0",),
    }
    for (method, constant), phrases in docs.items():
        module = sys.modules[method.__module__]
        # An array member's constant is each element's own (INPUT[n].active is INPUT_<n>_ACTIVE); the first element's stands for them.
        array, _, member = constant.partition("[n].")
        defined = f"{array}_{min(getattr(module, array))}_{member.upper()}" if member else constant
        text = docstrings.constant_docs(module)[defined]
        for phrase in phrases:
            assert phrase in text, (defined, phrase, text)
        assert (method.__doc__ or "").startswith(f"Read {constant}: "), (method.__qualname__, method.__doc__)
        assert phrases[0] not in (method.__doc__ or ""), f"{method.__qualname__} repeats its constant's docstring"
    assert "check_firmware=True" in (power.FixturePowerMeter.__doc__ or "")
    assert "check_firmware" not in (remote.FixtureRemoteIo.__doc__ or "")


def test_misuse_of_the_generated_fixture_clients_does_not_type_check(tmp_path: Path) -> None:
    python = generated_python()
    program = tmp_path / "misuse.py"
    program.write_text(
        "from fixture_power_meter import FixturePowerMeter, VOLTAGE_L1\n"
        "from fixture_remote_io import FixtureRemoteIo\n"
        "def f(m: FixturePowerMeter, io: FixtureRemoteIo) -> None:\n"
        "    m.write(VOLTAGE_L1, 1.0)\n"
        "    m.write_voltage_l1(1.0)\n"
        "    n: int = m.read_voltage_l1()\n"
        "    m.write_meter_label(5)\n"
        "    io.input(197).write_active(True)\n"
        "    s: str = io.read_alarm_output()\n",
        encoding="utf-8",
    )
    result = mypy_strict(str(program), cwd=python)
    assert result.returncode == 1
    for complaint in (
        'incompatible type "ReadOnly[float]"',
        '"FixturePowerMeter" has no attribute "write_voltage_l1"',
        'Incompatible types in assignment (expression has type "float", variable has type "int")',
        'Argument 1 to "write_meter_label" of "FixturePowerMeter" has incompatible type "int"; expected "str"',
        '"InputElement" has no attribute "write_active"',
        'Incompatible types in assignment (expression has type "bool", variable has type "str")',
    ):
        assert complaint in result.stdout, (complaint, result.stdout)
