"""Home Assistant back end: a `modbus:` hub per map (`homeassistant/<device>.yaml`, a Home Assistant package).

`hub` computes the hub as data from the model and the selection (`backends.selection`);
`homeauto.dump` writes it with the safe dumper. The target reads the `select` option.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace

from regmap.backends.homeassistant.hub import DATA_TYPE, hub, render_hub
from regmap.backends.selection import parse_patterns, select
from regmap.model import Device
from regmap.target import Files, Target, TargetOptions


def render_device(device: Device, patterns: tuple[str, ...] | None = None) -> Files:
    return render_hub(device, select(device, patterns))


def render_shared(devices: Sequence[Device]) -> Files:
    return {}


def _configure(options: TargetOptions) -> Target:
    patterns = parse_patterns(options["select"])
    return replace(TARGET, per_device=lambda d: render_device(d, patterns))


TARGET = Target(
    name="homeassistant",
    subdir="homeassistant",
    per_device=render_device,
    shared=render_shared,
    options=("select",),
    configure=_configure,
    order=60,
)

__all__ = ["DATA_TYPE", "TARGET", "hub", "render_device"]
