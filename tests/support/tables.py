"""Spreadsheets built from a map, changed the way a user would change them."""

from __future__ import annotations

import csv
import io
from pathlib import Path

from regmap.model import Device, Register
from regmap.tools.spreadsheet.export import export_csv


def table_changing_a_default(device: Device, tmp_path: Path) -> tuple[Path, Register, int]:
    """tmp_path/changed.csv: the device's table with one register's default raised by one; that register and its new default."""
    rows = list(csv.reader(io.StringIO(export_csv(device).lstrip("\ufeff"))))
    reg = next(r for r in device.registers if isinstance(r.default, int) and isinstance(r.max, int) and r.default < r.max)
    assert isinstance(reg.default, int)
    row = next(row for row in rows if row[0] == reg.name)
    row[rows[0].index("default")] = str(reg.default + 1)
    table = tmp_path / "changed.csv"
    with table.open("w", encoding="utf-8", newline="") as handle:
        csv.writer(handle).writerows(rows)
    return table, reg, reg.default + 1
