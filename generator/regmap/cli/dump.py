"""`regmap dump`: every readable register, by the read plan."""

from __future__ import annotations

import argparse

from regmap.cli.common import add_output, add_profile, link_from, live_parser, load_map, output_format, profile_from

HELP = "read every readable register with the read plan"


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> argparse.ArgumentParser:
    p = live_parser(
        sub,
        "dump",
        HELP,
        "Read every readable register of every data space with the fewest requests. A dump cut short by the bus or by Ctrl-C "
        "prints what was read and names what was not (exit 4, or 130 for Ctrl-C). Where the map gates registers by firmware and "
        "names its firmware register, the version is read first and the registers it lacks are left out (named on stderr).",
        "regmap dump maps/idm_rs.yaml --csv --tcp 192.168.1.50:502 > drive.csv",
    )
    add_output(p)
    add_profile(p)
    return p


def run(args: argparse.Namespace) -> int:
    from regmap.tools import live

    device = load_map(args.map)
    return live.cmd_dump(device, link_from(args), output_format(args), profile_from(args, device))
