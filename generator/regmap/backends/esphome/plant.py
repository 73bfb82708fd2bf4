"""The ESPHome package of a plant: a `uart` and a `modbus` per serial bus, a `modbus_controller` per device.

Each device is its map's `DevicePackage` under the device's name: its substitutions, ids (`<device>_<register>`)
and names (`<device> <title>`) carry the name, so one map appears once per device; its controller sits on its
bus's `modbus` at its slave id. ESPHome's `modbus` speaks RTU on a UART only, so a TCP bus is named as not
generated in the file's header.
"""

from __future__ import annotations

import re
from typing import Any

from regmap.backends.esphome.package import MAX_CMD_RETRIES, PARITY, PLATFORMS, DevicePackage
from regmap.homeauto.entities import dump_commented, gate_notes, plant_device_line, plant_header_lines, refuse_shared_ids
from regmap.homeauto.selection import DEFAULT_RULE, for_variant, select
from regmap.plant import Bus, Plant, PlantDevice
from regmap.target import Files

# Default UART pins of each serial bus of a plant, in bus order (ESP32 GPIOs free of flash and strapping
# duties; UART0 stays the logger's, so an ESP32 drives at most this many lines). Substitutions: override them.
BUS_PINS = (("GPIO17", "GPIO16"), ("GPIO25", "GPIO26"))


def _plant_package(plant: Plant) -> tuple[dict[str, Any], list[tuple[Bus, PlantDevice, DevicePackage]], list[str]]:
    substitutions: dict[str, str] = {}
    uarts: list[dict[str, Any]] = []
    buses: list[dict[str, Any]] = []
    controllers: list[dict[str, Any]] = []
    entities: dict[str, list[dict[str, Any]]] = {}
    built: list[tuple[Bus, PlantDevice, DevicePackage]] = []
    skipped: list[str] = []
    serial = [bus for bus in plant.buses if bus.serial is not None]
    for bus in plant.buses:
        if bus.serial is None:
            skipped.append(f"bus {bus.name} (Modbus TCP: ESPHome's modbus speaks RTU on a UART only)")
    for index, bus in enumerate(serial):
        line = bus.serial
        assert line is not None
        if index >= len(BUS_PINS):
            skipped.append(f"bus {bus.name} (an ESP32 has {len(BUS_PINS)} UARTs besides the logger's)")
            continue
        tx, rx = BUS_PINS[index]
        substitutions |= {f"{bus.name}_tx_pin": tx, f"{bus.name}_rx_pin": rx}
        uart = {
            "id": f"{bus.name}_uart",
            "tx_pin": "${" + bus.name + "_tx_pin}",
            "rx_pin": "${" + bus.name + "_rx_pin}",
            "baud_rate": line.baud,
            "data_bits": line.data_bits,
            "parity": PARITY[line.parity],
            "stop_bits": line.stop_bits,
        }
        uarts.append(uart)
        buses.append({"id": f"{bus.name}_modbus", "uart_id": f"{bus.name}_uart"})
        for dev in bus.devices:
            pkg = DevicePackage(dev.device, for_variant(select(dev.device, None), dev.variant), prefix=dev.name)
            pkg.build()
            built.append((bus, dev, pkg))
            substitutions |= {
                f"{dev.name}_device_id": dev.name,
                f"{dev.name}_name_prefix": f"{dev.name} ",
                f"{dev.name}_slave_id": str(dev.slave),
                **pkg.timing_substitutions(),
            }
            controllers.append(pkg.controller_data(f"{bus.name}_modbus"))
            for platform, items in pkg.platforms().items():
                entities.setdefault(platform, []).extend(items)
    _refuse_shared_ids(plant, built)
    out: dict[str, Any] = {"substitutions": substitutions, "uart": uarts, "modbus": buses, "modbus_controller": controllers}
    out.update({platform: entities[platform] for platform in PLATFORMS if platform in entities})
    return out, built, skipped


def _object_id(name: str) -> str:
    """ESPHome's object id of an entity name (`snake_case` then `sanitize`): the key of its API and web paths."""
    return re.sub(r"[^-_a-z0-9]", "_", name.replace(" ", "_").lower())


def _refuse_shared_ids(plant: Plant, built: list[tuple[Bus, PlantDevice, DevicePackage]]) -> None:
    """ESPHome refuses an id given twice and two entities of one platform with one object id: device `a`
    with `b_c` and device `a_b` with `c` would meet in both."""
    ids = []
    for _, dev, pkg in built:
        items = [(platform, item) for platform, entities in pkg.platforms().items() for item in entities]
        made = [item["id"].replace(pkg.sub("device_id"), dev.name) for _, item in items]
        made += [f"{platform}.{_object_id(dev.name + ' ' + item['name'].replace(pkg.sub('name_prefix'), ''))}" for platform, item in items]
        ids.append((dev, made))
    refuse_shared_ids(plant, ids, "ESPHome")


def plant_package(plant: Plant) -> dict[str, Any]:
    """The plant's ESPHome package as data: a uart and modbus per serial bus, a controller per device."""
    return _plant_package(plant)[0]


def render_plant(plant: Plant) -> Files:
    """The plant's ESPHome package (`<plant id>.yaml`); none when the plant has no serial bus ESPHome can drive."""
    data, built, skipped = _plant_package(plant)
    if not built:
        return {}
    about = [
        "",
        f"ESPHome package of the plant {' '.join(plant.title.split())}: a uart and a modbus per serial bus, a"
        " modbus_controller per device at its slave id.",
        f"Include it: packages: {{{plant.id}: !include {plant.id}.yaml}} and override the substitutions (<bus>_tx_pin,"
        " <bus>_rx_pin, <device>_name_prefix, ...) in your config.",
        "Every entity has the id <device>_<register> (fields: _<register>_<field>, buttons: _<command>) and its name"
        " starts with the device's name, so one map appears once per device.",
        f"Writes go out once: max_cmd_retries {MAX_CMD_RETRIES} on every controller; command_throttle keeps each"
        " device's pause between two requests to it.",
        f"Selection per device: {DEFAULT_RULE}.",
        *(plant_device_line(bus, dev, pkg.selection) for bus, dev, pkg in built),
    ]
    for _, dev, pkg in built:
        about += [f"{dev.name}: {note}" for note in gate_notes(dev.device, pkg.selection.registers, dev.variant)]
        about += [f"Not generated for {dev.name}: {s}" for s in pkg.skipped]
    about += [f"Not generated: {s}" for s in skipped]
    return {f"{plant.id}.yaml": dump_commented([*plant_header_lines(plant), *about], data)}
