"""The plant page `<plant>_plant.md`: buses and their line settings, the devices and their slave ids with the wiring
notes, each device's page linked (the device pages are written beside it), and each bus's poll order with the
line's timing budget per cycle, every number computed here (`runtime_bridge.plant_schedule`)."""

from __future__ import annotations

from regmap.backends.markdown import text as md
from regmap.backends.markdown.page import render_device
from regmap.core.decoding import FUNCTION_NAMES
from regmap.plant import Plant
from regmap.records import dataclass
from regmap.render import md_text, plant_header_lines, templates
from regmap.runtime_bridge import BusSchedule, plant_schedule
from regmap.target import Files


def _ms(seconds: float) -> str:
    return f"{seconds * 1000:.2f} ms"


@dataclass(frozen=True)
class DeviceRow:
    name: md.Md
    title: md.Md
    map: md.Md  # the device page's link
    slave: int
    turnaround: str
    requests: int
    line_time: str
    notes: md.Md


@dataclass(frozen=True)
class PollRow:
    number: int
    device: md.Md
    slave: int
    function: md.Md
    start: str
    count: int
    line_time: str


@dataclass(frozen=True)
class BusView:
    anchor: str
    heading: md.Md
    settings: tuple[tuple[str, md.Md], ...]
    notes: md.Md
    devices: tuple[DeviceRow, ...]
    poll: tuple[PollRow, ...]
    budget: md.Md


def _bus_view(schedule: BusSchedule) -> BusView:
    bus = schedule.bus
    settings: list[tuple[str, md.Md]] = []
    baud = None
    if bus.serial is not None:
        line = bus.serial
        baud = line.baud
        settings += [
            ("Line", md.Md("RS-485, Modbus RTU")),
            ("Port", md.escaped(line.port)),
            ("Baud rate", md.Md(str(line.baud))),
            ("Parity", md.Md(line.parity)),
            ("Data bits / stop bits", md.Md(f"{line.data_bits} / {line.stop_bits}")),
            ("Character", md.Md(f"{line.character_bits} bits ({line.character_bits / line.baud * 1e6:.0f} µs)")),
            (
                "Inter-frame silence",
                md.Md(f"{_ms(line.silence_s)} (3.5 characters{', fixed above 19200 baud' if line.baud > 19200 else ''})"),
            ),
        ]
    else:
        assert bus.tcp is not None
        settings += [
            ("Line", md.Md("Modbus TCP (the slave id travels as the unit id)")),
            ("Host", md.escaped(f"{bus.tcp.host}:{bus.tcp.port}")),
        ]
    times = {id(entry): schedule.exchange_s(entry) for entry in schedule.entries}
    devices = []
    for dev in bus.devices:
        mine = [e for e in schedule.entries if e.device is dev]
        spent = [times[id(e)] for e in mine]
        info = dev.device.info
        devices.append(
            DeviceRow(
                name=md.code(dev.name),
                title=md.escaped(dev.title),
                map=md.Md(
                    f"[{md.DocId(dev.device.id)}]({md.DocId(dev.device.id)}.md) ({md_text(info.vendor)} {md_text(info.model)})"
                    + (f", variant {md.code(dev.variant)}" if dev.variant else "")
                ),
                slave=dev.slave,
                turnaround=_ms(dev.turnaround_s(baud)),
                requests=len(mine),
                line_time=md.DASH if any(t is None for t in spent) else _ms(sum(t for t in spent if t is not None)),
                notes=md.escaped(dev.notes) if dev.notes else md.Md(md.DASH),
            )
        )
    poll = tuple(
        PollRow(
            number=n,
            device=md.code(e.device.name),
            slave=e.slave,
            function=md.Md(f"0x{e.function:02X} {md_text(FUNCTION_NAMES.get(e.function, ''))}".rstrip()),
            start=md.hex_value(e.start),
            count=e.count,
            line_time=md.DASH if (t := times[id(e)]) is None else _ms(t),
        )
        for n, e in enumerate(schedule.entries, start=1)
    )
    cycle = schedule.cycle_s
    if cycle is None:
        budget = md.Md(f"{len(poll)} requests a cycle; on Modbus TCP the gateway keeps the serial line's timing.")
    else:
        budget = md.Md(
            f"{len(poll)} requests a cycle take at most **{_ms(cycle)}** of line time: each is the request (8 bytes), the"
            " device's turnaround, its answer and the inter-frame silence. The devices are polled in turn, one block"
            " each, so a device waits at most one block of every other device between two of its own."
        )
    return BusView(
        anchor=md.anchor("bus", bus.name),
        heading=md.code(bus.name),
        settings=tuple(settings),
        notes=md.paragraph(bus.notes) if bus.notes else md.Md(""),
        devices=tuple(devices),
        poll=poll,
        budget=budget,
    )


def plant_page(plant: Plant) -> str:
    return (
        templates(__name__)
        .get_template("plant.md.jinja")
        .render(
            header=[md.html_comment(line) for line in plant_header_lines(plant, f"regmap generate {plant.source_path}")],
            title=md.escaped(plant.title or plant.id),
            plant_id=md.code(plant.id),
            source=md.escaped(plant.source_path),
            notes=md.paragraph(plant.notes) if plant.notes else md.Md(""),
            buses=[_bus_view(schedule) for schedule in plant_schedule(plant)],
            bus_count="one bus" if len(plant.buses) == 1 else f"{len(plant.buses)} buses",
        )
    )


def render_plant(plant: Plant) -> Files:
    """The plant page beside the pages of the devices it links."""
    files: Files = {}
    for device in plant.maps:
        files.update(render_device(device))
    files[f"{md.DocId(plant.id)}_plant.md"] = plant_page(plant)
    return files
