"""The Home Assistant package of one map: a `modbus:` hub with sensors, binary sensors and switches for the
selected registers, and (`scripts`) a `script:` per command and `template:` entities for flags and enum labels.

Home Assistant reads each entity with its own request, except virtual sensors: a run of array
elements of one type, scale and unit at consecutive addresses inside one read-plan request becomes
one sensor with `virtual_count` (one request for the whole run). What HA's modbus integration cannot
express from the map is listed in the file's header instead of being approximated: write-only
registers, multi-bit fields (in the register's sensor), text in encodings other than ASCII/UTF-8 (HA
decodes UTF-8 only). Enum labels and flags other than a lone bit 0 (HA's binary sensor reads `value & 1`
and loads one entity per address) are template entities over the register's sensor; a register with
labels shows its raw code in a sensor named "<title> (code)". A register scaled by another (`scale_from`) is
a raw sensor "<title> (raw)" and a template sensor with its value, a writable one also a set script (`scaled`).

Spaces: `input_type` holding / input for registers; coils and discrete inputs are binary sensors
(`input_type: coil` / `discrete_input`), a writable coil a switch (`write_type: coil`). Byte and word
order: `swap: byte` (bytes inside each word), `word` (words of a wide value), `word_byte` (both); HA
refuses `word` on 16-bit values and text. `scale` then `offset` (value = raw x scale + offset), as HA
applies them. Poll classes: `scan_interval` fast 5 s (HA warns below 5), normal 10 s (settings 300 s),
slow 60 s, static 0 (HA reads the entity once at start-up and never polls it).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from regmap.backends.homeassistant import scaled
from regmap.backends.homeassistant.scripts import RETRY_NOTE, Scripts, flag_sensor, label_sensor, object_id, template_flags, time_sensor
from regmap.core.text import na_mark
from regmap.homeauto.entities import (
    MAX_NAME_BYTES,
    Names,
    device_class,
    dump,
    dump_commented,
    gate_key,
    gate_notes,
    is_parameter,
    on_off,
    planned,
    plant_device_line,
    plant_header_lines,
    refuse_shared_ids,
    reserved,
    scale_float,
    shown_decimals,
    single_flag,
    state_class,
    swap_word,
    swapped,
    unit_text,
)
from regmap.homeauto.selection import DEFAULT_RULE, Selection, for_variant, select
from regmap.homeauto.yamltext import Hex
from regmap.model import DataType, Device, PollClass, Register, WordOrder
from regmap.records import dataclass
from regmap.runtime_bridge import runtime_alignment
from regmap.target import Files

if TYPE_CHECKING:  # only a plant's run imports the plant model (tests/project/test_generate_imports.py)
    from regmap.plant import Bus, Plant, PlantDevice

DATA_TYPE = {
    DataType.U16: "uint16",
    DataType.S16: "int16",
    DataType.U32: "uint32",
    DataType.S32: "int32",
    DataType.U64: "uint64",
    DataType.S64: "int64",
    DataType.F16: "float16",
    DataType.F32: "float32",
    DataType.F64: "float64",
    DataType.STRING: "string",
    DataType.TIMESTAMP: "uint32",
}
HASS_STRUCT = {DataType.U16: "H", DataType.S16: "h", DataType.U32: "I", DataType.S32: "i", DataType.U64: "Q", DataType.S64: "q"}
HASS_STRUCT |= {DataType.F32: "f", DataType.F64: "d"}  # the struct code of a custom sensor that reads a whole aligned unit
INPUT_TYPE = {"holding": "holding", "input": "input", "coil": "coil", "discrete_input": "discrete_input"}
TEXT_ENCODINGS = ("ascii", "utf-8")  # HA decodes a string register's bytes as UTF-8
PARITY = {"none": "N", "even": "E", "odd": "O"}
SCAN_INTERVAL = 10  # seconds, status values
PARAMETER_SCAN_INTERVAL = 300  # seconds, settings (they change only when written)
POLL_SCAN_INTERVAL = {PollClass.FAST: 5, PollClass.SLOW: 60, PollClass.STATIC: 0}  # normal: the two above
PORT = "/dev/ttyUSB0"


def swap_of(reg: Register) -> str | None:
    """HA's `swap` for the register's byte and word order (None: as HA reads by default, ABCD)."""
    words = reg.wide and reg.word_order is WordOrder.LOW_FIRST
    if swapped(reg):
        return "word_byte" if words else "byte"
    return "word" if words else None


def scan_interval(reg: Register) -> int:
    if reg.poll is PollClass.NORMAL:
        return PARAMETER_SCAN_INTERVAL if is_parameter(reg) else SCAN_INTERVAL
    if reg.poll is PollClass.SLOW and is_parameter(reg):
        return PARAMETER_SCAN_INTERVAL
    return POLL_SCAN_INTERVAL[reg.poll]


@dataclass(frozen=True)
class Instance:
    """Where one map's entities live and what keeps them apart from another device's in the same
    configuration: the hub and slave id, the prefix of every unique_id and script id, and of every name."""

    hub: str
    slave: int
    unique_prefix: str  # unique_id = <unique_prefix>_<register>
    script_prefix: str  # script id = <script_prefix>_<command>
    name_prefix: str = ""  # "axis_x " in a plant: HA slugs the name into the entity id


def single_instance(device: Device) -> Instance:
    """The package of one map: its own hub named after it, at the device's usual slave id."""
    t = device.transport
    slave = 1 if t.slave_min <= 1 <= t.slave_max else t.slave_min
    return Instance(hub=device.id, slave=slave, unique_prefix=device.id, script_prefix=device.id)


class _Hub:
    def __init__(self, device: Device, selection: Selection, instance: Instance | None = None) -> None:
        self.device = device
        self.selection = selection
        self.instance = instance or single_instance(device)
        self.names = Names(limit=MAX_NAME_BYTES - len(self.instance.name_prefix.encode()))
        self.slave = self.instance.slave
        codes = device.transport.function_codes
        self.input_type = "holding" if 0x03 in codes else "input"
        self.register_write = "holding" if 0x06 in codes else "holdings"
        self.coil_write = "coil" if 0x05 in codes else "coils"
        self.skipped: list[str] = []
        self.sensors: list[dict[str, Any]] = []
        self.binary_sensors: list[dict[str, Any]] = []
        self.switches: list[dict[str, Any]] = []
        self.template_sensors: list[dict[str, Any]] = []
        self.template_binary_sensors: list[dict[str, Any]] = []
        self.scripts = Scripts(device, self.instance.hub, self.slave, self.instance.script_prefix, self.instance.name_prefix)
        plan = planned(device, [r for r in selection.registers if r.access.readable])
        self.block_of = {s.name: i for i, (block, _, _) in enumerate(plan) for s in block.registers}
        self.alignment = runtime_alignment(device)
        self.aligned_addresses: set[tuple[str, int]] = set()
        self.factors = {r.scale_from for r in device.registers if r.scale_from is not None}  # the sf registers
        self.sensor_of: dict[str, str] = {}  # register -> the entity id of its (one-register) sensor
        self.scaled_points: list[tuple[Register, str, str]] = []  # (point, title, entity id of its raw sensor)

    def _name(self, title: str, qualifier: str) -> str:
        return self.instance.name_prefix + self.names.name(title, qualifier)

    def _base(self, reg: Register, title: str, qualifier: str) -> dict[str, Any]:
        return {
            "name": self._name(title, qualifier),
            "unique_id": f"{self.instance.unique_prefix}_{qualifier.replace('.', '_')}",
            "slave": self.slave,
            "address": Hex(reg.address),
            "scan_interval": scan_interval(reg),
        }

    def _input_type(self, reg: Register) -> str:
        return INPUT_TYPE[reg.space] if reg.space != "holding" else self.input_type

    def _sensor(self, reg: Register, title: str, virtual: int = 0) -> None:
        labelled = reg.enum is not None and not virtual
        point = reg.scale_from is not None  # its raw value: the template sensor (`scaled`) shows the value
        shown = f"{title} (code)" if labelled else f"{title} (raw)" if point else title
        entity = self._base(reg, shown, f"{reg.name}.raw" if point else reg.name)
        entity.update({"input_type": self._input_type(reg), "data_type": DATA_TYPE[reg.type]})
        if reg.type.is_string:
            entity["count"] = reg.words
        swap = swap_of(reg)
        if swap is not None:
            entity["swap"] = swap
        if reg.type.is_string:
            self.sensors.append(entity)
            return
        if not virtual:
            self.sensor_of[reg.name] = "sensor." + object_id(entity["name"])
        if point:
            entity["precision"] = 0
            if reg.na:  # the template checks every marker; HA's sensor takes one
                entity["nan_value"] = Hex(int(reg.na[0])) if reg.na[0] >= 0 else int(reg.na[0])
            self.sensors.append(entity)
            self.scaled_points.append((reg, title, self.sensor_of[reg.name]))
            return
        if reg.scaled:
            entity["scale"] = scale_float(reg.scale)
        if reg.offset_set:
            entity["offset"] = scale_float(reg.offset)
        entity["precision"] = shown_decimals(reg)
        self._not_available(reg, entity)
        entity.update(self._measured(reg))
        if virtual:
            entity["virtual_count"] = virtual
        self.sensors.append(entity)
        if virtual or not (reg.enum is not None or template_flags(reg) or reg.zone is not None):
            return
        if not entity["name"].isascii():  # HA transliterates it into the entity id; which way is not ours to guess
            self.skipped.append(f"{reg.name}'s labels and flags as templates (its name is not ASCII text)")
            return
        self._templates(reg, title, "sensor." + object_id(entity["name"]))

    def _widened(self, reg: Register) -> tuple[int, int] | None:
        """(address, count) of the aligned read of a register whose own words break the map's read alignment
        (HA's sensor reads just its own words); None where its own read is one the device answers."""
        alignment = self.alignment
        if alignment is None or not reg.access.readable or alignment.allows(reg.space, reg.address, reg.words):
            return None
        low, high = alignment.extent(reg.space, reg.first_address, reg.address + reg.words)
        return low, high - low

    def _aligned_sensor(self, reg: Register) -> None:
        """A sensor that reads the whole aligned unit (`data_type: custom`, the other words skipped as struct pad
        bytes); HA loads one entity per address, so a second register of the same unit is listed as skipped."""
        start, count = self._widened(reg) or (reg.address, reg.words)
        code = HASS_STRUCT.get(reg.type)
        key = (self._input_type(reg), start)
        if code is None or swap_of(reg) is not None or reg.enum is not None or reg.bitfields or key in self.aligned_addresses:
            self.skipped.append(
                f"{reg.name} (the device answers reads of whole {count}-word units only, and HA reads one entity per address"
                " with its own words)"
            )
            return
        self.aligned_addresses.add(key)
        self._sensor(reg, reg.title)
        entity = self.sensors[-1]
        before, after = 2 * (reg.address - start), 2 * (start + count - reg.address - reg.words)
        entity.update(
            address=Hex(start),
            data_type="custom",
            count=count,
            structure=">" + (f"{before}x" if before else "") + code + (f"{after}x" if after else ""),
        )

    def _measured(self, reg: Register) -> dict[str, Any]:
        """What HA is told of the quantity: its unit, device class and state class, where the register has them."""
        keys: dict[str, Any] = {"unit_of_measurement": unit_text(reg.unit) if reg.unit else None}
        keys |= {"device_class": device_class(reg), "state_class": state_class(self.device, reg)}
        return {key: value for key, value in keys.items() if value is not None}

    def _not_available(self, reg: Register, entity: dict[str, Any]) -> None:
        """HA's sensor is unavailable for its one `nan_value` (compared with the unpacked, signed value) and for
        a NaN float; a second integer marker HA cannot express is said in the skipped list."""
        if not reg.na:
            return
        mark = reg.na[0]
        entity["nan_value"] = Hex(mark) if isinstance(mark, int) and mark >= 0 else mark
        if len(reg.na) > 1:
            rest = ", ".join(na_mark(reg, m) for m in reg.na[1:])
            self.skipped.append(f"{reg.name}'s 'not available' marker(s) {rest} (HA takes one nan_value; it has the first)")

    def _templates(self, reg: Register, title: str, source: str) -> None:
        """The register's labels, flags and time as template entities over its sensor `source`."""
        if reg.zone is not None:
            self.template_sensors.append(time_sensor(reg, source, self._name(title, f"{reg.name} time"), self.instance.unique_prefix))
        if reg.enum is not None:
            name = self._name(title, f"{reg.name} label")
            self.template_sensors.append(label_sensor(reg, source, name, self.instance.unique_prefix))
        for field_name, field_title, mask in template_flags(reg):
            name = self._name(f"{title}: {field_title}", f"{reg.name}.{field_name}")
            entity = flag_sensor(reg, source, name, self.instance.unique_prefix, field_name, mask)
            self.template_binary_sensors.append(entity)
        if any(b.width > 1 for b in reg.bitfields):
            self.skipped.append(f"{reg.name}'s multi-bit fields as entities (the register's sensor shows them)")

    def _flag_sensor(self, reg: Register) -> bool:
        """A read-only register whose only field is bit 0 becomes a binary sensor (HA reads `value & 1`);
        HA loads one entity per address, so any other bitfield register stays one raw sensor."""
        field = single_flag(reg)
        if field is None or field.lsb != 0 or reg.access.writable or reg.words != 1 or swapped(reg) or reserved(field.title):
            return False
        entity = self._base(reg, f"{reg.title}: {field.title}", f"{reg.name}.{field.name}")
        entity["input_type"] = self._input_type(reg)
        self.binary_sensors.append(entity)
        return True

    def _bit(self, reg: Register, title: str, virtual: int = 0) -> None:
        """A coil or discrete input: a binary sensor (a run of them in one read: `virtual_count`), or a switch for a writable coil."""
        entity = self._base(reg, title, reg.name)
        if reg.access.writable and reg.space_info.writable:
            entity.update({"write_type": self.coil_write, "verify": {"input_type": "coil", "address": Hex(reg.address)}})
            self.switches.append(entity)
            return
        entity["input_type"] = self._input_type(reg)
        if virtual:
            entity["virtual_count"] = virtual
        self.binary_sensors.append(entity)

    def _switch(self, reg: Register, title: str, qualifier: str, on: int, off: int) -> None:
        entity = self._base(reg, title, qualifier)
        if swapped(reg):  # HA writes and compares the word as it is on the wire
            on, off = swap_word(on), swap_word(off)
        entity.update(
            {
                "write_type": self.register_write,
                "command_on": on,
                "command_off": off,
                "verify": {"input_type": self.input_type, "address": Hex(reg.address), "state_on": on, "state_off": off},
            }
        )
        self.switches.append(entity)

    def _run(self, regs: list[Register], i: int) -> int:
        """How many registers from regs[i] one virtual sensor can read (1 when none)."""
        first = regs[i]
        n = 1
        if first.array is None or first.enum is not None or first.bitfields or first.type.is_string:
            return 1
        if first.scale_from is not None or first.name in self.factors:
            return 1  # a point and its sf each need a sensor of their own (the template reads it)
        if first.type.is_bool and first.access.writable:
            return 1  # switches read one coil each
        while i + n < len(regs):
            nxt, prev = regs[i + n], regs[i + n - 1]
            same = (
                nxt.array is not None
                and nxt.array.array == first.array.array
                and nxt.array.member == first.array.member
                and (nxt.type, nxt.scale, nxt.offset, nxt.unit, nxt.access, nxt.word_order, nxt.byte_order, nxt.space, nxt.poll)
                == (
                    first.type,
                    first.scale,
                    first.offset,
                    first.unit,
                    first.access,
                    first.word_order,
                    first.byte_order,
                    first.space,
                    first.poll,
                )
                and gate_key(nxt) == gate_key(first)
                and (nxt.na, nxt.na_nan) == (first.na, first.na_nan)
                and nxt.address == prev.address + prev.words
                and not nxt.paired
                and not nxt.bitfields
                and nxt.enum is None
                and nxt.scale_from is None
                and nxt.name not in self.factors
                and self.block_of.get(nxt.name) == self.block_of.get(first.name)
            )
            if not same:
                break
            n += 1
        return n

    def _scaled(self) -> None:
        """The template sensor of each point scaled by another register, and a set script for a writable one."""
        for reg, title, raw_source in self.scaled_points:
            sf = self.device.register(reg.scale_from or "")
            sf_source = self.sensor_of.get(sf.name)
            if sf_source is None or not (raw_source.isascii() and sf_source.isascii()):
                self.skipped.append(f"{reg.name}'s value (raw x 10^{sf.name}): no plain sensor with an ASCII name reads {sf.name}")
                continue
            entity: dict[str, Any] = {"name": self._name(title, reg.name), "unique_id": f"{self.instance.unique_prefix}_{reg.name}"}
            entity.update(self._measured(reg))
            self.template_sensors.append(scaled.scaled_sensor(reg, raw_source, sf, sf_source, entity))
            if not reg.access.writable:
                continue
            reason = scaled.unwritable(reg)
            if reason is not None:
                self.skipped.append(reason)
                continue
            script_id = self.scripts.ids.id(object_id(f"{self.instance.script_prefix}_set_{reg.name}"))
            write = {"hub": self.instance.hub, "slave": self.slave, "address": Hex(reg.address)}
            alias = self.instance.name_prefix + "Set " + " ".join(title.split())
            script = scaled.set_script(reg, sf, sf_source, alias, write, self.scripts.single_write, RETRY_NOTE)
            self.scripts.scripts[script_id] = script

    def _with_factors(self, regs: list[Register]) -> list[Register]:
        """`regs` and the sf register of each point among them (a point's value needs it), in map order."""
        names = {r.name for r in regs} | {r.scale_from for r in regs if r.scale_from is not None}
        return [r for r in self.device.registers if r.name in names]

    def build(self) -> None:
        regs = self._with_factors([r for r in self.selection.registers if r.access.readable])
        regs = [r for r in regs if not reserved(r.title)]
        for reg in self.selection.registers:
            if not reg.access.readable:
                self.skipped.append(f"{reg.name} (write-only; write it with modbus.write_register)")
            elif reserved(reg.title):
                self.skipped.append(f"{reg.name} (reserved: the manual gives it no meaning)")
        i = 0
        while i < len(regs):
            reg = regs[i]
            if self._widened(reg) is not None:
                self._aligned_sensor(reg)
                i += 1
                continue
            n = self._run(regs, i)
            if n > 1:
                assert reg.array is not None
                array = next(a for a in self.device.arrays if a.name == reg.array.array)
                member = next(m for m in array.members if m.name == reg.array.member)
                if reg.type.is_bool:
                    self._bit(reg, f"{array.title}: {member.title}", virtual=n - 1)
                else:
                    self._sensor(reg, f"{array.title}: {member.title}", virtual=n - 1)
                i += n
                continue
            if reg.type.is_bool:
                self._bit(reg, reg.title)
                i += 1
                continue
            if reg.type.is_string and reg.encoding not in TEXT_ENCODINGS:
                self.skipped.append(f"{reg.name} ({reg.encoding} text: HA decodes string registers as UTF-8)")
                i += 1
                continue
            switch = on_off(reg.enum) if reg.access.writable and reg.words == 1 else None
            flag = single_flag(reg) if reg.access.writable and reg.words == 1 else None
            if switch is not None:
                self._switch(reg, reg.title, reg.name, *switch)
            elif flag is not None:
                self._switch(reg, f"{reg.title}: {flag.title}", f"{reg.name}.{flag.name}", flag.mask, 0)
            elif not self._flag_sensor(reg):
                self._sensor(reg, reg.title)
            i += 1
        self._scaled()
        for command in self.selection.commands:
            self.scripts.add(command)
        self.skipped += self.scripts.skipped

    def entities(self) -> dict[str, list[dict[str, Any]]]:
        """The hub's entity lists by key (`sensors`, `binary_sensors`, `switches`), the empty ones left out."""
        kinds = (("sensors", self.sensors), ("binary_sensors", self.binary_sensors), ("switches", self.switches))
        return {key: entities for key, entities in kinds if entities}

    def data(self) -> list[dict[str, Any]]:
        self.build()
        t = self.device.transport
        hub: dict[str, Any] = {
            "name": self.device.id,
            "type": "serial",
            "method": "rtu",
            "port": PORT,
            "baudrate": t.baud,
            "bytesize": t.data_bits,
            "parity": PARITY[t.parity],
            "stopbits": t.stop_bits,
        }
        return [hub | self.entities()]


def hub(device: Device, selection: Selection) -> list[dict[str, Any]]:
    """The `modbus:` list as data (the tests read the entities from it)."""
    return _Hub(device, selection).data()


def _package(hubs: list[_Hub], data: list[dict[str, Any]]) -> dict[str, Any]:
    """The package: the `modbus:` list, then the template entities and scripts of every device in `hubs`."""
    out: dict[str, Any] = {"modbus": data}
    template_sensors = [e for h in hubs for e in h.template_sensors]
    template_binary_sensors = [e for h in hubs for e in h.template_binary_sensors]
    kinds = (("sensor", template_sensors), ("binary_sensor", template_binary_sensors))
    templates = [{key: entities} for key, entities in kinds if entities]
    if templates:
        out["template"] = templates
    scripts = {script_id: script for h in hubs for script_id, script in h.scripts.scripts.items()}
    if scripts:
        out["script"] = scripts
    return out


def render_hub(device: Device, selection: Selection) -> Files:
    h = _Hub(device, selection)
    data = h.data()
    about = [
        "",
        f"Home Assistant modbus hub for {device.info.vendor} {device.info.model}, as a package. In configuration.yaml:",
        f"homeassistant: packages: {{{device.id}: !include {device.id}.yaml}}. Set `port` ({PORT}) and `slave` to your line.",
        f"32-bit values assume the device's factory word order ({device.transport.word_order.value}).",
        f"Selection: {selection.rule} ({len(selection.registers)} registers, {len(selection.commands)} commands).",
    ]
    if any(r.poll is not PollClass.NORMAL for r in selection.registers):
        about.append("Poll classes as scan_interval: fast 5 s, normal 10 s (settings 300 s), slow 60 s, static 0 (read once at start-up).")
    if any(r.type.is_string and r.padding == "nul" for r in selection.registers):
        about.append("Text: HA keeps a string register's NUL padding in the state (it decodes every byte).")
    about += [
        "Commands are scripts (script.<device>_<command>, mode single); destructive ones are left out of the default"
        " selection, and when chosen are named DESTRUCTIVE and send nothing unless called with confirm: <command>.",
        "Retries: HA's modbus hub gives pymodbus retries=3 for every request, writes included (the hub's `retries`"
        " option is deprecated and ignored in 2024.3, removed later): a command whose reply is lost may be sent again;"
        " nothing in this file can stop that.",
        "Template entities read sensor.<slug of the sensor's name>, the id HA gives it at first start: rename both together.",
    ]
    if h.scaled_points:
        about.append(scaled.SCALED_NOTE)
    about += gate_notes(device, selection.registers)
    about += [f"Not generated: {s}" for s in h.skipped]
    return {f"{device.id}.yaml": dump(device, about, _package([h], data))}


# -- a plant: several devices on buses -------------------------------------------------------------


def plant_hub_name(plant: Plant, bus: Bus) -> str:
    return f"{plant.id}_{bus.name}"


def plant_instance(plant: Plant, bus: Bus, dev: PlantDevice) -> Instance:
    """A device of a plant: on its bus's hub at its slave id; every name, unique_id and script id carries its name."""
    return Instance(
        hub=plant_hub_name(plant, bus),
        slave=dev.slave,
        unique_prefix=f"{plant.id}_{dev.name}",
        script_prefix=dev.name,
        name_prefix=f"{dev.name} ",
    )


def _bus_connection(plant: Plant, bus: Bus) -> dict[str, Any]:
    """The hub's own keys: one hub per bus (HA refuses a second hub on one port or host:port)."""
    if bus.serial is not None:
        line = bus.serial
        return {
            "name": plant_hub_name(plant, bus),
            "type": "serial",
            "method": "rtu",
            "port": line.port,
            "baudrate": line.baud,
            "bytesize": line.data_bits,
            "parity": PARITY[line.parity],
            "stopbits": line.stop_bits,
        }
    assert bus.tcp is not None
    return {"name": plant_hub_name(plant, bus), "type": "tcp", "host": bus.tcp.host, "port": bus.tcp.port}


def _plant_hubs(plant: Plant) -> tuple[list[dict[str, Any]], list[tuple[Bus, PlantDevice, _Hub]]]:
    data: list[dict[str, Any]] = []
    built: list[tuple[Bus, PlantDevice, _Hub]] = []
    for bus in plant.buses:
        hub_data = _bus_connection(plant, bus)
        for dev in bus.devices:
            h = _Hub(dev.device, for_variant(select(dev.device, None), dev.variant), plant_instance(plant, bus, dev))
            h.build()
            built.append((bus, dev, h))
            for key, entities in h.entities().items():
                hub_data.setdefault(key, []).extend(entities)
        data.append(hub_data)
    _refuse_shared_entity_ids(plant, built)
    return data, built


def _refuse_shared_entity_ids(plant: Plant, built: list[tuple[Bus, PlantDevice, _Hub]]) -> None:
    """HA makes each entity id of its name: device `a` with "b c" and device `a_b` with "c" would both be
    `sensor.a_b_c` (HA adds `_2` to one, and the templates read the other)."""
    ids = []
    for _, dev, h in built:
        named = [("sensor", e["name"]) for e in [*h.sensors, *h.template_sensors]]
        named += [("binary_sensor", e["name"]) for e in [*h.binary_sensors, *h.template_binary_sensors]]
        named += [("switch", e["name"]) for e in h.switches]
        ids.append((dev, [f"{domain}.{object_id(name)}" for domain, name in named] + [f"script.{s}" for s in h.scripts.scripts]))
    refuse_shared_ids(plant, ids, "Home Assistant")


def plant_hubs(plant: Plant) -> list[dict[str, Any]]:
    """The plant's `modbus:` list as data: a hub per bus, each device's entities at its slave id."""
    return _plant_hubs(plant)[0]


def render_plant(plant: Plant) -> Files:
    """The plant's package (`<plant id>.yaml`): a hub per bus, every device's entities, templates and scripts."""
    data, built = _plant_hubs(plant)
    buses = ", ".join(f"{bus.name} ({plant_hub_name(plant, bus)})" for bus in plant.buses)
    about = [
        "",
        f"Home Assistant modbus configuration of the plant {' '.join(plant.title.split())}, as a package. In configuration.yaml:",
        f"homeassistant: packages: {{{plant.id}: !include {plant.id}.yaml}}. One hub per bus: {buses}.",
        "Every entity's name starts with its device's name (the entity id HA makes of it too), every unique_id with"
        f" {plant.id}_<device>_, every script id with <device>_; each entity and script names its device's slave id.",
        f"Selection per device: {DEFAULT_RULE}.",
        *(plant_device_line(bus, dev, h.selection) for bus, dev, h in built),
        "Commands are scripts (script.<device>_<command>, mode single); destructive ones are left out of the default selection.",
        "Retries: HA's modbus hub gives pymodbus retries=3 for every request, writes included: a command whose reply"
        " is lost may be sent again; nothing in this file can stop that.",
        "Template entities read sensor.<slug of the sensor's name>, the id HA gives it at first start: rename both together.",
    ]
    if any(h.scaled_points for _, _, h in built):
        about.append(scaled.SCALED_NOTE)
    for _, dev, h in built:
        about += [f"{dev.name}: {note}" for note in gate_notes(dev.device, h.selection.registers, dev.variant)]
        about += [f"Not generated for {dev.name}: {s}" for s in h.skipped]
    hubs = [h for _, _, h in built]
    return {f"{plant.id}.yaml": dump_commented([*plant_header_lines(plant), *about], _package(hubs, data))}
