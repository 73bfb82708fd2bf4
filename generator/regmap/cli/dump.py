"""`regmap dump`: every readable register, by the read plan."""

from __future__ import annotations

import argparse

from regmap.cli.common import add_read_options, link_from, live_parser, load_map, output_format, profile_from, space_from

HELP = "read every readable register with the read plan"


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> argparse.ArgumentParser:
    p = live_parser(
        sub,
        "dump",
        HELP,
        "Read every readable register of every data space with the fewest requests. A dump cut short by the bus or by Ctrl-C "
        "prints what was read and names what was not (exit 4, or 130 for Ctrl-C). Where the map gates registers by firmware and "
        "names its firmware register, the version is read first and the registers it lacks are left out (named on stderr). "
        "-t SPACE dumps one data space; -r REF [-c N] (mbpoll's 1-based start and count) the readable registers of that space "
        "(default holding) from that address on.",
        "regmap dump maps/idm_rs.yaml --csv --tcp 192.168.1.50:502 > drive.csv",
        "regmap dump maps/idm_rs.yaml -r 402 -c 10 --tcp 192.168.1.50:502     # 10 registers from address 401 on",
    )
    add_read_options(p)
    return p


def run(args: argparse.Namespace) -> int:
    from regmap.tools import live
    from regmap.tools.selectors import dump_range, say_notes

    space = space_from(args)
    device = load_map(args.map)
    chosen, notes = dump_range(device, args.start, args.count, space, modicon=args.modicon)
    status = live.cmd_dump(device, link_from(args), output_format(args), profile_from(args, device), chosen)
    say_notes("dump", notes)
    return status
