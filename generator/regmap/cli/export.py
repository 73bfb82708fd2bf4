"""`regmap export`: the elaborated model as JSON (the documented contract for other tools)."""

from __future__ import annotations

import argparse
import json
import sys

from regmap.cli.common import add_map, examples, load_map
from regmap.diagnostics import ExitCode

HELP = "print the elaborated model of a map as JSON"


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> argparse.ArgumentParser:
    p = sub.add_parser(
        "export",
        help=HELP,
        description="Print the map as regmap understands it: arrays expanded, enums resolved, defaults applied (README: the JSON contract).",
        epilog=examples("regmap export maps/c630s.yaml > c630s.json"),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    add_map(p)
    p.add_argument("--format", choices=["json"], default="json")
    return p


def run(args: argparse.Namespace) -> int:
    from regmap.backends.export import export_json

    device = load_map(args.map)
    json.dump(export_json(device), sys.stdout, ensure_ascii=False, indent=2)
    sys.stdout.write("\n")
    return ExitCode.OK
