"""The Structured Text plant files: per device instance its slave id and turnaround, per bus its line settings and
its poll table as an ARRAY OF STRUCT constant, in the line order the Python plant client polls
(`runtime_bridge.plant_schedule`). The constructs are the same in IEC 61131-3 (matiec) and CODESYS: one text."""

from __future__ import annotations

from regmap.backends.st.names import StIdentifier
from regmap.diagnostics import UsageError
from regmap.plant import Plant
from regmap.records import dataclass
from regmap.render import plant_header_lines, st_comment, templates
from regmap.runtime_bridge import microseconds, plant_schedule
from regmap.target import Files

# The poll row's members: (name, type, what it holds); a row's values are given in this order.
ROW = (
    ("DEVICE", "USINT", "the device's index: the constant <PLANT>_DEVICE_<NAME>"),
    ("SLAVE", "USINT", "slave id (the unit id on TCP)"),
    ("FUNCTION_CODE", "USINT", "Modbus read function code"),
    ("START_ADDR", "UINT", "first register or bit address"),
    ("COUNT", "UINT", "registers or bits"),
)


@dataclass(frozen=True)
class Constant:
    name: str
    type: str
    value: str
    comment: str


@dataclass(frozen=True)
class PollTable:
    comment: str
    table_type: str
    last: int
    name: str
    rows: tuple[str, ...]  # each row's initialiser, already ST


def _us(seconds: float) -> str:
    return str(microseconds(seconds))


class _Names:
    def __init__(self, plant: Plant) -> None:
        self.plant = plant
        self.seen: set[str] = set()

    def __call__(self, *parts: str) -> str:
        name = StIdentifier(self.plant.id, *parts)
        if name.problem:
            raise UsageError(f"{self.plant.source_path}: {name.problem}")
        if name in self.seen:
            raise UsageError(f"{self.plant.source_path}: the ST plant files would declare {name} twice; rename a bus or device")
        self.seen.add(name)
        return name


def plant_context(plant: Plant) -> dict[str, object]:
    name = _Names(plant)
    row_type = "ST_" + name("POLL_ROW")
    constants: list[Constant] = []
    index_of: dict[str, str] = {}
    for index, dev in enumerate(plant.devices):
        bus, _ = plant.device(dev.name)
        baud = bus.serial.baud if bus.serial is not None else None
        what = st_comment(
            f"{dev.title or dev.name}: {dev.device.info.vendor} {dev.device.info.model} on bus {bus.name} ({dev.device.id}_constants.st)"
            + (f", variant {dev.variant}: its poll rows read only that variant's registers" if dev.variant else "")
        )
        index_of[dev.name] = str(index)
        constants += [
            Constant(name("DEVICE", dev.name), "USINT", str(index), what),
            Constant(name(dev.name, "SLAVE"), "USINT", str(dev.slave), "slave id (the unit id on TCP)"),
            Constant(name(dev.name, "TURNAROUND_US"), "UDINT", _us(dev.turnaround_s(baud)), "the device's turnaround, microseconds"),
        ]
    tables: list[PollTable] = []
    for schedule in plant_schedule(plant):
        bus = schedule.bus
        if bus.serial is not None:
            line = bus.serial
            cycle = schedule.cycle_s
            assert cycle is not None
            constants += [
                Constant(name(bus.name, "BAUD"), "UDINT", str(line.baud), f"bus {bus.name}: baud rate"),
                Constant(name(bus.name, "PARITY"), "STRING", f"'{line.parity}'", "parity"),
                Constant(name(bus.name, "DATA_BITS"), "USINT", str(line.data_bits), "data bits"),
                Constant(name(bus.name, "STOP_BITS"), "USINT", str(line.stop_bits), "stop bits"),
                Constant(
                    name(bus.name, "SILENCE_US"), "UDINT", _us(line.silence_s), "inter-frame silence before each request, microseconds"
                ),
                Constant(name(bus.name, "CYCLE_US"), "UDINT", _us(cycle), "the whole poll cycle's line time at worst, microseconds"),
            ]
            where = f"serial {line.port}, {line.baud} baud, parity {line.parity}"
        else:
            assert bus.tcp is not None
            constants.append(Constant(name(bus.name, "TCP_PORT"), "UINT", str(bus.tcp.port), f"bus {bus.name}: Modbus TCP port"))
            where = f"Modbus TCP {bus.tcp.host}:{bus.tcp.port}"
        constants.append(Constant(name(bus.name, "POLL_LEN"), "UINT", str(len(schedule.entries)), "requests a cycle"))
        rows = tuple(
            "("
            + ", ".join(
                f"{member} := {value}"
                for (member, _, _), value in zip(
                    ROW,
                    (index_of[e.device.name], str(e.slave), f"16#{e.function:02X}", f"16#{e.start:04X}", str(e.count)),
                    strict=True,
                )
            )
            + ")"
            for e in schedule.entries
        )
        tables.append(
            PollTable(
                comment=st_comment(f"Bus {bus.name}: {where}; the poll cycle in line order ({len(rows)} requests)"),
                table_type="ST_" + name(bus.name, "POLL_TABLE"),
                last=len(rows) - 1,
                name=name(bus.name, "POLL"),
                rows=rows,
            )
        )
    return {
        "header": [st_comment(line) for line in plant_header_lines(plant, f"regmap generate {plant.source_path}")],
        "title": st_comment(plant.title or plant.id),
        "row_type": row_type,
        "members": ROW,
        "constants": constants,
        "tables": [t for t in tables if t.rows],
    }


def render_plant(plant: Plant) -> Files:
    env = templates(__name__)
    context = plant_context(plant)
    return {
        f"{plant.id}_plant/{plant.id}_plant_{kind}.st": env.get_template(f"plant_{kind}.st.jinja").render(**context)
        for kind in ("types", "constants")
    }
