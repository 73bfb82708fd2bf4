"""`regmap dump`: every readable register, by the read plan."""

from __future__ import annotations

import argparse

from regmap.cli.common import (
    add_addressing,
    add_output,
    add_profile,
    add_space,
    link_from,
    live_parser,
    load_map,
    output_format,
    profile_from,
    space_from,
)

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
    add_space(p)
    add_addressing(p, start=True)
    add_output(p)
    add_profile(p)
    return p


def run(args: argparse.Namespace) -> int:
    from regmap.diagnostics import UsageError
    from regmap.tools import live
    from regmap.tools.selectors import Registers, parse_items, say_notes
    from regmap_runtime.spaces import DEFAULT_SPACE, SPACES

    space = space_from(args)
    if args.count is not None and args.start is None:
        raise UsageError(f"-c {args.count} counts from a start: give -r REF too")
    items = parse_items([], count=args.count, start=args.start, modicon=args.modicon, space=space) if args.start is not None else []
    device = load_map(args.map)
    regs = Registers(device)
    if not items:
        chosen = None if space is None else regs.from_on(space, 0)
    else:
        (item,) = items
        assert item.located is not None
        start_space = item.located.space or space or DEFAULT_SPACE
        chosen = regs.from_on(start_space, item.located.address)[: item.count]
        if not chosen:
            raise UsageError(f"{item.selector}: no readable {SPACES[start_space].title} from 0x{item.located.address:04X} on")
    status = live.cmd_dump(device, link_from(args), output_format(args), profile_from(args, device), chosen)
    say_notes("dump", [i.located.note for i in items if i.located is not None and i.located.note])
    return status
