"""Round trips through the home-automation configs: a map -> ESPHome / HA config -> `regmap import` -> the map again.

The entities are compared by what reads the device: platform, register type, address, value type (its
word order), bitmask, scale and offset, the options of a select, the size of a text. Names, ids, icons and
categories are the back end's presentation and are not compared.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from regmap.backends.esphome.package import package, render_package
from regmap.backends.homeassistant.hub import hub, render_hub
from regmap.frontend import load_map_text
from regmap.homeauto.selection import select
from regmap.model import Device
from regmap.tools.configimport.drafts import drafts, read

EVERYTHING = ("*",)


def esphome_entities(data: dict[str, Any]) -> list[tuple[Any, ...]]:
    """The ESPHome package's modbus_controller entities as what they read, sorted."""
    out = []
    for platform in ("sensor", "binary_sensor", "text_sensor", "number", "select", "switch"):
        for e in data.get(platform, []):
            if e.get("platform") != "modbus_controller":
                continue
            multiply = [f["multiply"] for f in e.get("filters", []) if isinstance(f, dict) and "multiply" in f]
            offset = [f["offset"] for f in e.get("filters", []) if isinstance(f, dict) and "offset" in f]
            out.append(
                (
                    platform,
                    e.get("register_type", "holding"),
                    int(e["address"]),
                    e.get("value_type"),
                    e.get("bitmask"),
                    tuple(multiply) or e.get("multiply"),
                    tuple(offset),
                    e.get("register_count"),
                    e.get("response_size"),
                    tuple(sorted((e.get("optionsmap") or {}).values())),
                    e.get("raw_encode"),
                    "lambda" in e,
                )
            )
    return sorted(out, key=repr)


def ha_entities(data: list[dict[str, Any]]) -> list[tuple[Any, ...]]:
    """The HA hubs' entities as what they read, sorted."""
    out = []
    for h in data:
        for kind in ("sensors", "binary_sensors", "switches"):
            for e in h.get(kind, []):
                out.append(
                    (
                        kind,
                        e.get("input_type", e.get("write_type")),
                        int(e["address"]),
                        e.get("data_type"),
                        e.get("swap"),
                        e.get("scale"),
                        e.get("offset"),
                        e.get("count"),
                        e.get("virtual_count"),
                        e.get("command_on"),
                        e.get("command_off"),
                        e.get("slave"),
                    )
                )
    return sorted(out, key=repr)


def reimport(text: str, tmp: Path, name: str, fmt: str | None = None) -> tuple[list[Device], list[str]]:
    """The config text imported, each draft through the front end (which must accept it)."""
    path = tmp / f"{name}.yaml"
    path.write_text(text, encoding="utf-8")
    _, imported = read(path, fmt)
    devices = [load_map_text(d.text, f"{d.device_id}.yaml") for d in drafts(imported, name, "vendor", "model", path.name)]
    return devices, imported.report


def esphome_round_trip(device: Device, tmp: Path) -> tuple[list[tuple[Any, ...]], list[tuple[Any, ...]], list[str]]:
    """(entities generated from the map, entities generated from its re-import, the import's report)."""
    chosen = select(device, EVERYTHING)
    first = package(device, chosen)
    (text,) = render_package(device, chosen).values()
    (again,), report = reimport(text, tmp, device.id)
    return esphome_entities(first), esphome_entities(package(again, select(again, EVERYTHING))), report


def ha_round_trip(device: Device, tmp: Path) -> tuple[list[tuple[Any, ...]], list[tuple[Any, ...]], list[str]]:
    chosen = select(device, EVERYTHING)
    first = hub(device, chosen)
    (text,) = render_hub(device, chosen).values()
    (again,), report = reimport(text, tmp, device.id)
    return ha_entities(first), ha_entities(hub(again, select(again, EVERYTHING))), report
