"""Spreadsheets in and out: export CSV/XLSX, import into a draft or an existing map, regmap new."""

from __future__ import annotations

import csv
import io
import re
import shutil
import subprocess
import sys
from fractions import Fraction
from pathlib import Path
from typing import Any

import openpyxl
import pytest
import yaml

from regmap.cli import main
from regmap.diagnostics import ExitCode
from regmap.frontend import load_map
from regmap.model import Device, Register
from regmap.tools.spreadsheet import cells
from regmap.tools.spreadsheet.cells import CellProblem
from regmap.tools.spreadsheet.export import export_csv, export_xlsx
from regmap_runtime.types import TYPES

from conftest import ROOT, manual
from support import c630s_table
from support.tables import table_changing_a_default

MAPS = sorted((ROOT / "maps").glob("*.yaml"))


def _fields(r: Register) -> dict[str, Any]:
    """The register fields a spreadsheet carries (issue #22)."""
    return {
        "name": r.name,
        "param": r.param,
        "address": r.address,
        "type": r.type.value,
        "access": r.access.value,
        "unit": r.unit,
        "scale": r.scale,
        "min": r.min,
        "max": r.max,
        "default": r.default,
        "enum": r.enum.name if r.enum else None,
        "bitfields": [(b.name, b.lsb, b.msb, b.title, b.enum.name if b.enum else None) for b in r.bitfields],
        "takes_effect": r.takes_effect,
        "settable": r.settable,
        "modes": list(r.modes),
        "source": list(r.source),
        "errata": sorted(r.errata),
        "title": r.title,
        "title_zh": r.title_zh,
        "range_text": r.range_text,
    }


def _draft_fields(draft: dict[str, Any]) -> dict[str, dict[str, Any]]:
    """The same fields read from a draft's YAML (a CSV draft names enums and errata it cannot define)."""
    errata: dict[str, list[str]] = {}
    for e in draft.get("errata") or []:
        for name in e.get("registers") or []:
            errata.setdefault(name, []).append(e["id"])
    out = {}
    for group in draft["groups"]:
        for r in group["registers"]:
            source = r["source"] if isinstance(r["source"], list) else [r["source"]]
            out[r["name"]] = {
                "name": r["name"],
                "param": r.get("param"),
                "address": r["address"],
                "type": r["type"],
                "access": r.get("access", "rw"),
                "unit": r.get("unit"),
                "scale": Fraction(str(r.get("scale", 1))),
                "min": r.get("min"),
                "max": r.get("max"),
                "default": r.get("default"),
                "enum": r.get("enum"),
                "bitfields": [(b["name"], *_bits(b["bits"]), b["title"], b.get("enum")) for b in r.get("bitfields", [])],
                "takes_effect": r.get("takes_effect"),
                "settable": r.get("settable"),
                "modes": r.get("modes", []),
                "source": [str(s) for s in source],
                "errata": sorted(errata.get(r["name"], [])),
                "title": r["title"],
                "title_zh": r.get("title_zh"),
                "range_text": r.get("range_text"),
            }
    return out


def _bits(spec: int | str) -> tuple[int, int]:
    if isinstance(spec, int):
        return spec, spec
    lo, hi = spec.split("-")
    return int(lo), int(hi)


def _regmap(*args: str, cwd: Path | None = None) -> subprocess.CompletedProcess[str]:
    return subprocess.run([str(Path(sys.executable).with_name("regmap")), *args], capture_output=True, text=True, cwd=cwd, check=False)


# -- cells ------------------------------------------------------------------------------------


@pytest.mark.parametrize(("text", "value"), [("0x0191", 0x191), ("0191h", 0x191), ("401", 401), ("-32768", -32768)])
def test_integers_as_manuals_print_them(text: str, value: int) -> None:
    assert cells.integer(text) == value


def test_ranges_units_and_choices() -> None:
    r = cells.printed_range("-32768~32767")
    assert (int(r.lo), int(r.hi)) == (-32768, 32767)
    r = cells.printed_range("0~655.35")
    assert cells.places(r.hi) == 2
    assert cells.printed_range("0rpm~9000rpm").unit == "rpm"
    assert cells.printed_range("0~99, 对应PB组参数号").hi == 99
    listed = cells.printed_range("0: 速度模式 1: 位置模式 2: 转矩模式")
    assert (int(listed.lo), int(listed.hi), listed.listed) == (0, 2, True)
    assert cells.unit("0.1A") == ("A", Fraction(1, 10))
    assert cells.unit("10 ms") == ("ms", Fraction(10))
    assert cells.unit("编码器 单位") == ("encoder unit", None)
    assert cells.choice("立即生效", cells.TAKES_EFFECT, "x") == "immediately"
    assert cells.choice("再次 通电", cells.TAKES_EFFECT, "x") == "after_restart"
    assert cells.modes("ALL") == ["P", "S", "T"]


@pytest.mark.parametrize("text", ["0~∞", "1.00 倍 ~8.00 倍额定转矩", "参考P03-03说明", "0.1rpm", "10~5"])
def test_unreadable_ranges_are_reported_not_guessed(text: str) -> None:
    with pytest.raises(CellProblem):
        cells.printed_range(text)


@pytest.mark.parametrize("text", ["ms(s)", "s(min)", "furlongs"])
def test_unknown_units_are_reported(text: str) -> None:
    with pytest.raises(CellProblem):
        cells.unit(text)


# -- export -----------------------------------------------------------------------------------


def test_csv_is_utf8_with_bom_one_row_per_register() -> None:
    device = load_map(ROOT / "maps" / "c630s.yaml")
    text = export_csv(device)
    assert text.startswith("\ufeffname,param,address_hex,address,")
    assert len(text.strip().split("\r\n")) >= 1 + len(device.registers)
    assert "AI1 偏置" in text


def test_xlsx_is_deterministic_with_sheets_and_frozen_header(tmp_path: Path) -> None:
    device = load_map(ROOT / "maps" / "idm_rs.yaml")
    first = export_xlsx(device)
    assert export_xlsx(device) == first
    assert main(["export", str(ROOT / "maps" / "idm_rs.yaml"), "--format", "xlsx", "--out", str(tmp_path / "a.xlsx")]) == 0
    assert (tmp_path / "a.xlsx").read_bytes() == first
    wb = openpyxl.load_workbook(io.BytesIO(first))
    assert wb.sheetnames == ["registers", "groups", "enums", "commands", "faults", "errata"]
    assert wb["registers"].freeze_panes == "B2"
    assert wb["registers"].max_row == 1 + len(device.registers)
    assert wb.properties.created == wb.properties.modified


def test_xlsx_needs_out(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["export", str(ROOT / "maps" / "idm_rs.yaml"), "--format", "xlsx"]) == ExitCode.USAGE
    assert "--out" in capsys.readouterr().err


# -- round trip -------------------------------------------------------------------------------


@pytest.mark.parametrize("path", MAPS, ids=lambda p: p.stem)
def test_round_trip_through_xlsx(path: Path, tmp_path: Path) -> None:
    device = load_map(path)
    table = tmp_path / f"{device.id}.xlsx"
    table.write_bytes(export_xlsx(device))
    draft = tmp_path / f"{device.id}.yaml"
    run = _regmap("import", str(table), "--into", str(draft))
    assert run.returncode == 0, run.stderr
    again = load_map(draft)  # enums, errata and groups come from their sheets: the draft validates
    assert [_fields(r) for r in again.registers] == [_fields(r) for r in device.registers]


@pytest.mark.parametrize("path", MAPS, ids=lambda p: p.stem)
def test_round_trip_through_csv(path: Path, tmp_path: Path) -> None:
    device = load_map(path)
    table = tmp_path / f"{device.id}.csv"
    table.write_text(export_csv(device), encoding="utf-8", newline="")
    draft = tmp_path / f"{device.id}.yaml"
    run = _regmap("import", str(table), "--into", str(draft))
    # One sheet carries no enum or erratum definitions: the draft names them, the front end asks for them.
    assert run.returncode in (ExitCode.OK, ExitCode.INVALID_MAP), run.stderr
    assert "cannot read" not in run.stderr
    got = _draft_fields(yaml.safe_load(draft.read_text(encoding="utf-8")))
    assert [got[r.name] for r in device.registers] == [_fields(r) for r in device.registers]


# -- the C630S manual's chapter 7 -------------------------------------------------------------


def test_c630s_manual_table_reproduces_the_map(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    manual("c630s.txt")
    summary = c630s_table.report(tmp_path)
    with capsys.disabled():
        print("\nC630S chapter 7 import:\n" + summary)
    draft = (tmp_path / "c630s_draft.yaml").read_text(encoding="utf-8")
    result = c630s_table.agreement(draft, ROOT / "maps" / "c630s.yaml")
    agree = result["agree"]
    assert isinstance(agree, dict)
    assert result["not_in_table"] == ["P0C-00"]  # printed POC-00 (letter O): reported, not guessed
    assert agree["address"] == result["in_table"] == 462
    assert agree["range"] >= 427 and agree["default"] >= 451 and agree["unit"] >= 411 and agree["scale"] >= 454
    load_map(tmp_path / "c630s_draft.yaml")  # the draft goes through the front end


# -- update keeps the map's text --------------------------------------------------------------


def test_update_changes_one_line_and_nothing_else(tmp_path: Path) -> None:
    original = ROOT / "maps" / "id243pro.yaml"
    target = tmp_path / "id243pro.yaml"
    shutil.copy(original, target)
    table, reg, default = table_changing_a_default(load_map(original), tmp_path)
    run = _regmap("import", str(table), "--into", str(target))
    assert run.returncode == 0, run.stderr
    assert "register_default_changed" in run.stdout and reg.name in run.stdout
    before, after = original.read_text(encoding="utf-8").splitlines(), target.read_text(encoding="utf-8").splitlines()
    assert len(before) == len(after)
    changed = [(a, b) for a, b in zip(before, after, strict=True) if a != b]
    assert len(changed) == 1 and str(default) in changed[0][1]


def test_update_with_the_same_table_changes_nothing(tmp_path: Path) -> None:
    for name in ("id243pro", "idm_rs", "c630s"):
        target = tmp_path / f"{name}.yaml"
        shutil.copy(ROOT / "maps" / f"{name}.yaml", target)
        table = tmp_path / f"{name}.xlsx"
        table.write_bytes(export_xlsx(load_map(target)))
        run = _regmap("import", str(table), "--into", str(target))
        assert run.returncode == 0, run.stderr
        assert "no changes" in run.stdout
        assert target.read_bytes() == (ROOT / "maps" / f"{name}.yaml").read_bytes()


# -- bad tables -------------------------------------------------------------------------------


def _bad(tmp_path: Path, name: str, data: bytes) -> subprocess.CompletedProcess[str]:
    table = tmp_path / name
    table.write_bytes(data)
    run = _regmap("import", str(table), "--into", str(tmp_path / "out.yaml"))
    assert run.returncode == ExitCode.USAGE, run.stderr
    assert "Traceback" not in run.stderr
    assert not (tmp_path / "out.yaml").exists()
    return run


def test_missing_address_column(tmp_path: Path) -> None:
    run = _bad(tmp_path, "t.csv", "名称,单位,出厂值\n峰值电流,A,2.2\n".encode())
    assert f"{tmp_path / 't.csv'}:1: no address column" in run.stderr


def test_duplicate_addresses(tmp_path: Path) -> None:
    run = _bad(tmp_path, "t.csv", "地址,名称,单位\n0x0191,峰值电流,A\n0191h,电流,A\n".encode())
    assert f"{tmp_path / 't.csv'}:3:1: address 0x0191 is also the address of row 2" in run.stderr


def test_duplicate_addresses_in_xlsx_name_the_sheet_and_cell(tmp_path: Path) -> None:
    wb = openpyxl.Workbook()
    ws = wb.active
    assert ws is not None
    ws.title = "Sheet1"
    for row in (["address", "name", "title"], ["0x0010", "a", "A"], ["16", "b", "B"]):
        ws.append(row)
    buffer = io.BytesIO()
    wb.save(buffer)
    run = _bad(tmp_path, "t.xlsx", buffer.getvalue())
    assert f"{tmp_path / 't.xlsx'}:Sheet1!A3: address 0x0010 is also the address of row 2" in run.stderr


def test_unreadable_xlsx(tmp_path: Path) -> None:
    run = _bad(tmp_path, "t.xlsx", b"this is not a workbook")
    assert f"{tmp_path / 't.xlsx'}: cannot read as an xlsx workbook" in run.stderr


def test_csv_in_gbk(tmp_path: Path) -> None:
    run = _bad(tmp_path, "t.csv", "地址,名称\n0x0191,峰值电流\n".encode("gbk"))
    assert f"{tmp_path / 't.csv'}:1:1: not UTF-8" in run.stderr and "CSV UTF-8" in run.stderr


def test_unreadable_cell_is_null_with_a_note(tmp_path: Path) -> None:
    table = tmp_path / "t.csv"
    table.write_text("地址,名称,设定范围,单位,出厂值\n0x0010,速度,0~∞,rpm,100\n0x0011,时间,0~655.35,ms,2.00\n", encoding="utf-8")
    run = _regmap("import", str(table), "--into", str(tmp_path / "acme.yaml"))
    assert f"{table}:2:3: cannot read range '0~∞'" in run.stderr
    draft = yaml.safe_load((tmp_path / "acme.yaml").read_text(encoding="utf-8"))
    regs = {r["address"]: r for r in draft["groups"][0]["registers"]}
    assert regs[0x10]["min"] is None and regs[0x10]["max"] is None and "0~∞" in regs[0x10]["notes"]
    assert (regs[0x11]["min"], regs[0x11]["max"], regs[0x11]["default"], regs[0x11]["scale"]) == (0, 65535, 200, 0.01)
    assert run.returncode == 0, run.stderr


# -- regmap new -------------------------------------------------------------------------------


def test_new_writes_a_skeleton_that_validates(tmp_path: Path) -> None:
    out = tmp_path / "acme_x1.yaml"
    assert main(["new", "acme_x1", "--vendor", "Acme", "--model", "X1 servo", "--out", str(out)]) == 0
    device: Device = load_map(out)
    assert device.info.vendor == "Acme" and len(device.registers) == 1
    assert "# check: the factory baud rate" in out.read_text(encoding="utf-8")
    assert main(["new", "acme_x1", "--vendor", "Acme", "--model", "X1", "--out", str(out)]) == ExitCode.USAGE
    assert _regmap("validate", str(out)).returncode == 0


# -- issue #19: spaces, wide and float types, strings, byte order, offsets, gates, poll classes --

# issue #35: registers scaled by a scale-factor register (scale_from) go through the same round trips
FIXTURES = [
    *sorted((ROOT / "tests" / "maps" / "fixtures").glob("*.yaml")),
    *sorted((ROOT / "tests" / "maps" / "scaled_from").glob("*.yaml")),
]
NEW_COLUMNS = [
    *("space", "byte_order", "offset", "encoding", "padding", "firmware_from", "firmware_until", "poll", "na", "zone", "variants"),
    "scale_from",
]


def _wire(r: Register) -> dict[str, Any]:
    """What a client needs to read a register right: the fields issue #19 added, and its range."""
    return {
        "name": r.name,
        "address": r.address,
        "space": r.space,
        "type": r.type.value,
        "words": r.words,
        "access": r.access.value,
        "word_order": r.word_order.value if r.word_order_fixed else None,  # the column names a register's own order
        "byte_order": r.byte_order.value if not r.type.is_bool else None,
        "scale": r.scale,
        "offset": r.offset,
        "min": r.min,
        "max": r.max,
        "default": r.default,
        "encoding": r.encoding if r.type.is_string else None,
        "padding": r.padding if r.type.is_string else None,
        "firmware": None if r.firmware is None else (r.firmware.first, r.firmware.until),
        "variants": list(r.variants),
        "poll": r.poll.value,
        "na": (r.na, r.na_nan),  # issue #34: the "not available" markers survive the round trip
        "zone": r.zone,  # issue #34: a timestamp's clock survives the round trip
        "scale_from": r.scale_from,  # issue #35: the scale-factor register survives the round trip
        "unit": r.unit,
        "title": r.title,
    }


def _draft_wire(r: dict[str, Any]) -> dict[str, Any]:
    """The same fields read from a draft's YAML, with the map format's defaults."""
    kind = r["type"]
    gate = r.get("firmware")
    default = r.get("default")
    return {
        "name": r["name"],
        "address": r["address"],
        "space": r.get("space", "holding"),
        "type": kind,
        "words": r.get("words", TYPES[kind].words or 1),
        "access": r.get("access", "rw"),
        "word_order": r.get("word_order"),
        "byte_order": None if kind == "bool" else r.get("byte_order", "high_first"),
        "scale": Fraction(str(r.get("scale", 1))),
        "offset": Fraction(str(r.get("offset", 0))),
        "min": r.get("min"),
        "max": r.get("max"),
        "default": int(default) if isinstance(default, bool) else default,
        "encoding": r.get("encoding", "ascii") if kind == "string" else None,
        "padding": r.get("padding", "nul") if kind == "string" else None,
        "firmware": None if gate is None else (gate.get("from"), gate.get("until")),
        "variants": r.get("variants", []),
        "poll": r.get("poll", "normal"),
        "na": _draft_na(kind, r.get("na") or []),
        "zone": r.get("zone"),
        "scale_from": r.get("scale_from"),
        "unit": r.get("unit"),
        "title": r["title"],
    }


def _draft_na(kind: str, marks: list[Any]) -> tuple[tuple[int | float, ...], bool]:
    """A draft's `na` as the model holds it: a signed register's bit patterns as its values, `nan` apart."""
    info = TYPES[kind]
    values = tuple(m - (1 << info.bits) if info.signed and isinstance(m, int) and m > info.raw_max else m for m in marks if m != "nan")
    return values, "nan" in marks


def test_seed_exports_only_gain_columns_at_the_end() -> None:
    """The columns before issue #19 keep their place and their values; the new ones hold the defaults."""
    for path in MAPS:
        rows = list(csv.reader(io.StringIO(export_csv(load_map(path)).lstrip("\ufeff"))))
        assert rows[0][-len(NEW_COLUMNS) :] == NEW_COLUMNS
        assert rows[0][: -len(NEW_COLUMNS)][:4] == ["name", "param", "address_hex", "address"]
        assert {tuple(r[-len(NEW_COLUMNS) :]) for r in rows[1:]} == {
            ("holding", "high_first", "0", "", "", "", "", "normal", "", "", "", "")
        }


@pytest.mark.parametrize("path", FIXTURES, ids=lambda p: p.stem)
def test_fixture_round_trip_through_xlsx(path: Path, tmp_path: Path) -> None:
    device = load_map(path)
    table = tmp_path / f"{device.id}.xlsx"
    table.write_bytes(export_xlsx(device))
    draft = tmp_path / f"{device.id}.yaml"
    run = _regmap("import", str(table), "--into", str(draft))
    assert run.returncode == 0, run.stderr
    assert "cannot read" not in run.stderr + run.stdout
    again = load_map(draft)  # the draft validates: function codes follow the spaces it uses
    assert [_wire(r) for r in again.registers] == [_wire(r) for r in device.registers]


@pytest.mark.parametrize("path", FIXTURES, ids=lambda p: p.stem)
def test_fixture_round_trip_through_csv(path: Path, tmp_path: Path) -> None:
    device = load_map(path)
    table = tmp_path / f"{device.id}.csv"
    table.write_text(export_csv(device), encoding="utf-8", newline="")
    draft = tmp_path / f"{device.id}.yaml"
    run = _regmap("import", str(table), "--into", str(draft))
    assert run.returncode in (ExitCode.OK, ExitCode.INVALID_MAP), run.stderr  # a CSV carries no enum definitions
    assert "cannot read" not in run.stderr
    data = yaml.safe_load(draft.read_text(encoding="utf-8"))
    got = {r["name"]: _draft_wire(r) for g in data["groups"] for r in g["registers"]}
    assert [got[r.name] for r in device.registers] == [_wire(r) for r in device.registers]


@pytest.mark.parametrize("path", FIXTURES, ids=lambda p: p.stem)
def test_fixture_update_with_its_own_table_changes_nothing(path: Path, tmp_path: Path) -> None:
    """Inherited spaces, gates and poll classes and the device's byte order compare equal, so nothing is written."""
    target = tmp_path / path.name
    shutil.copy(path, target)
    table = tmp_path / "table.xlsx"
    table.write_bytes(export_xlsx(load_map(target)))
    run = _regmap("import", str(table), "--into", str(target))
    assert run.returncode == 0, run.stderr
    assert "no changes" in run.stdout
    assert target.read_bytes() == path.read_bytes()


def test_update_changes_a_gate_and_a_byte_order_in_place(tmp_path: Path) -> None:
    path = ROOT / "tests" / "maps" / "fixtures" / "swapped_gated.yaml"
    target = tmp_path / path.name
    shutil.copy(path, target)
    rows = list(csv.reader(io.StringIO(export_csv(load_map(path)).lstrip("\ufeff"))))
    header = rows[0]
    row = next(r for r in rows if r[0] == "torque_limit")
    row[header.index("firmware_from")] = "2.1"
    row = next(r for r in rows if r[0] == "speed")
    row[header.index("byte_order")] = "high_first"
    table = tmp_path / "changed.csv"
    with table.open("w", encoding="utf-8", newline="") as handle:
        csv.writer(handle).writerows(rows)
    run = _regmap("import", str(table), "--into", str(target))
    assert run.returncode == 0, run.stderr
    assert "register_firmware_changed" in run.stdout and "register_byte_order_changed" in run.stdout
    again = load_map(target)
    gate = again.register("torque_limit").firmware
    assert gate is not None and gate.first == "2.1"
    assert again.register("speed").byte_order.value == "high_first"
    assert again.register("position").byte_order.value == "low_first"  # still the device's
    before, after = path.read_text(encoding="utf-8").splitlines(), target.read_text(encoding="utf-8").splitlines()
    assert len(before) == len(after) and sum(a != b for a, b in zip(before, after, strict=True)) == 2


VENDOR_TABLE = """\
地址,名称,寄存器类型,数据类型,字数,字节序,单位,设定范围,偏移量,字符编码,起始固件版本,轮询
0x0000,A相电压,输入寄存器,浮点数,,CDAB,V,0.0~500.0,,,,快
0x0002,有功电能,04,uint64,,,kWh,,,,,慢
0x0006,温度,3x,int16,,低字节在前,℃,-40.0~85.0,-40,,2.1,
0x0100,型号,保持寄存器,字符串,8,,,,,gbk,,静态
0x0000,继电器1,线圈,,,,,,,,,
0x0001,门磁,离散输入,,,,,,,,1.5,
"""


def test_a_vendor_table_with_the_new_columns_imports_into_a_valid_map(tmp_path: Path) -> None:
    """Chinese headers and the spellings vendors print: 输入寄存器, 04, 3x, 浮点数, CDAB, 低字节在前, 字符串, 线圈."""
    table = tmp_path / "meter.csv"
    table.write_text(VENDOR_TABLE, encoding="utf-8")
    draft = tmp_path / "meter.yaml"
    run = _regmap("import", str(table), "--into", str(draft))
    assert run.returncode == 0, run.stderr + run.stdout
    for header, field in (("寄存器类型", "space"), ("字节序", "byte_order"), ("偏移量", "offset"), ("起始固件版本", "firmware_from")):
        assert f"{header!r} -> {field}" in run.stdout
    device = load_map(draft)
    by_title = {r.title_zh: r for r in device.registers}
    voltage = by_title["A相电压"]
    assert (voltage.space, voltage.type.value, voltage.word_order.value, voltage.byte_order.value) == (
        "input",
        "f32",
        "low_first",
        "high_first",
    )
    assert (voltage.min, voltage.max, voltage.scale, voltage.poll.value) == (0.0, 500.0, Fraction(1), "fast")
    energy = by_title["有功电能"]
    assert (energy.space, energy.type.value, energy.poll.value) == ("input", "u64", "slow")
    temperature = by_title["温度"]
    assert (temperature.space, temperature.byte_order.value, temperature.offset, temperature.scale) == (
        "input",
        "low_first",
        Fraction(-40),
        Fraction(1, 10),
    )
    assert (temperature.min, temperature.max) == (0, 1250)  # (-40.0 - -40) / 0.1 .. (85.0 - -40) / 0.1
    assert temperature.firmware is not None and temperature.firmware.first == "2.1"
    model = by_title["型号"]
    assert (model.space, model.type.value, model.words, model.encoding, model.poll.value) == ("holding", "string", 8, "gbk", "static")
    relay, door = by_title["继电器1"], by_title["门磁"]
    assert (relay.space, relay.type.value, relay.access.value) == ("coil", "bool", "rw")
    assert (door.space, door.type.value, door.access.value) == ("discrete_input", "bool", "r")
    assert set(device.transport.function_codes) == {0x01, 0x02, 0x03, 0x04, 0x05, 0x06, 0x0F, 0x10}


@pytest.mark.parametrize(
    ("text", "value"),
    [
        ("04", "input"),
        ("0x03/0x06/0x10", "holding"),
        ("01", "coil"),
        ("2", "discrete_input"),
        ("4x", "holding"),
        ("离散输入", "discrete_input"),
    ],
)
def test_spaces_as_tables_print_them(text: str, value: str) -> None:
    assert cells.space(text) == value


@pytest.mark.parametrize(
    ("text", "value"),
    [
        ("ABCD", ("high_first", "high_first")),
        ("CDAB", ("low_first", "high_first")),
        ("DCBA", ("low_first", "low_first")),
        ("BA", (None, "low_first")),
        ("big endian", (None, "high_first")),
        ("低字节在前", (None, "low_first")),
    ],
)
def test_byte_orders_as_tables_print_them(text: str, value: tuple[str | None, str]) -> None:
    assert cells.byte_order(text) == value


@pytest.mark.parametrize("text", ["05", "holding-ish", "0x07"])
def test_unknown_spaces_are_reported(text: str) -> None:
    with pytest.raises(CellProblem):
        cells.space(text)


NEW_REGISTER_TABLE = "Address,Name,Title,Range,Access\n0xFE00,added_setting,Added setting,0~100,RW\n"


@pytest.mark.parametrize("path", [*MAPS, "groups at column 0"], ids=lambda p: p if isinstance(p, str) else p.name)
def test_a_new_register_goes_into_an_existing_map(tmp_path: Path, path: Path | str) -> None:
    """The appended group is indented as the map's own groups are, wherever their dashes stand."""
    target = tmp_path / "device.yaml"
    if isinstance(path, Path):
        target.write_text(path.read_text(encoding="utf-8"), encoding="utf-8")
    else:
        text = (ROOT / "tests" / "maps" / "small" / "idm_rs_small.yaml").read_text(encoding="utf-8")
        flush_left = re.sub(r"(?m)^  ", "", text[text.index("groups:") :])
        target.write_text(text[: text.index("groups:")] + flush_left, encoding="utf-8")
        assert "\n- id:" in target.read_text(encoding="utf-8")
    table = tmp_path / "new.csv"
    table.write_text(NEW_REGISTER_TABLE, encoding="utf-8")
    run = _regmap("import", str(table), "--into", str(target))
    assert run.returncode == ExitCode.OK, run.stderr
    added = next(r for r in load_map(target).registers if r.name == "added_setting")
    assert (added.address, added.min, added.max) == (0xFE00, 0, 100)
