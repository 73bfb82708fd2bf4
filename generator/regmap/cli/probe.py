"""`regmap probe`: check a live drive against its map, and learn what it tolerates."""

from __future__ import annotations

import argparse
import json
import sys
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING

from regmap.cli.common import WHERE, device_and_link, live_parser, positive_float, requests_per_second
from regmap.diagnostics import ExitCode, UsageError
from regmap.tools.output import check_output

if TYPE_CHECKING:
    from regmap.tools.probe.report import Findings

HELP = "check a live drive against its map and learn its limits (reads only)"


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> argparse.ArgumentParser:
    p = live_parser(
        sub,
        "probe",
        HELP,
        "Read every documented register and report where the drive and the map disagree: registers that do not answer "
        "(and the exception), values outside the range or the enum, the 32-bit word order the values show, the largest "
        "read the drive takes, whether it answers reads across undocumented addresses. Nothing is written unless "
        "--write-test names registers. Exit 0: agrees; 8: disagrees; 4: could not probe; 130: Ctrl-C (what was learned "
        "is printed first). --profile saves what was observed for `read`/`dump --profile` and the Python client.",
        f"regmap probe maps/idm_rs.yaml {WHERE}",
        "regmap probe maps/c630s.yaml --tcp 127.0.0.1:5020 --json --profile c630s.profile.json",
        "regmap probe maps/id243pro.yaml --tcp 127.0.0.1:5020 --scan-undocumented --write-test 0x0000 --budget 60 --rate 20",
        "regmap probe examples/plants/cell1.yaml --bus line1 --device spindle --tcp 127.0.0.1:5020",
        variant=False,
    )
    p.add_argument("--json", action="store_true", help="the report as JSON on stdout")
    p.add_argument("--profile", metavar="FILE", help="write the device profile learned (atomically)")
    p.add_argument(
        "--scan-undocumented",
        action="store_true",
        help="also read each undocumented address inside the map's address ranges, one at a time (bounded)",
    )
    p.add_argument(
        "--write-test",
        nargs="+",
        metavar="SELECTOR",
        default=[],
        help="write these registers' current values back and read them; check an out-of-range value is refused",
    )
    p.add_argument(
        "--sunspec",
        action="store_true",
        help="walk the SunSpec chain (the SunS marker at 40000, 50000 or 0, then model id + length) and report its models",
    )
    p.add_argument("--budget", type=positive_float, default=300.0, metavar="SECONDS", help="stop after this long (default 300)")
    p.add_argument(
        "--rate", type=requests_per_second, metavar="REQ_PER_S", help="at most this many requests per second (default: no limit)"
    )
    return p


def run(args: argparse.Namespace) -> int:
    from regmap.tools import live
    from regmap.tools.probe import Options, probe
    from regmap.tools.probe.profile import save
    from regmap.tools.probe.report import render_text
    from regmap.tools.probe.writetest import chosen

    device, link = device_and_link(args)
    if link.word_order not in (None, "auto"):
        raise UsageError("--word-order: the probe finds the word order itself")
    link = replace(link, variant=None)  # the probe finds the variant out (a plant's says what to expect)
    target = Path(args.profile) if args.profile else None
    if args.profile:
        check_output(args.profile, "--profile")  # now: after the probe, a directory or a full disk would lose what was learned
    progress = None
    if sys.stderr.isatty() and not args.json:

        def progress(text: str) -> None:
            sys.stderr.write(f"\r{text:<60}")
            sys.stderr.flush()

    options = Options(
        budget_s=args.budget,
        rate=args.rate,
        scan_undocumented=args.scan_undocumented,
        write_test=tuple(chosen(device, args.write_test)),
        sunspec=args.sunspec,
        progress=progress,
    )
    client = live.connect(device, link, reading=True)
    try:
        found, learned = probe(device, client, link.where, options)
    finally:
        client.close()
        if progress is not None:
            sys.stderr.write("\r" + " " * 60 + "\r")
    if target is not None and found.probed:
        save(target, learned)
    if args.json:
        document = found.as_json()
        document["profile"] = learned.to_json()
        json.dump(document, sys.stdout, ensure_ascii=False, indent=2)
        sys.stdout.write("\n")
    else:
        print(render_text(found))
        if target is not None:
            print(f"profile: {'written to ' + str(target) if found.probed else 'not written (nothing was learned)'}")
    return probe_status(found)


def probe_status(found: Findings) -> int:
    """0: the drive agrees with its map; 8: it disagrees; 4: it could not be probed (or the probe stopped early); 130: Ctrl-C."""
    if found.interrupted:
        return ExitCode.INTERRUPTED
    if not found.probed:
        return ExitCode.BUS  # nothing answered: a silence is no disagreement
    if found.disagreements:
        return ExitCode.PROBE_DISAGREES
    return ExitCode.BUS if found.stopped is not None else ExitCode.OK
