"""`regmap import`: a table -> a new map draft, or an update of an existing map.

An update edits the map's text in place: each changed value is spliced into the span its YAML node
occupies (PyYAML's marks) and each added key goes on a new line beside its siblings, so every
comment, key order, quoting and line break the table does not change stays byte for byte. (A
round-trip dump through ruamel.yaml re-flows long flow mappings and folded scalars: 161 lines of
maps/id243pro.yaml and thousands of maps/c630s.yaml change with no edit at all.)
"""

from __future__ import annotations

import re
from collections.abc import Iterable
from dataclasses import dataclass, field
from decimal import Decimal
from fractions import Fraction
from typing import Any

import yaml

from regmap.diagnostics import Diagnostic
from regmap.model import Device, Register
from regmap.tools.spreadsheet.cells import CellProblem
from regmap.tools.spreadsheet.export import engineering
from regmap.tools.spreadsheet.rows import Entry, Problem, engineering_to_raw, table_name
from regmap.tools.spreadsheet.skeleton import head
from regmap.tools.spreadsheet.table import Table
from regmap.tools.spreadsheet.yamltext import block, flow, scalar
from regmap_runtime.spaces import DEFAULT_SPACE, SPACES
from regmap_runtime.types import TYPES

# Keys in the order the maps write them.
KEY_ORDER = (
    "name",
    "param",
    "address",
    "space",
    "type",
    "zone",
    "words",
    "encoding",
    "padding",
    "word_order",
    "byte_order",
    "access",
    "paired",
    "title",
    "title_zh",
    "description",
    "unit",
    "scale",
    "scale_from",
    "offset",
    "min",
    "max",
    "default",
    "na",
    "range_text",
    "enum",
    "bitfields",
    "takes_effect",
    "settable",
    "modes",
    "firmware",
    "variants",
    "poll",
    "source",
    "notes",
)
NUMERIC = tuple(t.name for t in TYPES.values() if t.numeric)  # types with a range: min, max and default


def _register_yaml(e: Entry, source: str) -> dict[str, Any]:
    v = dict(e.values)
    v.setdefault("source", [source])
    if e.type_unknown:
        v["type"] = None  # the front end refuses it until the manual's type is filled in: a width is never made up
    elif "type" not in v:
        v["type"] = _type_from_range(v.get("min"), v.get("max"), e)
    notes = [v.pop("notes")] if v.get("notes") else []
    notes += e.notes
    if notes:
        v["notes"] = " ".join(n if n.endswith(".") else n + "." for n in notes)
    bounds = ("min", "max", "default") if v["type"] in NUMERIC else ("default",)
    out = {k: v[k] for k in KEY_ORDER if k in v and (v[k] is not None or k in bounds or k == "type")}
    for key, default in (("scale", 1), ("offset", 0), ("space", "holding"), ("byte_order", "high_first"), ("poll", "normal")):
        if key in out and out[key] == default:
            del out[key]  # the map's default: a draft says only what differs
    if not out.get("modes"):
        out.pop("modes", None)
    if len(out["source"]) == 1:
        out["source"] = out["source"][0]
    return out


def _type_from_range(lo: int | None, hi: int | None, e: Entry) -> str:
    """The narrowest type the raw range needs; u16 when the table gives no range (said in notes)."""
    if e.values.get("space") in ("coil", "discrete_input"):
        return "bool"
    if lo is None and hi is None:
        e.notes.append("type: the table gives neither type nor range; u16 until the manual says otherwise")
        return "u16"
    signed = lo is not None and lo < 0
    wide = (hi is not None and hi > (0x7FFF if signed else 0xFFFF)) or (lo is not None and lo < -0x8000)
    kind = ("s" if signed else "u") + ("32" if wide else "16")
    if kind != "u16":
        e.notes.append(f"type {kind} from the range: the table gives no type")
    return kind


def _function_codes(entries: list[Entry]) -> list[int]:
    """The function codes the draft's registers need (holding registers' 0x03/0x06/0x10 at least)."""
    codes = {0x03, 0x06, 0x10}
    for e in entries:
        space = SPACES[e.values.get("space") or DEFAULT_SPACE]
        codes |= set(space.codes.values())
    return sorted(codes)


@dataclass
class Draft:
    text: str
    registers: int
    groups: list[str] = field(default_factory=list)


def _group_titles(table: Table) -> dict[str, tuple[str, str | None]]:
    return {
        r["id"]: (r.get("title") or r["id"], r.get("title_zh") or None) for r in table.extra.get("groups", []) if r.get("id", "").strip()
    }


def _member_name(title: str, value: int, taken: set[str]) -> str:
    """A snake_case member name from the title a table prints (`2400` -> `value_2400`, `M` -> `m`), unique in its enum."""
    name = re.sub(r"[^a-z0-9]+", "_", title.lower()).strip("_")
    if not name or not name[0].isalpha():
        name = f"value_{name or value}"
    if name in taken:
        name = f"{name}_{value}"
    taken.add(name)
    return name


def _listed_enums(entries: list[Entry], defined: set[str]) -> list[str]:
    """An enum for every register whose range or description lists its values; the register takes its name."""
    lines = []
    for e in entries:
        if not e.value_table or "enum" in e.values:
            continue
        name = e.values["name"] if e.values["name"] not in defined else f"{e.values['name']}_values"
        defined.add(name)
        e.values["enum"] = name
        e.notes.append(f"enum {name} from the values the table lists: check their names")
        taken: set[str] = set()
        lines += [f"  {name}:", f"    title: {scalar(e.values.get('title') or name)}", "    values:"]
        for value, title in e.value_table:
            lines.append(f"      - {flow({'value': value, 'name': _member_name(title, value, taken), 'title': title})}")
    return lines


def _enums_section(table: Table, entries: list[Entry]) -> list[str]:
    rows = table.extra.get("enums", [])
    listed = _listed_enums(entries, {str(r.get("enum")) for r in rows})
    if not rows:
        return ["enums:", *listed] if listed else []
    lines = ["enums:"]
    current = None
    for r in rows:
        if r.get("enum") != current:
            current = r.get("enum")
            lines += [f"  {current}:", f"    title: {scalar(r.get('enum_title') or current)}", "    values:"]
        member: dict[str, Any] = {"value": int(r["value"]), "name": r["name"], "title": r.get("title") or r["name"]}
        for key in ("title_zh", "symbol", "description"):
            if r.get(key):
                member[key] = r[key]
        lines.append(f"      - {flow(member)}")
    return lines + listed


def _errata_section(table: Table, named: dict[str, list[str]]) -> list[str]:
    rows = table.extra.get("errata")
    lines = ["errata:"]
    if rows is not None:
        for r in rows:
            readings: list[dict[str, Any]] = []
            for line in (r.get("readings") or "").splitlines():
                src, _, says = line.partition(": ")
                readings.append({"source": [s.strip() for s in src.split(",") if s.strip()], "says": says})
            item: dict[str, Any] = {
                "id": r["id"],
                "title": r.get("title"),
                "readings": readings,
                "choice": r.get("choice"),
                "reason": r.get("reason"),
            }
            if r.get("registers"):
                item["registers"] = [s.strip() for s in r["registers"].split(",")]
            lines += block(item, 4, "- ")
        return lines if len(lines) > 1 else ["errata: []"]
    if not named:
        return ["errata: []"]
    lines.insert(0, "# The table names these errata but does not carry them: fill each from the manual.")
    for erratum, registers in sorted(named.items()):
        lines += block({"id": erratum, "title": None, "readings": [], "choice": None, "reason": None, "registers": registers}, 4, "- ")
    return lines


def build_draft(
    table: Table, entries: list[Entry], problems: list[Problem], device_id: str, vendor: str, model: str, rules: list[dict[str, Any]]
) -> Draft:
    source = table_name(table)
    made_by = f"a draft made by `regmap import {source}`"
    variants = list(dict.fromkeys(v for e in entries for v in e.values.get("variants", ())))
    lines = head(device_id, vendor, model, made_by=made_by, function_codes=_function_codes(entries), variants=variants).splitlines()
    if problems:
        lines.append(f"# {len(problems)} cell(s) of the table could not be read: those values are null, with a note.")
    lines += [f"# {said}" for said in table.said]
    if table.ignored:
        lines.append("# Columns not read: " + ", ".join(f"{table.position(i)} {table.heading(i)}" for i in sorted(table.ignored)) + ".")
    if rules:
        lines.append("param_ids:")
        lines += [f"  - {flow(r)}" for r in rules]
    lines += _enums_section(table, entries)
    titles = _group_titles(table)
    groups: dict[str, list[Entry]] = {}
    for e in entries:
        groups.setdefault(e.values.get("group") or "imported", []).append(e)
    lines.append("groups:")
    for gid, members in groups.items():
        title, title_zh = titles.get(gid, (f"Imported from {source}" if gid == "imported" else gid, None))
        group: dict[str, Any] = {"id": gid, "title": title}
        if title_zh:
            group["title_zh"] = title_zh
        lines += block(group, 4, "- ")
        lines.append("    registers:")
        for e in members:
            reg = _register_yaml(e, source)
            reg.pop("group", None)
            lines += block(reg, 8, "- ")
    named: dict[str, list[str]] = {}
    for e in entries:
        for erratum in e.errata:
            named.setdefault(erratum, []).append(e.values["name"])
    lines += ["examples: []", *_errata_section(table, named)]
    return Draft("\n".join(lines) + "\n", len(entries), list(groups))


# -- updating an existing map ------------------------------------------------------------------


@dataclass
class Edit:
    start: int
    end: int
    text: str


@dataclass
class Update:
    text: str
    changed: list[str] = field(default_factory=list)  # `register.key` for every value changed or added
    added: list[str] = field(default_factory=list)  # registers new to the map
    unchanged: int = 0
    skipped: list[str] = field(default_factory=list)  # what the table says that an import does not apply
    added_rows: set[int] = field(default_factory=set)  # the table rows of the added registers
    skipped_rows: set[int] = field(default_factory=set)  # the table rows of no register (no address)
    original: str = ""  # the map's text before the update
    edits: list[Edit] = field(default_factory=list)  # spans of the map's text, in its own offsets

    def locate(self, diag: Diagnostic) -> str:
        """A diagnostic of the updated text, told where it is in the map as it is on disk (the update is not written)."""
        old_offset = self._old_offset(_offset_of_line(self.text, diag.line))
        if old_offset is None:
            line = self.text.splitlines()[diag.line - 1].strip() if 0 < diag.line <= len(self.text.splitlines()) else ""
            return f"{diag.file}: in the text the update would write ({line!r}): {diag.message}"
        original = self.original[:old_offset].count("\n") + 1
        return f"{diag.file}:{original}:{diag.column}: {diag.message}"

    def _old_offset(self, offset: int) -> int | None:
        """An offset of the updated text -> the same place in the original, None inside text an edit wrote."""
        shift = 0
        for e in sorted(self.edits, key=lambda e: (e.start, e.end)):
            new_start = e.start + shift
            if offset < new_start:
                break
            if offset < new_start + len(e.text) or (not e.text and offset == new_start):
                return None
            shift += len(e.text) - (e.end - e.start)
        return offset - shift


def _offset_of_line(text: str, line: int) -> int:
    offset = 0
    for _ in range(line - 1):
        offset = text.find("\n", offset) + 1
    return offset


def _current(reg: Register, key: str) -> Any:
    """A register's effective value for a map key, as an entry holds it."""
    if key == "type":
        return reg.type.value
    if key == "access":
        return reg.access.value
    if key == "word_order":
        return reg.word_order.value if reg.words == 2 else None
    if key == "byte_order":
        return reg.byte_order.value if reg.type.info.has_byte_order else None
    if key in ("encoding", "padding"):
        return getattr(reg, key) if reg.type.is_string else None
    if key == "firmware":
        return None if reg.firmware is None else {k: v for k, v in (("from", reg.firmware.first), ("until", reg.firmware.until)) if v}
    if key == "poll":
        return reg.poll.value
    if key == "zone":
        return reg.zone
    if key == "na":  # as a cell reads it back: an integer's bit pattern (0x8000, not -32768), `nan`
        marks = [m & ((1 << reg.type.bits) - 1) if isinstance(m, int) else m for m in reg.na] + (["nan"] if reg.na_nan else [])
        return marks or None
    if key == "enum":
        return reg.enum.name if reg.enum else None
    if key in ("source", "modes"):
        return list(getattr(reg, key))
    if key == "variants":
        return list(reg.variants) or None
    if key == "bitfields":
        return [
            {"name": b.name, "bits": b.lsb if b.lsb == b.msb else f"{b.lsb}-{b.msb}", "title": b.title}
            | ({"enum": b.enum.name} if b.enum else {})
            for b in reg.bitfields
        ]
    if key in ("description", "notes"):
        return getattr(reg, key) or None
    return getattr(reg, key)


def _same(key: str, old: Any, new: Any) -> bool:
    if key == "scale":
        return Fraction(old) == Fraction(new if new is not None else 1)
    if key == "source":  # a cell joins sources with ", ", so a source "6.3, 6.6" reads back as two: the same text
        return ", ".join(old) == ", ".join(new)
    if key == "offset":
        return Fraction(old) == Fraction(new if new is not None else 0)
    if isinstance(old, float | int) and isinstance(new, float | int) and not isinstance(old, bool):
        return bool(old == new)
    if key == "bitfields":
        return [dict(sorted(b.items())) for b in old] == [dict(sorted(b.items())) for b in new]
    if isinstance(old, str) and isinstance(new, str):  # a cell holds text on one line, trimmed
        return old.split() == new.split()
    return bool(old == new)


def _key_nodes(mapping: yaml.MappingNode) -> dict[str, tuple[yaml.Node, yaml.Node]]:
    return {k.value: (k, v) for k, v in mapping.value if isinstance(k, yaml.ScalarNode)}


def _register_nodes(root: yaml.Node) -> dict[str, yaml.MappingNode]:
    """Register name -> its mapping node (registers outside arrays)."""
    out: dict[str, yaml.MappingNode] = {}
    groups = _key_nodes(root).get("groups") if isinstance(root, yaml.MappingNode) else None
    if groups is None or not isinstance(groups[1], yaml.SequenceNode):
        return out
    for group in groups[1].value:
        regs = _key_nodes(group).get("registers") if isinstance(group, yaml.MappingNode) else None
        if regs is None or not isinstance(regs[1], yaml.SequenceNode):
            continue
        for item in regs[1].value:
            if isinstance(item, yaml.MappingNode):
                name = _key_nodes(item).get("name")
                if name is not None and isinstance(name[1], yaml.ScalarNode):
                    out[name[1].value] = item
    return out


def _line_end(text: str, index: int) -> int:
    end = text.find("\n", index)
    return len(text) if end < 0 else end


def _edit(text: str, mapping: yaml.MappingNode, key: str, value: Any) -> Edit:
    nodes = _key_nodes(mapping)
    rendered = flow(value, key)
    if key in nodes:
        _, node = nodes[key]
        return Edit(node.start_mark.index, node.end_mark.index, rendered)
    _, last_value = mapping.value[-1]
    if mapping.flow_style:
        close = text.rindex("}", 0, mapping.end_mark.index)
        return Edit(close, close, f", {key}: {rendered}")
    indent = mapping.value[0][0].start_mark.column
    at = _line_end(text, max(last_value.end_mark.index - 1, last_value.start_mark.index))
    return Edit(at, at, "\n" + " " * indent + f"{key}: {rendered}")


def _apply(text: str, edits: Iterable[Edit]) -> str:
    for e in sorted(edits, key=lambda e: (e.start, e.end), reverse=True):
        text = text[: e.start] + e.text + text[e.end :]
    return text


def _match(entry: Entry, device: Device, by_param: dict[str, Register]) -> Register | None:
    name, param = entry.values.get("name") if "name" in entry.given else None, entry.values.get("param")
    if name is not None and name in {r.name for r in device.registers}:
        return device.register(name)
    if param is not None and param in by_param:
        return by_param[param]
    return device.at_address(entry.values["address"], entry.values.get("space") or DEFAULT_SPACE)


APPLIED = (*KEY_ORDER[1:],)


def update_map(text: str, device: Device, table: Table, entries: list[Entry]) -> Update:
    """The map's text with what the table says differently; registers new to the map go to a group `imported`."""
    root = yaml.compose(text)
    nodes = _register_nodes(root) if root is not None else {}
    by_param = {r.param: r for r in device.registers if r.param}
    update = Update(text, original=text, skipped_rows={row for row, _ in table.rows} - {e.row for e in entries})
    edits: list[Edit] = []
    new: list[Entry] = []
    for e in entries:
        reg = _match(e, device, by_param)
        if reg is None:
            new.append(e)
            continue
        update.skipped += _settle_printed(e, reg)
        diffs = [k for k in APPLIED if k in e.given and not _same(k, _current(reg, k), e.values[k])]
        if not diffs:
            update.unchanged += 1
            continue
        if reg.array is not None or reg.name not in nodes:
            update.skipped.append(
                f"{e.where}: {reg.name} is element {reg.array.index} of array {reg.array.array}: not updated (edit the array): "
                + ", ".join(diffs)
                if reg.array
                else f"{e.where}: {reg.name}: not found in the map's text: not updated"
            )
            continue
        for key in diffs:
            edits.append(_edit(text, nodes[reg.name], key, _stored(key, e.values[key])))
            update.changed.append(f"{reg.name}.{key}")
    if new:
        edits.append(_append_group(text, table, new))
        update.added = [e.values["name"] for e in new]
        update.added_rows = {e.row for e in new}
    update.edits = edits
    update.text = _apply(text, edits)
    return update


def _settle_printed(e: Entry, reg: Register) -> list[str]:
    """The export's engineering columns beside its raw ones: an edit of either is a change. An engineering value
    that differs from the map's (as the export prints it) while the raw cell did not change gives the raw value;
    both changed and disagreeing is reported and neither applied."""
    refused = []
    kind = reg.type.info.kind
    for key, printed in e.printed.items():
        if reg.scale_from is not None:  # raw x 10^sf: no value is known before the factor is read
            refused.append(f"{e.printed_at[key]}: {reg.name}.{key}_value: value = raw x 10^{reg.scale_from}, read at run time: not applied")
            continue
        current = getattr(reg, key)
        shown = engineering(reg, current)
        if isinstance(shown, int | float) and not isinstance(shown, bool) and Decimal(repr(shown)) == printed:  # as the export prints it
            continue
        scale = e.values.get("scale", reg.scale) if "scale" in e.given else reg.scale
        offset = e.values.get("offset", reg.offset) if "offset" in e.given else reg.offset
        try:
            raw = engineering_to_raw(printed, Fraction(scale), Fraction(offset), kind, key)
        except CellProblem as exc:
            refused.append(f"{e.printed_at[key]}: {reg.name}.{key}_value: {exc}: not applied")
            continue
        raw_changed = key in e.given and not _same(key, current, e.values[key])
        if not raw_changed:
            e.give(key, raw)
        elif not _same(key, raw, e.values[key]):
            refused.append(
                f"{e.printed_at[key]}: {reg.name}: {key} {e.values[key]} and {key}_value {printed} disagree (scale {float(scale):g}): "
                f"neither applied; change one of them"
            )
            e.given.discard(key)
    return refused


def _stored(key: str, value: Any) -> Any:
    if key == "source" and isinstance(value, list) and len(value) == 1:
        return value[0]
    return value


def _dash_column(text: str, item: yaml.Node) -> int:
    """The column of the `-` that opens a block sequence item (the item's own node starts after it)."""
    dash = text.rfind("-", 0, item.start_mark.index)
    return dash - (text.rfind("\n", 0, dash) + 1)


def _append_group(text: str, table: Table, entries: list[Entry]) -> Edit:
    """A group `imported` (`imported_2` when the map has one) at the end of `groups:`, before the next top-level key."""
    source = table_name(table)
    taken = {str(g.get("id")) for g in (yaml.safe_load(text) or {}).get("groups") or [] if isinstance(g, dict)}
    gid = next(g for g in ("imported", *(f"imported_{n}" for n in range(2, len(taken) + 2))) if g not in taken)
    lines = [f"  - id: {gid}", f"    title: {scalar('Imported from ' + source)}", "    registers:"]
    for e in entries:
        reg = _register_yaml(e, source)
        reg.pop("group", None)
        lines += block(reg, 8, "- ")
    root = yaml.compose(text)
    assert isinstance(root, yaml.MappingNode)
    keys = [k for k, _ in root.value]
    groups_at = next(i for i, k in enumerate(keys) if k.value == "groups")
    group_items = root.value[groups_at][1]
    dash = _dash_column(text, group_items.value[0]) if isinstance(group_items, yaml.SequenceNode) and group_items.value else 2
    lines = [" " * dash + line[2:] for line in lines]  # the lines above put the group's dash in column 2
    at = keys[groups_at + 1].start_mark.index if groups_at + 1 < len(keys) else len(text)
    if at == len(text):
        return Edit(len(text), len(text), ("" if text.endswith("\n") else "\n") + "\n".join(lines) + "\n")
    # before any comment lines that introduce the next key
    head_ = text[:at]
    cut = len(head_.rstrip(" "))
    while True:
        start = head_.rfind("\n", 0, cut - 1) + 1
        line = head_[start:cut].strip()
        if line.startswith("#") or (line == "" and start > 0 and start < cut):
            cut = start
            continue
        break
    return Edit(cut, cut, "\n".join(lines) + "\n")
