"""`regmap read`: registers from a drive, by name."""

from __future__ import annotations

import argparse

from regmap.cli.common import (
    SELECTOR_SYNTAX,
    WHERE,
    add_read_options,
    device_and_link,
    live_parser,
    output_format,
    profile_from,
    say_notes,
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
        f"text as text and bits as true/false.\n{SELECTOR_SYNTAX}; the same grammar as `regmap frame MAP read`. --words: "
        "ADDR [COUNT] reads COUNT 16-bit words (bits, in a bit space) at any address, documented or not.",
        f"regmap read maps/idm_rs.yaml peak_current Pr5.22 run_status {WHERE}",
        f"regmap read maps/idm_rs.yaml Pr5.22 3 {WHERE}          # three parameters from Pr5.22 on, one request",
        f"regmap read maps/idm_rs.yaml -r 402 -c 2 {WHERE}       # mbpoll's -r 402 -c 2: addresses 401 on",
        f"regmap read maps/c630s.yaml --words 0x0B11 2 {WHERE}   # two words, documented or not",
        "regmap read maps/c630s.yaml P05-02 --tcp 127.0.0.1:5020 --word-order high_first",
        "regmap read tests/maps/fixtures/remote_io.yaml 0x13 -t 0 --json --tcp 127.0.0.1:5020     # the coil at 0x0013",
    )
    p.add_argument("selectors", nargs="*", metavar="SELECTOR [COUNT]")
    p.add_argument(
        "--words", action="store_true", help="ADDR [COUNT]: 16-bit words (bits, in a bit space) at any address, documented or not"
    )
    add_read_options(p)
    return p


def run(args: argparse.Namespace) -> int:
    from regmap.cli.live_output import print_values, print_words, read_status
    from regmap.diagnostics import ExitCode, LinkError
    from regmap.tools import live
    from regmap.tools.frames import word_reads
    from regmap.tools.selectors import parse_items

    space = space_from(args)
    items = parse_items(args.selectors, count=args.count, start=args.start, modicon=args.modicon, space=space)
    device, link = device_and_link(args)
    profile = profile_from(args, device)
    if args.words:
        got = live.read_words(device, link, word_reads(device, items, space, modicon=args.modicon), profile)
        print_words(got.words, output_format(args))
        say_notes("read", got.notes)
        if got.error is not None:
            raise LinkError(f"the bus failed after {len(got.words)} word(s) were read: {got.error}")
        return ExitCode.OK
    result = live.read(device, link, items, profile, space, modicon=args.modicon)
    print_values(result.values, output_format(args))
    say_notes("read", result.notes)
    return read_status(result, "read")
