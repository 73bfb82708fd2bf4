"""`regmap import`: a register table (CSV or XLSX) -> a new map draft, or an update of an existing map."""

from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Any

import yaml

from regmap.cli.common import examples
from regmap.diagnostics import ExitCode, MapError, UsageError
from regmap.tools.output import check_output, write_output

if TYPE_CHECKING:
    from regmap.tools.spreadsheet.importer import Update
    from regmap.tools.spreadsheet.rows import Problem

HELP = "make a map draft from a register table (CSV/XLSX), or update a map from one"


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> argparse.ArgumentParser:
    p = sub.add_parser(
        "import",
        help=HELP,
        description="Read a register table as manuals print it (headers in English or Chinese: 地址 参数号 名称 设定范围 出厂值 单位 "
        "生效方式 ...; cells like 0x0191, 0191h, P05-02, 0~65535, 0.1A, 立即生效) and write --into MAP: a new draft when MAP does not "
        "exist, otherwise an update that changes only what the table says differently and keeps every comment. A cell regmap cannot "
        "read is reported (file:sheet!cell) and left null with a note, never guessed. The result goes through the front end: a new "
        "draft that fails it is still written (exit 1: edit it); an update that would make the map invalid writes nothing.",
        epilog=examples(
            "regmap import vendor-registers.xlsx --into maps/acme_x1.yaml            # a new draft",
            "regmap import c630s-ch7.csv --columns c630s-columns.yaml --into maps/c630s_draft.yaml",
            "regmap import id243pro.xlsx --sheet registers --into maps/id243pro.yaml  # update: prints the change summary",
            "regmap import table.csv --into maps/id243pro.yaml --dry-run              # show the changes, write nothing",
            "regmap import esphome/meter.yaml --into maps/sdm120.yaml                # an ESPHome modbus_controller config",
            "regmap import configuration.yaml --from homeassistant --into maps/plant/ # HA modbus: one map per distinct device",
            "regmap import model_1.json --chain model_103.json --chain model_160.json --repeats 2 --into maps/inverter.yaml  # SunSpec",
        )
        + "\n\nA mapping file (--columns) names columns and gives param_ids rules for tables without an address column:\n"
        "  columns: {Code: param, Name: title_zh}\n"
        "  param_ids: [{regex: '^P(?P<group>[0-9A-F]{2})-(?P<index>[0-9]{2})$', format: 'P{group:02X}-{index:02d}', "
        "group_radix: 16, group_stride: 256}]\n"
        "A Gain column divides (value = raw / gain); Scale, Multiplier and Resolution multiply; a Factor column is refused "
        "until the mapping says which ({Factor: gain} or {Factor: scale}).",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("table", metavar="TABLE", help="a .csv (UTF-8) or .xlsx register table, or an ESPHome / Home Assistant .yaml config")
    p.add_argument(
        "--into",
        required=True,
        metavar="MAP",
        help="the map to create or update; for a config of several distinct devices, a directory (one map per device)",
    )
    p.add_argument(
        "--from",
        dest="config_format",
        choices=["esphome", "homeassistant", "sunspec"],
        help="what wrote the config (default: ESPHome when it has modbus_controller:, Home Assistant when it has a modbus: list, "
        "SunSpec for a .json model definition)",
    )
    p.add_argument(
        "--chain",
        action="append",
        default=[],
        metavar="MODEL.json",
        help="SunSpec: a model definition chained after TABLE's (repeatable, in order: model 1, then 103, then 160 ...)",
    )
    p.add_argument("--base", type=int, choices=[40000, 50000, 0], default=40000, help="SunSpec: the address of the SunS marker")
    p.add_argument(
        "--repeats",
        type=int,
        default=1,
        metavar="N",
        help="SunSpec: how many times a repeating group whose count the device gives is present (default 1)",
    )
    p.add_argument("--sheet", help="the xlsx sheet to read (default: 'registers', else the first)")
    p.add_argument("--columns", metavar="MAPPING.yaml", help="column mapping file: header -> field, param_ids rules")
    p.add_argument("--vendor", default="unknown", help="vendor of a new draft (default 'unknown')")
    p.add_argument("--model", default="unknown", help="model of a new draft (default 'unknown')")
    p.add_argument(
        "--addresses",
        choices=["modicon", "plain"],
        help="how a decimal address column reads: modicon (30001 = input register 0, 40001 = holding register 0) or plain "
        "(default: Modicon numbers are recognised only when they cannot be addresses; a column that may be either is refused)",
    )
    p.add_argument("--dry-run", action="store_true", help="print what would change; write nothing")
    return p


def _device_id(into: Path) -> str:
    if not re.fullmatch(r"[a-z][a-z0-9_]{0,63}", into.stem):
        raise UsageError(f"--into {into}: the file name gives the device id, which must be snake_case")
    return into.stem


def _front_end(text: str, name: Path) -> int:
    """A new draft through the front end: OK, or INVALID_MAP with its problems printed (the draft is still written)."""
    from regmap.frontend import load_map_text

    try:
        load_map_text(text, str(name))
    except MapError as exc:
        for diag in exc.diagnostics:
            print(diag, file=sys.stderr)
        return ExitCode.INVALID_MAP
    return ExitCode.OK


def _map_rules(path: Path) -> list[dict[str, Any]]:
    data = yaml.safe_load(path.read_text(encoding="utf-8"))
    rules = data.get("param_ids", []) if isinstance(data, dict) else []
    return [r for r in rules if isinstance(r, dict)]


def run(args: argparse.Namespace) -> int:
    if Path(args.table).suffix.lower() in (".yaml", ".yml", ".json") or args.config_format:
        return _run_config(args)
    from regmap.frontend import load_map, load_map_text
    from regmap.tools.diff import compare, render_text
    from regmap.tools.spreadsheet.columns import Mapping, load_mapping
    from regmap.tools.spreadsheet.importer import build_draft, update_map
    from regmap.tools.spreadsheet.rows import param_rules, read_entries
    from regmap.tools.spreadsheet.table import TableError, read_table

    into = Path(args.into)
    if not args.dry_run:
        check_output(args.into, "--into")  # a directory or an unwritable place: refused before the table is read
    mapping = load_mapping(args.columns) if args.columns else Mapping()
    device = load_map(into) if into.exists() else None
    rules = [*(_map_rules(into) if device is not None else []), *mapping.param_ids]
    try:
        table = read_table(args.table, args.sheet, mapping)
        print(f"{table.label}: header in row {table.header_row}; columns:")
        print("\n".join(table.describe_columns()))
        known = {r.name: r.type.value for r in device.registers} if device is not None else {}  # scale factors of the map
        entries, problems = read_entries(table, param_rules(rules), args.addresses or mapping.addresses, known)
        for line in table.said:
            print(f"  {line}")
    except TableError as exc:
        for line in exc.problems:
            print(line, file=sys.stderr)
        print(f"regmap import: {args.table}: nothing written", file=sys.stderr)
        return ExitCode.USAGE
    except re.error as exc:
        raise UsageError(f"param_ids: bad regex: {exc}") from None
    for problem in problems:
        print(problem, file=sys.stderr)
    unread = f"{len(problems)} cell(s) could not be read" + (" (listed above; null with a note in the draft)" if problems else "")

    if device is None:
        draft = build_draft(table, entries, problems, _device_id(into), args.vendor, args.model, mapping.param_ids)
        status = _front_end(draft.text, into)
        if not args.dry_run:
            write_output(into, draft.text.encode(), "--into")
        if status == ExitCode.OK:
            verdict = "valid"
        else:
            verdict = "which the front end rejects (above)" if args.dry_run else "written, but the front end rejects it (above): edit it"
        action = "would write" if args.dry_run else "wrote"
        print(f"{action} {into}: a new draft, {draft.registers} registers in {len(draft.groups)} group(s), {verdict}; {unread}")
        return status

    text = into.read_text(encoding="utf-8")
    update = update_map(text, device, table, entries)
    for line in update.skipped:
        print(line, file=sys.stderr)
    unread = _unread_in_update(problems, update)
    if update.text == text:
        print(f"{into}: no changes ({update.unchanged} registers agree with the table); {unread}")
        return ExitCode.OK
    try:
        new = load_map_text(update.text, str(into))
    except MapError as exc:
        for diag in exc.diagnostics:
            print(update.locate(diag), file=sys.stderr)
        print(f"regmap import: the update would make {into} invalid (above): nothing written", file=sys.stderr)
        return ExitCode.INVALID_MAP
    sys.stdout.write(render_text(compare(device, new)))
    if not args.dry_run:
        write_output(into, update.text.encode(), "--into")
    action = "would update" if args.dry_run else "updated"
    print(
        f"{action} {into}: {len(update.changed)} value(s) changed, {len(update.added)} register(s) added, "
        f"{update.unchanged} unchanged, {len(update.skipped)} not applied; {unread}"
    )
    return ExitCode.OK


def _unread_in_update(problems: list[Problem], update: Update) -> str:
    """What became of the cells that could not be read: a register the map has keeps its value, an added one has null."""
    if not problems:
        return "0 cell(s) could not be read"
    added = sum(1 for p in problems if p.row in update.added_rows)
    kept = sum(1 for p in problems if p.row not in update.added_rows and p.row is not None and p.row not in update.skipped_rows)
    parts = [f"{kept} in registers the map has: not applied, the map keeps its values"] if kept else []
    if added:
        parts.append(f"{added} in added registers: null with a note")
    if len(problems) - kept - added:
        parts.append(f"{len(problems) - kept - added} in rows not imported")
    return f"{len(problems)} cell(s) could not be read (listed above): " + "; ".join(parts)


def _run_config(args: argparse.Namespace) -> int:
    """An ESPHome or Home Assistant config -> one map per distinct device, and the report of what became notes."""
    from regmap.tools.configimport.drafts import drafts, read
    from regmap.tools.configimport.reader import ConfigError

    into = Path(args.into)
    source = Path(args.table)
    if not source.is_file():
        raise UsageError(f"{source}: no such file")
    if args.repeats < 0:
        raise UsageError(f"--repeats {args.repeats}: a count of repetitions, 0 or more")
    chain = tuple(Path(c) for c in args.chain)
    for path in chain:
        if not path.is_file():
            raise UsageError(f"--chain {path}: no such file")
    try:
        fmt, imported = read(source, args.config_format, chain, args.base, args.repeats)
    except ConfigError as exc:
        for diag in exc.diagnostics:
            print(diag, file=sys.stderr)
        print(f"regmap import: {source}: nothing written", file=sys.stderr)
        return ExitCode.INVALID_MAP
    except UnicodeDecodeError as exc:
        raise UsageError(f"{source}: not UTF-8 text ({exc.reason} at byte {exc.start})") from None
    several = len({d.signature() for d in imported.devices}) > 1
    if several and into.suffix in (".yaml", ".yml"):
        raise UsageError(f"--into {into}: {source} describes several distinct devices; give a directory (one map per device)")
    made = drafts(imported, "device" if several else _device_id(into), args.vendor, args.model, source.name)
    targets = [(into / f"{d.device_id}.yaml" if several else into, d) for d in made]
    status: int = ExitCode.OK
    for target, draft in targets:
        status = max(status, _front_end(draft.text, target))
    for line in imported.report:
        print(f"  {line}")
    if not args.dry_run:
        if several:
            into.mkdir(parents=True, exist_ok=True)
        for target, _ in targets:
            check_output(str(target), "--into")
        for target, draft in targets:
            write_output(target, draft.text.encode(), "--into")
    action = "would write" if args.dry_run else "wrote"
    for target, draft in targets:
        registers = len(draft.devices[0].registers)
        where = ", ".join(f"{d.label} (slave {d.slave})" for d in draft.devices)
        print(f"{action} {target}: {registers} registers from {fmt} {where}")
    print(
        f"{len(imported.report)} thing(s) kept as notes or left out (listed above); {'valid' if status == ExitCode.OK else 'the front end rejects a draft (above)'}"
    )
    return status
