"""The target a home-automation back end declares: one file of entities per device, for the registers
and commands `--select` picks (the default selection without it)."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import replace
from typing import TYPE_CHECKING, Protocol

from regmap.homeauto.selection import parse_patterns
from regmap.model import Device
from regmap.target import Files, Target, TargetOptions

if TYPE_CHECKING:  # only a plant's run imports the plant model (tests/project/test_generate_imports.py)
    from regmap.plant import Plant


class SelectionRenderer(Protocol):
    def __call__(self, device: Device, patterns: tuple[str, ...] | None = None) -> Files: ...


def _no_shared_files(devices: Sequence[Device]) -> Files:
    return {}


def selecting_target(
    name: str, render_device: SelectionRenderer, *, order: int, plant: Callable[[Plant], Files] | None = None, scale_from: bool = False
) -> Target:
    """The target `name` (its files under `name/`), configured by the `select` option; `plant` renders a
    plant file (each device's default selection: `regmap generate PLANT` takes no `--select`); `scale_from`:
    it shows registers scaled by another register (Target.scale_from)."""

    def configure(options: TargetOptions) -> Target:
        patterns = parse_patterns(options["select"])
        return replace(target, per_device=lambda device: render_device(device, patterns))

    target = Target(
        name=name,
        subdir=name,
        per_device=render_device,
        shared=_no_shared_files,
        options=("select",),
        configure=configure,
        order=order,
        plant=plant,
        scale_from=scale_from,
    )
    return target
