"""Table rows -> register entries: each field the table gives, read by `cells`, with the cells it could not read."""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from decimal import Decimal
from fractions import Fraction
from pathlib import Path
from typing import Any

from regmap.frontend.values import _ParamRule
from regmap.tools.spreadsheet import cells, times
from regmap.tools.spreadsheet.cells import CellProblem
from regmap.tools.spreadsheet.scaled import check_scale_from
from regmap.tools.spreadsheet.table import Table, TableError
from regmap_runtime.types import TYPES


@dataclass
class Entry:
    """One register as the table gives it. `values` holds map keys with raw values; `given` the keys the
    table itself states (an update compares only those); `notes` what the draft must say about it."""

    row: int
    where: str
    values: dict[str, Any] = field(default_factory=dict)
    given: set[str] = field(default_factory=set)
    notes: list[str] = field(default_factory=list)
    errata: list[str] = field(default_factory=list)
    printed: dict[str, Decimal] = field(default_factory=dict)  # min/max/default in engineering units beside raw columns
    printed_at: dict[str, str] = field(default_factory=dict)  # where each of those cells is
    modicon_space: str | None = None  # the space a Modicon register number names
    value_table: list[tuple[int, str]] = field(default_factory=list)  # the values a range or description cell lists
    scale_from_at: str = ""  # where the cell naming the scale-factor register is (scaled.check_scale_from reads it)

    @property
    def type_unknown(self) -> bool:
        """The table prints a type regmap cannot read: the draft says `type: null`, never a width of its own."""
        return "type" in _noted(self) and "type" not in self.values

    def give(self, key: str, value: Any) -> None:
        self.values[key] = value
        self.given.add(key)


@dataclass
class Problem:
    where: str
    message: str
    row: int | None = None  # the table row, when the problem is one row's

    def __str__(self) -> str:
        return f"{self.where}: {self.message}"


def param_rules(specs: list[dict[str, Any]]) -> list[_ParamRule]:
    """The `param_ids` rules of a map or a mapping file (already checked by the front end for a map)."""
    return [
        _ParamRule(
            regex=re.compile(s["regex"]),
            format=s["format"],
            base=int(s.get("base", 0)),
            group_stride=int(s.get("group_stride", 0)),
            index_stride=int(s.get("index_stride", 1)),
            group_radix=int(s.get("group_radix", 10)),
            index_radix=int(s.get("index_radix", 10)),
        )
        for s in specs
    ]


def _rule_address(rules: list[_ParamRule], param: str) -> int | None:
    for rule in rules:
        try:
            address = rule.address_of(param)
        except ValueError:
            continue
        if address is not None:
            return address
    return None


WIDE_TYPES = tuple(t.name for t in TYPES.values() if t.wide)  # the types that have a word order

TEXT_FIELDS = ("title", "title_zh", "description", "range_text", "notes", "group")


class _Reader:
    def __init__(self, table: Table, rules: list[_ParamRule], addresses: str = "plain") -> None:
        self.table, self.rules, self.addresses = table, rules, addresses
        self.by_field = {name: i for i, name in table.columns.items()}
        self.problems: list[Problem] = []  # cells it could not read: reported, left null

    def cell(self, cells_: list[str], name: str) -> tuple[str, str] | None:
        """(text, position) of a field's cell in a row, or None when the table has no such column."""
        i = self.by_field.get(name)
        if i is None:
            return None
        return (cells_[i] if i < len(cells_) else ""), self.table.where(self.row, i)

    def read(self, entry: Entry, cells_: list[str], name: str, parse: Any) -> Any:
        """The parsed cell, `None` for a blank one; a problem is reported and gives `None` too."""
        i = self.by_field.get(name)
        if i is None:
            return None
        text = cells_[i] if i < len(cells_) else ""
        if cells.blank(text):
            return None
        try:
            return parse(text)
        except CellProblem as exc:
            self.problems.append(Problem(self.table.where(self.row, i), str(exc), entry.row))
            entry.notes.append(f"{name}: the table prints {text.strip()!r}, which regmap cannot read; left null")
            return None

    def take(self, entry: Entry, cells_: list[str], name: str, parse: Any) -> Any:
        """`read`, and the entry takes the value when the cell gives one."""
        value = self.read(entry, cells_, name, parse)
        if value is not None:
            entry.give(name, value)
        return value

    def has(self, name: str) -> bool:
        return name in self.by_field

    def entry(self, row: int, cells_: list[str]) -> Entry | None:
        self.row = row
        e = Entry(row, self.table.where(row))
        self._identity(e, cells_)
        if "address" not in e.values:
            return None
        self._kind(e, cells_)
        if "name" not in e.values:  # after the space: coil 0 and holding register 0 need two names
            param = e.values.get("param")
            e.values["name"] = _name_from(param, e.values["address"], e.values.get("space") or "holding")
            e.notes.append("name made from the " + ("parameter id" if param else "address") + ": the table has no name; rename it")
        self._numbers(e, cells_)
        self._text(e, cells_)
        self._value_table(e, cells_)
        if (got := self.cell(cells_, "scale_from")) is not None and not cells.blank(got[0]):
            e.give("scale_from", got[0].strip())  # a register's name or parameter id: resolved by scaled.check_scale_from
            e.scale_from_at = got[1]
        return e

    def _value_table(self, e: Entry, c: list[str]) -> None:
        """A list of values in the range cell, else in the description cell: an enum of the draft when raw = value."""
        for name in ("range", "description"):
            got = self.cell(c, name)
            if got is None or cells.blank(got[0]):
                continue
            table = cells.value_table(got[0])
            if table is None:
                continue
            if e.values.get("scale", 1) != 1 or e.values.get("offset", 0) != 0 or _kind_of(e.values.get("type")) != "int":
                e.notes.append(f"the {name} lists values ({got[0].strip()}); not an enum, as the raw value is not the value printed")
                return
            values = [v for v, _ in table]
            bounds = (e.values.get("min"), e.values.get("max"))
            if name == "description" and bounds != (None, None) and bounds != (min(values), max(values)):
                e.notes.append(f"the description lists values ({got[0].strip()}) that the range {bounds[0]}..{bounds[1]} does not bound")
                return
            e.value_table = table
            return

    # -- name, param, address

    def _identity(self, e: Entry, c: list[str]) -> None:
        param = self.take(e, c, "param", lambda t: t.strip())
        self.take(e, c, "name", lambda t: cells.identifier(t, "name"))
        address = self._modicon(e, c) if self.addresses == "modicon" else self._address(e, c, "address")
        if address is None:
            address = self._address(e, c, "address_hex")
        if address is None and param is not None and self.rules:
            address = _rule_address(self.rules, param)
            if address is None:
                got = self.cell(c, "param")
                assert got is not None
                self.problems.append(Problem(got[1], f"cannot read parameter id {param!r}: no param_ids rule gives its address", e.row))
        if address is None:
            got = self.cell(c, "address") or self.cell(c, "param")
            self.problems.append(Problem(got[1] if got else e.where, "row skipped: no address", e.row))
            return
        e.give("address", address)

    def _address(self, e: Entry, c: list[str], column: str) -> int | None:
        got = self.read(e, c, column, cells.address_with_o)
        if got is None:
            return None
        value, corrected = got
        if corrected is not None:
            where = self.cell(c, column)
            assert where is not None
            self.table.said.append(f"{where[1]}: {corrected}")
            e.notes.append(corrected)
        return int(value)

    def _modicon(self, e: Entry, c: list[str]) -> int | None:
        got = self.cell(c, "address")
        if got is None or cells.blank(got[0]):
            return None
        read = cells.modicon(got[0])
        if read is None:
            self.problems.append(Problem(got[1], f"{got[0].strip()!r} is not a Modicon register number (0xxxx 1xxxx 3xxxx 4xxxx)", e.row))
            return None
        e.modicon_space = read[0]
        return read[1]

    # -- type, access, enum, bitfields, word order

    def _timestamp(self, e: Entry, c: list[str], printed: tuple[str, str]) -> None:
        """A type cell naming seconds since 1970: `timestamp`, its zone from the cell or a zone column, else reported."""
        e.give("type", "timestamp")
        zone = self.read(e, c, "zone", lambda t: cells.choice(t, times.ZONES, "zone")) or times.printed_zone(printed[0])
        if zone is not None:
            e.give("zone", zone)
        else:
            e.notes.append(times.zone_note(printed[0]))
            self.problems.append(Problem(printed[1], f"{times.zone_note(printed[0])} (never guessed)", e.row))

    def _kind(self, e: Entry, c: list[str]) -> None:
        space = self.take(e, c, "space", cells.space)
        if e.modicon_space is not None:
            got = self.cell(c, "space")
            if space is not None and space != e.modicon_space and got is not None:
                self.problems.append(
                    Problem(got[1], f"space {space} contradicts the register number, which names a {e.modicon_space}", e.row)
                )
            e.give("space", e.modicon_space)
            space = e.modicon_space
        printed_type = self.cell(c, "type")
        timestamp = printed_type is not None and times.is_time_type(printed_type[0])
        if timestamp and printed_type is not None:
            self._timestamp(e, c, printed_type)
        for key, table, what in (("type", cells.TYPES, "type"), ("word_order", cells.WORD_ORDERS, "word order")):
            if key == "type" and timestamp:
                continue
            value = self.read(e, c, key, lambda t, table=table, what=what: cells.choice(t, table, what))
            if value is not None:
                e.give(key, value)
        if printed_type is not None and "type" in e.values and cells._squash(printed_type[0]).lower() in cells.TYPE_NOTES:
            e.notes.append(cells.TYPE_NOTES[cells._squash(printed_type[0]).lower()])
        if "type" not in e.values and space in ("coil", "discrete_input") and not e.type_unknown:
            e.values["type"] = "bool"  # a coil or discrete input is one bit
        words = self.read(e, c, "words", lambda t: cells.integer(t, "words"))
        words_at = self.cell(c, "words")
        if words is not None and e.values.get("type") == "string":
            e.give("words", words)
        elif words is not None and "type" not in e.values:
            if words not in (1, 2):
                self.problems.append(Problem(words_at[1] if words_at else e.where, f"words {words}: expected 1 or 2", e.row))
            else:
                e.give("type", "u32" if words == 2 else "u16")
                e.notes = [n for n in e.notes if not n.startswith("type:")]
                e.notes.append(f"type {e.values['type']} from the words column ({words}): signedness not in the table")
                if words_at is not None and printed_type is not None and not cells.blank(printed_type[0]):
                    e.notes[-1] += f"; the table prints the type {printed_type[0].strip()!r}, which regmap does not know"
        elif words is not None and TYPES[e.values["type"]].numeric and TYPES[e.values["type"]].words != words:
            width = TYPES[e.values["type"]].words
            self.problems.append(
                Problem(words_at[1] if words_at else e.where, f"{words} register(s), but type {e.values['type']} takes {width}", e.row)
            )
        orders = self.read(e, c, "byte_order", cells.byte_order)
        if orders is not None:
            word_order, byte_order = orders
            e.give("byte_order", byte_order)
            if word_order is not None and "word_order" not in e.values and e.values.get("type") in WIDE_TYPES:
                e.give("word_order", word_order)
        if e.values.get("type") == "string":
            self.take(e, c, "encoding", lambda t: cells.choice(t, cells.ENCODINGS, "encoding"))
            self.take(e, c, "padding", lambda t: cells.choice(t, cells.PADDINGS, "padding"))
        gate = {
            k: v
            for k, v in (
                ("from", self.read(e, c, "firmware_from", cells.version)),
                ("until", self.read(e, c, "firmware_until", cells.version)),
            )
            if v is not None
        }
        if gate:
            e.give("firmware", gate)
        self.take(e, c, "poll", lambda t: cells.choice(t, cells.POLLS, "poll class"))
        self.take(e, c, "na", cells.na_marks)
        self.take(e, c, "variants", cells.variant_names)
        settable_got = self.cell(c, "settable")
        settable_text = "" if settable_got is None else cells._squash(settable_got[0])
        if settable_text in READ_ONLY_SETTABLE:
            e.values["access"] = "r"
        else:
            settable = self.read(e, c, "settable", lambda t: cells.choice(t, cells.SETTABLE, "settable"))
            if settable is not None:
                e.give("settable", settable)
                if settable == "display_only":
                    e.values["access"] = "r"
        if self.take(e, c, "access", lambda t: cells.choice(t, cells.ACCESS, "access")) is not None:
            got = self.cell(c, "access")
            if got is not None and cells._squash(got[0]).lower() in ("r/wp", "rwp"):
                e.notes.append("access R/WP: written with a password, as the table says")
        self.take(e, c, "enum", lambda t: cells.identifier(t, "enum name"))
        bitfields = self.read(e, c, "bitfields", cells.bitfields)
        if bitfields:
            e.give("bitfields", bitfields)
        paired = self.read(e, c, "paired", lambda t: cells.boolean(t, "paired"))
        if paired:
            e.give("paired", True)
        takes = self.read(e, c, "takes_effect", lambda t: cells.choice(t, cells.TAKES_EFFECT, "takes effect"))
        if takes is not None or (self.has("takes_effect") and "takes_effect" not in _noted(e)):
            e.give("takes_effect", takes)
        modes = self.read(e, c, "modes", cells.modes)
        if modes is not None or (self.has("modes") and "modes" not in _noted(e)):
            e.give("modes", modes or [])

    # -- unit, scale, min, max, default

    def _numbers(self, e: Entry, c: list[str]) -> None:
        unit_step: Fraction | None = None
        if self.has("unit") and self.has("scale"):  # the map's own unit (the export's): the scale has its own column
            unit_text = self.read(e, c, "unit", lambda t: t.strip())
            e.give("unit", unit_text)
        elif self.has("unit"):
            got = self.read(e, c, "unit", cells.unit)
            if got is not None:
                e.give("unit", got[0])
                unit_step = got[1]
            elif "unit" not in _noted(e):
                e.give("unit", None)
        scale = self.read(e, c, "scale", lambda t: Fraction(cells.decimal(t, "scale")))
        gain = self.read(e, c, "gain", _gain)
        if scale is None and gain is not None:
            scale = gain
        if {"scale", "gain"} & _noted(e):
            if self.has("range") or self.has("default_value") or self.has("min_value"):
                e.notes.append("min, max and default: left null, as the scale cannot be read")
            return
        offset = self.read(e, c, "offset", lambda t: Fraction(cells.decimal(t, "offset")))
        if offset is not None:
            e.give("offset", offset)
        kind = _kind_of(e.values.get("type"))
        raw = {k: self.read(e, c, k, _raw_reader(kind, k)) for k in ("min", "max", "default")}
        if any(self.has(k) for k in ("min", "max", "default")):  # raw columns (the export's): engineering columns are derived
            for k in ("min", "max", "default"):
                if self.has(k) and k not in _noted(e):
                    e.give(k, raw[k])
            if scale is not None:
                e.give("scale", scale)
            if kind in ("int", "float"):
                self._printed_beside_raw(e, c, scale, offset, kind)
            return
        printed = self._printed(e, c)
        if printed is None:
            if scale is not None or unit_step is not None:
                e.give("scale", scale or unit_step)
            return
        if kind == "float":  # a float's printed decimals are not its step: its scale is 1 unless a column says
            scale = scale or unit_step or Fraction(1)
        shift = offset or Fraction(0)
        lo, hi, default, texts, range_unit = printed
        if range_unit is not None and "unit" not in e.values:
            e.give("unit", range_unit)
        numbers = [v for v in (lo, hi, default) if v is not None]
        decimals = max((cells.places(v) for v in numbers), default=0)
        if scale is None:
            if unit_step is not None and decimals:
                self.problems.append(
                    Problem(
                        e.where, f"unit step {float(unit_step):g} and printed decimals ({texts}) together: scale unclear; left null", e.row
                    )
                )
                e.notes.append("scale unclear: the unit has a step and the values have decimals; min, max and default left null")
                return
            scale = unit_step if unit_step is not None else Fraction(1, 10**decimals)
        if scale != 1 or self.has("scale"):
            e.give("scale", scale)
        for key, value in (("min", lo), ("max", hi), ("default", default)):
            if value is None:
                if key not in _noted(e) and ((key == "default" and self.has("default_value")) or (key != "default" and self._range_given)):
                    e.give(key, None)
                continue
            try:  # with a unit step (0.1%, 25ns) the table prints counts; otherwise engineering values
                if kind == "float":
                    e.give(key, float((Fraction(value) - shift) / scale))
                    continue
                step, zero = (Fraction(1), Fraction(0)) if unit_step is not None else (scale, shift)
                e.give(key, cells.raw_from(value, step, key, str(value), zero))
            except CellProblem as exc:
                self.problems.append(Problem(e.where, str(exc), e.row))
                e.notes.append(f"{key}: {exc}; left null")
        if self._range_text and (scale != 1 or range_unit or self._range_listed or not _plain_range(self._range_text)):
            e.give("range_text", self._range_text)

    def _printed_beside_raw(self, e: Entry, c: list[str], scale: Fraction | None, offset: Fraction | None, kind: str) -> None:
        """The export's engineering columns: kept for an update (an edit of either column counts); a raw cell left blank
        is filled from its engineering one."""
        for key in ("min", "max", "default"):
            printed = self.read(e, c, f"{key}_value", lambda t, key=key: cells.decimal(t, key))
            if printed is None:
                continue
            e.printed[key] = printed
            got = self.cell(c, f"{key}_value")
            e.printed_at[key] = got[1] if got else e.where
            if key in e.values or not self.has(key):
                continue
            try:
                e.give(key, engineering_to_raw(printed, scale or Fraction(1), offset or Fraction(0), kind, key))
            except CellProblem as exc:
                self.problems.append(Problem(e.where, str(exc), e.row))

    def _printed(self, e: Entry, c: list[str]) -> tuple[Decimal | None, Decimal | None, Decimal | None, str, str | None] | None:
        """The engineering-unit range and default as printed, or None when the table prints neither."""
        self._range_given, self._range_text, self._range_listed = False, "", False
        lo = hi = None
        unit: str | None = None
        if self.has("range"):
            self._range_given = True
            r = self.read(e, c, "range", cells.printed_range)
            got = self.cell(c, "range")
            self._range_text = "" if got is None or cells.blank(got[0]) else " ".join(got[0].split())
            if r is not None:
                lo, hi, unit, self._range_listed = r.lo, r.hi, r.unit, r.listed
        elif self.has("min_value") or self.has("max_value"):
            self._range_given = True
            lo = self.read(e, c, "min_value", lambda t: cells.decimal(t, "minimum"))
            hi = self.read(e, c, "max_value", lambda t: cells.decimal(t, "maximum"))
        default = self.read(e, c, "default_value", lambda t: _default(t, unit or e.values.get("unit")))
        if not self._range_given and not self.has("default_value"):
            return None
        return lo, hi, default, " ".join(t for t in (self._range_text, "" if default is None else str(default)) if t), unit

    # -- text

    def _text(self, e: Entry, c: list[str]) -> None:
        for key in TEXT_FIELDS:
            keep_lines = key in ("description", "notes")
            value = self.read(e, c, key, lambda t, keep_lines=keep_lines: t.strip() if keep_lines else " ".join(t.split()))
            if value:
                e.give(key, value)
        source = self.read(e, c, "source", cells.text_list)
        if source:
            e.give("source", source)
        errata = self.read(e, c, "errata", cells.text_list)
        if errata:
            e.errata = errata
        if "title" not in e.values:
            e.values["title"] = e.values.get("title_zh") or e.values["name"]
            e.notes.append("title copied from the " + ("Chinese name" if "title_zh" in e.values else "name") + ": translate it")


READ_ONLY_SETTABLE = {"通信只读", "只读"}


def _gain(text: str) -> Fraction:
    """A gain or divisor (value = raw / gain) -> the map's scale; refused when 1/gain is no exact decimal."""
    gain = Fraction(cells.decimal(text, "gain"))
    if gain <= 0:
        raise CellProblem(f"gain {text.strip()!r}: expected a number above 0 (value = raw / gain)")
    scale = 1 / gain
    rest = scale.denominator
    for prime in (2, 5):
        while rest % prime == 0:
            rest //= prime
    if rest != 1:
        raise CellProblem(f"gain {text.strip()!r}: 1/{text.strip()} is no exact decimal scale; write the scale in the map")
    return scale


def engineering_to_raw(value: Decimal, scale: Fraction, offset: Fraction, kind: str, key: str) -> int | float:
    """A value in engineering units -> the raw value the map stores ((value - offset) / scale)."""
    if kind == "float":
        return float((Fraction(value) - offset) / scale)
    return cells.raw_from(value, scale, key, str(value), offset)


def _kind_of(type_name: Any) -> str:
    """int, float, string or bool: how the raw min, max and default cells read."""
    info = TYPES.get(type_name) if isinstance(type_name, str) else None
    return info.kind if info is not None else "int"


def _raw_reader(kind: str, key: str) -> Any:
    """The reader of a raw min/max/default cell of a register of this kind."""
    if kind == "float":
        return lambda t: float(cells.decimal(t, key))
    if kind == "bool":
        return lambda t: cells.boolean(t, key)
    if kind == "string":
        return lambda t: "" if t.strip() == EMPTY_TEXT else t  # `""` is the empty text; a blank cell is no value
    return lambda t: cells.integer(t, key)


EMPTY_TEXT = '""'


def _noted(e: Entry) -> set[str]:
    """Fields whose cell could not be read (they stay out of `given`: an update leaves them alone)."""
    return {n.split(":", 1)[0] for n in e.notes}


def _plain_range(text: str) -> bool:
    return re.fullmatch(r"-?[0-9]+\s*~\s*-?[0-9]+", text) is not None


def _default(text: str, unit: str | None) -> Decimal:
    """A printed default, optionally followed by the row's unit (`3000rpm`)."""
    t = text.strip()
    if unit and t.endswith(unit) and t[: -len(unit)].strip():
        t = t[: -len(unit)].strip()
    return cells.decimal(t, "default")


NAME_PREFIX = {"holding": "reg", "input": "input", "coil": "coil", "discrete_input": "di"}


def _name_from(param: str | None, address: int, space: str = "holding") -> str:
    fallback = f"{NAME_PREFIX[space]}_{address:04x}"
    if param:
        name = re.sub(r"[^a-z0-9]+", "_", param.lower()).strip("_")
        if name and name[0].isalpha():
            return name
        return f"p{name}" if name else fallback
    return fallback


def address_form(table: Table, told: str | None) -> str:
    """How the address column reads: `modicon` (30001 = input register 0) or `plain`. A column of Modicon numbers
    is read as such only when it cannot be addresses (two spaces, six digits, a leading zero); one that may be
    either is refused until --addresses says. What was decided is added to `table.said`."""
    column = next((i for i, n in table.columns.items() if n == "address"), None)
    if column is None:
        return "plain"
    heading = f"{table.position(column)} {table.heading(column)}"
    if told is not None:
        table.said.append(f"{heading}: read as {'Modicon register numbers' if told == 'modicon' else 'addresses'}, as --addresses says")
        return told
    texts = [c[column].strip() for _, c in table.rows if column < len(c) and not cells.blank(c[column])]
    read = [cells.modicon(t) for t in texts]
    long = [len(t) >= 5 for t in texts]  # 1..9999 are Modicon coils only beside longer Modicon numbers
    if "address_hex" in table.columns.values() or not any(long) or not all(read):
        return "plain"
    first: dict[str, str] = {}
    for text, got in zip(texts, read, strict=True):
        assert got is not None
        first.setdefault(got[0], f"{text} -> {got[0]} 0x{got[1]:04X}")
    if (len(first) == 1 or not all(long)) and not any(len(t) == 6 or t.startswith("0") for t in texts):
        raise TableError(
            [
                f"{table.where(table.header_row, column)}: {heading} holds {texts[0]} .. {texts[-1]}: Modicon register numbers "
                f"({next(iter(first.values()))}) or addresses? say which: --addresses modicon or --addresses plain"
            ]
        )
    table.said.append(
        f"{heading}: Modicon register numbers, read as space and address n - base: {', '.join(first.values())} "
        "(--addresses plain reads them as addresses)"
    )
    return "modicon"


def read_entries(
    table: Table, rules: list[_ParamRule], addresses: str | None = None, known: dict[str, str] | None = None
) -> tuple[list[Entry], list[Problem]]:
    """Every row as an entry, and the cells that could not be read.

    Raises TableError for a table that cannot be imported at all: no address column (and no param_ids rule), two
    rows at one address, or a scale-factor register that is neither a row nor in `known` (the map's name -> type).
    """
    fields = set(table.columns.values())
    if not fields & {"address", "address_hex"} and not ("param" in fields and rules):
        found = ", ".join(f"{table.header[i].strip()!r}" for i in sorted(table.columns)) or "none"
        raise TableError(
            [
                f"{table.where(table.header_row)}: no address column (recognised: {found}); name one with --columns MAPPING.yaml, "
                "or give param_ids rules there (or in the map) that turn parameter ids into addresses"
            ]
        )
    reader = _Reader(table, rules, address_form(table, addresses))
    entries = [e for row, cells_ in table.rows if (e := reader.entry(row, cells_)) is not None]
    first: dict[tuple[str, int], Entry] = {}
    duplicates = []
    for e in entries:  # one address per space: coil 0 and holding register 0 are two registers
        space = e.values.get("space") or "holding"
        other = first.setdefault((space, e.values["address"]), e)
        if other is not e:
            column = next((i for i, n in sorted(table.columns.items()) if n in ("address", "address_hex", "param")), None)
            where = "" if space == "holding" else f" ({space})"
            duplicates.append(
                f"{table.where(e.row, column)}: address 0x{e.values['address']:04X}{where} is also the address of row {other.row}"
            )
    if duplicates:
        raise TableError(duplicates)
    check_scale_from(table, entries, known or {})
    return entries, reader.problems


def table_name(table: Table) -> str:
    return Path(table.path).name
