"""`regmap decode`: a frame or a capture log, named with the map's registers."""

from __future__ import annotations

import argparse
import json
import sys

from regmap.cli.common import add_map, add_word_order, examples, load_map
from regmap.diagnostics import ExitCode, UsageError

HELP = "decode a frame or a capture log"


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> argparse.ArgumentParser:
    p = sub.add_parser(
        "decode",
        help=HELP,
        description=(
            "Decode RTU frames: function, registers, raw and engineering values, enums, bitfields, CRC and exceptions. Every "
            "frame is read in its function's data space (0x03 holding, 0x04 input registers, 0x01/0x05/0x0F coils, 0x02 "
            "discrete inputs: bit by bit, the padding of a response checked); floats, 64-bit values and text by the map's types.\n"
            "A capture (--file, - for stdin) has one frame per line, optionally after a timestamp and a TX/RX tag "
            "(`12:00:00.001 TX: 01 03 ...`, `[2024-05-01 12:00:00.001] RX:`, `TX> ...`), mbpoll -v's `[01][03]...` (sent) and "
            "`<01><03>...` (received), or pymodbus's `send: 0x1 0x3 ...`/`recv:`/`Processing:`; # starts a comment; a response pairs with the request before it. UTF-8 or UTF-16 with a BOM; "
            "a binary file is refused.\n"
            "Exit status 3 when a frame (or its --request) has a CRC mismatch or another problem, a line is not a frame, or a "
            "capture holds no frame; --json then lists the bad lines with an error member."
        ),
        epilog=examples(
            'regmap decode maps/idm_rs.yaml 01 03 02 00 16 39 8A --request "01 03 01 91 00 01 D4 1B"',
            "regmap decode maps/idm_rs.yaml --file examples/capture.log --json",
            "cat examples/capture.log | regmap decode maps/idm_rs.yaml --file -",
            'regmap decode tests/maps/fixtures/remote_io.yaml 01 01 03 CD 6B 05 42 82 --request "01 01 00 13 00 13 8C 02"',
            'regmap decode tests/maps/fixtures/power_meter.yaml --mbap 00 01 00 00 00 05 01 17 02 00 07 --request "00 01 00 00 00 0D 01 17 01 20 00 01 01 20 00 01 02 00 07"',
        ),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    add_map(p)
    p.add_argument("hex", nargs="*", metavar="HEX", help="the frame, as one argument or one per byte")
    p.add_argument("--file", metavar="CAPTURE", help="a log of frames, one per line; - reads standard input")
    p.add_argument("--request", metavar="HEX", help="the request a response answers (names the registers of a read response)")
    p.add_argument("--direction", choices=["request", "response"], help="settle frames that read alike both ways")
    p.add_argument("--mbap", action="store_true", help="HEX (and --request) are Modbus TCP ADUs: MBAP header and PDU, no CRC")
    p.add_argument("--json", action="store_true", help="machine-readable output")
    add_word_order(p, live=False)
    return p


def _capture_bytes(name: str) -> bytes:
    try:
        if name == "-":
            return sys.stdin.buffer.read()
        with open(name, "rb") as handle:
            return handle.read()
    except OSError as exc:
        raise UsageError(f"cannot read {name}: {exc.strerror or exc}") from None


def run(args: argparse.Namespace) -> int:
    from regmap.tools import decode
    from regmap_runtime.rtu import FrameError, parse_hex

    device = load_map(args.map)
    entries: list[decode.Decoded | decode.CaptureError]
    if args.file:
        if args.hex:
            raise UsageError("give HEX or --file, not both")
        if args.request:
            raise UsageError("--request goes with one HEX frame; a capture pairs each response with the request before it")
        if args.mbap:
            raise UsageError("--mbap decodes one HEX ADU; a capture holds RTU frames")
        lines = decode.capture_lines(_capture_bytes(args.file), args.file)
        result = decode.decode_capture(device, lines, args.file, word_order=args.word_order)
        entries, decoded, errors = result.entries(), result.frames, result.errors
    else:
        if not args.hex:
            raise UsageError("give the frame as HEX (one argument or several) or --file CAPTURE")
        try:
            frame = parse_hex(" ".join(args.hex))
            request = parse_hex(args.request) if args.request else None
        except FrameError as exc:
            raise UsageError(str(exc)) from None
        if args.mbap:
            one = decode.decode_mbap(device, frame, direction=args.direction, request=request, word_order=args.word_order)
        elif request is not None:
            one = decode.decode_answer(device, frame, request, word_order=args.word_order)
        else:
            one = decode.decode_frame(device, frame, direction=args.direction, word_order=args.word_order)
        entries, decoded, errors = [one], [one], []
    if args.json:
        json.dump([entry.as_json() for entry in entries], sys.stdout, ensure_ascii=False, indent=2)
        sys.stdout.write("\n")
    elif decoded:
        print("\n".join(decode.render_text(d) for d in decoded))
    for error in errors:
        print(f"regmap decode: {error}", file=sys.stderr)
    return ExitCode.OK if all(d.ok for d in decoded) and not errors else ExitCode.BAD_FRAME
