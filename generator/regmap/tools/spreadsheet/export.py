"""`regmap export --format csv|xlsx`: one row per register (every field of the JSON contract), and for
xlsx one sheet each for groups, enums, commands, faults and errata.

The rows are built from `regmap.core.contract` (the JSON contract), so the three formats agree.
Output is deterministic: the same map gives the same bytes (the xlsx carries fixed timestamps).

No cell is a formula (OWASP, CSV injection): a CSV text cell that starts with = + - @ or a tab or CR (a
title `=HYPERLINK(...)`, `-2+3`) is written behind a single quote, which `regmap import` takes off again, so
the text comes back as the map has it; a plain number (-500, -0.5) is written as it is. The xlsx writes every
text cell as a string, never as a formula, marked "quote prefix" so that Excel keeps it text when edited.

A register scaled by another (`scale_from`: value = raw x 10^sf, sf that s16 register's raw value read from the
device) names it in the `scale_from` column; its engineering columns (min_value, max_value, default_value) stay
blank, as no value is known before the factor is read: the raw columns are never printed as if they were values.
"""

from __future__ import annotations

import csv
import datetime
import io
import re
import zipfile
from collections.abc import Sequence
from fractions import Fraction
from typing import Any

from regmap.core.contract import export_json, register_json
from regmap.core.text import na_list
from regmap.model import Device, Register
from regmap.tools.spreadsheet.table import FORMULA_LEAD

REGISTER_COLUMNS = (
    "name",
    "param",
    "address_hex",
    "address",
    "type",
    "words",
    "word_order",
    "paired",
    "access",
    "unit",
    "scale",
    "min",
    "max",
    "default",
    "min_value",
    "max_value",
    "default_value",
    "range_text",
    "enum",
    "bitfields",
    "takes_effect",
    "settable",
    "modes",
    "group",
    "array",
    "title",
    "title_zh",
    "description",
    "source",
    "errata",
    "notes",
    # Spaces, orders, offsets, strings, gates: appended, so that every column before keeps its place in old sheets
    "space",
    "byte_order",
    "offset",
    "encoding",
    "padding",
    "firmware_from",
    "firmware_until",
    "poll",
    "na",
    "zone",
    "variants",
    "scale_from",  # value = raw x 10^(that s16 register's raw value), read from the device: the value columns stay blank
)

Cell = str | int | float | bool | None

FIXED_TIME = datetime.datetime(2000, 1, 1)  # docProps created/modified: the same map exports the same bytes
_ZIP_TIME = (1980, 1, 1, 0, 0, 0)


def _number(value: Fraction) -> int | float:
    return value.numerator if value.denominator == 1 else float(value)


def engineering(r: Register, raw: int | float | str | None) -> Cell:
    """raw x scale + offset; text and bits as they are."""
    if raw is None or isinstance(raw, str) or not r.type.numeric:
        return _raw(r, raw)
    if isinstance(raw, float):
        return raw * float(r.scale) + float(r.offset)
    return _number(raw * r.scale + r.offset)


def _raw(r: Register, raw: int | float | str | None) -> Cell:
    """A raw value as a cell: a bit as true/false, the empty text as `""` (a blank cell says "no default")."""
    if r.type.is_bool and raw is not None:
        return bool(raw)
    if raw == "" and r.type.is_string:
        return EMPTY_TEXT
    return raw


EMPTY_TEXT = '""'


def bitfields_text(r: Register) -> str:
    """One field per line, `BITS NAME [<ENUM>]: TITLE` (cells.bitfields reads it back)."""
    return "\n".join(f"{b.bits_text} {b.name}{f' <{b.enum.name}>' if b.enum else ''}: {b.title}" for b in r.bitfields)


def register_row(r: Register) -> dict[str, Cell]:
    j = register_json(r)
    array = j["array"]
    return {
        "name": r.name,
        "param": r.param,
        "address_hex": f"0x{r.address:04X}",
        "address": r.address,
        "type": r.type.value,
        "words": r.words,
        "word_order": r.word_order.value if r.word_order_fixed and r.words == 2 else None,  # empty: the device's order
        "paired": r.paired,
        "access": r.access.value,
        "unit": r.unit,
        "scale": j["scale"],
        "min": r.min,
        "max": r.max,
        "default": _raw(r, r.default),
        "min_value": None if r.scale_from else engineering(r, r.min),  # raw x 10^sf is known only on the bus
        "max_value": None if r.scale_from else engineering(r, r.max),
        "default_value": None if r.scale_from else engineering(r, r.default),
        "range_text": r.range_text,
        "enum": j["enum"],
        "bitfields": bitfields_text(r) or None,
        "takes_effect": r.takes_effect,
        "settable": r.settable,
        "modes": "".join(r.modes) or None,
        "group": r.group,
        "array": None if array is None else f"{array['name']}[{array['index']}].{array['member']}",
        "title": r.title,
        "title_zh": r.title_zh,
        "description": r.description or None,
        "source": ", ".join(r.source) or None,
        "errata": ", ".join(r.errata) or None,
        "notes": r.notes or None,
        "space": j["space"],
        "byte_order": j["byte_order"],  # the register's own, or the device's it follows (empty for a bit)
        "offset": j["offset"],
        "encoding": j["encoding"],
        "padding": j["padding"],
        "firmware_from": r.firmware.first if r.firmware else None,
        "firmware_until": r.firmware.until if r.firmware else None,
        "poll": j["poll"],
        "na": na_list(r) or None,
        "zone": r.zone,
        "variants": ", ".join(r.variants) or None,
        "scale_from": r.scale_from,
    }


def _join(values: Sequence[Any]) -> str | None:
    return ", ".join(str(v) for v in values) or None


def sheets(device: Device) -> dict[str, tuple[tuple[str, ...], list[dict[str, Cell]]]]:
    """Every sheet of the workbook: name -> (columns, rows). `registers` comes first."""
    doc = export_json(device)
    groups = [{"id": g["id"], "title": g["title"], "title_zh": g["title_zh"], "source": _join(g["source"])} for g in doc["groups"]]
    enums = [
        {"enum": name, "enum_title": e["title"], "value": v["value"], "name": v["name"], "title": v["title"], "title_zh": v["title_zh"]}
        | {"symbol": v["symbol"], "description": v["description"] or None}
        for name, e in doc["enums"].items()
        for v in e["values"]
    ]
    commands = [
        {
            "name": c["name"],
            "register": c["register"],
            "address_hex": f"0x{c['address']:04X}",
            "value": c["value"],
            "argument": None if c["argument"] is None else f"{c['argument']['name']} {c['argument']['min']}..{c['argument']['max']}",
            "title": c["title"],
            "title_zh": c["title_zh"],
            "source": _join(c["source"]),
        }
        for c in doc["commands"]
    ]
    faults = [{k: _join(v) if k == "source" else v for k, v in f.items()} for f in doc["faults"]]
    errata = [
        {
            "id": e["id"],
            "title": e["title"],
            "readings": "\n".join(f"{_join(r['source'])}: {r['says']}" for r in e["readings"]),
            "choice": e["choice"],
            "reason": e["reason"],
            "registers": _join(e["registers"]),
        }
        for e in doc["errata"]
    ]
    return {
        "registers": (REGISTER_COLUMNS, [register_row(r) for r in device.registers]),
        "groups": (("id", "title", "title_zh", "source"), groups),
        "enums": (("enum", "enum_title", "value", "name", "title", "title_zh", "symbol", "description"), enums),
        "commands": (("name", "register", "address_hex", "value", "argument", "title", "title_zh", "source"), commands),
        "faults": (("code", "value", "name", "title", "title_zh", "kind", "resettable", "source"), faults),
        "errata": (("id", "title", "readings", "choice", "reason", "registers"), errata),
    }


def _text(value: Cell) -> str:
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    return str(value)


_PLAIN_NUMBER = re.compile(r"[+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?")


def neutralised(text: str) -> str:
    """A CSV cell that no spreadsheet runs as a formula: `=x` -> `'=x`, `'=x` -> `''=x` (so that an import gives back
    exactly the text); a plain number, and any other text, as it is."""
    if text.lstrip("'").startswith(FORMULA_LEAD) and not _PLAIN_NUMBER.fullmatch(text):
        return "'" + text
    return text


def export_csv(device: Device) -> str:
    """UTF-8 with a BOM (Excel then shows Chinese correctly), CRLF rows, one row per register."""
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\r\n")
    writer.writerow(REGISTER_COLUMNS)
    for row in (register_row(r) for r in device.registers):
        writer.writerow([neutralised(_text(row[c])) for c in REGISTER_COLUMNS])
    return "\ufeff" + out.getvalue()


_WIDTHS = {"description": 60, "notes": 60, "reason": 60, "readings": 60, "bitfields": 40, "title": 36, "title_zh": 24, "range_text": 24}


def _fixed_times(archive: bytes) -> bytes:
    """The same zip with every member stamped with one fixed time (openpyxl stamps the current time)."""
    out = io.BytesIO()
    with zipfile.ZipFile(io.BytesIO(archive)) as src, zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as dst:
        for info in src.infolist():
            dst.writestr(zipfile.ZipInfo(info.filename, date_time=_ZIP_TIME), src.read(info), compress_type=zipfile.ZIP_DEFLATED)
    return out.getvalue()


def export_xlsx(device: Device) -> bytes:
    """The workbook: registers first, frozen header rows, column widths that fit, fixed timestamps."""
    from openpyxl import Workbook
    from openpyxl.styles import Alignment, Font
    from openpyxl.utils import get_column_letter
    from openpyxl.writer.excel import ExcelWriter

    wb = Workbook()
    wb.remove(wb.active)  # type: ignore[arg-type]
    bold, wrap = Font(bold=True), Alignment(wrap_text=True, vertical="top")
    for title, (columns, rows) in sheets(device).items():
        ws = wb.create_sheet(title)
        ws.append(list(columns))
        for cell in ws[1]:
            cell.font = bold
        for row in rows:
            ws.append([row[c] for c in columns])
            for cell in ws[ws.max_row]:
                if isinstance(cell.value, str):
                    cell.data_type = "s"  # openpyxl takes a text that starts with = for a formula
                    if cell.value.startswith(FORMULA_LEAD):
                        cell.quotePrefix = True
        ws.freeze_panes = "B2" if title == "registers" else "A2"
        for i, column in enumerate(columns, start=1):
            longest = max([len(column), *(max((len(line) for line in _text(r[column]).splitlines()), default=0) for r in rows)])
            ws.column_dimensions[get_column_letter(i)].width = min(_WIDTHS.get(column, 40), max(8, longest + 2))
            if column in _WIDTHS:
                for (cell,) in ws.iter_rows(min_row=2, min_col=i, max_col=i):
                    cell.alignment = wrap
    wb.properties.creator = "regmap"
    wb.properties.title = f"{device.info.vendor} {device.info.model} register map {device.info.map_version}"
    wb.properties.created = wb.properties.modified = FIXED_TIME
    buffer = io.BytesIO()
    with zipfile.ZipFile(buffer, "w", zipfile.ZIP_DEFLATED) as archive:
        ExcelWriter(wb, archive).write_data()  # not openpyxl's save_workbook, which stamps `modified` with now
    return _fixed_times(buffer.getvalue())
