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

from regmap.diagnostics import ExitCode
from regmap.frontend import load_map
from regmap.model import Device, Register
from regmap.tools.spreadsheet.export import export_csv, export_xlsx

from conftest import MAPS, ROOT


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
    # EPOCH is seconds since 1970: a timestamp, whose zone the table does not give: left out, said, never guessed
    assert regs["Clock"]["type"] == "timestamp" and "zone" not in regs["Clock"] and "EPOCH" in str(regs["Clock"]["notes"])
    assert f"{tmp_path / 'meter.csv'}:7:3: type timestamp from the printed 'EPOCH' (seconds since 1970)" in run.stderr
    assert run.returncode == ExitCode.INVALID_MAP  # the draft is written, and the front end asks for the zone


def test_an_unknown_type_with_a_register_count_takes_its_width_from_the_count(tmp_path: Path) -> None:
    run, draft = _import(tmp_path, "Address,Title,Type,Number of registers\n0x0000,Flags,FLAGS32,2\n")
    reg = _registers(draft)["Flags"]
    assert reg["type"] == "u32" and "FLAGS32" in str(reg["notes"]) and "signedness" in str(reg["notes"])
    assert run.returncode == ExitCode.OK, run.stderr


TIMES = """Address,Title,Type,Number of registers,Zone
0x0000,Clock,EPOCH,2,
0x0002,Last reset,Epoch (UTC),2,
0x0004,Meter time,UNIX time,2,local
0x0006,Event,timestamp,2,UTC
0x0008,Set at,datetime (s since 1970),2,local time
0x000A,Calendar,datetime,3,
"""


def test_epoch_types_import_as_timestamps_with_the_zone_the_table_gives(tmp_path: Path) -> None:
    run, draft = _import(tmp_path, TIMES)
    regs = _registers(draft)
    got = {title: (regs[title]["type"], regs[title].get("zone")) for title in ("Clock", "Last reset", "Meter time", "Event", "Set at")}
    assert got == {
        "Clock": ("timestamp", None),  # EPOCH alone: the zone is not in the table
        "Last reset": ("timestamp", "utc"),
        "Meter time": ("timestamp", "local"),
        "Event": ("timestamp", "utc"),
        "Set at": ("timestamp", "local"),
    }
    assert regs["Calendar"]["type"] is None  # a bare `datetime` of 3 words is no count of seconds (BCD fields, likely)
    assert f"{tmp_path / 'meter.csv'}:2:3: type timestamp from the printed 'EPOCH'" in run.stderr and "never guessed" in run.stderr
    assert "zone" in str(regs["Clock"]["notes"])


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


@pytest.mark.parametrize(("header", "scale"), [("Multiplier", 100), ("Resolution", 100)])
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


# -- registers only some models have ------------------------------------------------------------------

MODELS = """Register,Name,Title,Type,Access,Applicable models,Unit
0x0000,voltage_a,Phase A voltage,U16,RO,,V
0x0001,voltage_b,Phase B voltage,U16,RO,Three-phase,V
0x0002,string_3,String 3 current,U16,RO,"X1-4 / Three-phase",A
0x0003,string_5,String 5 current,U16,RO,4-string,A
"""


def test_a_models_column_makes_variants_the_draft_declares(tmp_path: Path) -> None:
    run, draft = _import(tmp_path, MODELS)
    assert "column 6 'Applicable models' -> variants" in run.stdout
    assert f"{tmp_path / 'meter.csv'}:5:6: cannot read variant '4-string'" in run.stderr  # reported, never dropped
    assert run.returncode == ExitCode.OK, run.stderr + run.stdout
    device = load_map(draft)  # the draft declares every variant its registers name, so it validates
    assert [v.name for v in device.info.variants] == ["three_phase", "x1_4"]
    got = {r.name: r.variants for r in device.registers}
    assert got == {"voltage_a": (), "voltage_b": ("three_phase",), "string_3": ("x1_4", "three_phase"), "string_5": ()}
    assert "4-string" in (device.register("string_5").notes or "")  # on every model until the table is read again


def test_an_update_naming_a_variant_the_map_does_not_declare_is_refused_and_writes_nothing(tmp_path: Path) -> None:
    path = ROOT / "tests" / "maps" / "fixtures" / "float_meter.yaml"
    target = tmp_path / path.name
    target.write_bytes(path.read_bytes())
    rows = list(csv.reader(io.StringIO(export_csv(load_map(path)).lstrip("\ufeff"))))
    rows[next(i for i, r in enumerate(rows) if r[0] == "voltage_l2")][rows[0].index("variants")] = "four_phase"
    run = _regmap("import", str(_write(rows, tmp_path / "t.csv")), "--into", str(target))
    assert run.returncode == ExitCode.INVALID_MAP, run.stdout
    assert "four_phase" in run.stderr and "nothing written" in run.stderr and target.read_bytes() == path.read_bytes()


def test_an_update_moving_a_register_to_another_declared_variant_changes_that_line_only(tmp_path: Path) -> None:
    path = ROOT / "tests" / "maps" / "fixtures" / "float_meter.yaml"
    target = tmp_path / path.name
    target.write_bytes(path.read_bytes())
    rows = list(csv.reader(io.StringIO(export_csv(load_map(path)).lstrip("\ufeff"))))
    rows[next(i for i, r in enumerate(rows) if r[0] == "voltage_l2")][rows[0].index("variants")] = "single_phase, three_phase"
    run = _regmap("import", str(_write(rows, tmp_path / "t.csv")), "--into", str(target))
    assert run.returncode == ExitCode.OK, run.stderr
    changed = [line for line in difflib.ndiff(path.read_text().splitlines(), target.read_text().splitlines()) if line[:1] in "+-"]
    assert len(changed) == 2 and all("voltage_l2" in line for line in changed), changed
    assert load_map(target).register("voltage_l2").variants == ("single_phase", "three_phase")


# -- the engineer's loop on every shipped map: export, edit in engineering units, add, import back ----


def _rows(device: Device) -> list[list[str]]:
    return list(csv.reader(io.StringIO(export_csv(device).lstrip("\ufeff"))))


def _write(rows: list[list[str]], path: Path) -> Path:
    with path.open("w", encoding="utf-8", newline="") as handle:
        csv.writer(handle).writerows(rows)
    return path


def engineering(reg: Register, raw: int) -> str:
    """raw x scale + offset as the export prints it."""
    value = raw * reg.scale + reg.offset
    return str(value.numerator) if value.denominator == 1 else str(float(value))


def _scaled_default(device: Device) -> tuple[Register, int]:
    """A register with a scale, a default and room above it: its new raw default, one step up."""
    reg = next(
        r
        for r in device.registers
        if r.scale != 1 and r.array is None and isinstance(r.default, int) and isinstance(r.max, int) and r.default < r.max
    )
    assert isinstance(reg.default, int)
    return reg, reg.default + 1


def _added_row(header: list[str], device: Device) -> list[str]:
    free = next(a for a in range(0xFE00, 0x10000) if device.at_address(a, "holding") is None)
    cells = {"name": "added_setting", "address_hex": f"0x{free:04X}", "address": str(free), "type": "u16", "access": "rw"}
    cells |= {"title": "Added setting", "min": "0", "max": "100", "default": "5", "space": "holding"}
    return [cells.get(column, "") for column in header]


@pytest.mark.parametrize("path", MAPS, ids=lambda p: p.name)
def test_edit_a_default_in_engineering_units_and_add_a_register(tmp_path: Path, path: Path) -> None:
    target = tmp_path / path.name
    target.write_bytes(path.read_bytes())
    device = load_map(path)
    reg, raw = _scaled_default(device)
    rows = _rows(device)
    header = rows[0]
    row = next(r for r in rows if r[0] == reg.name)
    shown = engineering(reg, raw)
    row[header.index("default_value")] = str(shown)  # only the engineering column: the raw one still says the old default
    rows.append(_added_row(header, device))
    table = _write(rows, tmp_path / "edited.csv")

    dry = _regmap("import", str(table), "--into", str(target), "--dry-run")
    assert dry.returncode == ExitCode.OK, dry.stderr
    assert f"would update {target}: 1 value(s) changed, 1 register(s) added" in dry.stdout and "written" not in dry.stdout
    assert target.read_bytes() == path.read_bytes()

    run = _regmap("import", str(table), "--into", str(target))
    assert run.returncode == ExitCode.OK, run.stderr
    assert f"updated {target}: 1 value(s) changed, 1 register(s) added" in run.stdout
    after = load_map(target)
    assert after.register(reg.name).default == raw and after.register("added_setting").max == 100
    before_lines, after_lines = path.read_text(encoding="utf-8").splitlines(), target.read_text(encoding="utf-8").splitlines()
    ops = [op for op in difflib.SequenceMatcher(None, before_lines, after_lines, autojunk=False).get_opcodes() if op[0] != "equal"]
    assert [op[0] for op in ops] == ["replace", "insert"], ops
    _, i1, i2, j1, j2 = ops[0]
    assert i2 - i1 == j2 - j1 == 1
    assert re.sub(rf"default: {reg.default}\b", f"default: {raw}", before_lines[i1]) == after_lines[j1] != before_lines[i1]
    inserted = after_lines[ops[1][3] : ops[1][4]]
    assert inserted[0].strip() == "- id: imported" and any("name: added_setting" in line for line in inserted)


def test_a_change_of_only_an_engineering_column_is_a_change(tmp_path: Path) -> None:
    path = ROOT / "maps" / "id243pro.yaml"
    target = tmp_path / path.name
    target.write_bytes(path.read_bytes())
    device = load_map(path)
    reg, raw = _scaled_default(device)
    rows = _rows(device)
    rows[next(i for i, r in enumerate(rows) if r[0] == reg.name)][rows[0].index("default_value")] = engineering(reg, raw)
    run = _regmap("import", str(_write(rows, tmp_path / "t.csv")), "--into", str(target))
    assert run.returncode == ExitCode.OK, run.stderr
    assert "no changes" not in run.stdout and load_map(target).register(reg.name).default == raw


def test_raw_and_engineering_columns_that_disagree_are_refused(tmp_path: Path) -> None:
    path = ROOT / "maps" / "id243pro.yaml"
    target = tmp_path / path.name
    target.write_bytes(path.read_bytes())
    device = load_map(path)
    reg, raw = _scaled_default(device)
    rows = _rows(device)
    row = rows[next(i for i, r in enumerate(rows) if r[0] == reg.name)]
    row[rows[0].index("default")] = str(raw)
    row[rows[0].index("default_value")] = engineering(reg, raw + 1)
    run = _regmap("import", str(_write(rows, tmp_path / "t.csv")), "--into", str(target))
    column = rows[0].index("default_value") + 1
    assert re.search(rf"t.csv:[0-9]+:{column}: {reg.name}: default {raw} and default_value", run.stderr) and "neither applied" in run.stderr
    assert target.read_bytes() == path.read_bytes()


def test_unreadable_cells_in_an_update_say_the_map_keeps_its_values(tmp_path: Path) -> None:
    path = ROOT / "maps" / "id243pro.yaml"
    target = tmp_path / path.name
    target.write_bytes(path.read_bytes())
    device = load_map(path)
    rows = _rows(device)
    reg = next(r for r in device.registers if isinstance(r.max, int) and r.array is None)
    rows[next(i for i, r in enumerate(rows) if r[0] == reg.name)][rows[0].index("max")] = "lots"
    run = _regmap("import", str(_write(rows, tmp_path / "t.csv")), "--into", str(target))
    assert run.returncode == ExitCode.OK, run.stderr
    assert "cannot read max 'lots'" in run.stderr
    assert "1 cell(s) could not be read (listed above): 1 in registers the map has: not applied, the map keeps its values" in run.stdout
    assert "null with a note" not in run.stdout and target.read_bytes() == path.read_bytes()


def test_a_rejected_update_names_lines_of_the_map_on_disk(tmp_path: Path) -> None:
    path = ROOT / "maps" / "idm_rs.yaml"
    target = tmp_path / path.name
    target.write_bytes(path.read_bytes())
    device = load_map(path)
    below = next(r.address - 1 for r in device.registers if r.space == "holding" and device.at_address(r.address - 1, "holding") is None)
    table = tmp_path / "t.csv"
    table.write_text(f"Address,Name,Title,Type\n0x{below:04X},clash,Clash,u32\n", encoding="utf-8")  # its high word overlaps a register
    run = _regmap("import", str(table), "--into", str(target))
    assert run.returncode == ExitCode.INVALID_MAP, run.stdout
    assert "nothing written" in run.stderr and target.read_bytes() == path.read_bytes()
    lines = [line for line in run.stderr.splitlines() if "nothing written" not in line]
    # the overlap is in the group the update adds: no line number of a file that holds no such line
    assert lines and all(line.startswith(f"{target}: in the text the update would write (") and "clash" in line for line in lines), lines


def test_dry_run_of_a_draft_the_front_end_rejects_says_nothing_was_written(tmp_path: Path) -> None:
    run, draft = _import(tmp_path, "Address,Title,Type\n0x0000,Clock,EPOCH\n", "--dry-run")
    assert run.returncode == ExitCode.INVALID_MAP and not draft.exists()
    assert f"would write {draft}: a new draft, 1 registers in 1 group(s), which the front end rejects (above)" in run.stdout
    assert "written" not in run.stdout


# -- exports write no formula, and an import gives the text back --------------------------------

FORMULAS = ['=HYPERLINK("http://evil.example","click")', "+1+cmd|' /C calc'!A0", "-2+3", "@SUM(1)", "'=already quoted"]


def _map_with_titles(tmp_path: Path) -> Path:
    text = (ROOT / "tests" / "maps" / "small" / "idm_rs_small.yaml").read_text(encoding="utf-8")
    for old, new in zip(
        ("Command pulses per revolution", "Motor direction", "Peak current", "DI2 function", "DI3 function"), FORMULAS, strict=True
    ):
        assert f"title: {old}," in text
        text = text.replace(f"title: {old},", f"title: {yaml.safe_dump(new, default_style=chr(34)).strip()},", 1)
    target = tmp_path / "device.yaml"
    target.write_text(text, encoding="utf-8")
    return target


def test_csv_export_neutralises_formulas_and_an_import_gives_them_back(tmp_path: Path) -> None:
    target = _map_with_titles(tmp_path)
    device = load_map(target)
    assert {r.title for r in device.registers} >= set(FORMULAS)
    text = export_csv(device)
    for row in csv.reader(io.StringIO(text.lstrip("\ufeff"))):
        for cell in row:
            assert not cell.startswith(("=", "+", "@", "\t", "\r")), cell
            assert not cell.startswith("-") or re.fullmatch(r"-[0-9.]+", cell), cell
    assert "'=HYPERLINK(" in text and "''=already quoted" in text
    table = tmp_path / "device.csv"
    table.write_text(text, encoding="utf-8")
    run = _regmap("import", str(table), "--into", str(target))
    assert run.returncode == ExitCode.OK and "no changes" in run.stdout, run.stderr + run.stdout
    draft = tmp_path / "again.yaml"
    _regmap("import", str(table), "--into", str(draft))  # a CSV carries no enums: the draft names them, the front end asks for them
    assert set(_registers(draft)) >= set(FORMULAS)


def test_xlsx_export_writes_text_cells_never_formulas_and_an_import_gives_them_back(tmp_path: Path) -> None:
    target = _map_with_titles(tmp_path)
    book = tmp_path / "device.xlsx"
    book.write_bytes(export_xlsx(load_map(target)))
    sheet = openpyxl.load_workbook(book)["registers"]
    titles = [c for row in sheet.iter_rows() for c in row if c.value in FORMULAS]
    assert len(titles) == len(FORMULAS) and all(c.data_type == "s" for c in titles)
    run = _regmap("import", str(book), "--into", str(target))
    assert run.returncode == ExitCode.OK and "no changes" in run.stdout, run.stderr + run.stdout
    draft = tmp_path / "again.yaml"
    _regmap("import", str(book), "--into", str(draft))
    assert set(_registers(draft)) >= set(FORMULAS)


# -- spellings as datasheets print them ----------------------------------------------------------

SPELLINGS = """Address,Title,Type,Access,Units
00 0C,Reactive power,F32,R/WP,VAr
0x00O2,Reactive energy,F32,RO,kVArh
001EH,Phase angle,F32,WO,Degrees
0x0020,Apparent energy,F32,R/W,kVAh
0x0022,Charge,F32,RO,Ah
0x0024,Demand time,U16,RO,minutes
0x0025,Count,U16,RO,None
0x0026,Supply,F32,RO,VOLTS
"""


def test_addresses_units_and_access_as_datasheets_print_them(tmp_path: Path) -> None:
    run, draft = _import(tmp_path, SPELLINGS)
    assert run.returncode == ExitCode.OK, run.stderr + run.stdout
    assert f"{tmp_path / 'meter.csv'}:3:1: address '0x00O2' read as 0x0002: a letter O taken for a zero" in run.stdout
    regs = {r.title: r for r in load_map(draft).registers}
    got = {t: (r.address, r.unit, r.access.value) for t, r in regs.items()}
    assert got == {
        "Reactive power": (0x000C, "var", "rw"),
        "Reactive energy": (0x0002, "kvarh", "r"),
        "Phase angle": (0x001E, "°", "w"),
        "Apparent energy": (0x0020, "kVAh", "rw"),
        "Charge": (0x0022, "Ah", "r"),
        "Demand time": (0x0024, "min", "r"),
        "Count": (0x0025, None, "r"),
        "Supply": (0x0026, "V", "r"),
    }
    assert "password" in (regs["Reactive power"].notes or "")


VALUE_TABLES = """Address,Title,Type,Range,Description
0x0000,Baud rate,U16,"0 = 2400, 1 = 4800",
0x0001,Prefix,U16,,"0: k, 1: M"
0x0002,CT ratio,U16,"60, 100, 200",
0x0003,Speed,U16,0~100,0 = stop 1 = go
"""


def test_values_listed_in_a_range_or_description_cell_become_an_enum(tmp_path: Path) -> None:
    run, draft = _import(tmp_path, VALUE_TABLES)
    assert run.returncode == ExitCode.OK, run.stderr + run.stdout
    regs = {r.title: r for r in load_map(draft).registers}

    def members(title: str) -> list[tuple[int, str]]:
        enum = regs[title].enum
        assert enum is not None, title
        return [(m.value, m.title) for m in enum.members]

    assert members("Baud rate") == [(0, "2400"), (1, "4800")]
    assert members("Prefix") == [(0, "k"), (1, "M")]
    assert members("CT ratio") == [(60, "60"), (100, "100"), (200, "200")]
    assert (regs["CT ratio"].min, regs["CT ratio"].max) == (60, 200)
    assert regs["Speed"].enum is None and "does not bound" in (regs["Speed"].notes or "")  # 0..100 is no list of two values


def test_the_mapping_file_can_say_how_addresses_read(tmp_path: Path) -> None:
    mapping = tmp_path / "columns.yaml"
    mapping.write_text("addresses: modicon\n", encoding="utf-8")
    run, draft = _import(tmp_path, "Register,Title,Type\n40001,Mode,U16\n", "--columns", str(mapping))
    assert run.returncode == ExitCode.OK, run.stderr
    assert [(r.space, r.address) for r in load_map(draft).registers] == [("holding", 0)]
    mapping.write_text("addresses: 1-based\n", encoding="utf-8")
    run, _ = _import(tmp_path, "Register,Title,Type\n40001,Mode,U16\n", "--columns", str(mapping), name="bad")
    assert run.returncode == ExitCode.USAGE and f"{mapping}: addresses: expected modicon or plain" in run.stderr
    assert "Traceback" not in run.stderr


def test_a_diagnostic_after_an_insertion_names_the_line_of_the_map_on_disk() -> None:
    from regmap.diagnostics import Diagnostic
    from regmap.tools.spreadsheet import importer

    original = "a: 1\nb: 2\nc: 3\n"
    edits = [importer.Edit(5, 5, "x: 9\ny: 8\n"), importer.Edit(13, 14, "30")]  # two lines before b; c's value
    update = importer.Update(importer._apply(original, edits), original=original, edits=edits)
    assert update.text == "a: 1\nx: 9\ny: 8\nb: 2\nc: 30\n"
    assert update.locate(Diagnostic("m.yaml", 4, 4, "bad b")) == "m.yaml:2:4: bad b"
    assert update.locate(Diagnostic("m.yaml", 1, 1, "bad a")) == "m.yaml:1:1: bad a"
    assert update.locate(Diagnostic("m.yaml", 2, 1, "bad x")) == "m.yaml: in the text the update would write ('x: 9'): bad x"


def test_coils_whose_leading_zeros_a_spreadsheet_dropped_are_not_read_as_addresses_silently(tmp_path: Path) -> None:
    table = "Register,Title,Type\n1,Relay 1,\n2,Relay 2,\n30001,Voltage,U16\n40001,Mode,U16\n"  # 00001 and 00002, as an xlsx keeps them
    run, draft = _import(tmp_path, table)
    assert run.returncode == ExitCode.USAGE and not draft.exists()
    assert "Modicon register numbers" in run.stderr and "--addresses modicon or --addresses plain" in run.stderr
    run, draft = _import(tmp_path, table, "--addresses", "modicon", name="told")
    assert run.returncode == ExitCode.OK, run.stderr
    assert {r.title: (r.space, r.address) for r in load_map(draft).registers} == {
        "Relay 1": ("coil", 0),
        "Relay 2": ("coil", 1),
        "Voltage": ("input", 0),
        "Mode": ("holding", 0),
    }
