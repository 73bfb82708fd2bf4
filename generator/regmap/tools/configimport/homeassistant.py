"""A Home Assistant `modbus:` config -> one `Device` per hub and slave: the inverse of backends/homeassistant.

Read as HA's modbus integration reads it (homeassistant/components/modbus/__init__.py): `input_type`
(holding by default; input, coil, discrete_input), `data_type` (int16 by default ... float64, string
with `count` registers), `swap` (byte: bytes inside each word, word: the words of a wide value, word_byte:
both), `scale` then `offset` (value = raw x scale + offset), `slave` or `device_address` (1 by default),
`virtual_count`/`slave_count` (that many more values at the following addresses: an array),
`scan_interval` as a poll class. Switches, fans and lights write `command_on`/`command_off` (an on/off
enum; a coil is a bool) and read `verify`; a climate is its current temperature, its target
temperature (read-write) and its mode, on/off and fan registers (enums of the states it names); a
cover is its command register (or coil) and its status register. A template sensor of the shape regmap writes
for a register scaled by another makes the point `scale_from` its sf (tools/configimport/hatemplates.py). A `custom` structure becomes one register per value
it unpacks (tools/configimport/hastruct.py). What a map cannot say (a byte-sized value, `zero_suppress`, `min_value`/`max_value` clamps, a verify at
another address) is kept as a note and reported.
"""

from __future__ import annotations

from dataclasses import replace
from fractions import Fraction
from typing import Any

from regmap.tools.configimport.draft import Device, Flag, Import, Imported, Member, fraction
from regmap.tools.configimport.hastruct import StructureError, structure_fields
from regmap.tools.configimport.hatemplates import entity_id, scaled_templates
from regmap.tools.configimport.reader import Config, ConfigError, ConfigReader, poll_class, substitute

# HA's data_type -> regmap type (the inverse of backends/homeassistant's DATA_TYPE); custom has none (hastruct reads it).
DATA_TYPE = {
    "int16": "s16",
    "uint16": "u16",
    "int32": "s32",
    "uint32": "u32",
    "int64": "s64",
    "uint64": "u64",
    "float16": "f16",
    "float32": "f32",
    "float64": "f64",
    "string": "string",
}
SWAP = {
    None: ("high_first", "high_first"),
    "none": ("high_first", "high_first"),
    "byte": ("high_first", "low_first"),
    "word": ("low_first", "high_first"),
    "word_byte": ("low_first", "low_first"),
}
REGISTER_INPUT = {"holding": "holding", "input": "input"}
BIT_INPUT = {"coil": "coil", "discrete_input": "discrete_input", "holding": "holding", "input": "input"}
WRITE_TYPE = {"holding": "holding", "holdings": "holding", "coil": "coil", "coils": "coil"}
DEFAULT_SCAN_INTERVAL = 15  # seconds (HA's DEFAULT_SCAN_INTERVAL)
PLATFORMS = ("sensors", "binary_sensors", "switches", "fans", "lights", "climates", "covers")
UNSUPPORTED = ("zero_suppress", "min_value", "max_value", "lazy_error_count")
PARITY = {"N": "none", "E": "even", "O": "odd"}
CLIMATE_MODES = ("state_off", "state_heat", "state_cool", "state_heat_cool", "state_auto", "state_dry", "state_fan_only")


class _Reader(ConfigReader):
    def __init__(self, config: Config) -> None:
        super().__init__(config)
        self.devices: dict[tuple[str, int], Device] = {}
        self.sensors: dict[str, tuple[Device, Imported]] = {}  # entity id -> a one-value sensor's register (templates read it)

    def read(self) -> Import:
        data = self.config.data
        hubs = data.get("modbus") if isinstance(data, dict) else None
        if not isinstance(hubs, list):
            self.fail(("modbus",) if isinstance(data, dict) and "modbus" in data else (), "expected `modbus:` with a list of hubs")
            raise ConfigError(self.problems)
        unresolved: set[str] = set()
        hubs = substitute(hubs, {}, unresolved)
        for i, hub in enumerate(hubs):
            if not isinstance(hub, dict):
                self.fail(("modbus", i), "a hub is a mapping (name, type, port ...)")
                continue
            self._hub(hub, ("modbus", i))
        scaled_templates(data, self.sensors, self.report)
        if self.problems:
            raise ConfigError(self.problems)
        return Import(list(self.devices.values()), self.report)

    def _hub(self, hub: dict[str, Any], path: tuple[str | int, ...]) -> None:
        name = str(hub.get("name", "modbus_hub"))
        serial: dict[str, Any] = {}
        if isinstance(hub.get("baudrate"), int):
            serial["baud"] = hub["baudrate"]
        if hub.get("parity") in PARITY:
            serial["parity"] = PARITY[hub["parity"]]
        if hub.get("stopbits") in (1, 2):
            serial["stop_bits"] = hub["stopbits"]
        for platform in PLATFORMS:
            entities = hub.get(platform) or []
            if not isinstance(entities, list):
                entities = [entities]
            for i, entity in enumerate(entities):
                epath = (*path, platform, i)
                if not isinstance(entity, dict):
                    self.fail(epath, f"{platform} entry: expected a mapping")
                    continue
                slave = entity.get("slave", entity.get("device_address", 1))
                if isinstance(slave, bool) or not isinstance(slave, int) or not 0 <= slave <= 255:
                    self.fail((*epath, "slave"), f"slave {slave!r}: expected a slave id 0..255")
                    continue
                device = self.devices.setdefault((name, slave), Device(label=f"{name} slave {slave}", slave=slave, serial=dict(serial)))
                regs = getattr(self, "_" + platform)(entity, epath)
                if platform == "sensors" and len(regs) == 1 and regs[0].count == 1 and isinstance(entity.get("name"), str):
                    self.sensors[entity_id(entity["name"])] = (device, regs[0])
                for reg in regs:
                    problem = device.add(reg)
                    if problem is not None:
                        self.report.append(f"{reg.origin}: not imported: {problem}")

    # -- helpers -----------------------------------------------------------------------------

    def _address(self, entity: dict[str, Any], path: tuple[str | int, ...], key: str = "address") -> int | None:
        address = entity.get(key)
        if isinstance(address, bool) or not isinstance(address, int) or not 0 <= address <= 0xFFFF:
            self.fail((*path, key), f"{key} {address!r}: expected a register address 0..0xFFFF")
            return None
        return address

    def _choice(self, entity: dict[str, Any], path: tuple[str | int, ...], key: str, table: dict[Any, Any], default: Any) -> Any:
        value = entity.get(key, default)
        if value not in table:
            self.fail((*path, key), f"{key} {value!r}: expected one of {', '.join(str(k) for k in table if k is not None)}")
            return None
        return table[value]

    def _base(self, entity: dict[str, Any], path: tuple[str | int, ...], space: str, kind: str, writable: bool) -> Imported | None:
        address = self._address(entity, path)
        if address is None:
            return None
        key = str(entity.get("unique_id") or entity.get("name") or f"{space}_{address:04x}")
        title = str(entity.get("name") or key)
        reg = Imported(key=key, title=title, address=address, space=space, type=kind, origin=self.where(path), writable=writable)
        scan = entity.get("scan_interval", DEFAULT_SCAN_INTERVAL)
        if isinstance(scan, int) and not isinstance(scan, bool):
            reg.poll = poll_class(scan, writable, DEFAULT_SCAN_INTERVAL)  # HA: 0 reads once at start-up
        if "nan_value" in entity:
            self._nan_value(reg, entity["nan_value"])
        for extra in UNSUPPORTED:
            if extra in entity:
                self._note(reg, f"Home Assistant {extra}: {entity[extra]} (not part of the register's reading)")
        return reg

    def _nan_value(self, reg: Imported, value: Any) -> None:
        """HA's nan_value: the raw value (a number, or hex text "0xFFFF") the device sends for "not available"."""
        if isinstance(value, str):
            try:
                value = int(value, 16) if value.lower().startswith("0x") else float(value)
            except ValueError:
                self._note(reg, f"Home Assistant nan_value: {value!r} is not a number (kept as a note)")
                return
        if isinstance(value, bool) or not isinstance(value, int | float):
            self._note(reg, f"Home Assistant nan_value: {value!r} is not a number (kept as a note)")
            return
        reg.na = [value]

    def _note(self, reg: Imported, note: str) -> None:
        reg.notes.append(note)
        self.report.append(f"{reg.origin}: {reg.title}: {note}")

    def _value(self, reg: Imported, entity: dict[str, Any], path: tuple[str | int, ...], default_type: str = "int16") -> bool:
        """Type, word and byte order, scale and offset of a register read as a number or text."""
        data_type = entity.get("data_type", default_type)
        if data_type == "custom":
            self.report.append(f"{reg.origin}: {reg.title}: data_type {data_type} has no regmap type: not imported")
            return False
        kind = self._choice(entity, path, "data_type", DATA_TYPE, default_type)
        swap = self._choice(entity, path, "swap", SWAP, None)
        if kind is None or swap is None:
            return False
        reg.type = kind
        reg.word_order, reg.byte_order = swap
        if kind == "string":
            count = entity.get("count")
            if isinstance(count, bool) or not isinstance(count, int) or count < 1:
                self.fail((*path, "count"), "a string needs count: how many registers it reads")
                return False
            reg.words = count
            return True
        for key in ("scale", "offset"):
            value = entity.get(key)
            if value is not None and (isinstance(value, bool) or not isinstance(value, int | float)):
                self.fail((*path, key), f"{key} {value!r}: expected a number")
                return False
        reg.scale = fraction(entity.get("scale", 1))
        reg.offset = fraction(entity.get("offset", 0))
        if reg.scale == 0:
            self.fail((*path, "scale"), "scale 0 makes every value 0")
            return False
        unit = entity.get("unit_of_measurement")
        reg.unit = str(unit) if unit else None
        return True

    def _count(self, reg: Imported, entity: dict[str, Any], path: tuple[str | int, ...]) -> None:
        extra = entity.get("virtual_count", entity.get("slave_count", 0))
        if isinstance(extra, bool) or not isinstance(extra, int) or extra < 0:
            self.fail((*path, "virtual_count"), f"virtual_count {extra!r}: expected a count")
            return
        reg.count = extra + 1

    # -- platforms ---------------------------------------------------------------------------

    def _sensors(self, entity: dict[str, Any], path: tuple[str | int, ...]) -> list[Imported]:
        space = self._choice(entity, path, "input_type", REGISTER_INPUT, "holding")
        reg = self._base(entity, path, space, "s16", False) if space else None
        if reg is not None and entity.get("data_type") == "custom":
            return self._custom(reg, entity, path)
        if reg is None or not self._value(reg, entity, path):
            return []
        self._count(reg, entity, path)
        return [reg]

    def _custom(self, reg: Imported, entity: dict[str, Any], path: tuple[str | int, ...]) -> list[Imported]:
        """A `custom` structure: one register per value it unpacks, scale and offset applied to each as HA does."""
        count, structure = entity.get("count"), entity.get("structure")
        if isinstance(count, bool) or not isinstance(count, int) or count < 1 or not isinstance(structure, str):
            self.fail(path, "data_type custom needs count (registers) and structure (a struct format)")
            return []
        try:
            fields, order = structure_fields(structure, count)
        except StructureError as exc:
            self.report.append(f"{reg.origin}: {reg.title}: {exc}: not imported")
            return []
        numbers: dict[str, Any] = {
            "data_type": "int16",
            **{k: entity[k] for k in ("scale", "offset", "unit_of_measurement") if k in entity},
        }
        if not self._value(reg, numbers, path):
            return []
        regs = [
            replace(
                reg,
                key=reg.key if len(fields) == 1 else f"{reg.key}_{i}",
                title=reg.title if len(fields) == 1 else f"{reg.title} {i}",
                address=reg.address + f.word_offset,
                type=f.type,
                word_order=f.word_order,
                byte_order=f.byte_order,
                words=f.words,
            )
            for i, f in enumerate(fields, start=1)
        ]
        if len(fields) > 1:
            self._note(
                reg,
                f"custom structure {structure!r} ({order} endian): {len(fields)} values, imported as {len(fields)} registers; Home Assistant shows them as one text, joined by commas",
            )
        elif order != "big":
            self._note(reg, f"custom structure {structure!r}: read {order} endian (byte and word order low first)")
        unpacked = sum(f.size for f in fields)
        if unpacked < count:  # padding: HA reads whole units, which a device may demand; a map says so only from its datasheet
            self._note(
                reg,
                f"custom structure {structure!r} reads {count} registers for {unpacked} word(s) of values (padding): "
                f"if the device answers only whole {count}-register reads, add transport.read_alignment (not inferred)",
            )
        for r in regs:
            r.notes = list(reg.notes)
            if r.type == "string":
                r.scale, r.offset, r.unit = Fraction(1), Fraction(0), None
        return regs

    def _binary_sensors(self, entity: dict[str, Any], path: tuple[str | int, ...]) -> list[Imported]:
        space = self._choice(entity, path, "input_type", BIT_INPUT, "coil")
        if space is None:
            return []
        bits = space in ("coil", "discrete_input")
        reg = self._base(entity, path, space, "bool" if bits else "u16", False)
        if reg is None:
            return []
        if not bits:  # HA reads `value & 1` of a register
            reg.flags.append(Flag(key=reg.key, mask=1, title=reg.title))
        self._count(reg, entity, path)
        return [reg]

    def _switch_like(self, entity: dict[str, Any], path: tuple[str | int, ...]) -> list[Imported]:
        space = self._choice(entity, path, "write_type", WRITE_TYPE, "holding")
        reg = self._base(entity, path, space, "bool" if space == "coil" else "u16", True) if space else None
        if reg is None:
            return []
        verify = entity.get("verify", False)
        if verify is False:
            self._note(reg, "Home Assistant does not read it back (no verify): its state is assumed")
            verify = {}
        verify = verify or {}  # `verify:` with nothing under it reads the written register back
        if not isinstance(verify, dict):
            self.fail((*path, "verify"), "verify: expected a mapping (address, input_type, state_on, state_off)")
            return []
        if verify.get("address", reg.address) != reg.address or verify.get("input_type", entity.get("write_type", "holding")) not in (
            entity.get("write_type", "holding"),
            "holdings" if space == "holding" else "coils",
        ):
            self._note(
                reg, f"Home Assistant reads its state at {verify.get('input_type', 'holding')} 0x{verify.get('address', reg.address):04X}"
            )
        if space == "coil":
            return [reg]
        on, off = entity.get("command_on", 1), entity.get("command_off", 0)
        state_on, state_off = verify.get("state_on", on), verify.get("state_off", off)
        values = (on, off, state_on, state_off)
        if not all(isinstance(v, int) and not isinstance(v, bool) and 0 <= v <= 0xFFFF for v in values) or on == off:
            self.fail((*path, "command_on"), f"command_on {on!r} / command_off {off!r}: expected two different register values")
            return []
        reg.members = [Member(value=on, title="On", readable=on == state_on), Member(value=off, title="Off", readable=off == state_off)]
        for value, title in ((state_on, "On (state)"), (state_off, "Off (state)")):
            if value not in (on, off):
                reg.members.append(Member(value=value, title=title, writable=False))
        return [reg]

    _switches = _switch_like
    _fans = _switch_like
    _lights = _switch_like

    def _climates(self, entity: dict[str, Any], path: tuple[str | int, ...]) -> list[Imported]:
        space = self._choice(entity, path, "input_type", REGISTER_INPUT, "holding")
        current = self._base(entity, path, space, "s16", False) if space else None
        if current is None or not self._value(current, entity, path):
            return []
        current.title = f"{current.title} current temperature"
        out = [current]
        targets = entity.get("target_temp_register")
        targets = targets if isinstance(targets, list) else [targets]
        for i, address in enumerate(targets):
            if isinstance(address, bool) or not isinstance(address, int):
                self.fail((*path, "target_temp_register"), f"target_temp_register {address!r}: expected a register address")
                return out
            if i and address == targets[0]:
                continue  # HA's list gives one target per HVAC mode; the same register is one register
            target = Imported(**{**current.__dict__, "key": f"{current.key} target {i}" if i else f"{current.key} target", "notes": []})
            target.title = f"{entity.get('name')} target temperature" + (f" {i}" if i else "")
            target.address, target.space, target.writable, target.poll = address, "holding", True, "normal"
            low, high = entity.get("min_temp", 5), entity.get("max_temp", 35)
            if all(isinstance(v, int | float) for v in (low, high)):
                raw = [(fraction(v) - target.offset) / target.scale for v in (low, high)]
                if target.type in ("f16", "f32") or all(r.denominator == 1 for r in raw):
                    target.min, target.max = (float(r) if target.type in ("f16", "f32", "f64") else int(r) for r in raw)
            out.append(target)
        for key, title, states in (
            ("hvac_mode_register", "HVAC mode", CLIMATE_MODES),
            ("fan_mode_register", "fan mode", None),
        ):
            mode = entity.get(key)
            if mode is None:
                continue
            reg = self._mode(mode, (*path, key), f"{entity.get('name')} {title}", states)
            if reg is not None:
                out.append(reg)
        onoff = entity.get("hvac_onoff_register")
        if onoff is not None:
            reg = self._base(
                {"address": onoff, "name": f"{entity.get('name')} on/off"}, (*path, "hvac_onoff_register"), "holding", "u16", True
            )
            if reg is not None:
                reg.members = [Member(value=1, title="On"), Member(value=0, title="Off")]
                out.append(reg)
        return out

    def _mode(self, mode: Any, path: tuple[str | int, ...], title: str, states: tuple[str, ...] | None) -> Imported | None:
        if not isinstance(mode, dict) or not isinstance(mode.get("values"), dict):
            self.fail(path, "expected {address: ..., values: {state_...: value}}")
            return None
        address = mode.get("address")
        address = address[0] if isinstance(address, list) and address else address
        reg = self._base({"address": address, "name": title}, path, "holding", "u16", True)
        if reg is None:
            return None
        for state, value in mode["values"].items():
            values = value if isinstance(value, list) else [value]
            for v in values:
                if isinstance(v, bool) or not isinstance(v, int) or not 0 <= v <= 0xFFFF:
                    self.fail((*path, "values", state), f"{state}: {v!r} is not a register value")
                    continue
                if all(m.value != v for m in reg.members):
                    reg.members.append(Member(value=v, title=str(state).removeprefix("state_").replace("_", " ").capitalize()))
        return reg

    def _covers(self, entity: dict[str, Any], path: tuple[str | int, ...]) -> list[Imported]:
        space = self._choice(entity, path, "input_type", {"holding": "holding", "coil": "coil"}, "holding")
        reg = self._base(entity, path, space, "bool" if space == "coil" else "u16", True) if space else None
        if reg is None:
            return []
        states = [(entity.get(f"state_{s}", d), s.capitalize()) for s, d in (("closed", 0), ("open", 1), ("opening", 2), ("closing", 3))]
        status = entity.get("status_register")
        if space == "holding":  # HA writes state_open / state_closed and, without a status register, reads the states here
            reg.members = [Member(value=v, title=t, writable=t in ("Open", "Closed")) for v, t in states]
        if status is None:
            return [reg]
        status_space = self._choice(entity, path, "status_register_type", REGISTER_INPUT, "holding")
        read = self._base(
            {"address": status, "name": f"{entity.get('name')} status"}, (*path, "status_register"), status_space or "holding", "u16", False
        )
        if read is None:
            return [reg]
        read.members = [Member(value=v, title=t, writable=False) for v, t in states]
        if status == reg.address and read.space == reg.space:
            return [reg]
        return [reg, read]


def read_homeassistant(config: Config) -> Import:
    """The devices of a Home Assistant modbus config (one per hub and slave) and the report."""
    return _Reader(config).read()
