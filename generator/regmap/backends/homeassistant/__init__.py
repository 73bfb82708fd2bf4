"""Home Assistant back end: a `modbus:` hub per map (`homeassistant/<device>.yaml`, a Home Assistant package).

`hub` computes the hub as data from the model and the selection (`regmap.homeauto.selection`);
`homeauto.entities.dump` writes it with the safe dumper. The target reads the `select` option.
"""

from __future__ import annotations

from regmap.backends.homeassistant.hub import DATA_TYPE, hub, render_hub
from regmap.homeauto.selection import select
from regmap.homeauto.target import selecting_target
from regmap.model import Device
from regmap.target import Files


def render_device(device: Device, patterns: tuple[str, ...] | None = None) -> Files:
    return render_hub(device, select(device, patterns))


TARGET = selecting_target("homeassistant", render_device, order=60)

__all__ = ["DATA_TYPE", "TARGET", "hub", "render_device"]
