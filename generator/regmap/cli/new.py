"""`regmap new`: a commented skeleton map that validates, to start transcribing a manual."""

from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path

from regmap.cli.common import examples
from regmap.diagnostics import ExitCode, MapError, UsageError
from regmap.tools.output import check_output, is_stdout, write_output

HELP = "write a commented skeleton map for a new device"


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> argparse.ArgumentParser:
    p = sub.add_parser(
        "new",
        help=HELP,
        description="Write maps/DEVICE_ID.yaml (or --out): a skeleton that validates, every transport field explained in a comment. "
        "Its transport values are Modbus's defaults marked 'check': replace each with the manual's. Refuses to overwrite a file.",
        epilog=examples(
            "regmap new acme_x1 --vendor Acme --model 'X1 servo'",
            "regmap new acme_x1 --vendor Acme --model X1 --out /tmp/acme_x1.yaml",
            "regmap import x1-registers.xlsx --into maps/acme_x1.yaml     # then fill it from a spreadsheet",
        ),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("device_id", metavar="DEVICE_ID", help="snake_case id: prefix of generated files and C macros")
    p.add_argument("--vendor", required=True, help="vendor name (English)")
    p.add_argument("--model", required=True, help="model name as the manual prints it")
    p.add_argument("--out", metavar="FILE", help="where to write, - for stdout (default maps/DEVICE_ID.yaml)")
    return p


def _argument_at(skeleton: str, line: int, args: argparse.Namespace) -> str:
    """The command-line argument that wrote the skeleton's line `line` (its `vendor:`, `model:` or, else, the device id)."""
    lines = skeleton.splitlines()
    key = lines[line - 1].strip().partition(":")[0] if 0 < line <= len(lines) else ""
    return {"vendor": f"--vendor {args.vendor!r}", "model": f"--model {args.model!r}"}.get(key, f"DEVICE_ID {args.device_id!r}")


def run(args: argparse.Namespace) -> int:
    from regmap.frontend import load_map_text
    from regmap.generate import reserved_ids
    from regmap.tools.spreadsheet.skeleton import skeleton

    if not re.fullmatch(r"[a-z][a-z0-9_]{0,63}", args.device_id):
        raise UsageError(f"device id {args.device_id!r}: expected snake_case (a-z, 0-9, _), starting with a letter")
    for name, value in (("--vendor", args.vendor), ("--model", args.model)):
        if not value.strip() or any(ch in value for ch in "\r\n"):
            raise UsageError(f"{name}: expected one line of text")
    out: str | Path = args.out or Path("maps") / f"{args.device_id}.yaml"
    if not is_stdout(out) and Path(out).exists():
        raise UsageError(f"{out} exists: regmap new does not overwrite a map (use regmap import --into to update one)")
    text = skeleton(args.device_id, args.vendor.strip(), args.model.strip())
    try:
        # It validates, for every target it may be generated for (a device id that one reserves does not).
        reserved = reserved_ids([load_map_text(text, "skeleton")])
        if reserved:
            raise MapError(reserved)
    except MapError as exc:  # the skeleton differs only by the arguments: the problem is in one of them, not in a file
        problems = "; ".join(f"{_argument_at(text, diag.line, args)}: {diag.message}" for diag in exc.diagnostics)
        raise UsageError(f"{problems}; nothing written") from None
    check_output(out, "--out", stdout=True)
    write_output(out, text.encode(), "--out")
    print(
        f"{'stdout' if is_stdout(out) else out}: skeleton for {args.vendor.strip()} {args.model.strip()}; "
        "check every value marked 'check' against the manual",
        file=sys.stderr if is_stdout(out) else sys.stdout,
    )
    return ExitCode.OK
