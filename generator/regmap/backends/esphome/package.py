"""The ESPHome package of one map: `modbus_controller` on a UART, an entity per selected register, a button per command.

Everything is computed here as plain data and dumped by `homeauto.dump`; map text only ever lands in
string values (`name`, units, option labels), with `$` replaced so ESPHome's substitution and Jinja
pass cannot evaluate it.

Read ranges: ESPHome merges entities at contiguous addresses into one read (`create_register_ranges_`)
and gives a range the smallest non-zero `skip_updates` of its entities. The package follows the read
plan of `runtime_bridge.read_plan`: where two plan requests touch, the first register of the second
gets `force_new_range` (ESPHome then reads it alone and starts the next range after it), so no ESPHome
range is longer than a plan request or spans an address the plan does not read. A plan request whose
registers are all settings is polled every `<id>_parameter_skip_updates`+1 updates, others every update.
"""

from __future__ import annotations

from typing import Any

from regmap.backends.homeauto import (
    DEVICE_CLASS,
    Hex,
    Lambda,
    Names,
    decimals,
    dump,
    flags,
    is_parameter,
    scale_float,
    single_flag,
    unit_text,
)
from regmap.backends.selection import Selection
from regmap.generate import Files
from regmap.model import Command, DataType, Device, Register, WordOrder
from regmap.runtime_bridge import read_plan

# ESPHome's spelling of a register's type: (type, word order) -> value_type.
VALUE_TYPE = {
    (DataType.U16, WordOrder.HIGH_FIRST): "U_WORD",
    (DataType.U16, WordOrder.LOW_FIRST): "U_WORD",
    (DataType.S16, WordOrder.HIGH_FIRST): "S_WORD",
    (DataType.S16, WordOrder.LOW_FIRST): "S_WORD",
    (DataType.U32, WordOrder.HIGH_FIRST): "U_DWORD",
    (DataType.U32, WordOrder.LOW_FIRST): "U_DWORD_R",
    (DataType.S32, WordOrder.HIGH_FIRST): "S_DWORD",
    (DataType.S32, WordOrder.LOW_FIRST): "S_DWORD_R",
}
PARITY = {"none": "NONE", "even": "EVEN", "odd": "ODD"}
NUMBER_LIMIT = 16777215  # ESPHome's number keeps min/max within 24 bits (float precision)
MAX_BUTTONS_PER_COMMAND = 16  # a command with an argument gets a button per value, up to this many
UPDATE_INTERVAL = "10s"
PARAMETER_SKIP_UPDATES = 29  # settings every 30th update: 5 minutes at the default interval


def esp_text(text: str) -> str:
    """Map text as an ESPHome string: `$` would start a substitution or a Jinja expression, and ESPHome
    reserves `/` in names (URL paths); both become their look-alikes."""
    return " ".join(text.split()).replace("$", "\uff04").replace("/", "\u2044")


class _Package:
    def __init__(self, device: Device, selection: Selection) -> None:
        self.device = device
        self.selection = selection
        self.prefix = device.id
        self.controller = f"{device.id}_controller"
        self.names = Names(esp_text)
        t = device.transport
        self.register_type = "holding" if 0x03 in t.function_codes else "read"
        self.single_write = 0x06 in t.function_codes
        self.skipped: list[str] = []
        self.entities: dict[str, list[dict[str, Any]]] = {}
        self.item_keys: dict[str, dict[str, Any]] = self._ranges()

    def sub(self, name: str) -> str:
        return "${" + self.prefix + "_" + name + "}"

    # -- read ranges -------------------------------------------------------------------------

    def _entity_registers(self) -> list[Register]:
        return [r for r in self.selection.registers if r.access.readable]

    def _ranges(self) -> dict[str, dict[str, Any]]:
        """Per register, the range keys of its entities: `force_new_range`, `skip_updates`."""
        keys: dict[str, dict[str, Any]] = {}
        previous_end: int | None = None
        for block in read_plan(self.device, self._entity_registers()):
            regs = [self.device.register(s.name) for s in block.registers]
            slow = all(is_parameter(r) for r in regs)
            for i, reg in enumerate(regs):
                item: dict[str, Any] = {}
                if i == 0 and previous_end == reg.address:
                    item["force_new_range"] = True
                if slow:
                    item["skip_updates"] = self.sub("parameter_skip_updates")
                keys[reg.name] = item
                previous_end = reg.address + reg.words
        return keys

    def _item(self, reg: Register, **extra: Any) -> dict[str, Any]:
        return {
            "modbus_controller_id": self.controller,
            "register_type": self.register_type,
            "address": Hex(reg.address),
            **extra,
            **self.item_keys[reg.name],
        }

    # -- entities ----------------------------------------------------------------------------

    def add(self, platform: str, entity: dict[str, Any]) -> None:
        self.entities.setdefault(platform, []).append(entity)

    def register(self, reg: Register) -> None:
        if not reg.access.readable:
            self.skipped.append(f"{reg.name} (write-only: ESPHome's number/select/switch read their register back)")
            return
        if reg.bitfields:
            self._bitfields(reg)
        elif reg.enum is not None:
            self._enum(reg)
        elif reg.access.writable and reg.raw_min < reg.raw_max:
            self._number(reg)
        else:
            self._sensor(reg)

    def _name(self, title: str, qualifier: str) -> str:
        return self.names.name(title, qualifier)

    def _value_type(self, reg: Register) -> str:
        return VALUE_TYPE[(reg.type, reg.word_order)]

    def _sensor(self, reg: Register) -> None:
        entity: dict[str, Any] = {"platform": "modbus_controller", "name": self._name(reg.title, reg.name)}
        entity.update(self._item(reg, value_type=self._value_type(reg)))
        if reg.unit:
            entity["unit_of_measurement"] = unit_text(esp_text(reg.unit))
            if reg.unit in DEVICE_CLASS:
                entity["device_class"] = DEVICE_CLASS[reg.unit]
        entity["accuracy_decimals"] = decimals(reg.scale)
        if not reg.access.writable:
            entity["state_class"] = "measurement"
        if reg.scaled:
            entity["filters"] = [{"multiply": scale_float(reg.scale)}]
        self.add("sensor", entity)

    def _number(self, reg: Register) -> None:
        low, high = (max(-NUMBER_LIMIT, float(reg.raw_min * reg.scale)), min(NUMBER_LIMIT, float(reg.raw_max * reg.scale)))
        entity: dict[str, Any] = {"platform": "modbus_controller", "name": self._name(reg.title, reg.name)}
        entity.update(self._item(reg, value_type=self._value_type(reg)))
        entity.update({"min_value": _num(low), "max_value": _num(high), "step": scale_float(reg.scale)})
        if reg.scaled:
            entity["multiply"] = scale_float(1 / reg.scale)  # ESPHome: raw = value x multiply, value = raw / multiply
        if reg.words == 1 and not self.single_write:
            entity["use_write_multiple"] = True
        if reg.unit:
            entity["unit_of_measurement"] = unit_text(esp_text(reg.unit))
        entity["mode"] = "box"
        self.add("number", entity)

    def _options(self, reg: Register) -> list[tuple[str, int]]:
        assert reg.enum is not None
        labels: list[tuple[str, int]] = []
        seen: set[str] = set()
        for member in reg.enum.members:
            label = esp_text(member.title) or member.name
            if label in seen:
                label = f"{label} ({member.value})"
            seen.add(label)
            labels.append((label, member.value))
        return labels

    def _enum(self, reg: Register) -> None:
        options = self._options(reg)
        if reg.access.writable:
            entity: dict[str, Any] = {"platform": "modbus_controller", "name": self._name(reg.title, reg.name)}
            entity.update(self._item(reg, value_type=self._value_type(reg)))
            entity["optionsmap"] = dict(options)
            if reg.words == 1 and not self.single_write:
                entity["use_write_multiple"] = True
            del entity["register_type"]  # select only talks to holding registers
            self.add("select", entity)
            return
        # Read-only: the register's bytes as hex (`raw_encode: HEXBYTES`), mapped to the manual's labels.
        entity = {"platform": "modbus_controller", "name": self._name(reg.title, reg.name)}
        entity.update(self._item(reg, response_size=2 * reg.words, raw_encode="HEXBYTES"))
        entity["filters"] = [{"map": [{"from": hexbytes(reg, value), "to": label} for label, value in options]}]
        self.add("text_sensor", entity)

    def _bitfields(self, reg: Register) -> None:
        flag = single_flag(reg)
        if flag is not None and reg.access.writable and reg.words == 1:
            entity: dict[str, Any] = {"platform": "modbus_controller", "name": self._name(f"{reg.title}: {flag.title}", reg.name)}
            entity.update(self._item(reg, bitmask=Hex(flag.mask)))
            if not self.single_write:
                entity["use_write_multiple"] = True
            self.add("switch", entity)
            return
        for field in reg.bitfields:
            name = self._name(f"{reg.title}: {field.title}", f"{reg.name}.{field.name}")
            if field in flags(reg) and reg.words == 1:  # a binary_sensor reads one word; 32-bit flags are sensors
                entity = {"platform": "modbus_controller", "name": name}
                entity.update(self._item(reg, bitmask=Hex(field.mask, 4 * reg.words)))
                self.add("binary_sensor", entity)
            else:
                entity = {"platform": "modbus_controller", "name": name}
                entity.update(self._item(reg, value_type=self._value_type(reg), bitmask=Hex(field.mask, 4 * reg.words)))
                entity["accuracy_decimals"] = 0
                self.add("sensor", entity)

    def command(self, command: Command) -> None:
        arg = command.argument
        if arg is None:
            self._button(command, command.title, command.raw_value())
        elif arg.max - arg.min + 1 <= MAX_BUTTONS_PER_COMMAND:
            for value in range(arg.min, arg.max + 1):
                self._button(command, f"{command.title} {arg.name} {value}", command.raw_value(value))
        else:
            self.skipped.append(f"command {command.name} (its argument has more than {MAX_BUTTONS_PER_COMMAND} values)")

    def _button(self, command: Command, title: str, raw: int) -> None:
        reg = command.register
        words = _words(reg, raw)
        ctrl = f"id({self.controller})"
        if len(words) == 1 and self.single_write:
            make = f"create_write_single_command({ctrl}, 0x{reg.address:04X}, 0x{words[0]:04X})"
        else:
            values = ", ".join(f"0x{w:04X}" for w in words)
            make = f"create_write_multiple_command({ctrl}, 0x{reg.address:04X}, {len(words)}, {{{values}}})"
        code = f"{ctrl}->queue_command(esphome::modbus_controller::ModbusCommandItem::{make});"
        self.add("button", {"platform": "template", "name": self._name(title, command.name), "on_press": [{"lambda": Lambda(code)}]})

    # -- the file ----------------------------------------------------------------------------

    def data(self) -> dict[str, Any]:
        t = self.device.transport
        slave = 1 if t.slave_min <= 1 <= t.slave_max else t.slave_min
        p = self.prefix
        for reg in self.selection.registers:
            self.register(reg)
        for command in self.selection.commands:
            self.command(command)
        out: dict[str, Any] = {
            "substitutions": {
                f"{p}_tx_pin": "GPIO17",
                f"{p}_rx_pin": "GPIO16",
                f"{p}_baud_rate": str(t.baud),
                f"{p}_slave_id": str(slave),
                f"{p}_update_interval": UPDATE_INTERVAL,
                f"{p}_parameter_skip_updates": str(PARAMETER_SKIP_UPDATES),
            },
            "uart": [
                {
                    "id": f"{p}_uart",
                    "tx_pin": self.sub("tx_pin"),
                    "rx_pin": self.sub("rx_pin"),
                    "baud_rate": self.sub("baud_rate"),
                    "data_bits": t.data_bits,
                    "parity": PARITY[t.parity],
                    "stop_bits": t.stop_bits,
                }
            ],
            "modbus": [{"id": f"{p}_modbus", "uart_id": f"{p}_uart"}],
            "modbus_controller": [
                {
                    "id": self.controller,
                    "modbus_id": f"{p}_modbus",
                    "address": self.sub("slave_id"),
                    "update_interval": self.sub("update_interval"),
                }
            ],
        }
        for platform in ("sensor", "binary_sensor", "text_sensor", "number", "select", "switch", "button"):
            if platform in self.entities:
                out[platform] = self.entities[platform]
        return out


def _num(value: float) -> float | int:
    return int(value) if value == int(value) else value


def _words(reg: Register, raw: int) -> list[int]:
    """The wire words of a raw value, in the register's word order."""
    unsigned = raw & ((1 << reg.type.bits) - 1)
    words = [(unsigned >> (16 * i)) & 0xFFFF for i in reversed(range(reg.words))]
    return words if reg.word_order is WordOrder.HIGH_FIRST else words[::-1]


def hexbytes(reg: Register, raw: int) -> str:
    """What ESPHome's `raw_encode: HEXBYTES` makes of a register holding `raw`: its wire bytes, `%02x` each."""
    return "".join(f"{w:04x}" for w in _words(reg, raw))


def package(device: Device, selection: Selection) -> dict[str, Any]:
    """The package's content as data (the tests read the entities from it, as ESPHome does from the file)."""
    return _Package(device, selection).data()


def render_package(device: Device, selection: Selection) -> Files:
    pkg = _Package(device, selection)
    data = pkg.data()
    t = device.transport
    about = [
        "",
        f"ESPHome package for {device.info.vendor} {device.info.model}: modbus_controller on a UART, entities from the map.",
        f"Include it: packages: {{{device.id}: !include {device.id}.yaml}} and override the substitutions "
        f"({device.id}_tx_pin, {device.id}_rx_pin, {device.id}_slave_id, ...) in your config.",
        f"Serial line from the map: {t.baud} baud, {t.data_bits} data bits, parity {t.parity}, {t.stop_bits} stop bit(s).",
        f"Reads follow the map's read plan (at most {t.max_read_registers} registers a request, no undocumented address).",
        f"32-bit values assume the device's factory word order ({t.word_order.value}).",
        f"Selection: {selection.rule} ({len(selection.registers)} registers, {len(selection.commands)} commands).",
    ]
    about += [f"Not generated: {s}" for s in pkg.skipped]
    return {f"{device.id}.yaml": dump(device, about, data)}
