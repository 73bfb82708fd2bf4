"""Plant files for tests: written beside a temporary directory, maps referred to relative to the plant file."""

from __future__ import annotations

import importlib
import os
import subprocess
import sys
from pathlib import Path
from types import ModuleType

from conftest import ROOT


def write_plant(tmp_path: Path, plant_id: str, bus: str, devices: list[tuple[str, str, int]]) -> Path:
    """A plant file with one bus (`bus`: the YAML flow mapping of its `serial:` or `tcp:` key) and
    `devices` as (name, map file under maps/, slave id)."""
    path = tmp_path / f"{plant_id}.yaml"
    lines = [
        "format: regmap-plant/1",
        f"plant: {{id: {plant_id}, title: Test plant {plant_id}}}",
        "buses:",
        "  - name: line1",
        f"    {bus}",
        "    devices:",
    ]
    for name, map_file, slave in devices:
        rel = os.path.relpath(ROOT / "maps" / map_file, tmp_path)
        lines.append(f"      - {{name: {name}, map: {rel}, slave: {slave}}}")
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def generate_python_plant(plant_file: Path, out: Path) -> ModuleType:
    """`regmap generate PLANT --target python`, then the plant module imported from the output."""
    result = subprocess.run(
        [sys.executable, "-m", "regmap", "generate", str(plant_file), "--out", str(out), "--target", "python"],
        cwd=ROOT,
        capture_output=True,
        text=True,
        check=False,
    )
    assert result.returncode == 0, result.stderr
    sys.path.insert(0, str(out / "python"))
    try:
        return importlib.import_module(f"{plant_file.stem}_plant")
    finally:
        sys.path.remove(str(out / "python"))


FLOAT_METER = ROOT / "tests" / "maps" / "fixtures" / "float_meter.yaml"
METER_VARIANTS = {"m1": (1, "single_phase"), "m3": (3, "three_phase")}  # device -> (slave id, variant)


def write_meter_plant(tmp_path: Path, plant_id: str, bus: str) -> Path:
    """Two float meters (tests/maps/fixtures/float_meter.yaml) on one bus: `m1` single-phase at slave 1, `m3`
    three-phase at slave 3 (only the three-phase model has voltage_l2)."""
    path = tmp_path / f"{plant_id}.yaml"
    rel = os.path.relpath(FLOAT_METER, tmp_path)
    lines = [
        "format: regmap-plant/1",
        f"plant: {{id: {plant_id}, title: Two meters {plant_id}}}",
        "buses:",
        "  - name: line1",
        f"    {bus}",
        "    devices:",
        *(f"      - {{name: {name}, map: {rel}, slave: {slave}, variant: {variant}}}" for name, (slave, variant) in METER_VARIANTS.items()),
    ]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path
