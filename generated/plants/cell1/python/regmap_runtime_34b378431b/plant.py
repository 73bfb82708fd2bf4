"""A plant's bus at run time: one pymodbus connection, the typed clients of the devices on it, and one
`read_all()` that polls them interleaved (`line.interleave`) while a serial line keeps its timing (`line.PacedLine`).

Each device client is its generated class bound to its slave id on the shared connection, so every rule of
the single-device client holds unchanged: value checks, retries of reads and settings only, OutcomeUnknown
for a lost answer to a command, confirm for destructive commands.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Mapping
from typing import Any, TypeVar

from pymodbus import FramerType
from pymodbus.client import ModbusSerialClient, ModbusTcpClient

from .client import SyncClient
from .errors import ConnectionLost
from .line import PacedLine, interleave
from .plan import ReadBlock
from .wire import PARITY, LineWatch

C = TypeVar("C", bound=SyncClient)


class PlantBus:
    """One bus of a plant: its connection, its line hook and the device clients on it, in the plant file's order."""

    def __init__(self, name: str, modbus: ModbusSerialClient | ModbusTcpClient, line: LineWatch) -> None:
        self.name = name
        self.modbus = modbus
        self.line = line
        self.clients: dict[str, SyncClient] = {}

    @classmethod
    def serial(
        cls,
        name: str,
        port: str,
        *,
        baud: int,
        parity: str,
        data_bits: int,
        stop_bits: int,
        silence_s: float,
        turnaround_s: Mapping[int, float],
        timeout: float = 1.0,
        clock: Callable[[], float] = time.monotonic,
        sleep: Callable[[float], None] = time.sleep,
    ) -> PlantBus:
        """An RS-485 line: every request waits for the inter-frame silence and the last addressed device's turnaround."""
        character_bits = 1 + data_bits + (0 if parity == "none" else 1) + stop_bits
        line = PacedLine(silence_s, turnaround_s, character_bits=character_bits, baud=baud, clock=clock, sleep=sleep)
        modbus = ModbusSerialClient(
            port,
            baudrate=baud,
            parity=PARITY[parity],
            bytesize=data_bits,
            stopbits=stop_bits,
            timeout=timeout,
            retries=0,
            trace_packet=line,
        )
        return cls(name, modbus, line)

    @classmethod
    def tcp(cls, name: str, host: str, port: int = 502, *, timeout: float = 1.0) -> PlantBus:
        """A Modbus TCP gateway or device: the slave id travels as the unit id; the gateway keeps the serial timing."""
        line = LineWatch(rtu_framing=False)
        modbus = ModbusTcpClient(host, port=port, framer=FramerType.SOCKET, timeout=timeout, retries=0, trace_packet=line)
        return cls(name, modbus, line)

    def attach(self, name: str, client: C) -> C:
        """Keep a device client (built on this bus's connection and line) under its plant name."""
        if client.modbus is not self.modbus:
            raise ValueError(f"{name}: the client is not on bus {self.name}'s connection")
        self.clients[name] = client
        return client

    def connect(self) -> None:
        if not self.modbus.connect():
            raise ConnectionLost(f"bus {self.name}: cannot connect to {next(iter(self.clients.values())).where if self.clients else '?'}")
        self.detect_firmware()

    def detect_firmware(self) -> None:
        """Read the firmware of each device that checks it (its plan depends on it), before the first poll."""
        for client in self.clients.values():
            if client.firmware_pending:
                client.detect_firmware()

    def close(self) -> None:
        self.modbus.close()  # type: ignore[no-untyped-call]

    def schedule(self) -> list[tuple[str, ReadBlock]]:
        """Every device's read plan, interleaved in line order: (device name, block)."""
        names = list(self.clients)
        plans = [client.plan_reads(client.readable()) for client in self.clients.values()]
        return [(names[index], block) for index, block in interleave(plans)]

    def read_all(self) -> dict[str, dict[str, Any]]:
        """Every readable register of every device on the bus, device name -> register name -> value."""
        self.detect_firmware()
        values: dict[str, dict[str, Any]] = {name: {} for name in self.clients}
        for name, block in self.schedule():
            client = self.clients[name]
            words = client.read_raw(block.address, block.count, space=block.space)
            values[name].update(client.values_of(block, words))
        return values
