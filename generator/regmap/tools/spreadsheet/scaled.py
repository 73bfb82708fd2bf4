"""A row scaled by another register (`scale_from`, SunSpec's SF: value = raw x 10^sf, sf that s16 register's raw
value read from the device): the register it names must be a row of the table (or, for an update, of the map) and
an s16. Its value is known only on the bus, so a value printed in engineering units beside it, or a scale or
offset of its own, cannot be turned into raw: each is a TableError at its cell and nothing is written, never a
draft that shows raw as the value or drops the factor."""

from __future__ import annotations

from fractions import Fraction
from typing import TYPE_CHECKING

from regmap.tools.spreadsheet import cells
from regmap.tools.spreadsheet.table import Table, TableError

if TYPE_CHECKING:
    from regmap.tools.spreadsheet.rows import Entry

ENGINEERING = ("range", "min_value", "max_value", "default_value")  # printed as values: raw x 10^sf, unknown here
OWN_SCALE = ("scale", "gain", "unit", "offset")  # the columns a scale or offset of its own comes from


def check_scale_from(table: Table, entries: list[Entry], known: dict[str, str]) -> None:
    """Each `scale_from` cell names a register by its name (or parameter id) and becomes that register's name;
    `known` is the map's registers (name -> type) for an update. Raises TableError naming every bad cell."""
    by_name = {str(e.values["name"]): e for e in entries}
    by_param = {str(e.values["param"]): e for e in entries if e.values.get("param")}
    columns = {name: i for i, name in table.columns.items()}
    row_cells = dict(table.rows)
    problems: list[str] = []
    for e in entries:
        named = e.values.get("scale_from")
        if named is None:
            continue
        target = by_name.get(named) or by_param.get(named)
        if target is not None:
            e.values["scale_from"] = name = str(target.values["name"])
            kind = target.values.get("type")
        elif named in known:
            name, kind = named, known[named]
        else:
            problems.append(
                f"{e.scale_from_at}: scale_from {named!r}: no row of the table is that register (by name or parameter id); "
                "the scale factor register must be in the table"
            )
            continue
        if name == e.values["name"]:
            problems.append(f"{e.scale_from_at}: scale_from {named!r}: a register cannot be its own scale factor")
        elif kind != "s16":
            shown = f"type {kind}" if kind else "of no type the table gives"
            problems.append(f"{e.scale_from_at}: scale_from {named!r}: {name} is {shown}; a scale factor is an s16 register")
        elif target is not None and target.values.get("scale_from") is not None:
            problems.append(f"{e.scale_from_at}: scale_from {named!r}: {name} is itself scaled; a scale factor is a plain s16")
        cells_ = row_cells.get(e.row, [])
        for key in ENGINEERING:
            i = columns.get(key)
            if i is not None and i < len(cells_) and not cells.blank(cells_[i]):
                problems.append(
                    f"{table.where(e.row, i)}: {key} {cells_[i].strip()!r} beside scale_from {named}: the value is raw x 10^{name}, "
                    "known only when the factor is read from the device; give raw min, max and default"
                )
        if Fraction(e.values.get("scale", 1)) != 1 or Fraction(e.values.get("offset", 0)) != 0:
            at = next(
                (i for i in (columns.get(k) for k in OWN_SCALE) if i is not None and i < len(cells_) and not cells.blank(cells_[i])), None
            )
            where = e.where if at is None else f"{table.where(e.row, at)}: {cells_[at].strip()!r}"
            problems.append(f"{where}: a scale or offset of its own beside scale_from {named}: value = raw x 10^{name}, nothing else")
    if problems:
        raise TableError(problems)
