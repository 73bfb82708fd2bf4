"""The ESPHome package of one map: `modbus_controller` on a UART, an entity per selected register, a button per command.

Everything is computed here as plain data and dumped by `homeauto.entities.dump`; map text only ever lands in
string values (`name`, units, option labels), with `$` replaced so ESPHome's substitution and Jinja
pass cannot evaluate it.

Read ranges: ESPHome merges entities at contiguous addresses into one read (`create_register_ranges_`)
and gives a range the smallest non-zero `skip_updates` of its entities. The package follows the read
plan of `runtime_bridge.read_plan`: where two plan requests touch, the first register of the second
gets `force_new_range` (ESPHome then reads it alone and starts the next range after it), so no ESPHome
range is longer than a plan request or spans an address the plan does not read. A plan request whose
registers are all settings is polled every `<id>_parameter_skip_updates`+1 updates, others every update.

Spaces: `register_type` holding / read (input registers) / coil / discrete_input; coils and discrete
inputs are binary sensors, a writable coil a switch. Types: U_/S_WORD, U_/S_DWORD(_R), U_/S_QWORD(_R),
FP32(_R); ESPHome has no FP64 and no byte-swap type, so doubles and byte-swapped values are read by a
`lambda` (`lambdas.py`, from integers only) over the register's bytes, and a byte-swapped 16-bit number
writes through a `write_lambda`; a byte-swapped value of more than one word, or a double, is not
writable from ESPHome (its sensor is generated; the file's header says so). Text: a text_sensor with
`register_count`/`response_size` and a lambda that reads it as the Python client does (GBK text is
not decoded on the device: listed as not generated). Scale and offset: `filters: multiply`, then `offset`.

Poll classes (`skip_updates`; a range takes the smallest non-zero skip of its items, so no range mixes
classes): fast registers every update; normal ones every update (settings every
`parameter_skip_updates`+1); slow every `slow_skip_updates`+1; static once at boot (ESPHome reads each
range at its first update) and then only after `static_skip_updates` (65535) updates. A map with fast
registers updates every 5 s and skips normal ones every other update, so the rates stay 10 s normal,
300 s settings, 60 s slow. Reads never mix firmware gates either (a register the firmware lacks fails
only its own range); the header lists which entities need which firmware.
"""

from __future__ import annotations

from typing import Any

from regmap.backends.esphome import lambdas, scaled
from regmap.backends.esphome.text import esp_text, esp_unit, num
from regmap.core.text import na_list
from regmap.homeauto.entities import (
    MAX_NAME_BYTES,
    Ids,
    Names,
    command_category,
    command_throttle_ms,
    device_class,
    dump,
    entity_category,
    flags,
    gate_notes,
    is_parameter,
    planned,
    presses,
    reserved,
    scale_float,
    shown_decimals,
    single_flag,
    state_class,
    swap_word,
    swapped,
    too_many_presses,
    unit_text,
    writable_members,
)
from regmap.homeauto.selection import Selection
from regmap.homeauto.yamltext import Hex, Lambda
from regmap.model import Command, DataType, Device, EnumMember, FirmwareGate, PollClass, Register, WordOrder
from regmap.runtime_bridge import runtime_alignment, wire_specs
from regmap.target import Files
from regmap_runtime.codec import raw_to_words
from regmap_runtime.plan import ReadBlock

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
    (DataType.U64, WordOrder.HIGH_FIRST): "U_QWORD",
    (DataType.U64, WordOrder.LOW_FIRST): "U_QWORD_R",
    (DataType.S64, WordOrder.HIGH_FIRST): "S_QWORD",
    (DataType.S64, WordOrder.LOW_FIRST): "S_QWORD_R",
    (DataType.F32, WordOrder.HIGH_FIRST): "FP32",
    (DataType.F32, WordOrder.LOW_FIRST): "FP32_R",
    (DataType.TIMESTAMP, WordOrder.HIGH_FIRST): "U_DWORD",
    (DataType.TIMESTAMP, WordOrder.LOW_FIRST): "U_DWORD_R",
}
# A value a lambda decodes is still given a type of its size, so that ESPHome reads the right count of registers.
SIZED = {1: "U_WORD", 2: "U_DWORD", 4: "U_QWORD"}
REGISTER_TYPE = {"input": "read", "coil": "coil", "discrete_input": "discrete_input"}  # holding: see DevicePackage
MAX_RANGE_BITS = 255  # ESPHome counts a range's coils in a uint8_t
FAST_UPDATE_INTERVAL = "5s"
SKIPS = {  # substitution -> (skip without fast registers at 10 s, with them at 5 s)
    "normal_skip_updates": (0, 1),
    "parameter_skip_updates": (29, 59),
    "slow_skip_updates": (5, 11),
    "static_skip_updates": (65535, 65535),
}
PARITY = {"none": "NONE", "even": "EVEN", "odd": "ODD"}
NUMBER_LIMIT = 16777215  # ESPHome's number keeps min/max within 24 bits (float precision)
UPDATE_INTERVAL = "10s"
NAME_PREFIX_BYTES = 24  # names leave room for a `<id>_name_prefix` this long within ESPHome's 120 bytes
# ESPHome's modbus_controller re-sends a request nobody answered `max_cmd_retries` times (default 4:
# `should_retry` allows send_count <= max). The count belongs to the controller, and a second controller
# for the same address on one bus would take the other's responses (modbus.cpp hands each frame to every
# device with that address), so the one controller of a device sends every request once: a lost reply
# to a command is not answered by sending the command again; a lost read costs one update.
MAX_CMD_RETRIES = 0
READ_ONLY_PLATFORMS = ("sensor", "binary_sensor", "text_sensor")
PLATFORMS = ("sensor", "binary_sensor", "text_sensor", "number", "select", "switch", "button")
COMMAND_THROTTLE_FLOOR_MS = 50  # between two requests to one device; longer when the map documents a slower device


class DevicePackage:
    """One map's entities and controller; `prefix` names its substitutions (the map's id, or in a plant the
    device's name, so that one map appears twice)."""

    def __init__(self, device: Device, selection: Selection, prefix: str | None = None) -> None:
        self.device = device
        self.selection = selection
        self.prefix = prefix or device.id
        self.controller = self.sub("device_id") + "_controller"
        # Names leave room for the `<prefix>_name_prefix` (a plant sets it to the device's name and a space).
        self.names = Names(esp_text, MAX_NAME_BYTES - max(NAME_PREFIX_BYTES, len(self.prefix) + 1))
        self.ids = Ids(("controller",))
        t = device.transport
        self.register_type = "holding" if 0x03 in t.function_codes else "read"
        self.single_write = 0x06 in t.function_codes
        self.single_coil_write = 0x05 in t.function_codes
        self.specs = {spec.name: spec for spec in wire_specs(device)}
        self.skipped: list[str] = []
        self.registers = scaled.with_factors(device, selection.registers)  # and the scale factors its points need
        self.added_factors = [r.name for r in self.registers[len(selection.registers) :]]
        self.made: dict[tuple[str, ...], tuple[str, dict[str, Any]]] = {}  # (platform, entity) by key
        self.scaled_points: list[tuple[Register, dict[str, Any], str]] = []
        readable = self._entity_registers()
        self.fast = any(r.poll is PollClass.FAST for r in readable)
        self.used_skips: set[str] = set()
        self.entities: dict[str, list[dict[str, Any]]] = {}
        self.item_keys: dict[str, dict[str, Any]] = self._ranges()

    def sub(self, name: str) -> str:
        return "${" + self.prefix + "_" + name + "}"

    # -- read ranges -------------------------------------------------------------------------

    def _entity_registers(self) -> list[Register]:
        return [r for r in self.registers if r.access.readable]

    def _skip(self, poll: PollClass, settings: bool) -> str | None:
        """The skip_updates substitution of a read of this class (None: every update)."""
        if poll is PollClass.FAST:
            return None
        key = {PollClass.SLOW: "slow_skip_updates", PollClass.STATIC: "static_skip_updates"}.get(poll)
        if key is None:
            key = "parameter_skip_updates" if settings else "normal_skip_updates"
        if SKIPS[key][1 if self.fast else 0] == 0:
            return None
        self.used_skips.add(key)
        return self.sub(key)

    def _ranges(self) -> dict[str, dict[str, Any]]:
        """Per register, the range keys of its entities: `force_new_range`, `skip_updates`. A register
        another read's register ends at starts a new range, so ESPHome never joins two reads."""
        keys: dict[str, dict[str, Any]] = {}
        self.blocks = blocks = planned(self.device, self._entity_registers(), MAX_RANGE_BITS)
        self.widened = self._widened(blocks)
        ends: dict[tuple[str, int], int] = {}
        for index, (block, _, _) in enumerate(blocks):
            for spec in block.registers:
                start, count = self.widened.get(spec.name, (spec.address, spec.words))
                ends[(spec.space, start + count)] = index
        for index, (block, poll, _) in enumerate(blocks):
            regs = [self.device.register(s.name) for s in block.registers]
            skip = self._skip(poll, all(is_parameter(r) for r in regs))
            for reg in regs:
                item: dict[str, Any] = {}
                start, count = self.widened.get(reg.name, (reg.address, reg.words))
                if start != reg.address or count != reg.words:
                    item.update(address=Hex(start), offset=2 * (reg.address - start), register_count=count)
                if ends.get((reg.space, start), index) != index:
                    item["force_new_range"] = True
                if skip is not None:
                    item["skip_updates"] = skip
                keys[reg.name] = item
        return keys

    def _widened(self, blocks: list[tuple[ReadBlock, PollClass, FirmwareGate | None]]) -> dict[str, tuple[int, int]]:
        """(address, register_count) of each register whose own words break the map's read alignment, widened to
        whole units: ESPHome joins items at contiguous addresses into one read, so items of whole units make
        aligned reads only. A register the map exempts and its planned read reads alone keeps its own words."""
        alignment = runtime_alignment(self.device)
        widened: dict[str, tuple[int, int]] = {}
        if alignment is None:
            return widened
        alone = {(b.space, b.address, b.count) for b, _, _ in blocks if len(b.registers) == 1}
        for block, _, _ in blocks:
            for spec in block.registers:
                first, end = spec.first_address, spec.address + spec.words
                if alignment.aligned(spec.space, first, end - first) or (spec.space, spec.address, spec.words) in alone:
                    continue
                low, high = alignment.extent(spec.space, first, end)
                widened[spec.name] = (low, high - low)
        return widened

    def _item(self, reg: Register, **extra: Any) -> dict[str, Any]:
        return {
            "modbus_controller_id": self.controller,
            "register_type": REGISTER_TYPE.get(reg.space, self.register_type),
            "address": Hex(reg.address),
            **extra,
            **self.item_keys[reg.name],
        }

    # -- entities ----------------------------------------------------------------------------

    def add(self, platform: str, entity: dict[str, Any], *key: str, category: str | None = None) -> None:
        """Add an entity with its id: `${<id>_device_id}_` and `key` (a register, field or command name)."""
        made = {"platform": entity.pop("platform"), "id": self.sub("device_id") + "_" + self.ids.id(*key), **entity}
        if category == "config" and platform in READ_ONLY_PLATFORMS:
            category = "diagnostic"  # ESPHome allows no `config` on what only reads: a setting it cannot write
        if category is not None:
            made["entity_category"] = category
        self.entities.setdefault(platform, []).append(made)
        if platform != "button":
            self.made[key] = (platform, made)

    def register(self, reg: Register) -> None:
        if reserved(reg.title):
            self.skipped.append(f"{reg.name} (reserved: the manual gives it no meaning)")
            return
        if not reg.access.readable:
            self.skipped.append(f"{reg.name} (write-only: ESPHome's number/select/switch read their register back)")
            return
        if reg.name in self.widened and reg.access.writable:
            self.skipped.append(
                f"{reg.name} (the device reads whole {self.widened[reg.name][1]}-word units, and ESPHome's number/select would write"
                " the whole unit it reads)"
            )
            return
        if reg.type.is_bool:
            self._bit(reg)
        elif reg.type.is_string:
            self._text(reg)
        elif reg.type.is_timestamp:
            self._time(reg)
        elif reg.bitfields:
            self._bitfields(reg)
        elif reg.enum is not None:
            self._enum(reg)
        elif reg.scale_from is not None:
            scaled.add_point(self, reg)
        elif reg.access.writable and reg.raw_min < reg.raw_max and self._writable(reg):
            self._number(reg)
        else:
            self._sensor(reg)

    def _writable(self, reg: Register) -> bool:
        """Whether ESPHome's number can write the register (else its sensor is generated, and the header says so)."""
        if reg.type in (DataType.F16, DataType.F64):
            bits = reg.type.bits
            self.skipped.append(f"writes of {reg.name} (ESPHome has no {bits}-bit float type; its sensor reads it)")
            return False
        if swapped(reg) and reg.words > 1:
            self.skipped.append(f"writes of {reg.name} (ESPHome writes no byte-swapped value wider than a word; its sensor reads it)")
            return False
        return True

    def _lambda(self, reg: Register) -> bool:
        """A value_type cannot say how to read it: a half float or a double (no FP16, FP64) or a byte-swapped value."""
        return reg.type in (DataType.F16, DataType.F64) or swapped(reg)

    def _bit(self, reg: Register) -> None:
        entity: dict[str, Any] = {"platform": "modbus_controller", "name": self._name(reg.title, reg.name)}
        entity.update(self._item(reg))
        category = entity_category(self.device, reg)
        if reg.access.writable and reg.space_info.writable:
            if not self.single_coil_write:
                entity["use_write_multiple"] = True
            self.add("switch", entity, reg.name, category=category)
        else:
            self.add("binary_sensor", entity, reg.name, category=category)

    def _text(self, reg: Register) -> None:
        if reg.encoding not in ("ascii", "latin-1", "utf-8"):
            self.skipped.append(f"{reg.name} ({reg.encoding} text: ESPHome has no decoder for it on the device)")
            return
        entity: dict[str, Any] = {"platform": "modbus_controller", "name": self._name(reg.title, reg.name)}
        entity.update(self._item(reg, register_count=reg.words, response_size=2 * reg.words, raw_encode="ANSI"))
        entity["lambda"] = Lambda(lambdas.text_lambda(reg))
        if reg.access.writable:
            self.skipped.append(f"writes of {reg.name} (ESPHome's modbus_controller has no text entity)")
        self.add("text_sensor", entity, reg.name, category=entity_category(self.device, reg))

    def _time(self, reg: Register) -> None:
        """A timestamp as ISO 8601 text (Home Assistant shows a utc one, device_class timestamp, as a time)."""
        entity: dict[str, Any] = {"platform": "modbus_controller", "name": self._name(reg.title, reg.name)}
        entity.update(self._item(reg, register_count=reg.words, response_size=2 * reg.words, raw_encode="NONE"))
        entity["lambda"] = Lambda(lambdas.time_lambda(reg))
        if reg.zone == "utc":  # a local time has no zone: Home Assistant's timestamp would need one, so it is plain text
            entity["device_class"] = "timestamp"
        if reg.access.writable:
            self.skipped.append(f"writes of {reg.name} (a timestamp: ESPHome's number would round 32-bit seconds to a float)")
        self.add("text_sensor", entity, reg.name, category=entity_category(self.device, reg))

    def _name(self, title: str, qualifier: str) -> str:
        """The entity's name after the `<id>_name_prefix` substitution (empty unless a config sets it)."""
        return self.sub("name_prefix") + self.names.name(title, qualifier)

    def _value_type(self, reg: Register) -> str:
        if self._lambda(reg):
            return SIZED[reg.words]
        return VALUE_TYPE[(reg.type, reg.word_order if reg.wide else WordOrder.HIGH_FIRST)]

    def _sensor(self, reg: Register) -> None:
        entity: dict[str, Any] = {"platform": "modbus_controller", "name": self._name(reg.title, reg.name)}
        # A "not available" marker is read through a lambda that gives NaN for it: ESPHome shows NaN as unknown.
        decoded = self._lambda(reg) or bool(reg.na)
        entity.update(self._item(reg, value_type=SIZED[reg.words] if decoded else self._value_type(reg)))
        if decoded:
            entity["lambda"] = Lambda(lambdas.raw_lambda(reg))
        if reg.unit:
            entity["unit_of_measurement"] = unit_text(esp_unit(reg.unit))
        if device_class(reg) is not None:
            entity["device_class"] = device_class(reg)
        entity["accuracy_decimals"] = shown_decimals(reg)
        if state_class(self.device, reg) is not None:
            entity["state_class"] = state_class(self.device, reg)
        filters: list[dict[str, Any]] = []
        if reg.scaled:
            filters.append({"multiply": scale_float(reg.scale)})
        if reg.offset_set:
            filters.append({"offset": scale_float(reg.offset)})
        if filters:
            entity["filters"] = filters
        self.add("sensor", entity, reg.name, category=entity_category(self.device, reg))

    def _number(self, reg: Register) -> None:
        if reg.has_na:
            self.skipped.append(f"{reg.name}'s 'not available' marker ({na_list(reg)}): ESPHome's number shows it as a value")
        low, high = (max(-NUMBER_LIMIT, float(reg.raw_min * reg.scale)), min(NUMBER_LIMIT, float(reg.raw_max * reg.scale)))
        entity: dict[str, Any] = {"platform": "modbus_controller", "name": self._name(reg.title, reg.name)}
        entity.update(self._item(reg, value_type=self._value_type(reg)))
        low, high = low + float(reg.offset), high + float(reg.offset)
        step = scale_float(reg.scale) if not reg.type.is_float else 10.0 ** -shown_decimals(reg)
        entity.update({"min_value": num(low), "max_value": num(high), "step": step})
        if reg.scaled:
            entity["multiply"] = scale_float(1 / reg.scale)  # ESPHome: raw = value x multiply, value = raw / multiply
        if swapped(reg):  # one word (wider ones are not numbers): read and write it through lambdas
            entity["lambda"] = Lambda(lambdas.number_read_lambda(reg))
            entity["write_lambda"] = Lambda(lambdas.number_write_lambda(reg))
        elif reg.offset_set:
            entity["lambda"] = Lambda(lambdas.offset_read_lambda(reg))
            entity["write_lambda"] = Lambda(lambdas.offset_write_lambda(reg))
        if reg.words == 1 and not self.single_write:
            entity["use_write_multiple"] = True
        if reg.unit:
            entity["unit_of_measurement"] = unit_text(esp_unit(reg.unit))
        entity["mode"] = "box"
        self.add("number", entity, reg.name, category=entity_category(self.device, reg))

    def _options(self, members: tuple[EnumMember, ...]) -> list[tuple[str, int]]:
        labels: list[tuple[str, int]] = []
        seen: set[str] = set()
        for member in members:
            label = esp_text(member.title) or member.name
            if label in seen:
                label = f"{label} ({member.value})"
            seen.add(label)
            labels.append((label, member.value))
        return labels

    def _enum(self, reg: Register) -> None:
        """A select offers the members a write may send; the states the device only reports (and every
        value of a read-only register) are shown by a text sensor with the manual's labels."""
        assert reg.enum is not None
        writable = writable_members(reg.enum) if reg.access.writable else ()
        reported = tuple(m for m in reg.enum.members if m.readable)
        state = not writable or any(not m.writable for m in reported)
        if state:
            # The register's bytes as hex (`raw_encode: HEXBYTES`), mapped to the manual's labels.
            entity: dict[str, Any] = {"platform": "modbus_controller", "name": self._name(reg.title, reg.name)}
            entity.update(self._item(reg, response_size=2 * reg.words, raw_encode="HEXBYTES"))
            options = self._options(reported)
            entity["filters"] = [{"map": [{"from": self._hexbytes(reg, value), "to": label} for label, value in options]}]
            self.add("text_sensor", entity, reg.name, category=None if writable else entity_category(self.device, reg))
        if not writable:
            return
        title, key = (f"{reg.title} (write)", (reg.name, "write")) if state else (reg.title, (reg.name,))
        entity = {"platform": "modbus_controller", "name": self._name(title, reg.name)}
        entity.update(self._item(reg, value_type=self._wire_type(reg)))
        entity["optionsmap"] = {label: self._wire_value(reg, value) for label, value in self._options(writable)}
        if reg.words == 1 and not self.single_write:
            entity["use_write_multiple"] = True
        del entity["register_type"]  # select only talks to holding registers
        self.add("select", entity, *key, category=entity_category(self.device, reg))

    def _wire_words(self, reg: Register, raw: int) -> list[int]:
        return raw_to_words(self.specs[reg.name], raw)

    def _hexbytes(self, reg: Register, raw: int) -> str:
        """What ESPHome's `raw_encode: HEXBYTES` makes of a register holding `raw`: its wire bytes, `%02x` each."""
        return "".join(f"{w:04x}" for w in self._wire_words(reg, raw))

    def _wire_type(self, reg: Register) -> str:
        """A select's value type: a byte-swapped register is compared word for word as it is on the wire."""
        if reg.type.is_float and not swapped(reg):  # a float's bits as the unsigned integer of its size (no FP32 select)
            return VALUE_TYPE[({1: DataType.U16, 2: DataType.U32, 4: DataType.U64}[reg.words], reg.word_order)]
        return SIZED[reg.words] if swapped(reg) else self._value_type(reg)

    def _wire_value(self, reg: Register, raw: int) -> int:
        if not swapped(reg) and reg.type.is_float:
            # ESPHome's select compares and writes an FP32's bits, not its number: a setting coded as a float
            value = 0
            for word in reg.type.info.to_words(float(raw)):
                value = (value << 16) | word
            return value
        if not swapped(reg):
            return raw
        value = 0
        for word in self._wire_words(reg, raw):
            value = (value << 16) | word
        return value

    def _bitfields(self, reg: Register) -> None:
        flag = single_flag(reg)
        if flag is not None and reg.access.writable and reg.words == 1:
            entity: dict[str, Any] = {"platform": "modbus_controller", "name": self._name(f"{reg.title}: {flag.title}", reg.name)}
            entity.update(self._item(reg, bitmask=Hex(swap_word(flag.mask) if swapped(reg) else flag.mask)))
            if not self.single_write:
                entity["use_write_multiple"] = True
            self.add("switch", entity, reg.name, category=entity_category(self.device, reg))
            return
        for field in reg.bitfields:
            if reserved(field.title):
                self.skipped.append(f"{reg.name}.{field.name} (the manual gives the field no meaning)")
                continue
            name = self._name(f"{reg.title}: {field.title}", f"{reg.name}.{field.name}")
            entity = {"platform": "modbus_controller", "name": name}
            if field in flags(reg) and reg.words == 1:  # a binary_sensor reads one word; 32-bit flags are sensors
                entity.update(self._item(reg, bitmask=Hex(swap_word(field.mask) if swapped(reg) else field.mask, 4 * reg.words)))
                self.add("binary_sensor", entity, reg.name, field.name)
                continue
            if swapped(reg):  # the field's bits are not where the wire word has them: a lambda takes them out
                entity.update(self._item(reg, value_type=SIZED[reg.words]))
                entity["lambda"] = Lambda(lambdas.raw_lambda(reg, field))
            else:
                entity.update(self._item(reg, value_type=self._value_type(reg), bitmask=Hex(field.mask, 4 * reg.words)))
            entity["accuracy_decimals"] = 0
            self.add("sensor", entity, reg.name, field.name)

    def command(self, command: Command) -> None:
        chosen = presses(command)
        if chosen is None:
            self.skipped.append(too_many_presses(command))
        for press in chosen or ():
            self._button(command, press.title, press.raw, press.key)

    def _button(self, command: Command, title: str, raw: int, key: tuple[str, ...]) -> None:
        """A button that queues the command's write once (the controller does not retry: MAX_CMD_RETRIES).
        A destructive command is disabled until the user enables it, under the device's configuration."""
        reg = command.register
        words = self._wire_words(reg, raw)
        ctrl = f"id({self.controller})"
        if len(words) == 1 and self.single_write:
            make = f"create_write_single_command({ctrl}, 0x{reg.address:04X}, 0x{words[0]:04X})"
        else:
            values = ", ".join(f"0x{w:04X}" for w in words)
            make = f"create_write_multiple_command({ctrl}, 0x{reg.address:04X}, {len(words)}, {{{values}}})"
        code = f"{ctrl}->queue_command(esphome::modbus_controller::ModbusCommandItem::{make});"
        entity: dict[str, Any] = {"platform": "template", "name": self._name(title, command.name)}
        if command.destructive:
            entity["disabled_by_default"] = True
        entity["on_press"] = [{"lambda": Lambda(code)}]
        self.add("button", entity, *key, category=command_category(command))

    # -- the file ----------------------------------------------------------------------------

    def build(self) -> None:
        for reg in self.registers:
            self.register(reg)
        for command in self.selection.commands:
            self.command(command)
        scaled.finish(self)

    def timing_substitutions(self) -> dict[str, str]:
        """The controller's polling and pacing substitutions (after `build`: which skips it uses)."""
        p = self.prefix
        return {
            f"{p}_update_interval": FAST_UPDATE_INTERVAL if self.fast else UPDATE_INTERVAL,
            f"{p}_command_throttle": f"{command_throttle_ms(self.device, COMMAND_THROTTLE_FLOOR_MS)}ms",
            f"{p}_parameter_skip_updates": str(SKIPS["parameter_skip_updates"][1 if self.fast else 0]),
            **{f"{p}_{key}": str(SKIPS[key][1 if self.fast else 0]) for key in sorted(self.used_skips - {"parameter_skip_updates"})},
        }

    def controller_data(self, modbus_id: str) -> dict[str, Any]:
        return {
            "id": self.controller,
            "modbus_id": modbus_id,
            "address": self.sub("slave_id"),
            "update_interval": self.sub("update_interval"),
            "max_cmd_retries": MAX_CMD_RETRIES,
            "command_throttle": self.sub("command_throttle"),
        }

    def data(self) -> dict[str, Any]:
        t = self.device.transport
        slave = 1 if t.slave_min <= 1 <= t.slave_max else t.slave_min
        p = self.prefix
        self.build()
        timing = self.timing_substitutions()
        out: dict[str, Any] = {
            "substitutions": {
                f"{p}_device_id": p,
                f"{p}_name_prefix": "",
                f"{p}_bus_id": p,
                f"{p}_tx_pin": "GPIO17",
                f"{p}_rx_pin": "GPIO16",
                f"{p}_baud_rate": str(t.baud),
                f"{p}_slave_id": str(slave),
                **timing,
            },
            # One mapping each (not a list): packages merge mappings, so two drives included on one bus share them.
            "uart": {
                "id": self.sub("bus_id") + "_uart",
                "tx_pin": self.sub("tx_pin"),
                "rx_pin": self.sub("rx_pin"),
                "baud_rate": self.sub("baud_rate"),
                "data_bits": t.data_bits,
                "parity": PARITY[t.parity],
                "stop_bits": t.stop_bits,
            },
            "modbus": {"id": self.sub("bus_id") + "_modbus", "uart_id": self.sub("bus_id") + "_uart"},
            "modbus_controller": [self.controller_data(self.sub("bus_id") + "_modbus")],
        }
        out.update(self.platforms())
        return out

    def platforms(self) -> dict[str, list[dict[str, Any]]]:
        """The entity lists by platform, in ESPHome's usual order, the empty ones left out."""
        return {platform: self.entities[platform] for platform in PLATFORMS if platform in self.entities}


def package(device: Device, selection: Selection) -> dict[str, Any]:
    """The package's content as data (the tests read the entities from it, as ESPHome does from the file)."""
    return DevicePackage(device, selection).data()


def render_package(device: Device, selection: Selection) -> Files:
    pkg = DevicePackage(device, selection)
    data = pkg.data()
    t = device.transport
    about = [
        "",
        f"ESPHome package for {device.info.vendor} {device.info.model}: modbus_controller on a UART, entities from the map.",
        f"Include it: packages: {{{device.id}: !include {device.id}.yaml}} and override the substitutions "
        f"({device.id}_tx_pin, {device.id}_rx_pin, {device.id}_slave_id, ...) in your config.",
        f"Every entity has the id ${{{device.id}_device_id}}_<register> (fields: _<register>_<field>, buttons: _<command>),"
        " for !extend and !remove. Two drives on one bus: include the file twice, the second with"
        f" vars {{{device.id}_device_id: drive2, {device.id}_slave_id: 2, {device.id}_name_prefix: 'Drive 2 '}}"
        f" (a prefix of at most {NAME_PREFIX_BYTES} bytes); both share the uart and modbus of {device.id}_bus_id.",
        f"Writes go out once: max_cmd_retries {MAX_CMD_RETRIES}. ESPHome counts retries per controller (default 4: an"
        " unanswered command would be sent up to 5 times, a motion repeated); one controller serves one address"
        " (a second one on the same bus would take this one's responses), so reads are not retried either:"
        " a lost reply costs one update. command_throttle keeps a pause between two requests to the device"
        f" ({COMMAND_THROTTLE_FLOOR_MS} ms, or the map's documented turnaround when longer).",
        "Destructive commands are left out of the default selection; chosen with --select they are"
        " disabled_by_default and entity_category config (enable one in Home Assistant before pressing it).",
        f"Serial line from the map: {t.baud} baud, {t.data_bits} data bits, parity {t.parity}, {t.stop_bits} stop bit(s).",
        f"Reads follow the map's read plan (at most {t.max_read_registers} registers a request, no undocumented address).",
        f"32-bit values assume the device's factory word order ({t.word_order.value}).",
        f"Selection: {selection.rule} ({len(selection.registers)} registers, {len(selection.commands)} commands).",
    ]
    if any(r.poll is not PollClass.NORMAL for r in selection.registers):
        about.append(
            "Poll classes as skip_updates: fast every update, normal every update (settings: parameter_skip_updates),"
            " slow every slow_skip_updates+1, static once at boot (then after static_skip_updates updates)."
        )
    if any(r.type.words == 4 and r.type.numeric for r in selection.registers):
        about.append("64-bit values: ESPHome publishes a float (24 significant bits).")
    about += gate_notes(device, selection.registers)
    about += scaled.notes(pkg)
    about += [f"Not generated: {s}" for s in pkg.skipped]
    return {f"{device.id}.yaml": dump(device, about, data)}
