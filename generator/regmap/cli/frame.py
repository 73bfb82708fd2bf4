"""`regmap frame`: the request frame a master sends, as hex bytes."""

from __future__ import annotations

import argparse
from typing import Any

from regmap.cli.common import (
    SELECTOR_SYNTAX,
    VALUE_SYNTAX,
    add_addressing,
    add_map,
    add_space,
    add_word_order,
    examples,
    load_map,
    say_notes,
    slave_id,
    space_from,
)
from regmap.diagnostics import ExitCode, UsageError

HELP = "print a request frame as hex bytes"


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> argparse.ArgumentParser:
    p = sub.add_parser(
        "frame",
        help=HELP,
        description=(
            "Build the request frame a master sends.\n\n"
            f"{SELECTOR_SYNTAX}.\n"
            f"{VALUE_SYNTAX}.\n"
            "read SELECTOR [COUNT] ... reads each register, or COUNT of the map's readable registers from SELECTOR on, with the "
            "fewest requests (as `regmap read` does); -r REF [-c N] is mbpoll's start and count.\n"
            "Every data space has its functions: holding registers 0x03/0x06/0x10, input registers 0x04 (read-only), coils "
            "0x01/0x05/0x0F, discrete inputs 0x02 (read-only); contiguous coils share one 0x0F frame.\n"
            "--raw: values are raw register values (no scaling), checked as any value (a state the drive only reports is refused). --words: ADDR=WORD[,WORD...] writes 16-bit words at any Modbus "
            "address (one word: 0x06; contiguous words: one 0x10, as mbpoll sends them) with none of the map's checks, and read ADDR COUNT reads COUNT words; "
            "with -t/--space another space (mbpoll's -t: 0 coils, 1 discrete inputs, 3 input registers, 4 holding registers), "
            "whose words are bits 0/1 in a bit space (-t 0 0x13=1,0,1: one 0x0F).\n"
            "A bitfield register needs every field, a base word first, or --replace: `frame` has no drive to read the rest from.\n"
            "Where the map lists them: echo [WORD] (0x08 return query data, A5 37 unless given), server-id (0x11), "
            "identification [basic|regular|extended|OBJECT] (0x2B/0x0E; an object id reads that object alone), "
            "mask SELECTOR=FIELD:VALUE,... (0x16: only the named bitfields change, the device keeps the rest; --words ADDR=AND,OR), "
            "write-read SELECTOR [COUNT] SELECTOR=VALUE ... (0x17: the items without = are the read, one block; the others the write, "
            "one run of adjacent holding registers; --words ADDR COUNT ADDR=WORD,...).\n"
            "--mbap prints the Modbus TCP ADU (MBAP header, unit = --slave, --transaction) instead of the RTU frame."
        ),
        epilog=examples(
            "regmap frame maps/idm_rs.yaml write peak_current=1.5              # 01 06 01 91 00 0F 99 DF",
            "regmap frame maps/idm_rs.yaml read Pr5.22 3                       # three parameters, one request",
            "regmap frame maps/idm_rs.yaml read -r 402                         # mbpoll's -r 402: address 401, Pr5.00",
            "regmap frame maps/idm_rs.yaml read --modicon 40402                # Modicon 40402: holding register 401",
            "regmap frame maps/idm_rs.yaml write --words 0x6209=0xFFFC          # one word, as manual 7.4 prints it",
            "regmap frame maps/c630s.yaml read --words 0x0B11 2                 # a 32-bit parameter as '2 registers'",
            "regmap frame maps/idm_rs.yaml write Pr4.02=0x00A8,function:ctrg    # a base word and one field",
            "regmap frame maps/idm_rs.yaml command trigger_path 3",
            "regmap frame tests/maps/fixtures/remote_io.yaml write alarm_output=on          # 0x05, FF 00",
            "regmap frame tests/maps/fixtures/remote_io.yaml read --words -t 1 0xC4 22      # 22 discrete inputs",
            "regmap frame tests/maps/fixtures/remote_io.yaml write --words -t 0 0x13=1,0,1  # three coils, one 0x0F",
            "regmap frame tests/maps/fixtures/power_meter.yaml server-id --mbap             # 00 01 00 00 00 02 01 11",
            "regmap frame tests/maps/fixtures/power_meter.yaml identification regular",
            "regmap frame tests/maps/fixtures/power_meter.yaml write-read firmware_version ct_ratio=7",
            "regmap frame tests/maps/protocol/mask_write.yaml mask --words 0x0004=0x00F2,0x0025  # MBAP 6.16's example",
        ),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    add_map(p)
    p.add_argument("action", choices=["read", "write", "command", "echo", "server-id", "identification", "mask", "write-read"])
    p.add_argument(
        "items",
        nargs="*",
        metavar="ARG",
        help="read: SELECTOR [COUNT] ... (or -r REF [-c N]); write: SELECTOR=VALUE ...; command: NAME [ARGUMENT]; the others: see above",
    )
    p.add_argument("--slave", type=slave_id, default=1, help="slave id (default 1)")
    p.add_argument("--raw", action="store_true", help="values are raw register integers")
    p.add_argument(
        "--words",
        action="store_true",
        help="addresses and 16-bit words (bits, in a bit space), documented or not (write ADDR=WORD,...; read ADDR COUNT)",
    )
    add_space(p)
    add_addressing(p, start=True)
    p.add_argument("--replace", action="store_true", help="bitfield fields not named become 0 (replace the whole word)")
    p.add_argument("--confirm", metavar="NAME", help="command: a destructive command's frame is built only with its name repeated here")
    p.add_argument("--mbap", action="store_true", help="print Modbus TCP ADUs (MBAP header + PDU) instead of RTU frames")
    p.add_argument("--transaction", type=transaction_id, default=1, help="the first MBAP transaction id (default 1; with --mbap)")
    add_word_order(p, live=False)
    return p


def transaction_id(text: str) -> int:
    try:
        value = int(text, 0)
    except ValueError:
        value = -1
    if not 0 <= value <= 0xFFFF:
        raise argparse.ArgumentTypeError(f"{text!r} is not a transaction id (0..65535)")
    return value


def run(args: argparse.Namespace) -> int:
    from regmap.tools import frames
    from regmap.tools.selectors import Registers, parse_items
    from regmap_runtime.rtu import to_hex

    space = space_from(args)
    device = load_map(args.map)
    notes: list[str] = []
    if args.words and args.raw:
        raise UsageError("--words already means raw words; give one of --words and --raw")
    if args.confirm is not None and args.action != "command":
        raise UsageError(f"--confirm names a destructive command: `frame {args.action}` sends none")
    if args.action != "read" and (args.start is not None or args.count is not None):
        raise UsageError(f"-r and -c name what to read: `frame {args.action}` takes neither")
    if args.action == "read":
        items = parse_items(args.items, count=args.count, start=args.start, modicon=args.modicon, space=space)
        if args.words:
            reads = frames.word_reads(device, items, space, modicon=args.modicon)
            built = frames.word_read_frames(device, reads, args.slave)
            notes = [r.note for r in reads if r.note]
        else:
            regs = Registers(device, space, modicon=args.modicon)
            built = frames.read_frames(device, regs, items, args.slave)
            notes = regs.notes
    elif args.action == "write":
        if args.words:
            writes = frames.parse_word_writes(args.items, space, modicon=args.modicon)
            built = frames.word_write_frames(device, writes, args.slave)
            notes = [w.located for w in writes if w.located]
        else:
            built, notes = frames.write_frames(
                device,
                args.items,
                args.slave,
                args.raw,
                replace=args.replace,
                word_order=args.word_order,
                space=space,
                modicon=args.modicon,
            )
    elif args.action == "command":
        if not 1 <= len(args.items) <= 2:
            raise UsageError("command wants NAME [ARGUMENT]")
        built = frames.command_frames(
            device, args.items[0], args.items[1] if len(args.items) == 2 else None, args.slave, args.word_order, args.confirm
        )
    else:
        built, notes = _other_function(frames, device, args)
    if args.transaction != 1 and not args.mbap:
        raise UsageError("--transaction is an MBAP header's: give --mbap too")
    for number, frame in enumerate(built):
        print(to_hex(frames.mbap_adu(frame, args.transaction + number) if args.mbap else frame))
    say_notes("frame", notes)
    return ExitCode.OK


def _other_function(frames: Any, device: Any, args: argparse.Namespace) -> tuple[list[bytes], list[str]]:
    """echo, server-id, identification, mask, write-read."""
    items = list(args.items)
    if args.action in ("echo", "identification", "server-id"):
        most = 0 if args.action == "server-id" else 1
        if len(items) > most:
            raise UsageError(f"{args.action} takes {'no argument' if most == 0 else 'at most one argument'}, got {' '.join(items)}")
        if args.action == "echo":
            return [frames.echo_frame(device, args.slave, items[0] if items else None)], []
        if args.action == "server-id":
            return [frames.server_id_frame(device, args.slave)], []
        return [frames.identification_frame(device, args.slave, items[0] if items else None)], []
    if args.action == "mask":
        return frames.mask_frames(device, items, args.slave, words=args.words, modicon=args.modicon), []
    built, notes = frames.read_write_frame(
        device, items, args.slave, args.raw, words=args.words, modicon=args.modicon, word_order=args.word_order
    )
    return [built], notes
