"""`regmap show`: the map for humans (registers, enums, commands), or one of them."""

from __future__ import annotations

import argparse

from regmap.cli.common import add_map, examples, load_map
from regmap.diagnostics import ExitCode

HELP = "print the map for humans: registers, enums, commands (or one of them)"


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> argparse.ArgumentParser:
    p = sub.add_parser(
        "show",
        aliases=["list"],
        help=HELP,
        description="Print the map as regmap understands it, as `cantools dump` does: every register with address, type, access, "
        "range and default; enums; commands. With SELECTOR, one register (all its facts and bits), enum or command.",
        epilog=examples("regmap show maps/idm_rs.yaml | less", "regmap show maps/idm_rs.yaml Pr5.00", "regmap show maps/c630s.yaml p05-02"),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    add_map(p)
    p.add_argument("selector", nargs="?", metavar="SELECTOR", help="a register (name, parameter id, address), an enum or a command")
    return p


def run(args: argparse.Namespace) -> int:
    from regmap.tools.show import show

    print(show(load_map(args.map), args.selector))
    return ExitCode.OK
