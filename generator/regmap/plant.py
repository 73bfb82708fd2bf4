"""The plant model: buses and the devices on them, each device a map at a slave id.

A plant file (`format: regmap-plant/1`, docs/plants.md) names the buses of an installation — an RS-485
line or a Modbus TCP gateway — and the devices on each. `regmap.frontend.plant.load_plant` checks it
and returns a frozen `Plant`; the back ends that render plants (`Target.plant`) receive it whole.
"""

from __future__ import annotations

from dataclasses import field
from functools import cached_property

from regmap.model import Device, SourcePos
from regmap.records import dataclass

PLANT_FORMAT = "regmap-plant/1"


@dataclass(frozen=True)
class SerialLine:
    """An RS-485 line as the bus master drives it: every device on it must accept these settings."""

    port: str
    baud: int
    parity: str  # none, even, odd
    data_bits: int = 8
    stop_bits: int = 1

    @property
    def character_bits(self) -> int:
        """Bits on the wire per character: start, data, parity, stop."""
        return 1 + self.data_bits + (0 if self.parity == "none" else 1) + self.stop_bits

    @property
    def silence_s(self) -> float:
        """The RTU inter-frame silence (3.5 characters); 1.75 ms above 19200 baud, as the serial line spec fixes it."""
        return 0.00175 if self.baud > 19200 else 3.5 * self.character_bits / self.baud


@dataclass(frozen=True)
class TcpLine:
    """A Modbus TCP endpoint, typically a gateway to an RS-485 line: the slave id travels as the unit id."""

    host: str
    port: int = 502


@dataclass(frozen=True)
class PlantDevice:
    """One device instance: its name (the prefix of every generated name), its map, its slave id and, when its
    map declares variants, the one it is (None: not said, so every variant's registers are its)."""

    name: str
    title: str
    map_path: str  # as the plant file writes it, relative to the plant file
    device: Device
    slave: int
    notes: str = ""
    variant: str | None = None
    pos: SourcePos | None = field(default=None, compare=False, repr=False)

    @property
    def variants(self) -> tuple[str, ...]:
        """The variants a read plan of this device serves (`runtime_bridge.read_plan(variants=...)`): its own, or () for any."""
        return () if self.variant is None else (self.variant,)

    def turnaround_s(self, baud: int | None = None) -> float:
        """How long the device may take to answer, as its map records it: the timing row of `baud` when the
        map has one, else the longest it records (0 when it records none)."""
        t = self.device.transport
        rows = [row.total_ms for row in t.timing if row.total_ms is not None and (baud is None or row.baud == baud)]
        if not rows:
            rows = [row.total_ms for row in t.timing if row.total_ms is not None]
        if t.response_delay_ms is not None:
            rows.append(t.response_delay_ms)
        return max(rows, default=0.0) / 1000


@dataclass(frozen=True)
class Bus:
    name: str
    devices: tuple[PlantDevice, ...]
    serial: SerialLine | None = None
    tcp: TcpLine | None = None
    notes: str = ""
    pos: SourcePos | None = field(default=None, compare=False, repr=False)

    @property
    def kind(self) -> str:
        return "serial" if self.serial is not None else "tcp"

    def device(self, name: str) -> PlantDevice:
        for dev in self.devices:
            if dev.name == name:
                return dev
        raise KeyError(name)


@dataclass(frozen=True)
class Plant:
    id: str
    title: str
    buses: tuple[Bus, ...]
    source_path: str
    fingerprint: str
    notes: str = ""

    def bus(self, name: str) -> Bus:
        for bus in self.buses:
            if bus.name == name:
                return bus
        raise KeyError(name)

    @property
    def devices(self) -> tuple[PlantDevice, ...]:
        """Every device instance, bus by bus, in the order the plant file lists them."""
        return tuple(dev for bus in self.buses for dev in bus.devices)

    def device(self, name: str) -> tuple[Bus, PlantDevice]:
        for bus in self.buses:
            for dev in bus.devices:
                if dev.name == name:
                    return bus, dev
        raise KeyError(name)

    @cached_property
    def maps(self) -> tuple[Device, ...]:
        """Each distinct map once (two drives of one model share it), in first-use order."""
        seen: dict[str, Device] = {}
        for dev in self.devices:
            seen.setdefault(dev.device.source_path, dev.device)
        return tuple(seen.values())
