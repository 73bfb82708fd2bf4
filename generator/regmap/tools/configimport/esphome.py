"""An ESPHome `modbus_controller` config -> one `Device` per controller: the inverse of backends/esphome.

Read as ESPHome reads it: `register_type` (holding, read = input registers, coil, discrete_input),
`address` plus `offset` (bytes into the read), `value_type` (U_WORD ... FP32_R: `_R` is low word first),
`bitmask` (a bit field; on a coil, nothing), `register_count`/`response_size` of text, `optionsmap` of a
select, `multiply` of a number (raw = value x multiply), the `multiply`/`offset` filters of a sensor
(value = raw x scale + offset), `skip_updates` as a poll class. A lambda, any other filter, a
`force_new_range` and a `custom_command` cannot be a map's value: each is kept as a note and reported.
"""

from __future__ import annotations

import re
from fractions import Fraction
from typing import Any

from regmap.tools.configimport.draft import Device, Flag, Import, Imported, Member, fraction, identifier
from regmap.tools.configimport.reader import STATIC_PERIOD, Config, ConfigError, ConfigReader, Tagged, poll_class, substitute

# ESPHome's value_type -> (regmap type, word order). The inverse of backends/esphome's VALUE_TYPE.
VALUE_TYPE = {
    "U_WORD": ("u16", "high_first"),
    "S_WORD": ("s16", "high_first"),
    "U_DWORD": ("u32", "high_first"),
    "U_DWORD_R": ("u32", "low_first"),
    "S_DWORD": ("s32", "high_first"),
    "S_DWORD_R": ("s32", "low_first"),
    "U_QWORD": ("u64", "high_first"),
    "U_QWORD_R": ("u64", "low_first"),
    "S_QWORD": ("s64", "high_first"),
    "S_QWORD_R": ("s64", "low_first"),
    "FP32": ("f32", "high_first"),
    "FP32_R": ("f32", "low_first"),
}
REGISTER_TYPE = {"holding": "holding", "read": "input", "coil": "coil", "discrete_input": "discrete_input"}
PLATFORMS = ("sensor", "binary_sensor", "text_sensor", "number", "select", "switch")
NORMAL_PERIOD = 10.0  # seconds: regmap's ESPHome back end reads normal registers every 10 s
STATIC_SKIP = 65535  # ESPHome's skip_updates is a uint16: this many means "read at boot, then hardly ever"
_INTERVAL = re.compile(r"^\s*([0-9]+(?:\.[0-9]+)?)\s*(ms|s|min|h)?\s*$")
_SECONDS = {"ms": 0.001, "s": 1.0, "min": 60.0, "h": 3600.0, None: 1.0}


def seconds(value: Any) -> float | None:
    """An ESPHome time period (`10s`, `500ms`, `1min`, a bare number of seconds) in seconds; None when it is not one."""
    if isinstance(value, bool):
        return None
    if isinstance(value, int | float):
        return float(value)
    match = _INTERVAL.match(str(value))
    return float(match.group(1)) * _SECONDS[match.group(2)] if match else None


def skip_poll_class(skip: int, interval: float, writable: bool) -> str:
    """The map's poll class of an entity read every `skip`+1 updates of `interval` seconds."""
    return poll_class(STATIC_PERIOD if skip >= STATIC_SKIP else interval * (skip + 1), writable, NORMAL_PERIOD)


class _Reader(ConfigReader):
    def __init__(self, config: Config) -> None:
        super().__init__(config)
        data = config.data if isinstance(config.data, dict) else {}
        subs = data.get("substitutions")
        self.substitutions = {str(k): str(v) for k, v in subs.items() if not isinstance(v, dict | list)} if isinstance(subs, dict) else {}
        self.unresolved: set[str] = set()
        self.devices_found: list[Device] = []
        self.data = substitute(data, self.substitutions, self.unresolved)

    def devices(self) -> Import:
        if not isinstance(self.config.data, dict):
            self.fail((), "an ESPHome config is a mapping (substitutions:, modbus_controller:, sensor: ...)")
            raise ConfigError(self.problems)
        controllers = self._controllers()
        for platform in PLATFORMS:
            entities = self.data.get(platform) or []
            if not isinstance(entities, list):
                self.fail((platform,), f"{platform}: expected a list of entities")
                continue
            for i, entity in enumerate(entities):
                self._entity(controllers, platform, entity, (platform, i))
        if "packages" in self.data:
            self.report.append(f"{self.where(('packages',))}: packages are not followed (an !include is never opened); import each file")
        for key in sorted(self.unresolved):
            self.report.append(f"{self.config.name}: substitution ${{{key}}} is not given in the file: left as written")
        if self.problems:
            raise ConfigError(self.problems)
        return Import(self.devices_found, self.report)

    def _controllers(self) -> dict[str | None, Device]:
        raw = self.data.get("modbus_controller")
        items = raw if isinstance(raw, list) else [raw] if isinstance(raw, dict) else []
        if not items:
            self.fail(("modbus_controller",) if raw is not None else (), "no modbus_controller: this is not an ESPHome Modbus config")
            raise ConfigError(self.problems)
        serial = self._serial()
        controllers: dict[str | None, Device] = {}
        for i, item in enumerate(items):
            path = ("modbus_controller", i) if isinstance(raw, list) else ("modbus_controller",)
            if not isinstance(item, dict):
                self.fail(path, "a modbus_controller entry is a mapping")
                continue
            slave = item.get("address", 1)
            if isinstance(slave, bool) or not isinstance(slave, int) or not 0 < slave < 248:
                self.fail((*path, "address"), f"modbus_controller address {slave!r}: expected a slave id 1..247")
                slave = 1
            interval = seconds(item.get("update_interval", "60s"))
            device = Device(label=str(item.get("id") or f"controller {slave}"), slave=slave, serial=dict(serial))
            device.interval = interval if interval is not None else 60.0
            self.devices_found.append(device)
            controllers[str(item["id"]) if item.get("id") is not None else None] = device
        if len(self.devices_found) == 1:
            controllers[None] = self.devices_found[0]  # entities may leave out modbus_controller_id
        return controllers

    def _serial(self) -> dict[str, Any]:
        uart = self.data.get("uart")
        uart = uart[0] if isinstance(uart, list) and uart else uart
        if not isinstance(uart, dict):
            return {}
        out: dict[str, Any] = {}
        if isinstance(uart.get("baud_rate"), int):
            out["baud"] = uart["baud_rate"]
        parity = str(uart.get("parity", "NONE")).lower()
        if parity in ("none", "even", "odd"):
            out["parity"] = parity
        if uart.get("stop_bits") in (1, 2):
            out["stop_bits"] = uart["stop_bits"]
        return out

    def _entity(self, controllers: dict[str | None, Device], platform: str, entity: Any, path: tuple[str | int, ...]) -> None:
        if not isinstance(entity, dict):
            self.fail(path, f"{platform} entry: expected a mapping")
            return
        if entity.get("platform") != "modbus_controller":
            return
        device = controllers.get(str(entity["modbus_controller_id"]) if "modbus_controller_id" in entity else None)
        if device is None:
            self.fail(
                (*path, "modbus_controller_id"), f"modbus_controller_id {entity.get('modbus_controller_id')!r} names no modbus_controller"
            )
            return
        origin = self.where(path)
        label = str(entity.get("name") or entity.get("id") or f"{platform} {path[-1]}")
        if "custom_command" in entity:
            self.report.append(f"{origin}: {label}: custom_command is not a register read: not imported")
            return
        address = self._address(entity, path)
        if address is None:
            return
        reg = self._register(device, platform, entity, path, origin, address)
        problem = device.add(reg) if reg is not None else None
        if problem is not None:
            self.report.append(f"{origin}: not imported: {problem}")

    def _address(self, entity: dict[str, Any], path: tuple[str | int, ...]) -> int | None:
        address = entity.get("address")
        if isinstance(address, bool) or not isinstance(address, int) or not 0 <= address <= 0xFFFF:
            self.fail((*path, "address"), f"address {address!r}: expected a register address 0..0xFFFF")
            return None
        offset = entity.get("offset", 0)
        bits = entity.get("register_type", "holding") in ("coil", "discrete_input")
        if isinstance(offset, bool) or not isinstance(offset, int) or offset < 0 or (offset % 2 and not bits):
            self.fail((*path, "offset"), f"offset {offset!r}: a byte offset into the read; regmap reads whole registers (an even offset)")
            return None
        return address + (offset if bits else offset // 2)  # ESPHome: bytes into the read, a coil's position for bits

    def _register(
        self, device: Device, platform: str, entity: dict[str, Any], path: tuple[str | int, ...], origin: str, address: int
    ) -> Imported | None:
        raw = self._raw(path)  # before substitution: `${x_device_id}_speed` names the register `speed`
        key = str(raw.get("id") or raw.get("name") or f"{platform}_{address:04x}")
        title = looks(re.sub(r"^\$\{[^}]*\}", "", str(raw.get("name") or ""))) or identifier(key, "register")
        register_type = entity.get("register_type", "holding")
        if platform == "select":
            register_type = "holding"
        if register_type not in REGISTER_TYPE:
            self.fail((*path, "register_type"), f"register_type {register_type!r}: expected one of {', '.join(REGISTER_TYPE)}")
            return None
        space = REGISTER_TYPE[register_type]
        writable = platform in ("number", "select", "switch")
        reg = Imported(key=key, title=title, address=address, space=space, type="u16", origin=origin, writable=writable)
        bits = space in ("coil", "discrete_input")
        if bits:
            reg.type = "bool"
        elif platform == "text_sensor":
            reading = self._text(reg, entity, path)
            if reading is None:
                return None
            if reading == "labels":
                entity = {k: v for k, v in entity.items() if k != "filters"}  # the map filter became the labels
        elif platform in ("sensor", "number", "select") or "value_type" in entity:
            value_type = entity.get("value_type", "U_WORD")
            if value_type not in VALUE_TYPE:
                self.fail((*path, "value_type"), f"value_type {value_type!r}: expected one of {', '.join(VALUE_TYPE)}")
                return None
            reg.type, reg.word_order = VALUE_TYPE[value_type]
        if "bitmask" in entity or (platform in ("binary_sensor", "switch") and not bits):
            self._bitmask(reg, entity, path, platform)
        if platform == "sensor":
            self._filters(reg, entity, path)
        elif platform == "number":
            self._number(reg, entity, path)
        elif platform == "select":
            self._select(reg, entity, path)
        if platform in ("binary_sensor", "switch", "text_sensor") and entity.get("filters"):
            self._notes(reg, f"filters {_text(entity['filters'])} (not part of the register's reading)", origin)
        for code in ("lambda", "write_lambda"):
            if code in entity:
                self._notes(reg, f"ESPHome {code} kept as text, not run: {_text(entity[code])}", origin, f"{code} kept as a note")
        if entity.get("force_new_range") is True:
            self._notes(reg, "force_new_range: ESPHome starts a new read at this register", origin, "force_new_range kept as a note")
        if entity.get("unit_of_measurement") and reg.type != "string":
            reg.unit = looks(str(entity["unit_of_measurement"]))
        skip = entity.get("skip_updates", 0)
        if isinstance(skip, int) and not isinstance(skip, bool) and skip >= 0:
            reg.poll = skip_poll_class(skip, device.interval, writable)
        else:
            self.fail((*path, "skip_updates"), f"skip_updates {skip!r}: expected a count of updates (0..65535)")
        return reg

    def _raw(self, path: tuple[str | int, ...]) -> dict[str, Any]:
        node: Any = self.config.data
        for step in path:
            node = node[step]
        return node if isinstance(node, dict) else {}

    def _notes(self, reg: Imported, note: str, origin: str, reported: str | None = None) -> None:
        reg.notes.append(note)
        self.report.append(f"{origin}: {reg.key}: {reported or note}")

    def _bitmask(self, reg: Imported, entity: dict[str, Any], path: tuple[str | int, ...], platform: str) -> None:
        mask = entity.get("bitmask", 1)
        limit = (1 << (16 * reg.width)) - 1
        if isinstance(mask, bool) or not isinstance(mask, int) or not mask > 0:
            self.fail((*path, "bitmask"), f"bitmask {mask!r}: expected a positive integer")
            return
        if mask >= limit and platform not in ("binary_sensor", "switch"):
            return  # ESPHome's default for a sensor: the whole value
        if mask > limit:
            self.fail((*path, "bitmask"), f"bitmask 0x{mask:X} is wider than the {16 * reg.width}-bit register")
            return
        raw = self._raw(path)
        name = str(raw.get("name") or raw.get("id") or f"bit_{mask:x}")
        field_title = looks(re.sub(r"^\$\{[^}]*\}", "", name))
        head, sep, tail = field_title.rpartition(": ")
        reg.flags.append(Flag(key=identifier(str(raw.get("id") or name), "bit"), mask=mask, title=tail if sep else field_title))
        reg.title = head if sep else f"0x{reg.address:04X} bits"
        reg.key = f"{reg.space}_{reg.address:04x}" if not sep else identifier(head, "register")

    def _text(self, reg: Imported, entity: dict[str, Any], path: tuple[str | int, ...]) -> str | None:
        """Read a text sensor: `text` (a string register), `labels` (HEXBYTES mapped to labels: an enum) or None (a problem)."""
        encode = entity.get("raw_encode", "NONE")
        words = entity.get("register_count")
        size = entity.get("response_size")
        if words is None and isinstance(size, int) and not isinstance(size, bool):
            words = (size + 1) // 2
        if isinstance(words, bool) or not isinstance(words, int) or words < 1:
            self.fail((*path, "register_count"), "a text_sensor needs register_count (or response_size): how many registers it reads")
            return None
        if encode == "HEXBYTES" and words in (1, 2, 4) and _maps(entity.get("filters")):
            reg.type = {1: "u16", 2: "u32", 4: "u64"}[words]
            for source, target in _maps(entity.get("filters")):
                try:
                    value = int(source, 16)
                except ValueError:
                    self.fail((*path, "filters"), f"map entry {source!r}: HEXBYTES text is hex digits")
                    continue
                reg.members.append(Member(value=value, title=looks(target), writable=False))
            return "labels"
        reg.type, reg.words = "string", words
        if encode not in ("ANSI", "NONE"):
            reg.notes.append(f"raw_encode {encode}: ESPHome shows the bytes as {encode.lower()}, regmap reads them as text")
        return "text"

    def _filters(self, reg: Imported, entity: dict[str, Any], path: tuple[str | int, ...]) -> None:
        filters = entity.get("filters") or []
        if not isinstance(filters, list):
            self.fail((*path, "filters"), "filters: expected a list")
            return
        scale, offset = Fraction(1), Fraction(0)
        kept: list[str] = []
        linear = True  # multiply and offset after another filter are not the register's scale
        for i, item in enumerate(filters):
            name, arg = next(iter(item.items())) if isinstance(item, dict) and len(item) == 1 else (item, None)
            number = isinstance(arg, int | float) and not isinstance(arg, bool)
            if linear and name == "multiply" and number:
                scale, offset = scale * fraction(arg), offset * fraction(arg)
            elif linear and name == "offset" and number:
                offset += fraction(arg)
            else:
                linear = False
                kept.append(_text(item))
                if name in ("multiply", "offset") and not number:
                    self.fail((*path, "filters", i, str(name)), f"{name}: expected a number, got {arg!r}")
        if reg.type in ("u16", "s16", "u32", "s32", "u64", "s64", "f32", "f64"):
            reg.scale, reg.offset = scale, offset
        if kept:
            self._notes(
                reg, "ESPHome filters kept as text: " + "; ".join(kept), self.where(path), "filters kept as a note: " + "; ".join(kept)
            )

    def _number(self, reg: Imported, entity: dict[str, Any], path: tuple[str | int, ...]) -> None:
        multiply = entity.get("multiply", 1)
        if isinstance(multiply, bool) or not isinstance(multiply, int | float) or multiply == 0:
            self.fail((*path, "multiply"), f"multiply {multiply!r}: expected a non-zero number")
            return
        reg.scale = 1 / fraction(multiply)
        for key, attr in (("min_value", "min"), ("max_value", "max")):
            value = entity.get(key)
            if isinstance(value, bool) or not isinstance(value, int | float):
                continue
            raw = fraction(value) * fraction(multiply)
            if reg.type == "f32":
                setattr(reg, attr, float(raw))
            elif raw.denominator == 1:
                setattr(reg, attr, int(raw))
            else:
                reg.notes.append(f"{key} {value} is raw {float(raw)}, not an integer: no {attr}")

    def _select(self, reg: Imported, entity: dict[str, Any], path: tuple[str | int, ...]) -> None:
        options = entity.get("optionsmap")
        if not isinstance(options, dict) or not options:
            self.fail((*path, "optionsmap"), "a select needs optionsmap: {label: value}")
            return
        for label, value in options.items():
            if isinstance(value, bool) or not isinstance(value, int):
                self.fail((*path, "optionsmap", label), f"option {label!r}: expected an integer value, got {value!r}")
                continue
            reg.members.append(Member(value=value, title=looks(str(label))))


def looks(text: str) -> str:
    """Text with the look-alikes regmap's ESPHome back end writes for `/` and `$` (`esp_text`) turned back."""
    return text.replace("\u2044", "/").replace("\uff04", "$")


def _maps(filters: Any) -> list[tuple[str, str]]:
    """The `from`/`to` pairs of a text sensor's `map` filters (ESPHome: `- map: ["a -> b", ...]`, or from/to mappings)."""
    pairs: list[tuple[str, str]] = []
    for item in filters if isinstance(filters, list) else []:
        if not isinstance(item, dict) or not isinstance(item.get("map"), list):
            return []
        for entry in item["map"]:
            if isinstance(entry, dict) and "from" in entry and "to" in entry:
                pairs.append((str(entry["from"]), str(entry["to"])))
            elif isinstance(entry, str) and " -> " in entry:
                source, _, target = entry.partition(" -> ")
                pairs.append((source.strip(), target.strip()))
            else:
                return []
    return pairs


def _text(value: Any) -> str:
    """A config value as one line of text for a note (a lambda's code, a filter)."""
    if isinstance(value, Tagged):
        value = value.value
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k}: {_text(v)}" for k, v in value.items()) + "}"
    if isinstance(value, list):
        return "[" + ", ".join(_text(v) for v in value) + "]"
    return " ".join(str(value).split())


def read_esphome(config: Config) -> Import:
    """The devices of an ESPHome config (one per modbus_controller) and the report; ConfigError lists every problem at file:line:col."""
    return _Reader(config).devices()
