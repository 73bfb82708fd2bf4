"""The simulator serves f16 registers: a half's default as its one word, a written half kept, and a write of a
half outside the register's range (or infinity, NaN) refused with illegal data value, as the map says."""

from __future__ import annotations

from pathlib import Path

from pymodbus.client import ModbusTcpClient

from conftest import SimulatorFactory
from support.half_map import half_bits, write_half_map


def test_the_simulator_serves_and_checks_half_floats(simulator: SimulatorFactory, tmp_path: Path) -> None:
    sim = simulator(write_half_map(tmp_path))
    assert sim.port is not None
    client = ModbusTcpClient("127.0.0.1", port=sim.port, timeout=2)
    assert client.connect()  # type: ignore[no-untyped-call]
    try:
        held = client.read_holding_registers(0x0100, count=1, device_id=1)
        assert not held.isError() and held.registers == [half_bits(21.5)]  # the default
        assert not client.write_register(0x0100, half_bits(24.5), device_id=1).isError()
        assert client.read_holding_registers(0x0100, count=1, device_id=1).registers == [half_bits(24.5)]
        for refused in (half_bits(30.5), half_bits(4.5), 0x7C00, 0x7E00):  # above, below, infinity, NaN
            answer = client.write_register(0x0100, refused, device_id=1)
            assert answer.isError() and answer.exception_code == 0x03, hex(refused)
        assert not client.write_register(0x0101, half_bits(2.0), device_id=1).isError()  # fan mode high
        answer = client.write_register(0x0101, half_bits(2.5), device_id=1)  # no member
        assert answer.isError() and answer.exception_code == 0x03
        assert client.read_holding_registers(0x0100, count=2, device_id=1).registers == [half_bits(24.5), half_bits(2.0)]
    finally:
        client.close()  # type: ignore[no-untyped-call]
