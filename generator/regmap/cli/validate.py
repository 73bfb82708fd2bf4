"""`regmap validate`: schema, semantic rules and every back end's own checks."""

from __future__ import annotations

import argparse
import sys

from regmap.cli.common import examples, load_map, map_paths
from regmap.diagnostics import ExitCode, MapError

HELP = "check maps: schema, semantic rules, and every back end's own rules"


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> argparse.ArgumentParser:
    p = sub.add_parser(
        "validate",
        help=HELP,
        description="Check maps against the JSON Schema, the semantic rules (overlaps, ranges, enums, example CRCs ...) and the rules "
        "of every back end (names the generated code would use twice). Every problem is printed as file:line:col: message.",
        epilog=examples("regmap validate                      # every maps/*.yaml", "regmap validate maps/idm_rs.yaml"),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("maps", nargs="*", metavar="MAP", help="map files (default: every maps/*.yaml)")
    return p


def run(args: argparse.Namespace) -> int:
    from regmap.generate import check

    status = ExitCode.OK
    for path in map_paths(args.maps):
        try:
            device = load_map(path)
            problems = check([device])
            if problems:
                raise MapError(problems)
        except MapError as exc:
            for diag in exc.diagnostics:
                print(diag, file=sys.stderr)
            status = ExitCode.INVALID_MAP
            continue
        name = " ".join(f"{device.info.vendor} {device.info.model}".split())  # map text stays on one line
        print(
            f"{path}: ok: {name} map {device.info.map_version}, "
            f"{len(device.registers)} registers ({len(device.arrays)} arrays), {len(device.enums)} enums, "
            f"{len(device.commands)} commands, {len(device.examples)} examples, {len(device.errata)} errata"
        )
    return status
