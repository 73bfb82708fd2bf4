"""Spreadsheets and f16: an exported half-float map imports back with the same registers, and a vendor table's
`float16` / `half` type cell is an f16."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from regmap.frontend import load_map
from regmap.model import Device
from regmap.tools.spreadsheet.export import export_xlsx

from support.half_map import write_half_map


def _regmap(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "regmap", *args], capture_output=True, text=True, check=False)


def test_a_half_float_map_round_trips_through_xlsx(tmp_path: Path) -> None:
    device = load_map(write_half_map(tmp_path))
    table = tmp_path / "half.xlsx"
    table.write_bytes(export_xlsx(device))
    run = _regmap("import", str(table), "--into", str(tmp_path / "again.yaml"))
    assert run.returncode == 0, run.stderr + run.stdout
    again = load_map(tmp_path / "again.yaml")

    def wire(d: Device) -> list[tuple[object, ...]]:
        return [(r.address, r.space, r.type.value, r.byte_order.value, r.raw_min, r.raw_max, r.default) for r in d.registers]

    assert wire(again) == wire(device) and {r.type.value for r in again.registers} == {"f16"}


def test_float16_and_half_cells_are_f16(tmp_path: Path) -> None:
    table = tmp_path / "vendor.csv"
    table.write_text("address,name,type,unit\n0x0000,level,float16,m\n0x0001,flow,half,l/min\n0x0002,power,float,kW\n", encoding="utf-8")
    run = _regmap("import", str(table), "--into", str(tmp_path / "vendor.yaml"))
    assert run.returncode == 0, run.stderr + run.stdout
    regs = load_map(tmp_path / "vendor.yaml").registers
    assert [(r.address, r.type.value) for r in regs] == [(0, "f16"), (1, "f16"), (2, "f32")]
