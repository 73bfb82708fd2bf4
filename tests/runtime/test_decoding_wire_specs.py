"""Decoding (the Markdown pages' example values, the CLI's decode and check) reads a register's wire spec: it scales
and orders words by the spec and takes enum members from the model, so it gives what the runtime specs, enum
classes and all, give; and rendering the seed maps builds none of the runtime's enum classes."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

from regmap import runtime_bridge
from regmap.core.decoding import RegisterSpecs, describe_value
from regmap.frontend import load_map
from regmap.generate import _targets, target_names
from regmap.model import Register
from regmap_runtime.spec import RegisterSpec

from conftest import FIXTURE_MAPS, MAPS


class _RuntimeSpecs:
    """The specs decoding used before: the runtime's, with their enum classes."""

    def __init__(self, specs: list[RegisterSpec[Any]]) -> None:
        self.specs = {s.name: s for s in specs}

    def spec(self, reg: Register) -> RegisterSpec[Any]:
        return self.specs[reg.name]


def _raws(reg: Register) -> list[int | float]:
    """Both ends of the register's range, one past each, zero, and every enum member's value."""
    members = [m.value for m in reg.enum.members] if reg.enum is not None else []
    return sorted({reg.raw_min, reg.raw_max, reg.raw_min - 1, reg.raw_max + 1, 0, *members})


@pytest.mark.parametrize("path", [*MAPS, *FIXTURE_MAPS], ids=lambda p: Path(p).stem)
def test_decoding_by_wire_specs_says_what_the_runtime_specs_say(path: Path) -> None:
    device = load_map(path)
    wire, runtime = RegisterSpecs(device), _RuntimeSpecs(runtime_bridge.runtime_specs(device))
    compared = 0
    for reg in device.registers:
        if reg.type.is_string or reg.type.value.startswith("timestamp"):
            continue
        for raw in _raws(reg):
            assert describe_value(device, reg, raw, wire) == describe_value(device, reg, raw, runtime), (reg.name, raw)
            compared += 1
    assert compared > 0


def test_rendering_the_seed_maps_builds_no_runtime_enum_class(monkeypatch: pytest.MonkeyPatch) -> None:
    def refused(*_: object) -> None:
        raise AssertionError("a back end built the runtime's enum classes")

    monkeypatch.setattr(runtime_bridge, "runtime_enum", refused)
    targets = _targets()
    devices = [load_map(p) for p in MAPS]
    for name in target_names():
        for device in devices:
            assert targets[name].per_device(device)
        targets[name].shared(devices)
