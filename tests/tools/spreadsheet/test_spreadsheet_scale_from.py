"""Spreadsheets carry `scale_from` (issue #35: value = raw x 10^sf, sf an s16 register read from the device): a
datasheet's "SF" / "Scale factor register" column imports into a map that scales by it; a cell naming a register
the table does not have, or one that is no s16, stops the import at that cell and nothing is written."""

from __future__ import annotations

import io
import shutil
import subprocess
import sys
from pathlib import Path

import openpyxl
import pytest
import yaml

from regmap.diagnostics import ExitCode
from regmap.frontend import load_map
from regmap.tools.spreadsheet.columns import AMBIGUOUS, Mapping, normalise, recognise
from regmap.tools.spreadsheet.export import export_csv

from conftest import ROOT

INVERTER = ROOT / "tests" / "maps" / "scaled_from" / "inverter.yaml"


def _import(table: Path, into: Path) -> subprocess.CompletedProcess[str]:
    regmap = str(Path(sys.executable).with_name("regmap"))
    return subprocess.run([regmap, "import", str(table), "--into", str(into)], capture_output=True, text=True, check=False)


def _csv(tmp_path: Path, text: str) -> Path:
    table = tmp_path / "datasheet.csv"
    table.write_text(text, encoding="utf-8")
    return table


@pytest.mark.parametrize("header", ["SF", "Scale factor register", "scale factor point", "SF register", "比例因子寄存器", "scale_from"])
def test_a_datasheet_names_the_scale_factor_column_as_it_prints_it(header: str) -> None:
    assert recognise(["Address", "Name", header], Mapping()) == {0: "address", 1: "name", 2: "scale_from"}


def test_a_bare_scale_factor_header_stays_ambiguous() -> None:
    """ "Scale factor" beside a number may multiply or divide: it is not taken for a register's name."""
    assert recognise(["Address", "Scale factor"], Mapping()) == {0: "address"}
    assert normalise("Scale factor") in AMBIGUOUS


SUNSPEC_SHEET = """Address,Name,Parameter,Type,Access,Units,SF,Title
0x0054,dca,DCA,u16,r,A,DCA_SF,DC current
0x0055,dcv,DCV,u16,r,V,dcv_sf,DC voltage
0x005A,dca_sf,DCA_SF,s16,r,,,DC current scale factor
0x005B,dcv_sf,DCV_SF,s16,r,,,DC voltage scale factor
0x005C,st,St,u16,r,,,State
"""


def test_a_sunspec_datasheet_imports_into_a_map_that_scales_by_the_factor(tmp_path: Path) -> None:
    """The SF cell names the factor by its name or its parameter id (as SunSpec prints it); the draft validates."""
    run = _import(_csv(tmp_path, SUNSPEC_SHEET), tmp_path / "mppt.yaml")
    assert run.returncode == ExitCode.OK, run.stderr + run.stdout
    device = load_map(tmp_path / "mppt.yaml")
    assert {r.name: r.scale_from for r in device.registers} == {
        "dca": "dca_sf",
        "dcv": "dcv_sf",
        "dca_sf": None,
        "dcv_sf": None,
        "st": None,
    }
    assert device.register("dca").scale == 1


BAD_CELLS = [
    ("SF", "0x0054,dca,DCA,u16,r,A,DCB_SF,DC current", "2:7", "scale_from 'DCB_SF': no row of the table is that register"),
    ("SF", "0x0054,dca,DCA,u16,r,A,st,DC current", "2:7", "scale_from 'st': st is type u16; a scale factor is an s16 register"),
    ("SF", "0x0054,dca,DCA,u16,r,A,dca,DC current", "2:7", "a register cannot be its own scale factor"),
    ("Factory default", "0x0054,dca,DCA,u16,r,A,DCA_SF,12.5", "2:8", "default_value '12.5' beside scale_from DCA_SF"),
    ("Multiplier", "0x0054,dca,DCA,u16,r,A,DCA_SF,0.1", "2:8", "a scale or offset of its own beside scale_from DCA_SF"),
]


@pytest.mark.parametrize(("last", "row", "where", "message"), BAD_CELLS, ids=[b[3][:40] for b in BAD_CELLS])
def test_a_bad_scale_factor_cell_is_reported_at_its_cell_and_nothing_is_written(
    tmp_path: Path, last: str, row: str, where: str, message: str
) -> None:
    lines = SUNSPEC_SHEET.splitlines()
    lines[0] = lines[0].replace("Title", last)
    rows = [row, *(line.rsplit(",", 1)[0] + "," for line in lines[2:])]
    table = _csv(tmp_path, "\n".join([lines[0], *rows]) + "\n")
    run = _import(table, tmp_path / "mppt.yaml")
    assert run.returncode == ExitCode.USAGE, run.stdout + run.stderr
    assert f"{table}:{where}: " in run.stderr and message in run.stderr, run.stderr
    assert "nothing written" in run.stderr and "Traceback" not in run.stderr
    assert not (tmp_path / "mppt.yaml").exists()


def test_an_xlsx_names_the_sheet_and_cell_of_a_factor_that_is_no_s16(tmp_path: Path) -> None:
    wb = openpyxl.Workbook()
    ws = wb.active
    assert ws is not None
    ws.title = "Inverter"
    for row in (["Address", "Name", "Type", "Scale factor register"], [0, "w", "s16", "w_sf"], [1, "w_sf", "u32", None]):
        ws.append(row)
    buffer = io.BytesIO()
    wb.save(buffer)
    table = tmp_path / "t.xlsx"
    table.write_bytes(buffer.getvalue())
    run = _import(table, tmp_path / "inv.yaml")
    assert run.returncode == ExitCode.USAGE
    assert f"{table}:Inverter!D2: scale_from 'w_sf': w_sf is type u32; a scale factor is an s16 register" in run.stderr
    assert not (tmp_path / "inv.yaml").exists()


def test_an_update_may_name_a_factor_of_the_map_and_changes_only_that_key(tmp_path: Path) -> None:
    """A table of one row updates a map: its SF names a register the map has (not a row); the text changes on one line."""
    target = tmp_path / "sf_inverter.yaml"
    shutil.copy(INVERTER, target)
    table = _csv(tmp_path, "name,address,type,scale_from\nw,2,s16,a_sf\n")
    run = _import(table, target)
    assert run.returncode == ExitCode.OK, run.stderr + run.stdout
    assert "w.scale_from" in run.stdout or "register_scale_changed" in run.stdout, run.stdout
    assert load_map(target).register("w").scale_from == "a_sf"
    before, after = INVERTER.read_text(encoding="utf-8").splitlines(), target.read_text(encoding="utf-8").splitlines()
    line = next(i for i, text in enumerate(before) if "{name: w," in text)
    assert [(a, b) for a, b in zip(before, after, strict=True) if a != b] == [
        (before[line], before[line].replace("scale_from: w_sf", "scale_from: a_sf"))
    ]


def test_an_update_refuses_a_factor_the_map_has_as_no_s16(tmp_path: Path) -> None:
    target = tmp_path / "sf_inverter.yaml"
    shutil.copy(INVERTER, target)
    table = _csv(tmp_path, "name,address,type,scale_from\nw,2,s16,wh\n")
    run = _import(table, target)
    assert run.returncode == ExitCode.USAGE
    assert f"{table}:2:4: scale_from 'wh': wh is type u32" in run.stderr
    assert target.read_bytes() == INVERTER.read_bytes()


def test_an_export_of_a_scaled_map_keeps_text_as_data(tmp_path: Path) -> None:
    """A title that looks like a formula beside a scale_from register comes back as the same text."""
    text = INVERTER.read_text(encoding="utf-8").replace("title: AC power}", "title: '=HYPERLINK(\"x\")'}")
    source = tmp_path / "sf_inverter.yaml"
    source.write_text(text, encoding="utf-8")
    exported = export_csv(load_map(source))
    assert "'=HYPERLINK" in exported
    table = tmp_path / "t.csv"
    table.write_text(exported, encoding="utf-8", newline="")
    run = _import(table, tmp_path / "again.yaml")
    assert run.returncode == ExitCode.OK, run.stderr
    again = {r["name"]: r for g in yaml.safe_load((tmp_path / "again.yaml").read_text(encoding="utf-8"))["groups"] for r in g["registers"]}
    assert again["w"]["title"] == '=HYPERLINK("x")' and again["w"]["scale_from"] == "w_sf"


def test_a_factor_that_is_itself_scaled_is_refused_at_the_cell(tmp_path: Path) -> None:
    table = _csv(tmp_path, "Address,Name,Type,SF\n0x0000,a,u16,b\n0x0001,b,s16,c\n0x0002,c,s16,\n")
    run = _import(table, tmp_path / "chain.yaml")
    assert run.returncode == ExitCode.USAGE
    assert f"{table}:2:4: scale_from 'b': b is itself scaled; a scale factor is a plain s16" in run.stderr
    assert not (tmp_path / "chain.yaml").exists()


def test_an_update_never_takes_a_printed_value_of_a_scaled_register_for_its_raw_value(tmp_path: Path) -> None:
    """A table without the scale_from column that prints a value for a register the map scales: raw x 10^sf is
    known only on the bus, so the value is not applied (it would be stored as raw) and the map keeps its text."""
    target = tmp_path / "sf_inverter.yaml"
    shutil.copy(INVERTER, target)
    table = _csv(tmp_path, "name,address,type,default,default_value\na,0,u16,1234,12.5\n")
    run = _import(table, target)
    assert run.returncode == ExitCode.OK, run.stderr + run.stdout
    assert f"{table}:2:5: a.default_value: value = raw x 10^a_sf, read at run time: not applied" in run.stderr
    assert "no changes" in run.stdout and target.read_bytes() == INVERTER.read_bytes()
