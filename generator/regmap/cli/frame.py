"""`regmap frame`: the request frame a master sends, as hex bytes."""

from __future__ import annotations

import argparse
import sys

from regmap.cli.common import VALUE_SYNTAX, add_map, add_space, add_word_order, examples, load_map, slave_id, space_from
from regmap.diagnostics import ExitCode, UsageError

HELP = "print a request frame as hex bytes"


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> argparse.ArgumentParser:
    p = sub.add_parser(
        "frame",
        help=HELP,
        description=(
            "Build the request frame a master sends.\n\n"
            "SELECTOR is a register name, the manual's parameter id (Pr5.00, P05-02, 0302) or a register's address (0x0191, 0191h, 401).\n"
            f"{VALUE_SYNTAX}.\n"
            "read SELECTOR COUNT reads COUNT of the map's readable registers from SELECTOR on (with the fewest requests).\n"
            "Every data space has its functions: holding registers 0x03/0x06/0x10, input registers 0x04 (read-only), coils "
            "0x01/0x05/0x0F, discrete inputs 0x02 (read-only); contiguous coils share one 0x0F frame.\n"
            "--raw: values are raw register values (no scaling). --words: ADDR=WORD[,WORD...] writes 16-bit words at any Modbus "
            "address (one word: 0x06; contiguous words: one 0x10, as mbpoll sends them), and read ADDR COUNT reads COUNT words; "
            "with -t/--space another space (mbpoll's -t: 0 coils, 1 discrete inputs, 3 input registers, 4 holding registers), "
            "whose words are bits 0/1 in a bit space (-t 0 0x13=1,0,1: one 0x0F).\n"
            "A bitfield register needs every field, a base word first, or --replace: `frame` has no drive to read the rest from."
        ),
        epilog=examples(
            "regmap frame maps/idm_rs.yaml write peak_current=1.5              # 01 06 01 91 00 0F 99 DF",
            "regmap frame maps/idm_rs.yaml read Pr5.22 3                       # three parameters, one request",
            "regmap frame maps/idm_rs.yaml write --words 0x6209=0xFFFC          # one word, as manual 7.4 prints it",
            "regmap frame maps/c630s.yaml read --words 0x0B11 2                 # a 32-bit parameter as '2 registers'",
            "regmap frame maps/idm_rs.yaml write Pr4.02=0x00A8,function:ctrg    # a base word and one field",
            "regmap frame maps/idm_rs.yaml command trigger_path 3",
            "regmap frame tests/maps/fixtures/remote_io.yaml write alarm_output=on          # 0x05, FF 00",
            "regmap frame tests/maps/fixtures/remote_io.yaml read --words -t 1 0xC4 22      # 22 discrete inputs",
            "regmap frame tests/maps/fixtures/remote_io.yaml write --words -t 0 0x13=1,0,1  # three coils, one 0x0F",
        ),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    add_map(p)
    p.add_argument("action", choices=["read", "write", "command"])
    p.add_argument("items", nargs="*", metavar="ARG", help="read: SELECTOR [COUNT]; write: SELECTOR=VALUE ...; command: NAME [ARGUMENT]")
    p.add_argument("--slave", type=slave_id, default=1, help="slave id (default 1)")
    p.add_argument("--raw", action="store_true", help="values are raw register integers")
    p.add_argument(
        "--words",
        action="store_true",
        help="addresses and 16-bit words (bits, in a bit space), documented or not (write ADDR=WORD,...; read ADDR COUNT)",
    )
    add_space(p)
    p.add_argument("--replace", action="store_true", help="bitfield fields not named become 0 (replace the whole word)")
    add_word_order(p, live=False)
    return p


def run(args: argparse.Namespace) -> int:
    from regmap.tools import frames
    from regmap.tools.selectors import parse_int
    from regmap_runtime.rtu import to_hex

    space = space_from(args)
    device = load_map(args.map)
    notes: list[str] = []
    if args.words and args.raw:
        raise UsageError("--words already means raw words; give one of --words and --raw")
    if args.action == "read":
        if not 1 <= len(args.items) <= 2:
            raise UsageError("read wants SELECTOR [COUNT]" + (" (--words: ADDR COUNT)" if args.words else ""))
        count = parse_int(args.items[1], "COUNT") if len(args.items) == 2 else None
        if args.words:
            built = [frames.read_words_frame(device, args.items[0], 1 if count is None else count, args.slave, space or "holding")]
        else:
            if count is not None and count < 1:
                raise UsageError(f"COUNT {count}: give at least 1 register")
            built = frames.read_frames(device, args.items[0], count, args.slave, space)
    elif args.action == "write":
        if args.words:
            built = frames.write_words_frames(device, args.items, args.slave, space or "holding")
        else:
            built, notes = frames.write_frames(
                device, args.items, args.slave, args.raw, replace=args.replace, word_order=args.word_order, space=space
            )
    else:
        if not 1 <= len(args.items) <= 2:
            raise UsageError("command wants NAME [ARGUMENT]")
        built = frames.command_frames(device, args.items[0], args.items[1] if len(args.items) == 2 else None, args.slave, args.word_order)
    for frame in built:
        print(to_hex(frame))
    for note in notes:
        print(f"regmap frame: note: {note}", file=sys.stderr)
    return ExitCode.OK
