"""`regmap dump`: every readable register, by the read plan."""

from __future__ import annotations

import argparse
import sys
from typing import TYPE_CHECKING

from regmap.cli.common import (
    add_read_options,
    device_and_link,
    live_parser,
    output_format,
    profile_from,
    say_notes,
    space_from,
)

if TYPE_CHECKING:
    from regmap.tools.live import Firmware

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
        "regmap dump examples/plants/cell1.yaml --bus line1 --device axis_y   # a plant's device, on its bus's line",
    )
    add_read_options(p)
    return p


def _say_lacking(known: Firmware) -> None:
    absent = known.absent
    names = ", ".join(r.name for r in absent[:10]) + (f" and {len(absent) - 10} more" if len(absent) > 10 else "")
    print(f"regmap dump: firmware {known.text} lacks {len(absent)} register(s) of the map, not read: {names}", file=sys.stderr)


def run(args: argparse.Namespace) -> int:
    from regmap.cli.live_output import ProgressBar, print_values, read_status
    from regmap.tools import live
    from regmap.tools.selectors import dump_range

    space = space_from(args)
    device, link = device_and_link(args)
    chosen, notes = dump_range(device, args.start, args.count, space, modicon=args.modicon)
    progress = ProgressBar() if sys.stderr.isatty() else None
    try:
        result = live.dump(device, link, profile_from(args, device), chosen, progress=progress, lacking=_say_lacking)
    finally:
        if progress is not None:
            progress.end()
    print_values(result.values, output_format(args))
    status = read_status(result, "dump")
    say_notes("dump", notes)
    return status
