"""`regmap write`: checked values to a drive, then read back."""

from __future__ import annotations

import argparse

from regmap.cli.common import VALUE_SYNTAX, WHERE, add_addressing, add_space, device_and_link, live_parser, say_notes, space_from

HELP = "write registers, then read them back"


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> argparse.ArgumentParser:
    p = live_parser(
        sub,
        "write",
        HELP,
        "Every value is checked (range, resolution, enum, bitfield widths, access, two values for one word; never a state the "
        "drive only reports, such as a read-back value of a trigger register, even with --raw) before the port "
        f"is opened, then written and read back.\n{VALUE_SYNTAX}. Naming some fields of a bitfield register reads the register "
        "first and changes only those fields (read-modify-write); --replace writes the whole word with the unnamed fields 0.",
        f"regmap write maps/idm_rs.yaml Pr5.00=1.5 {WHERE}",
        f"regmap write maps/idm_rs.yaml di3_function=function:ctrg {WHERE}     # the other fields are kept",
        f"regmap write maps/idm_rs.yaml --words 0x6209=0xFFFC,0xF2C0 {WHERE}",
        "regmap write tests/maps/fixtures/remote_io.yaml relay_20_on=on relay_21_on=off --tcp 127.0.0.1:5020   # one 0x0F",
        "regmap write tests/maps/fixtures/remote_io.yaml --words -t 0 0x13=1,0,1 --tcp 127.0.0.1:5020",
    )
    p.add_argument("assignments", nargs="+", metavar="SELECTOR=VALUE")
    p.add_argument("--raw", action="store_true", help="values are raw register integers")
    p.add_argument(
        "--words",
        action="store_true",
        help="ADDR=WORD[,WORD...]: 16-bit words (bits 0/1 with -t 0) at any address (no read-back); words on a register the map lists pass its checks",
    )
    add_space(p)
    add_addressing(p, start=False)
    p.add_argument("--replace", action="store_true", help="bitfield fields not named become 0 instead of keeping the drive's")
    p.add_argument("--no-verify", action="store_true", help="skip the read-back")
    return p


def run(args: argparse.Namespace) -> int:
    from regmap.cli.live_output import write_status
    from regmap.tools import live

    space = space_from(args)
    device, link = device_and_link(args)
    plan = live.plan_write(
        device, args.assignments, raw=args.raw, replace=args.replace, words=args.words, space=space, modicon=args.modicon
    )
    say_notes("write", plan.notes)
    return write_status(live.write(device, link, plan, verify=not args.no_verify and not args.words))
