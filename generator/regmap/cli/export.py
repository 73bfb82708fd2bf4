"""`regmap export`: the elaborated model as JSON (the documented contract for other tools), or as a spreadsheet."""

from __future__ import annotations

import argparse
import json

from regmap.cli.common import add_map, examples, load_map
from regmap.diagnostics import ExitCode, UsageError
from regmap.tools.output import STDOUT, check_output, write_output

HELP = "print the elaborated model of a map as JSON, or write it as CSV or XLSX"


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> argparse.ArgumentParser:
    p = sub.add_parser(
        "export",
        help=HELP,
        description="Print the map as regmap understands it: arrays expanded, enums resolved, defaults applied (README: the JSON contract). "
        "csv and xlsx give one row per register with every field (raw and engineering values); xlsx adds sheets for groups, enums, "
        "commands, faults and errata. CSV is UTF-8 with a BOM so that Excel shows Chinese; the same map always gives the same bytes. No cell is a formula: "
        "a CSV text that starts with = + - @ is written behind a single quote (import takes it off), an xlsx text is a string.",
        epilog=examples(
            "regmap export maps/c630s.yaml > c630s.json",
            "regmap export maps/c630s.yaml --format csv > c630s.csv",
            "regmap export maps/c630s.yaml --format xlsx --out c630s.xlsx",
        ),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    add_map(p)
    p.add_argument("--format", choices=["json", "csv", "xlsx"], default="json")
    p.add_argument(
        "--out", metavar="FILE", help="write to FILE, or to stdout with - (required for xlsx; json and csv go to stdout without it)"
    )
    return p


def run(args: argparse.Namespace) -> int:
    if args.format == "xlsx" and not args.out:
        raise UsageError("--format xlsx writes a binary workbook: give --out FILE.xlsx (or --out - for stdout)")
    where = args.out or STDOUT
    check_output(where, "--out", stdout=True, binary=args.format == "xlsx")
    device = load_map(args.map)
    data: bytes
    if args.format == "json":
        from regmap.core.contract import export_json

        data = (json.dumps(export_json(device), ensure_ascii=False, indent=2) + "\n").encode()
    elif args.format == "csv":
        from regmap.tools.spreadsheet.export import export_csv

        data = export_csv(device).encode()
    else:
        from regmap.tools.spreadsheet.export import export_xlsx

        data = export_xlsx(device)
    write_output(where, data, "--out")
    return ExitCode.OK
