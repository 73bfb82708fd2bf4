"""`regmap read`: registers from a drive, by name."""

from __future__ import annotations

import argparse

from regmap.cli.common import (
    WHERE,
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

HELP = "read registers from a drive"


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> argparse.ArgumentParser:
    p = live_parser(
        sub,
        "read",
        HELP,
        "Read registers by name, manual parameter id or address, with the fewest requests; values are shown with units, enum "
        "names and bitfields, in the order given; every data space with its own function (0x03 holding, 0x04 input, 0x01 "
        "coils, 0x02 discrete inputs). A value outside the map's range is marked OUTSIDE. JSON and CSV give floats as numbers, "
        "text as text and bits as true/false.",
        f"regmap read maps/idm_rs.yaml peak_current Pr5.22 run_status {WHERE}",
        "regmap read maps/c630s.yaml P05-02 --tcp 127.0.0.1:5020 --word-order high_first",
        "regmap read tests/maps/fixtures/remote_io.yaml 0x13 -t 0 --json --tcp 127.0.0.1:5020     # the coil at 0x0013",
    )
    p.add_argument("selectors", nargs="+", metavar="SELECTOR")
    add_space(p)
    add_output(p)
    add_profile(p)
    return p


def run(args: argparse.Namespace) -> int:
    from regmap.tools import live

    device = load_map(args.map)
    return live.cmd_read(device, link_from(args), args.selectors, output_format(args), profile_from(args, device), space_from(args))
