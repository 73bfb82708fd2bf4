"""ESPHome back end: an ESPHome package per map (`esphome/<device>.yaml`) for `modbus_controller`, and for a
plant one package (`esphome/<plant>.yaml`): a uart and modbus per serial bus, a controller per device.

`package` computes the package as data from the model and the selection (`regmap.homeauto.selection`);
`homeauto.entities.dump` writes it with the safe dumper. The target reads the `select` option
(`regmap generate --select`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from regmap.backends.esphome.package import VALUE_TYPE, package, render_package
from regmap.backends.esphome.text import esp_text, hexbytes
from regmap.homeauto.selection import select
from regmap.homeauto.target import selecting_target
from regmap.model import Device
from regmap.target import Files

if TYPE_CHECKING:
    from regmap.plant import Plant


def render_device(device: Device, patterns: tuple[str, ...] | None = None) -> Files:
    return render_package(device, select(device, patterns))


def render_plant(plant: Plant) -> Files:
    """The plant's package (backends/esphome/plant.py): imported only when a plant is rendered."""
    from regmap.backends.esphome.plant import render_plant as render

    return render(plant)


TARGET = selecting_target("esphome", render_device, order=50, plant=render_plant, scale_from=True)

__all__ = ["TARGET", "VALUE_TYPE", "esp_text", "hexbytes", "package", "render_device", "render_plant"]
