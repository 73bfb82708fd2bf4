"""Datasheet tables as vendors print them, and the engineer's export -> edit -> import loop: never silently wrong."""

from __future__ import annotations

import csv
import difflib
import io
import re
import subprocess
import sys
from pathlib import Path

import openpyxl
import pytest
import yaml

from conftest import MAPS, ROOT
from regmap.diagnostics import ExitCode
from regmap.frontend import load_map
from regmap.model import Device, Register
from regmap.tools.spreadsheet.export import engineering, export_csv, export_xlsx


def _regmap(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([str(Path(sys.executable).with_name("regmap")), *args], capture_output=True, text=True, check=False)


def _import(tmp_path: Path, table_text: str, *options: str, name: str = "meter") -> tuple[subprocess.CompletedProcess[str], Path]:
    table = tmp_path / f"{name}.csv"
    table.write_text(table_text, encoding="utf-8")
    draft = tmp_path / f"{name}.yaml"
    return _regmap("import", str(table), "--into", str(draft), *options), draft


def _registers(draft: Path) -> dict[str, dict[str, object]]:
    data = yaml.safe_load(draft.read_text(encoding="utf-8"))
    return {r["title"]: r for g in data["groups"] for r in g["registers"]}


# -- Modicon register numbers ------------------------------------------------------------------

MODICON = """Parameter Number,Register,Title,Type,Units
1,30001,Phase 1 voltage,F32,Volts
2,30003,Phase 2 voltage,F32,Volts
3,40001,Demand period,U16,minutes
4,00017,Relay,,
"""


def test_a_column_of_modicon_numbers_is_read_as_space_and_offset_and_said(tmp_path: Path) -> None:
    run, draft = _import(tmp_path, MODICON)
    assert run.returncode == ExitCode.OK, run.stderr + run.stdout
    assert "column 2 'Register': Modicon register numbers" in run.stdout
    assert "30001 -> input 0x0000" in run.stdout and "40001 -> holding 0x0000" in run.stdout and "00017 -> coil 0x0010" in run.stdout
    regs = {r.title: r for r in load_map(draft).registers}
    assert (regs["Phase 1 voltage"].space, regs["Phase 1 voltage"].address) == ("input", 0)
    assert (regs["Phase 2 voltage"].space, regs["Phase 2 voltage"].address) == ("input", 2)
    assert (regs["Demand period"].space, regs["Demand period"].address, regs["Demand period"].unit) == ("holding", 0, "min")
    assert (regs["Relay"].space, regs["Relay"].address, regs["Relay"].type.value) == ("coil", 16, "bool")


def test_six_digit_modicon_numbers(tmp_path: Path) -> None:
    run, draft = _import(tmp_path, "Register,Title,Type\n300001,Grid voltage,U16\n300002,Grid current,U16\n")
    assert run.returncode == ExitCode.OK, run.stderr
    assert [(r.space, r.address) for r in load_map(draft).registers] == [("input", 0), ("input", 1)]


def test_a_column_that_may_be_modicon_numbers_or_addresses_is_refused_until_told(tmp_path: Path) -> None:
    table = "Register,Title,Type\n40001,Mode,U16\n40002,Speed,U16\n"
    run, draft = _import(tmp_path, table)
    assert run.returncode == ExitCode.USAGE and not draft.exists()
    assert f"{tmp_path / 'meter.csv'}:1:1: column 1 'Register' holds 40001 .. 40002: Modicon register numbers" in run.stderr
    assert "--addresses modicon or --addresses plain" in run.stderr and "Traceback" not in run.stderr
    run, draft = _import(tmp_path, table, "--addresses", "modicon", name="modicon")
    assert run.returncode == ExitCode.OK, run.stderr
    assert [(r.space, r.address) for r in load_map(draft).registers] == [("holding", 0), ("holding", 1)]
    run, draft = _import(tmp_path, table, "--addresses", "plain", name="plain")
    assert run.returncode == ExitCode.OK, run.stderr
    assert [(r.space, r.address) for r in load_map(draft).registers] == [("holding", 40001), ("holding", 40002)]


# -- types the importer does not know are never a width of its own ---------------------------

TYPES = """Register,Title,Type,Quantity
30001,Voltage,I16,1
30002,Power,I32,2
30004,Status,Bitfield16,1
30005,Alarms,Bitfield32,2
40001,Mode,E16,1
40002,Clock,EPOCH,
"""


def test_a_type_name_the_importer_does_not_know_is_never_made_u16(tmp_path: Path) -> None:
    run, draft = _import(tmp_path, TYPES)
    regs = _registers(draft)
    assert {t: regs[t]["type"] for t in ("Voltage", "Power", "Status", "Alarms", "Mode")} == {
        "Voltage": "s16",
        "Power": "s32",
        "Status": "u16",
        "Alarms": "u32",
        "Mode": "u16",
    }
    assert "Bitfield16" in str(regs["Status"]["notes"]) and "E16" in str(regs["Mode"]["notes"])
    assert regs["Clock"]["type"] is None and "EPOCH" in str(regs["Clock"]["notes"])  # unknown, said, never 1 word
    assert f"{tmp_path / 'meter.csv'}:7:3: cannot read type 'EPOCH'" in run.stderr
    assert run.returncode == ExitCode.INVALID_MAP  # the draft is written, and the front end asks for the type


def test_an_unknown_type_with_a_register_count_takes_its_width_from_the_count(tmp_path: Path) -> None:
    run, draft = _import(tmp_path, "Address,Title,Type,Number of registers\n0x0000,Clock,EPOCH,2\n")
    reg = _registers(draft)["Clock"]
    assert reg["type"] == "u32" and "EPOCH" in str(reg["notes"]) and "signedness" in str(reg["notes"])
    assert run.returncode == ExitCode.OK, run.stderr


def test_a_register_count_that_contradicts_the_type_is_reported(tmp_path: Path) -> None:
    run, _ = _import(tmp_path, "Address,Title,Type,Quantity\n0x0000,Power,I32,1\n")
    assert f"{tmp_path / 'meter.csv'}:2:4: 1 register(s), but type s32 takes 2" in run.stderr


# -- gain divides, scale multiplies -----------------------------------------------------------

GAIN = """Register,Title,Type,Units,Gain,Range
30001,Grid frequency,U16,Hz,100,45~65
30002,Grid voltage,U16,V,10,0~500.0
"""


def test_a_gain_column_divides(tmp_path: Path) -> None:
    run, draft = _import(tmp_path, GAIN, "--addresses", "modicon")
    assert run.returncode == ExitCode.OK, run.stderr
    assert "'Gain' -> gain" in run.stdout
    regs = {r.title: r for r in load_map(draft).registers}
    frequency, voltage = regs["Grid frequency"], regs["Grid voltage"]
    assert (float(frequency.scale), frequency.min, frequency.max) == (0.01, 4500, 6500)  # 50.00 Hz is raw 5000
    assert (float(voltage.scale), voltage.min, voltage.max) == (0.1, 0, 5000)


@pytest.mark.parametrize(("header", "scale"), [("Multiplier", 100), ("Resolution", 100), ("Scale", 100)])
def test_a_multiplier_multiplies(tmp_path: Path, header: str, scale: int) -> None:
    run, draft = _import(tmp_path, f"Address,Title,Type,{header}\n0x0010,Energy,U32,100\n")
    assert run.returncode == ExitCode.OK, run.stderr
    assert load_map(draft).registers[0].scale == scale


def test_an_ambiguous_factor_header_is_refused_until_a_mapping_names_it(tmp_path: Path) -> None:
    table = "Address,Title,Type,Factor\n0x0010,Frequency,U16,100\n"
    run, draft = _import(tmp_path, table)
    assert run.returncode == ExitCode.USAGE and not draft.exists()
    assert f"{tmp_path / 'meter.csv'}:1:4: column 'Factor': raw x factor or raw / factor?" in run.stderr
    mapping = tmp_path / "columns.yaml"
    mapping.write_text("columns: {Factor: gain}\n", encoding="utf-8")
    run, draft = _import(tmp_path, table, "--columns", str(mapping), name="mapped")
    assert run.returncode == ExitCode.OK, run.stderr
    assert float(load_map(draft).registers[0].scale) == 0.01


# -- every column the import does not read is named -------------------------------------------


def test_every_ignored_column_is_named(tmp_path: Path) -> None:
    table = "Parameter Number,Address,Title,Units,Quantity,Remarks,Scope,,Address\n1,0x0010,Voltage,Volts,1,measured,all,x,16\n"
    run, _ = _import(tmp_path, table)
    assert run.returncode == ExitCode.OK, run.stderr
    out = run.stdout
    assert "column 1 'Parameter Number' ignored: not a header regmap knows" in out
    assert "column 7 'Scope' ignored: not a header regmap knows" in out
    assert "column 8 (no header) ignored" in out
    assert "column 9 'Address' ignored: address already comes from another column" in out
    assert "column 4 'Units' -> unit" in out and "column 5 'Quantity' -> words" in out and "column 6 'Remarks' -> notes" in out


# -- a Default column beside a Range column ----------------------------------------------------


def test_a_default_column_beside_a_range_is_a_printed_default_and_keeps_the_range(tmp_path: Path) -> None:
    table = (ROOT / "examples" / "x1-registers.csv").read_text(encoding="utf-8") + "0x0203,P02-03,top_speed,Top speed,0~∞,100,rpm,RW\n"
    run, draft = _import(tmp_path, table, name="x1")
    assert "'Default' -> default_value" in run.stdout
    assert f"{tmp_path / 'x1.csv'}:7:5: cannot read range '0~∞'" in run.stderr  # reported, not dropped
    regs = {r["name"]: r for r in yaml.safe_load(draft.read_text(encoding="utf-8"))["groups"][0]["registers"]}
    assert (regs["control_mode"]["min"], regs["control_mode"]["max"], regs["control_mode"]["default"]) == (0, 2, 0)
    assert (regs["motor_speed"]["min"], regs["motor_speed"]["max"], regs["motor_speed"]["type"]) == (-6000, 6000, "s16")
    assert (regs["acceleration_time"]["max"], regs["acceleration_time"]["default"]) == (10000, 100)
    assert regs["top_speed"]["min"] is None and "0~∞" in regs["top_speed"]["notes"]
