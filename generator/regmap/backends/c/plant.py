"""The C plant header `<plant>_plant.h`: per bus its line settings and its poll table (device, slave, function,
start, count) in line order, the order the Python plant client polls (`runtime_bridge.plant_schedule`)."""

from __future__ import annotations

from typing import Any

from regmap.backends.c.names import CIdentifier, CSymbol, c_hex, c_unsigned
from regmap.diagnostics import UsageError
from regmap.plant import Plant
from regmap.records import dataclass
from regmap.render import c_comment, plant_header_lines, templates
from regmap.runtime_bridge import BusSchedule, microseconds, plant_schedule
from regmap.target import Files


def _registers(registers: tuple[Any, ...]) -> str:
    """A block's registers as the device headers' read plans name them: the first, the last and how many."""
    names = [spec.param or spec.name for spec in registers]
    return names[0] if len(names) == 1 else f"{names[0]} .. {names[-1]} ({len(names)} registers)"


def _us(seconds: float) -> str:
    return c_unsigned(microseconds(seconds))


@dataclass(frozen=True)
class DeviceMacros:
    index: str  # <PLANT>_DEVICE_<NAME>
    index_value: str
    slave: str
    slave_value: str
    turnaround: str
    turnaround_value: str
    comment: str


@dataclass(frozen=True)
class BusTable:
    comment: str
    settings: tuple[tuple[str, str, str], ...]  # (macro, value, comment)
    length: str
    length_value: str
    table: str
    rows: tuple[tuple[str, str, str, str, str, str], ...]  # device macro, slave, function, start, count, comment


def _bus_table(plant: Plant, schedule: BusSchedule, indexes: dict[str, str], names: set[str]) -> BusTable:
    bus = schedule.bus

    def macro(*parts: str) -> str:
        name = CIdentifier(plant.id, *parts)
        if name in names:
            raise UsageError(f"{plant.source_path}: the C plant header would define {name} twice; rename a bus or device")
        names.add(name)
        return name

    settings: list[tuple[str, str, str]] = []
    if bus.serial is not None:
        line = bus.serial
        settings += [
            (macro(bus.name, "BAUD"), c_unsigned(line.baud), "baud rate"),
            (macro(bus.name, "DATA_BITS"), c_unsigned(line.data_bits), "data bits"),
            (macro(bus.name, "PARITY"), f"'{line.parity[0].upper()}'", f"parity {line.parity}"),
            (macro(bus.name, "STOP_BITS"), c_unsigned(line.stop_bits), "stop bits"),
            (macro(bus.name, "SILENCE_US"), _us(line.silence_s), "inter-frame silence before each request, microseconds"),
        ]
        cycle = schedule.cycle_s
        assert cycle is not None
        settings.append((macro(bus.name, "CYCLE_US"), _us(cycle), "the whole poll cycle's line time at worst, microseconds"))
        where = f"serial {line.port}, {line.baud} baud, parity {line.parity}"
    else:
        assert bus.tcp is not None
        settings.append((macro(bus.name, "TCP_PORT"), c_unsigned(bus.tcp.port), f"Modbus TCP port of {bus.tcp.host}"))
        where = f"Modbus TCP {bus.tcp.host}:{bus.tcp.port}"
    rows = tuple(
        (
            indexes[entry.device.name],
            c_unsigned(entry.slave),
            f"0x{entry.function:02X}u",
            c_hex(entry.start),
            c_unsigned(entry.count),
            c_comment(f"{entry.device.name}: {_registers(entry.block.registers)}"),
        )
        for entry in schedule.entries
    )
    return BusTable(
        comment=c_comment(f"Bus {bus.name}: {where}; {len(rows)} requests a cycle, in line order"),
        settings=tuple(settings),
        length=macro(bus.name, "POLL_LEN"),
        length_value=c_unsigned(len(rows)),
        table=CSymbol(plant.id, bus.name, "poll"),
        rows=rows,
    )


def plant_header(plant: Plant) -> str:
    names: set[str] = set()
    devices = []
    indexes: dict[str, str] = {}
    for index, dev in enumerate(plant.devices):
        bus, _ = plant.device(dev.name)
        baud = bus.serial.baud if bus.serial is not None else None
        view = DeviceMacros(
            index=CIdentifier(plant.id, "DEVICE", dev.name),
            index_value=c_unsigned(index),
            slave=CIdentifier(plant.id, dev.name, "SLAVE"),
            slave_value=c_unsigned(dev.slave),
            turnaround=CIdentifier(plant.id, dev.name, "TURNAROUND_US"),
            turnaround_value=_us(dev.turnaround_s(baud)),
            comment=c_comment(
                f"{dev.title or dev.name}: {dev.device.info.vendor} {dev.device.info.model} ({dev.map_path}, header {dev.device.id}.h) on bus {bus.name}"
                + (f", variant {dev.variant}: its poll rows read only that variant's registers" if dev.variant else "")
            ),
        )
        for name in (view.index, view.slave, view.turnaround):
            if name in names:
                raise UsageError(f"{plant.source_path}: the C plant header would define {name} twice; rename a bus or device")
            names.add(name)
        indexes[dev.name] = view.index
        devices.append(view)
    buses = [_bus_table(plant, schedule, indexes, names) for schedule in plant_schedule(plant)]
    return (
        templates(__name__)
        .get_template("plant.h.jinja")
        .render(
            header=[c_comment(line) for line in plant_header_lines(plant, f"regmap generate {plant.source_path}")],
            title=c_comment(plant.title or plant.id),
            guard=CIdentifier("REGMAP", plant.id, "PLANT_H"),
            implementation=CIdentifier(plant.id, "PLANT_IMPLEMENTATION"),
            implemented=CIdentifier("REGMAP", plant.id, "PLANT_IMPLEMENTED"),
            poll_type=CSymbol(plant.id, "poll"),
            file=plant_file(plant),
            device_prefix=CIdentifier(plant.id, "DEVICE") + "_",
            device_count=CIdentifier(plant.id, "DEVICE_COUNT"),
            device_count_value=c_unsigned(len(devices)),
            devices=devices,
            buses=buses,
        )
    )


def plant_file(plant: Plant) -> str:
    return f"{plant.id}_plant.h"


def render_plant(plant: Plant) -> Files:
    return {plant_file(plant): plant_header(plant)}
