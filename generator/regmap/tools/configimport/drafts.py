"""A config file -> the map drafts of its devices (one per distinct device) and what the import reported."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from regmap.tools.configimport.draft import Device, Import, identifier, map_text
from regmap.tools.configimport.esphome import read_esphome
from regmap.tools.configimport.reader import Config, ConfigError, read_config

FORMATS = ("esphome", "homeassistant", "sunspec")


@dataclass
class Draft:
    """One map to write: its device id, text, and the devices (controllers, hub slaves) it describes."""

    device_id: str
    text: str
    devices: list[Device]


def detect(config: Config) -> str:
    """Which tool wrote the file: ESPHome has `modbus_controller:`, Home Assistant a `modbus:` list of hubs."""
    data = config.data if isinstance(config.data, dict) else {}
    if "modbus_controller" in data:
        return "esphome"
    if isinstance(data.get("modbus"), list):
        return "homeassistant"
    raise ConfigError(
        [config.error((), "neither an ESPHome config (no modbus_controller:) nor a Home Assistant one (no modbus: list of hubs)")]
    )


def read(path: Path, fmt: str | None, chain: tuple[Path, ...] = (), base: int = 40000, repeats: int = 1) -> tuple[str, Import]:
    """The file's format and what it holds; ConfigError at file:line:col for what cannot be read. A SunSpec
    model definition (.json) is chained with the `chain` models after it, from `base`."""
    if fmt == "sunspec" or (fmt is None and path.suffix.lower() == ".json"):
        from regmap.tools.configimport import sunspec

        return "sunspec", sunspec.device(sunspec.read_models([path, *chain]), base, repeats)
    config = read_config(path.read_text(encoding="utf-8"), str(path))
    fmt = fmt or detect(config)
    if fmt == "esphome":
        return fmt, read_esphome(config)
    from regmap.tools.configimport.homeassistant import read_homeassistant

    return fmt, read_homeassistant(config)


def drafts(imported: Import, device_id: str, vendor: str, model: str, source: str) -> list[Draft]:
    """One map per distinct device: devices whose registers read the same (two slaves of one model) share it."""
    distinct: dict[tuple[object, ...], list[Device]] = {}
    for device in imported.devices:
        distinct.setdefault(device.signature(), []).append(device)
    out: list[Draft] = []
    for same in distinct.values():
        name = device_id if len(distinct) == 1 else identifier(same[0].label, "device")
        out.append(Draft(name, map_text(same[0], name, vendor, model, source, imported.report), same))
    return out
