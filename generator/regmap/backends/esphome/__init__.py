"""ESPHome back end: an ESPHome package per map (`esphome/<device>.yaml`) for `modbus_controller`.

`package` computes the package as data from the model and the selection (`backends.selection`);
`homeauto.dump` writes it with the safe dumper. The target reads the `select` option
(`regmap generate --select`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace

from regmap.backends.esphome.package import VALUE_TYPE, esp_text, hexbytes, package, render_package
from regmap.backends.selection import parse_patterns, select
from regmap.model import Device
from regmap.target import Files, Target, TargetOptions


def render_device(device: Device, patterns: tuple[str, ...] | None = None) -> Files:
    return render_package(device, select(device, patterns))


def render_shared(devices: Sequence[Device]) -> Files:
    return {}


def _configure(options: TargetOptions) -> Target:
    patterns = parse_patterns(options["select"])
    return replace(TARGET, per_device=lambda d: render_device(d, patterns))


TARGET = Target(
    name="esphome", subdir="esphome", per_device=render_device, shared=render_shared, options=("select",), configure=_configure, order=50
)

__all__ = ["TARGET", "VALUE_TYPE", "esp_text", "hexbytes", "package", "render_device"]
