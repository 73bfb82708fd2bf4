"""`regmap diff`: what changed between two versions of a map, what it breaks, the version bump it needs."""

from __future__ import annotations

import argparse
import sys

from regmap.cli.common import examples

EXIT_HELP = (
    "exit status: 0 no differences, 6 differences that are all compatible, 7 breaking differences present, "
    "1 a map that is missing or invalid, 2 bad input (an unknown git revision)"
)
HELP = "what changed between two versions of a map, what it breaks, and the version bump it needs"


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> argparse.ArgumentParser:
    p = sub.add_parser(
        "diff",
        help=HELP,
        description="Compare two maps: registers are matched by name, then parameter id, then address, so a rename or a move is one "
        "change. Each change is breaking or compatible; the report suggests the map_version bump.",
        epilog="OLD and NEW are map files; PATH@GITREV reads the map at a git revision (maps/idm_rs.yaml@HEAD~1).\n"
        + EXIT_HELP
        + "\n\n"
        + examples(
            "regmap diff maps/idm_rs.yaml@HEAD maps/idm_rs.yaml          # the working copy against the last commit",
            "regmap diff maps/c630s.yaml@v1.0.0 maps/c630s.yaml --format markdown > c630s-changes.md",
        ),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("old", metavar="OLD", help="the earlier map: PATH or PATH@GITREV")
    p.add_argument("new", metavar="NEW", help="the later map: PATH or PATH@GITREV")
    p.add_argument("--format", choices=["text", "markdown", "json"], default="text", help="text (default), markdown (a changelog) or json")
    return p


def run(args: argparse.Namespace) -> int:
    from regmap.tools import diff

    report = diff.compare(diff.load_spec(args.old), diff.load_spec(args.new))
    sys.stdout.write(diff.render(report, args.format))
    return report.exit_status
