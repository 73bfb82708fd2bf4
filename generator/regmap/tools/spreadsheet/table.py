"""Reading a table: a CSV (UTF-8, with or without a BOM) or one sheet of an XLSX, cells as text with
their positions (`file:row:col` for CSV, `file:Sheet!E17` for XLSX)."""

from __future__ import annotations

import csv
import io
import zipfile
from dataclasses import dataclass, field
from pathlib import Path

from regmap.tools.spreadsheet.columns import AMBIGUOUS, Mapping, ignored, looks_like_header, normalise, recognise


class TableError(Exception):
    """A table that cannot be imported: one line per problem, each naming file, sheet, row and column."""

    def __init__(self, problems: list[str]) -> None:
        self.problems = problems
        super().__init__("\n".join(problems))


def _column_letter(index: int) -> str:
    """0 -> A, 25 -> Z, 26 -> AA."""
    letters = ""
    index += 1
    while index:
        index, rest = divmod(index - 1, 26)
        letters = chr(ord("A") + rest) + letters
    return letters


@dataclass
class Table:
    path: str
    sheet: str | None  # None for CSV
    header: list[str]
    header_row: int  # 1-based
    columns: dict[int, str]  # column index -> field
    rows: list[tuple[int, list[str]]]  # (1-based row number, cells)
    extra: dict[str, list[dict[str, str]]] = field(default_factory=dict)  # xlsx: other sheets by name, rows as header -> text
    ignored: dict[int, str] = field(default_factory=dict)  # column index -> why no field reads it
    said: list[str] = field(default_factory=list)  # how the import read the table where it could have read it otherwise

    def where(self, row: int, column: int | None = None) -> str:
        if self.sheet is None:
            return f"{self.path}:{row}" + ("" if column is None else f":{column + 1}")
        return f"{self.path}:{self.sheet}!" + ("" if column is None else _column_letter(column)) + str(row)

    @property
    def label(self) -> str:
        return self.path if self.sheet is None else f"{self.path}:{self.sheet}"

    def position(self, column: int) -> str:
        return f"column {column + 1}" if self.sheet is None else f"column {_column_letter(column)}"

    def heading(self, column: int) -> str:
        return repr(self.header[column].strip()) if column < len(self.header) and self.header[column].strip() else "(no header)"

    def describe_columns(self) -> list[str]:
        """Every column: the field it is read as, or that it is ignored and why."""
        said = {i: f"-> {name}" for i, name in self.columns.items()} | {i: f"ignored: {why}" for i, why in self.ignored.items()}
        return [f"  {self.position(i)} {self.heading(i)} {text}" for i, text in sorted(said.items())]


FORMULA_LEAD = ("=", "+", "-", "@", "\t", "\r")
"""What makes a spreadsheet read a cell as a formula (OWASP, CSV injection): the CSV export writes such a text
cell behind a single quote, and a CSV import takes the quote off again (an xlsx holds such text as a string)."""


def unquote(text: str) -> str:
    """A cell as the export neutralised it (`'=HYPERLINK(...)`, `''=x`) -> its text; any other cell as it is."""
    body = text.lstrip("'")
    if text.startswith("'") and body.startswith(FORMULA_LEAD):
        return text[1:]
    return text


def _cell_text(value: object) -> str:
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float) and value.is_integer():
        return str(int(value))
    return str(value)


def _decode_csv(path: Path, data: bytes) -> str:
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        before = data[: exc.start]
        line = before.count(b"\n") + 1
        column = exc.start - (before.rfind(b"\n") + 1) + 1
        raise TableError(
            [
                f"{path}:{line}:{column}: not UTF-8 (byte 0x{data[exc.start]:02X}); a CSV saved as GBK/ANSI by Excel: "
                "save it as 'CSV UTF-8' and import again"
            ]
        ) from None


def _csv_rows(path: Path) -> list[list[str]]:
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise TableError([f"{path}: cannot read: {exc.strerror or exc}"]) from None
    text = _decode_csv(path, data)
    try:
        return [[unquote(c) for c in r] for r in csv.reader(io.StringIO(text, newline=""))]
    except csv.Error as exc:
        raise TableError([f"{path}: not a CSV table: {exc}"]) from None


def _xlsx_sheets(path: Path) -> dict[str, list[list[str]]]:
    from openpyxl import load_workbook

    try:
        workbook = load_workbook(path, read_only=True, data_only=True)
    except FileNotFoundError:
        raise TableError([f"{path}: no such file"]) from None
    except (zipfile.BadZipFile, OSError, KeyError, ValueError, TypeError) as exc:
        raise TableError([f"{path}: cannot read as an xlsx workbook: {type(exc).__name__}: {exc}"]) from None
    except Exception as exc:  # openpyxl raises its own exception types for damaged parts
        raise TableError([f"{path}: cannot read as an xlsx workbook: {type(exc).__name__}: {exc}"]) from None
    try:
        return {ws.title: [[_cell_text(v) for v in row] for row in ws.iter_rows(values_only=True)] for ws in workbook.worksheets}
    except Exception as exc:
        raise TableError([f"{path}: cannot read as an xlsx workbook: {type(exc).__name__}: {exc}"]) from None
    finally:
        workbook.close()


def _header_index(rows: list[list[str]], mapping: Mapping) -> int | None:
    for i, cells in enumerate(rows[:50]):
        if looks_like_header(cells, mapping):
            return i
    return None


def read_table(path: str | Path, sheet: str | None, mapping: Mapping) -> Table:
    """The table's header (the first row with two recognised headers) and its data rows.

    Blank rows and rows that repeat the header (manuals print it again on every page) are skipped.
    """
    p = Path(path)
    extra: dict[str, list[dict[str, str]]] = {}
    if p.suffix.lower() == ".csv":
        if sheet is not None:
            raise TableError([f"{p}: --sheet applies to xlsx workbooks; a CSV has one table"])
        rows, sheet_name = _csv_rows(p), None
    elif p.suffix.lower() in (".xlsx", ".xlsm"):
        sheets = _xlsx_sheets(p)
        sheet_name = sheet or mapping.sheet or ("registers" if "registers" in sheets else next(iter(sheets), None))
        if sheet_name not in sheets:
            raise TableError([f"{p}: no sheet {sheet_name!r} (sheets: {', '.join(sheets) or 'none'})"])
        rows = sheets[sheet_name]
        for name, other in sheets.items():
            if name != sheet_name and other:
                head = other[0]
                extra[name] = [dict(zip(head, r, strict=False)) for r in other[1:] if any(c.strip() for c in r)]
    else:
        raise TableError([f"{p}: expected a .csv or .xlsx table"])
    where = str(p) if sheet_name is None else f"{p}:{sheet_name}"
    index = _header_index(rows, mapping)
    if index is None:
        raise TableError([f"{where}: no header row: no row in the first 50 names two known columns (give --columns MAPPING.yaml)"])
    header = rows[index]
    columns = recognise(header, mapping)
    data = [
        (n + 1, cells)
        for n, cells in enumerate(rows)
        if n > index and any(c.strip() for c in cells) and [c.strip() for c in cells] != [c.strip() for c in header]
    ]
    table = Table(str(p), sheet_name, header, index + 1, columns, data, extra)
    table.ignored = ignored(header, columns, [c for _, c in data])
    ambiguous = [i for i, why in table.ignored.items() if why == "ambiguous"]
    if ambiguous:
        raise TableError(
            [
                f"{table.where(index + 1, i)}: column {table.heading(i)}: {AMBIGUOUS[normalise(header[i])]}? "
                f"name it in --columns MAPPING.yaml: {{{header[i].strip()}: gain}} (value = raw / gain) "
                f"or {{{header[i].strip()}: scale}} (value = raw x scale)"
                for i in ambiguous
            ]
        )
    return table
