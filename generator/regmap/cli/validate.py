"""`regmap validate`: schema, semantic rules and every back end's own checks."""

from __future__ import annotations

import argparse
import sys

from regmap.cli.common import examples, load_map, load_plant, map_paths, plant_argument
from regmap.diagnostics import ExitCode, MapError

HELP = "check maps: schema, semantic rules, and every back end's own rules"


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> argparse.ArgumentParser:
    p = sub.add_parser(
        "validate",
        help=HELP,
        description="Check maps against the JSON Schema, the semantic rules (overlaps, ranges, enums, example CRCs ...) and the rules "
        "of every back end (names the generated code would use twice). Every problem is printed as file:line:col: message.",
        epilog=examples(
            "regmap validate                      # every maps/*.yaml",
            "regmap validate maps/idm_rs.yaml",
            "regmap validate examples/plants/cell1.yaml   # a plant: its buses, devices and their maps",
        ),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument(
        "maps", nargs="*", metavar="MAP", help="map files (default: every maps/*.yaml), or one plant file (format: regmap-plant/1)"
    )
    return p


def run(args: argparse.Namespace) -> int:
    from regmap.generate import check

    plant_path = plant_argument(args.maps)
    if plant_path is not None:
        return _validate_plant(plant_path)
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


def _validate_plant(path: str) -> int:
    from regmap.generate import check

    try:
        plant = load_plant(path)
        problems = check(list(plant.maps))
        if problems:
            raise MapError(problems)
    except MapError as exc:
        for diag in exc.diagnostics:
            print(diag, file=sys.stderr)
        return ExitCode.INVALID_MAP
    for bus in plant.buses:
        line = (
            f"{bus.serial.port} {bus.serial.baud} {bus.serial.parity}"
            if bus.serial is not None
            else f"tcp {bus.tcp.host}:{bus.tcp.port}"
            if bus.tcp
            else ""
        )
        devices = ", ".join(f"{d.name}@{d.slave} ({d.device.id}{', ' + d.variant if d.variant else ''})" for d in bus.devices)
        print(f"{path}: bus {bus.name} ({line}): {devices}")
    print(f"{path}: ok: plant {plant.id}, {len(plant.buses)} bus(es), {len(plant.devices)} device(s), {len(plant.maps)} map(s)")
    return ExitCode.OK
