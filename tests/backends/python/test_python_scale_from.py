"""The generated Python client of a map with `scale_from` registers: mypy --strict passes on it and on a typed
use (a scaled read is `float | None`: the scale factor may read "not available"), and against the simulator its
reads are the runtime's scaled values (value = raw x 10^sf from the map's defaults)."""

from __future__ import annotations

import importlib
import sys
from pathlib import Path

from regmap.frontend import load_map
from regmap.generate import render
from regmap_runtime.scaling import scaled

from conftest import ROOT, SimulatorFactory, mypy_strict

MAP = ROOT / "tests" / "maps" / "scaled_from" / "inverter.yaml"

USE = """
from typing import assert_type

from sf_inverter import SfInverter


def use(inverter: SfInverter) -> float | None:
    assert_type(inverter.read_w(), float | None)
    assert_type(inverter.read_w_sf(), int | None)
    inverter.write_wmax_lim_pct(50.5)
    return inverter.read_all()["wh"]
"""


def _tree(tmp_path: Path) -> Path:
    for name, text in render([load_map(MAP)], ["python"])["python"].items():
        path = tmp_path / "python" / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")
    return tmp_path / "python"


def test_the_client_and_a_typed_use_pass_mypy_strict(tmp_path: Path) -> None:
    tree = _tree(tmp_path)
    (tree / "use_inverter.py").write_text(USE, encoding="utf-8")
    result = mypy_strict("sf_inverter", "use_inverter.py", cwd=tree)
    assert result.returncode == 0, result.stdout + result.stderr


def test_the_client_reads_scaled_values(tmp_path: Path, simulator: SimulatorFactory) -> None:
    device = load_map(MAP)
    tree = _tree(tmp_path)
    loaded = set(sys.modules)  # only what this test imports is unloaded after it: other tests hold the runtime's classes
    sys.path.insert(0, str(tree))
    try:
        module = importlib.import_module("sf_inverter")
        sim = simulator(MAP)
        with module.SfInverter.tcp("127.0.0.1", sim.port) as inverter:
            for name in ("a", "w", "wh", "wmax_lim_pct"):
                reg = device.register(name)
                raw, sf = reg.default, device.register(str(reg.scale_from)).default
                assert isinstance(raw, int) and isinstance(sf, int)
                assert getattr(inverter, f"read_{name}")() == scaled(raw, sf), name
            inverter.write_wmax_lim_pct(12.5)
            assert inverter.read_wmax_lim_pct() == 12.5
    finally:
        sys.path.remove(str(tree))
        for name in set(sys.modules) - loaded:
            del sys.modules[name]
