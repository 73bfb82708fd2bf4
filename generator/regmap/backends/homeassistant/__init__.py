"""Home Assistant back end: a `modbus:` hub per map (`homeassistant/<device>.yaml`, a Home Assistant package),
and for a plant one package (`homeassistant/<plant>.yaml`) with a hub per bus and every device's entities.

`hub` computes the hub as data from the model and the selection (`regmap.homeauto.selection`);
`homeauto.entities.dump` writes it with the safe dumper. The target reads the `select` option.
"""

from __future__ import annotations

from regmap.backends.homeassistant.hub import DATA_TYPE, hub, plant_hubs, render_hub, render_plant
from regmap.homeauto.selection import select
from regmap.homeauto.target import selecting_target
from regmap.model import Device
from regmap.target import Files


def render_device(device: Device, patterns: tuple[str, ...] | None = None) -> Files:
    return render_hub(device, select(device, patterns))


TARGET = selecting_target("homeassistant", render_device, order=60, plant=render_plant, scale_from=True)

__all__ = ["DATA_TYPE", "TARGET", "hub", "plant_hubs", "render_device", "render_plant"]
