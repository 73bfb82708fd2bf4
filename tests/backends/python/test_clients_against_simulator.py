"""The fixture maps' clients (built from the map at run time, and the generated modules) against
`regmap simulate`: every table, type and order written and read back, the simulator's words checked
with `struct` (not with regmap's codec), firmware gates against the simulator's --firmware.

test_clients_against_libmodbus.py runs the same clients against a libmodbus server, an implementation regmap
did not write; this file shows the simulator and the clients agree with each other and with struct."""

from __future__ import annotations

import struct
from typing import Any

import pytest

from conftest import FIXTURE_MAPS, SimulatorFactory
from support.fixture_clients import FLAVOURS, POWER, REMOTE, SWAPPED, flavour, read, write

PATHS = {p.stem: p for p in FIXTURE_MAPS}


def words(fmt: str, value: Any) -> list[int]:
    """Big-endian words of one value (ABCD), by struct."""
    data = struct.pack(">" + fmt, value)
    return [int.from_bytes(data[i : i + 2], "big") for i in range(0, len(data), 2)]


def swap(ws: list[int]) -> list[int]:
    return [((w & 0xFF) << 8) | (w >> 8) for w in ws]


@pytest.mark.parametrize("kind", FLAVOURS)
def test_power_meter_round_trips_through_the_simulator(kind: str, simulator: SimulatorFactory) -> None:
    f = flavour(kind, POWER)
    sim = simulator(PATHS["power_meter"], "--firmware", "2.00")  # read_all reads the power-quality registers of 2.00
    client, _ = f.client(sim.port or 0)
    with client:
        values = client.read_all()
        assert type(values["voltage_l1"]) is float and type(values["model_name"]) is str
        assert type(values["active_energy"]) is float  # a u64 counter x 0.001
        assert values["demand_period"] == 900.0 and values["ct_ratio"] == 1  # the map's defaults
        write(f, client, "demand_period", 120.5)
        write(f, client, "voltage_alarm", 250.25)
        write(f, client, "ct_ratio", 50)
        write(f, client, "meter_label", "Hall 3")
        assert client.read_raw(0x0122, 2) == words("f", 120.5)  # ABCD
        assert client.read_raw(0x0124, 2) == words("f", 250.25)[::-1]  # CDAB: the map's word_order low_first
        assert client.read_raw(0x0126, 4) == words("8s", b"Hall 3\0\0")
        assert read(f, client, "demand_period") == 120.5 and read(f, client, "voltage_alarm") == 250.25
        assert read(f, client, "meter_label") == "Hall 3" and read(f, client, "ct_ratio") == 50
        with pytest.raises(ValueError, match="the register holds 8"):
            write(f, client, "meter_label", "nine char")  # 9 bytes; the register holds 8
        assert read(f, client, "meter_label") == "Hall 3"


@pytest.mark.parametrize("kind", FLAVOURS)
def test_remote_io_coils_through_the_simulator(kind: str, simulator: SimulatorFactory) -> None:
    f = flavour(kind, REMOTE)
    sim = simulator(PATHS["remote_io"])
    client, _ = f.client(sim.port or 0)
    bits = [1, 0, 1, 1, 0, 0, 1, 1, 1, 0]  # MBAP §6.11's CD 01 for coils 20..29
    with client:
        client.write_many({f.spec(f"relay_{20 + i}_on"): bool(b) for i, b in enumerate(bits)})
        write(f, client, "alarm_output", True)
        assert client.read_raw(0x13, 10, space="coil") == bits
        assert [read(f, client, f"relay_{20 + i}_on") for i in range(10)] == [bool(b) for b in bits]
        assert read(f, client, "alarm_output") is True
        assert all(type(v) is bool for k, v in client.read_all().items() if k.startswith(("relay", "input")))
        with pytest.raises(f.errors.AccessError):
            client.write(f.spec("input_197_active"), True)


@pytest.mark.parametrize("kind", FLAVOURS)
def test_the_swapped_drive_and_its_firmware_gates(kind: str, simulator: SimulatorFactory) -> None:
    f = flavour(kind, SWAPPED)
    old = simulator(PATHS["swapped_gated"], "--firmware", "1.9")
    client, _ = f.client(old.port or 0, check_firmware=True)
    with client:
        assert client.firmware == (1, 9)
        write(f, client, "position", 0x12345678)
        assert client.read_raw(0x0003, 2) == swap(words("i", 0x12345678))[::-1]  # DCBA: little-endian on the wire
        write(f, client, "gain", 2.5)
        assert client.read_raw(0x0005, 2) == words("f", 2.5)[::-1]  # the register's own byte order: CDAB
        write(f, client, "speed", -12.5)
        assert client.read_raw(0x0002, 1) == swap(words("h", -125))
        assert read(f, client, "legacy_mode") is not None  # until 2.0: present in 1.9
        with pytest.raises(f.errors.FirmwareError, match="torque_limit"):
            read(f, client, "torque_limit")
        assert "runtime_hours" not in client.read_all()
    new = simulator(PATHS["swapped_gated"], "--firmware", "2.5")
    client, _ = f.client(new.port or 0, check_firmware=True)
    with client:
        assert client.firmware == (2, 5)
        assert read(f, client, "runtime_hours") == 0.0 and read(f, client, "torque_limit") == 100
        with pytest.raises(f.errors.FirmwareError, match="legacy_mode"):
            write(f, client, "legacy_mode", 1)
