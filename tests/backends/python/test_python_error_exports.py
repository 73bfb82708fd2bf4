"""Every generated module re-exports every error its runtime raises, whatever its map holds."""

from __future__ import annotations

import importlib
import inspect
import sys

import pytest

from regmap.frontend import load_map

from conftest import FIXTURE_MAPS, MAPS, fixture_maps_generated

DEVICES = [load_map(p).id for p in MAPS] + [load_map(p).id for p in FIXTURE_MAPS]


@pytest.mark.parametrize("device_id", DEVICES)
def test_the_module_exports_every_runtime_error(device_id: str) -> None:
    fixture_maps_generated()  # the fixture maps' modules become importable
    module = importlib.import_module(device_id)
    runtime_errors = sys.modules[module.RegmapError.__module__]  # the module's own runtime copy
    raised = {
        name
        for name, obj in vars(runtime_errors).items()
        if inspect.isclass(obj) and issubclass(obj, runtime_errors.RegmapError) and obj.__module__ == runtime_errors.__name__
    }
    assert {"AccessError", "FirmwareError", "OutcomeUnknown"} <= raised
    missing = sorted(name for name in raised if getattr(module, name, None) is not getattr(runtime_errors, name))
    assert not missing, f"{device_id} does not re-export {missing}"
    assert raised <= set(module.__all__), sorted(raised - set(module.__all__))
