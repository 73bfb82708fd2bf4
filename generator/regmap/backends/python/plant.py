"""The Python plant module: one `PlantBus` per bus (one connection each) and every device's typed client as an
attribute, bound to its slave id on its bus's connection; `read_all()` polls each bus in the shared schedule's order."""

from __future__ import annotations

from regmap.backends.python.package import render_shared, runtime_package
from regmap.diagnostics import MapError, at
from regmap.plant import Plant
from regmap.records import dataclass
from regmap.render import plant_header_lines, py_doc, py_str, templates
from regmap.runtime_bridge import plant_schedule
from regmap.target import Files

# The plant class's own names: a device or bus of the same name would shadow them.
PLANT_NAMES = frozenset({"buses", "connect", "close", "read_all", "schedule"})


@dataclass(frozen=True)
class DeviceView:
    attr: str
    client_class: str
    values_class: str
    slave: int
    bus: str
    doc: str
    variant: str  # the client's variant= argument, already a literal ("" when the plant names none)


@dataclass(frozen=True)
class BusView:
    attr: str
    name_literal: str
    serial: bool
    params: tuple[tuple[str, str, str], ...]  # constructor parameters: (name, type, default literal)
    factory_args: str  # the PlantBus.serial / .tcp arguments after the name, already literals
    devices: tuple[DeviceView, ...]
    doc: str


def _check_names(plant: Plant) -> None:
    problems = []
    taken: dict[str, str] = {}
    for bus in plant.buses:
        for name, what, pos in [(bus.name, f"bus {bus.name}", bus.pos)] + [(d.name, f"device {d.name}", d.pos) for d in bus.devices]:
            if name in PLANT_NAMES:
                problems.append(
                    at(plant.source_path, pos, f"{what}: the plant's Python attribute {name!r} would shadow its own {name}(); rename it")
                )
            elif name in taken:
                problems.append(at(plant.source_path, pos, f"{what}: the Python plant has {name!r} already as {taken[name]}; rename one"))
            taken.setdefault(name, what)
    if problems:
        raise MapError(problems)


def _bus_view(plant: Plant, index: int) -> BusView:
    from regmap.backends.python import camel, snapshot_name  # the package imports this module for its TARGET

    bus = plant.buses[index]
    devices = tuple(
        DeviceView(
            attr=dev.name,
            client_class=camel(dev.device.id),
            values_class=snapshot_name(dev.device),
            slave=dev.slave,
            bus=bus.name,
            doc=py_doc(
                f"{dev.title or dev.name}: {dev.device.info.vendor} {dev.device.info.model} at slave {dev.slave} on bus {bus.name}"
                + (f", variant {dev.variant}." if dev.variant else ".")
            ),
            variant=py_str(dev.variant) if dev.variant else "",
        )
        for dev in bus.devices
    )
    if bus.serial is not None:
        line = bus.serial
        turnaround = ", ".join(f"{dev.slave}: {round(dev.turnaround_s(line.baud), 9)!r}" for dev in bus.devices)
        params: tuple[tuple[str, str, str], ...] = ((f"{bus.name}_port", "str", py_str(line.port)),)
        args = (
            f"{bus.name}_port, baud={line.baud}, parity={py_str(line.parity)}, data_bits={line.data_bits},"
            f" stop_bits={line.stop_bits}, silence_s={line.silence_s!r}, turnaround_s={{{turnaround}}},"
            " timeout=timeout, clock=clock, sleep=sleep"
        )
        where = f"serial {line.port}, {line.baud} baud, parity {line.parity}, {line.data_bits} data bits, {line.stop_bits} stop bit(s)"
    else:
        assert bus.tcp is not None
        params = ((f"{bus.name}_host", "str", py_str(bus.tcp.host)), (f"{bus.name}_port", "int", str(bus.tcp.port)))
        args = f"{bus.name}_host, {bus.name}_port, timeout=timeout"
        where = f"Modbus TCP {bus.tcp.host}:{bus.tcp.port}"
    doc = py_doc(f"Bus {bus.name}: {where}; " + ", ".join(f"{d.name} (slave {d.slave})" for d in bus.devices) + ".")
    return BusView(
        attr=bus.name,
        name_literal=py_str(bus.name),
        serial=bus.serial is not None,
        params=params,
        factory_args=args,
        devices=devices,
        doc=doc,
    )


def plant_module(plant: Plant) -> str:
    from regmap.backends.python import camel, snapshot_name  # the package imports this module for its TARGET

    _check_names(plant)
    imported = sorted({(dev.device.id, camel(dev.device.id), snapshot_name(dev.device)) for dev in plant.devices})
    requests = {schedule.bus.name: len(schedule.entries) for schedule in plant_schedule(plant)}
    return (
        templates(__name__)
        .get_template("plant.py.jinja")
        .render(
            header=plant_header_lines(plant, f"regmap generate {plant.source_path}"),
            title=py_doc(f"{plant.title or plant.id}: the plant's buses and device clients"),
            class_name=camel(plant.id),
            values_class=camel(plant.id) + "Values",
            doc=py_doc(plant.notes),
            runtime=runtime_package(),
            imports=imported,
            buses=[_bus_view(plant, index) for index in range(len(plant.buses))],
            requests=requests,
        )
    )


def render_plant(plant: Plant) -> Files:
    """The plant module beside the device packages it uses and the runtime: the directory is importable as it is."""
    from regmap.backends.python import render_device

    files: Files = dict(render_shared(plant.maps))
    for device in plant.maps:
        files.update(render_device(device))
    files[f"{plant.id}_plant.py"] = plant_module(plant)
    return files
