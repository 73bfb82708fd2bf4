"""`regmap command`: one of the map's commands, sent to a drive."""

from __future__ import annotations

import argparse
import sys

from regmap.cli.common import WHERE, device_and_link, live_parser

HELP = "run one of the map's commands on a drive"


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> argparse.ArgumentParser:
    p = live_parser(
        sub,
        "command",
        HELP,
        "Send a command the map declares (save, factory reset, alarm reset, trigger a path ...). `regmap show MAP` lists them.",
        f"regmap command maps/idm_rs.yaml save_all_parameters {WHERE}",
        f"regmap command maps/idm_rs.yaml trigger_path 3 {WHERE}",
        f"regmap command maps/idm_rs.yaml restore_factory_defaults --confirm restore_factory_defaults {WHERE}",
    )
    p.add_argument("name", metavar="NAME")
    p.add_argument("argument", nargs="?", metavar="ARGUMENT", help="for a command that takes one (a path number ...)")
    p.add_argument(
        "--confirm",
        metavar="NAME",
        help="a destructive command (factory reset, initialisation ...) is sent only with its name repeated here",
    )
    return p


def run(args: argparse.Namespace) -> int:
    from regmap.diagnostics import ExitCode
    from regmap.tools import live

    device, link = device_and_link(args)
    sent = live.send_command(device, link, args.name, args.argument, args.confirm)
    if sent.unknown is not None:
        print(f"regmap command: outcome unknown: {sent.name}: {sent.unknown}", file=sys.stderr)
        return ExitCode.OUTCOME_UNKNOWN
    shown = " ".join(f"0x{w:04X}" for w in sent.words)
    print(f"sent {sent.name}: {shown} to {sent.register.label} (0x{sent.register.address:04X})")
    return ExitCode.OK
