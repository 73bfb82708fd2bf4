"""SunSpec model definitions (the JSON files pysunspec2 ships, `model_<id>.json`) -> a map of a SunSpec device.

A device is the `SunS` marker (0x53756E53) at the base address (40000, 50000 or 0), then each model: its ID
and L points, its points, its repeating groups, and after the last model the end marker (ID 0xFFFF, L 0).
One map group per model. Types: int16/uint16/acc16/count/pad/sunssf/enum16/bitfield16 are one word,
int32/uint32/acc32/enum32/bitfield32/ipaddr/float32 two, int64/uint64/acc64/float64 four, string `size`
words; enum symbols become the enum, bitfield symbols (bit numbers) the bit fields.

A scale factor that names a `sunssf` point (value = raw x 10^sf, sf read from the device) is `scale_from` on an
integer point, found as pysunspec2 finds it (in the point's own group, else among the model's points); each
`sunssf` register and each scaled point has its "not implemented" value as `na`, so the value reads as None.
What a map cannot say is a note on the register and a line of the report: a scale factor on a point that is no
plain integer or that names no `sunssf` point, the value that means
"not implemented" on the other points (0xFFFF, 0x8000, NaN ...), an EUI-48 (read as the u64 of
its four words), an IPv4 address (the u32 of its four bytes) and an IPv6 address (its 16 bytes as latin-1 text). A repeating group whose count the
device gives (count 0 or the name of a point) is repeated `repeats` times: the caller says how many the
device has.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path
from typing import Any

from regmap.diagnostics import Diagnostic
from regmap.tools.configimport.draft import Device, Flag, Import, Imported, Member
from regmap.tools.configimport.reader import Config, ConfigError, read_config

# SunSpec type -> (regmap type, words, the raw value that means "not implemented"; None: every value is one)
TYPES: dict[str, tuple[str, int, int | str | None]] = {
    "int16": ("s16", 1, -0x8000),
    "uint16": ("u16", 1, 0xFFFF),
    "count": ("u16", 1, 0xFFFF),
    "acc16": ("u16", 1, 0),
    "enum16": ("u16", 1, 0xFFFF),
    "bitfield16": ("u16", 1, 0xFFFF),
    "pad": ("u16", 1, None),
    "sunssf": ("s16", 1, -0x8000),
    "int32": ("s32", 2, -0x80000000),
    "uint32": ("u32", 2, 0xFFFFFFFF),
    "acc32": ("u32", 2, 0),
    "enum32": ("u32", 2, 0xFFFFFFFF),
    "bitfield32": ("u32", 2, 0xFFFFFFFF),
    "ipaddr": ("u32", 2, 0),
    "int64": ("s64", 4, -0x8000000000000000),
    "uint64": ("u64", 4, 0xFFFFFFFFFFFFFFFF),
    "acc64": ("u64", 4, 0),
    "float32": ("f32", 2, "NaN (0x7FC00000)"),
    "float64": ("f64", 4, "NaN (0x7FF8000000000000)"),
    "string": ("string", 0, "a first byte NUL"),
    "eui48": ("u64", 4, "FF:FF:FF:FF:FF:FF"),
    "ipv6addr": ("string", 8, "all zero"),
}
MARKER = 0x53756E53  # "SunS"
END_ID = 0xFFFF
BASES = (40000, 50000, 0)
MAX_STRING_WORDS = 125  # a map's string is read in one request


@dataclass(frozen=True)
class Point:
    """One point of a model laid out: its register name, offset from the model's ID, and definition."""

    name: str
    offset: int
    pdef: dict[str, Any]
    group: str  # the repeating group's path and index (`module_1`), or "" for the model's own points


def _snake(name: str) -> str:
    out = re.sub(r"(?<=[a-z0-9])(?=[A-Z])", "_", name)
    return re.sub(r"[^a-z0-9]+", "_", out.lower()).strip("_")


def points(model: dict[str, Any], repeats: int) -> list[Point]:
    """The model's points in register order; a repeating group whose count the device gives is repeated `repeats` times."""
    out: list[Point] = []

    def walk(group: dict[str, Any], prefix: str, offset: int) -> int:
        for pdef in group.get("points", []):
            out.append(Point(prefix + _snake(pdef["name"]), offset, pdef, prefix.rstrip("_")))
            offset += int(pdef.get("size") or TYPES[pdef["type"]][1])
        for sub in group.get("groups", []):
            count = sub.get("count")
            times = count if isinstance(count, int) and count > 0 else repeats if count is not None else 1
            for i in range(times):
                label = f"{prefix}{_snake(sub['name'])}_{i + 1}_" if count is not None else f"{prefix}{_snake(sub['name'])}_"
                offset = walk(sub, label, offset)
        return offset

    walk(model["group"], "", 0)
    return out


def _count_points(group: dict[str, Any]) -> set[str]:
    """The points that give a repeating group's count (`"count": "NMod"`)."""
    names = {g["count"] for g in group.get("groups", []) if isinstance(g.get("count"), str)}
    for sub in group.get("groups", []):
        names |= _count_points(sub)
    return names


def model_length(model: dict[str, Any], repeats: int) -> int:
    """The L of the model laid out with `repeats` repetitions: registers after ID and L."""
    laid = points(model, repeats)
    last = laid[-1]
    return last.offset + int(last.pdef.get("size") or TYPES[last.pdef["type"]][1]) - 2


def _register(point: Point, address: int, model: dict[str, Any], prefix: str, origin: str, report: list[str]) -> Imported:
    pdef = point.pdef
    kind, words, unimplemented = TYPES[pdef["type"]]
    title = str(pdef.get("label") or pdef["name"])
    if point.group:
        title = f"{title} ({point.group.replace('_', ' ')})"
    reg = Imported(
        key=f"{prefix}{point.name}",
        title=title,
        address=address,
        space="holding",
        type=kind,
        origin=origin,
        writable=pdef.get("access") == "RW",
        unit=pdef.get("units") or None,
        group=f"model_{model['id']}",
        group_title=f"Model {model['id']}: {model['group'].get('label') or model['group']['name']}",
    )
    if kind == "string":
        reg.words = int(pdef.get("size") or words)
        reg.encoding = "utf-8"  # pysunspec2 decodes SunSpec strings as UTF-8
    if pdef["name"] == "ID" and not point.group:
        reg.default = int(model["id"])
    sf = pdef.get("sf")
    if isinstance(sf, int):
        reg.scale = Fraction(10) ** sf
    if pdef["type"] == "sunssf":
        reg.na = [0x8000]  # "not implemented": a point it scales reads as None
    if unimplemented is not None:
        shown = f"0x{unimplemented & ((1 << (16 * words)) - 1):X}" if isinstance(unimplemented, int) else unimplemented
        reg.notes.append(f"not implemented: {shown} (SunSpec's n/a value)")
    if pdef["type"] == "eui48":
        reg.notes.append("an EUI-48: the low six bytes of the u64")
    if pdef["type"] == "ipaddr":  # the u32 pysunspec2 reads too; the map has no display form for an address
        reg.notes.append("an IPv4 address: its four bytes high first (0xC0A80101 is 192.168.1.1)")
    if pdef["type"] == "ipv6addr":
        reg.encoding = "latin-1"
        reg.notes.append("an IPv6 address: its 16 bytes as latin-1 text")
    symbols = pdef.get("symbols") or []
    if pdef["type"].startswith("enum"):
        reg.members = [Member(value=int(s["value"]), title=str(s.get("label") or s["name"])) for s in symbols]
    elif pdef["type"].startswith("bitfield"):
        reg.flags = [
            Flag(key=_snake(s["name"]) or f"bit_{s['value']}", mask=1 << int(s["value"]), title=str(s.get("label") or s["name"]))
            for s in symbols
        ]
    return reg


INTEGERS = {"s16", "u16", "s32", "u32", "s64", "u64"}


def _scale_from(laid: list[Point], pairs: list[tuple[Point, Imported]]) -> None:
    """Each point whose `sf` names a point: `scale_from` that `sunssf` register (pysunspec2 looks in the point's
    own group, then among the model's points) and its "not implemented" value as `na`; else a note."""
    by_name = {point.name: point for point in laid}
    keys = {point.name: reg.key for point, reg in pairs}
    for point, reg in pairs:
        sf = point.pdef.get("sf")
        if sf is None or isinstance(sf, int):
            continue
        own = f"{point.group}_{_snake(str(sf))}" if point.group else None
        target = by_name.get(own or "") or by_name.get(_snake(str(sf)))
        kind, _, unimplemented = TYPES[point.pdef["type"]]
        plain = kind in INTEGERS and not point.pdef["type"].startswith(("enum", "bitfield"))
        if target is None or target.pdef["type"] != "sunssf" or target.name not in keys or not plain:
            why = "names no sunssf point" if target is None or target.pdef["type"] != "sunssf" else f"on a {point.pdef['type']} point"
            reg.notes.append(f"scaled by 10^{sf} ({why}): value = raw x 10^{sf}; the map cannot express it")
            continue
        reg.scale_from = keys[target.name]
        if isinstance(unimplemented, int):
            reg.na = [unimplemented]


def read_models(paths: list[Path]) -> list[dict[str, Any]]:
    """The model definitions, checked: a problem is a ConfigError at file:line:col (the JSON read by the safe
    YAML reader, which keeps positions: JSON is YAML)."""
    models = []
    problems = []
    for path in paths:
        config = read_config(path.read_text(encoding="utf-8"), str(path))
        model = config.data
        if not isinstance(model, dict) or not isinstance(model.get("group"), dict) or not isinstance(model.get("id"), int):
            raise ConfigError([config.error((), "not a SunSpec model definition (expected {id: ..., group: {...}})")])
        problems += _check_group(config, model["group"], ("group",))
        model["_file"] = config.file_name
        models.append(model)
    if problems:
        raise ConfigError(problems)
    return models


def _check_group(config: Config, group: Any, path: tuple[str | int, ...]) -> list[Diagnostic]:
    """Every point has a name, a SunSpec type and (a string) a size; every group a name."""
    if not isinstance(group, dict) or not isinstance(group.get("name"), str):
        return [config.error(path, "a group is a mapping with a name, points and groups")]
    problems = []
    for i, pdef in enumerate(group.get("points") or []):
        where = (*path, "points", i)
        if not isinstance(pdef, dict) or not isinstance(pdef.get("name"), str):
            problems.append(config.error(where, "a point is a mapping with a name and a type"))
        elif pdef.get("type") not in TYPES:
            problems.append(config.error((*where, "type"), f"point {pdef['name']}: type {pdef.get('type')!r} is not a SunSpec type"))
        elif pdef["type"] == "string" and (isinstance(pdef.get("size"), bool) or not isinstance(pdef.get("size"), int) or pdef["size"] < 1):
            problems.append(config.error((*where, "size"), f"point {pdef['name']}: a string needs its size in registers"))
    for i, sub in enumerate(group.get("groups") or []):
        problems += _check_group(config, sub, (*path, "groups", i))
    return problems


def device(models: list[dict[str, Any]], base: int = 40000, repeats: int = 1) -> Import:
    """One SunSpec device: the marker at `base`, the models chained after it, the end marker."""
    if base not in BASES:
        raise ValueError(f"a SunSpec device starts at {', '.join(map(str, BASES))}")
    found = Device(label="sunspec", slave=1)
    report: list[str] = []
    marker = Imported(key="suns", title="SunSpec marker", address=base, space="holding", type="u32", origin="SunSpec", default=MARKER)
    marker.group, marker.group_title = "sunspec", "SunSpec marker"
    found.registers.append(marker)
    address = base + 2
    taken: set[str] = set()
    for model in models:
        prefix = f"m{model['id']}_"
        while prefix in taken:
            prefix = f"m{model['id']}_{len(taken)}_"
        taken.add(prefix)
        laid = points(model, repeats)
        counted = _count_points(model["group"])
        pairs: list[tuple[Point, Imported]] = []
        for point in laid:
            size = int(point.pdef.get("size") or 0)
            if point.pdef["type"] == "string" and size > MAX_STRING_WORDS:
                report.append(f"{model['_file']}: {point.pdef['name']}: a string of {size} registers is longer than one read: not imported")
                continue
            reg = _register(point, address + point.offset, model, prefix, f"{model['_file']}:{point.pdef['name']}", report)
            if point.pdef["name"] == "L" and not point.group:
                reg.default = model_length(model, repeats)
            elif (point.pdef["name"] in counted or point.pdef["type"] == "count") and not point.group:
                reg.default = repeats  # the count of the repeating group as laid out
            found.registers.append(reg)
            pairs.append((point, reg))
        _scale_from(laid, pairs)
        address += model_length(model, repeats) + 2
    end = Imported(
        key="end_id", title="End of the SunSpec models", address=address, space="holding", type="u16", origin="SunSpec", default=END_ID
    )
    end_len = Imported(
        key="end_length", title="End marker length", address=address + 1, space="holding", type="u16", origin="SunSpec", default=0
    )
    for reg in (end, end_len):
        reg.group, reg.group_title = "sunspec_end", "End of the SunSpec models"
        found.registers.append(reg)
    scaled = sum(1 for r in found.registers if r.scale_from is not None)
    noted = sum(1 for r in found.registers if any(n.startswith("scaled by") for n in r.notes))
    report.append(f"{scaled} point(s) scaled by a scale-factor point (scale_from: value = raw x 10^sf, read from the device)")
    if noted:
        report.append(f"{noted} point(s) with a scale factor the map cannot express: noted, the value read is the raw one")
    return Import([found], report)
