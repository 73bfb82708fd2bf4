"""The `regmap` command line. Thin: parse arguments, call the front end and a back end, report."""

from __future__ import annotations

import argparse
import json
import logging
import os
import sys
import traceback
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from regmap import __version__
from regmap.diagnostics import LinkError, MapError, UsageError
from regmap.frontend import load_map
from regmap.model import Device

DEFAULT_MAPS_DIR = Path("maps")


def _maps(paths: Sequence[str]) -> list[Path]:
    if paths:
        return [Path(p) for p in paths]
    found = sorted(DEFAULT_MAPS_DIR.glob("*.yaml"))
    if not found:
        raise UsageError(f"no maps given and none found in {DEFAULT_MAPS_DIR}/")
    return found


def load_all(paths: Sequence[str]) -> list[Device]:
    """Load every map, reporting the problems of all of them before failing."""
    devices, errors = [], []
    for path in _maps(paths):
        try:
            devices.append(load_map(path))
        except MapError as exc:
            errors.extend(exc.diagnostics)
    if errors:
        raise MapError(errors)
    seen: dict[str, str] = {}
    for device in devices:
        if device.id in seen:
            raise UsageError(
                f"{device.source_path} and {seen[device.id]} both have device id {device.id!r}; their generated files would overwrite each other"
            )
        seen[device.id] = device.source_path
    return devices


def cmd_validate(args: argparse.Namespace) -> int:
    status = 0
    for path in _maps(args.maps):
        try:
            device = load_map(path)
        except MapError as exc:
            for diag in exc.diagnostics:
                print(diag, file=sys.stderr)
            status = 1
            continue
        arrays = device.arrays
        name = " ".join(f"{device.info.vendor} {device.info.model}".split())  # map text stays on one line
        print(
            f"{path}: ok: {name} map {device.info.map_version}, "
            f"{len(device.registers)} registers ({len(arrays)} arrays), {len(device.enums)} enums, "
            f"{len(device.commands)} commands, {len(device.examples)} examples, {len(device.errata)} errata"
        )
    return status


def cmd_export(args: argparse.Namespace) -> int:
    from regmap.backends.export import export_json

    device = load_map(args.map)
    json.dump(export_json(device), sys.stdout, ensure_ascii=False, indent=2)
    sys.stdout.write("\n")
    return 0


def cmd_generate(args: argparse.Namespace) -> int:
    from regmap.diff import changelog_pages, write_pages
    from regmap.generate import generate, target_names

    targets = args.target or target_names()
    devices = load_all(args.maps)
    pages = changelog_pages(devices, args.since, targets) if args.since else {}  # first: a bad revision writes nothing
    written = generate(devices, Path(args.out), targets, complete=not args.maps)
    written += write_pages(Path(args.out), pages)
    print(f"regmap generate: {len(written)} files for {len(devices)} map(s), targets {', '.join(targets)} -> {args.out}/")
    return 0


def cmd_simulate(args: argparse.Namespace) -> int:
    from regmap.simulator import FAULT_KINDS, FaultPlan, run

    if args.tcp and args.serial:
        raise UsageError("give --tcp or --serial, not both")
    if args.fault not in FAULT_KINDS:
        raise UsageError(f"--fault must be one of {', '.join(FAULT_KINDS)}")
    if args.rtu_gap is not None and not 0 < args.rtu_gap <= 10000:
        raise UsageError(f"--rtu-gap {args.rtu_gap:g} ms is outside 0..10000 ms")
    device = load_map(args.map)
    faults = FaultPlan(
        kind=args.fault, count=args.fault_count, after=args.fault_after, delay_s=args.fault_delay, exception_code=args.fault_exception
    )
    return run(
        device,
        tcp=args.tcp,
        serial=args.serial,
        slave=args.slave,
        state=Path(args.state) if args.state else None,
        faults=faults,
        rtu_over_tcp=args.rtu_over_tcp,
        log=Path(args.log) if args.log else None,
        verbose=args.verbose,
        rtu_gap_s=args.rtu_gap / 1000 if args.rtu_gap is not None else None,
    )


def cmd_frame(args: argparse.Namespace) -> int:
    from regmap import frames
    from regmap_runtime.rtu import to_hex

    device = load_map(args.map)
    if args.action == "read":
        if not 1 <= len(args.items) <= 2:
            raise UsageError("read wants SELECTOR [COUNT]")
        count = frames.parse_int(args.items[1], "COUNT") if len(args.items) == 2 else None
        if count is not None and not 1 <= count <= 125:
            raise UsageError(f"COUNT {count} is outside 1..125")
        built = frames.read_frames(device, args.items[0], count, args.slave)
    elif args.action == "write":
        if not args.items:
            raise UsageError("write wants SELECTOR=VALUE [SELECTOR=VALUE ...]")
        built = frames.write_frames(device, args.items, args.slave, args.raw)
    else:
        if not 1 <= len(args.items) <= 2:
            raise UsageError("command wants NAME [ARGUMENT]")
        built = frames.command_frames(device, args.items[0], args.items[1] if len(args.items) == 2 else None, args.slave)
    for frame in built:
        print(to_hex(frame))
    return 0


def cmd_decode(args: argparse.Namespace) -> int:
    from regmap import frames
    from regmap_runtime.rtu import FrameError, parse_frame, parse_hex

    device = load_map(args.map)
    if args.file:
        if args.hex:
            raise UsageError("give HEX or --file, not both")
        try:
            with open(args.file, encoding="utf-8") as handle:
                lines = handle.read().splitlines()
        except (OSError, UnicodeDecodeError) as exc:
            raise UsageError(f"cannot read {args.file}: {exc}") from None
        decoded = frames.decode_capture(device, lines, args.file)
    else:
        if not args.hex:
            raise UsageError("give the frame as HEX (one argument or several) or --file CAPTURE")
        try:
            frame = parse_hex(" ".join(args.hex))
            request = parse_frame(parse_hex(args.request), "request") if args.request else None
        except FrameError as exc:
            raise UsageError(str(exc)) from None
        direction = "response" if request is not None else args.direction
        decoded = [frames.decode_frame(device, frame, direction=direction, request=request)]
    if args.json:
        json.dump([d.as_json() for d in decoded], sys.stdout, ensure_ascii=False, indent=2)
        sys.stdout.write("\n")
    else:
        print("\n".join(frames.render_text(d) for d in decoded))
    return 0 if all(d.frame.crc_valid for d in decoded) else 3


def _link(args: argparse.Namespace) -> Any:
    from regmap.live import Link

    return Link(
        tcp=args.tcp,
        serial=args.serial,
        slave=args.slave,
        baud=args.baud,
        parity=args.parity,
        stop_bits=args.stop_bits,
        timeout=args.timeout,
        retries=args.retries,
        rtu_over_tcp=args.rtu_over_tcp,
    )


def cmd_read(args: argparse.Namespace) -> int:
    from regmap import live

    return live.cmd_read(load_map(args.map), _link(args), args.selectors, args.json)


def cmd_write(args: argparse.Namespace) -> int:
    from regmap import live

    return live.cmd_write(load_map(args.map), _link(args), args.assignments, args.raw, not args.no_verify)


def cmd_dump(args: argparse.Namespace) -> int:
    from regmap import live

    output = "json" if args.json else "csv" if args.csv else "text"
    return live.cmd_dump(load_map(args.map), _link(args), output)


def _add_link_options(p: argparse.ArgumentParser) -> None:
    where = p.add_mutually_exclusive_group()
    where.add_argument("--serial", metavar="DEVICE", help="serial port (RTU); settings default to the map's")
    where.add_argument("--tcp", metavar="HOST:PORT", help="Modbus TCP gateway or simulator")
    p.add_argument("--rtu-over-tcp", action="store_true", help="RTU framing on the TCP connection")
    p.add_argument("--slave", type=int, default=1, help="slave id (default 1)")
    p.add_argument("--baud", type=int, help="override the map's default baud rate")
    p.add_argument("--parity", choices=["none", "even", "odd"], help="override the map's parity")
    p.add_argument("--stop-bits", type=int, choices=[1, 2], help="override the map's stop bits")
    p.add_argument("--timeout", type=float, default=1.0, help="seconds to wait for an answer (default 1)")
    p.add_argument("--retries", type=int, default=2, help="retries after a timeout (default 2)")


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="regmap", description="Declarative Modbus RTU register maps for motor drives.")
    parser.add_argument("--version", action="version", version=f"regmap {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    p = sub.add_parser("validate", help="check maps against the schema and the semantic rules")
    p.add_argument("maps", nargs="*", metavar="MAP", help="map files (default: every maps/*.yaml)")
    p.set_defaults(func=cmd_validate)

    p = sub.add_parser("export", help="print the elaborated model of a map as JSON")
    p.add_argument("map", metavar="MAP")
    p.add_argument("--format", choices=["json"], default="json")
    p.set_defaults(func=cmd_export)
    p = sub.add_parser("generate", help="generate Python clients, C headers and docs from maps")
    p.add_argument("maps", nargs="*", metavar="MAP", help="map files (default: every maps/*.yaml)")
    p.add_argument("--out", default="generated", metavar="DIR", help="output directory (default: generated)")
    p.add_argument("--target", action="append", choices=_target_choices(), help="only this target (repeatable)")
    p.add_argument("--since", metavar="GITREV", help="also write docs/<device>-changelog.md: `regmap diff` of each map against GITREV")
    p.set_defaults(func=cmd_generate)

    p = sub.add_parser(
        "frame",
        help="print a request frame as hex bytes",
        description="Build the request frame a master sends. SELECTOR is a register name, the manual's parameter id (Pr5.00, P05-02, 0302) or an address (0x0191, 401). VALUE is in engineering units or an enum member name; --raw takes raw integers (and lets you write any address: ADDR=W1,W2,...).",
    )
    p.add_argument("map", metavar="MAP")
    p.add_argument("action", choices=["read", "write", "command"])
    p.add_argument("items", nargs="*", metavar="ARG", help="read: SELECTOR [COUNT]; write: SELECTOR=VALUE ...; command: NAME [ARGUMENT]")
    p.add_argument("--slave", type=int, default=1, help="slave id (default 1)")
    p.add_argument("--raw", action="store_true", help="values are raw register integers")
    p.set_defaults(func=cmd_frame)

    p = sub.add_parser(
        "decode",
        help="decode a frame or a capture log",
        description="Decode RTU frames: function, registers, raw and engineering values, enums, bitfields, CRC and exceptions. Exit status 3 when a CRC does not match.",
    )
    p.add_argument("map", metavar="MAP")
    p.add_argument("hex", nargs="*", metavar="HEX", help="the frame, as one argument or one per byte")
    p.add_argument(
        "--file",
        metavar="CAPTURE",
        help="a log of frames, one per line (optional TX/RX prefix); responses pair with the request before them",
    )
    p.add_argument("--request", metavar="HEX", help="the request a response answers (names the registers of a read response)")
    p.add_argument("--direction", choices=["request", "response"], help="settle frames that read alike both ways")
    p.add_argument("--json", action="store_true", help="machine-readable output")
    p.set_defaults(func=cmd_decode)

    p = sub.add_parser(
        "read",
        help="read registers from a drive",
        description="Read registers by name, manual parameter id or address; values shown with units, enum names and bitfields.",
    )
    p.add_argument("map", metavar="MAP")
    p.add_argument("selectors", nargs="+", metavar="SELECTOR")
    p.add_argument("--json", action="store_true", help="machine-readable output")
    _add_link_options(p)
    p.set_defaults(func=cmd_read)

    p = sub.add_parser(
        "write",
        help="write registers, then read them back",
        description="Values are checked against range, enum and access before anything is sent, then read back and confirmed.",
    )
    p.add_argument("map", metavar="MAP")
    p.add_argument("assignments", nargs="+", metavar="SELECTOR=VALUE")
    p.add_argument("--raw", action="store_true", help="values are raw register integers")
    p.add_argument("--no-verify", action="store_true", help="skip the read-back")
    _add_link_options(p)
    p.set_defaults(func=cmd_write)

    p = sub.add_parser("dump", help="read every readable register with the read plan")
    p.add_argument("map", metavar="MAP")
    fmt = p.add_mutually_exclusive_group()
    fmt.add_argument("--json", action="store_true", help="JSON output")
    fmt.add_argument("--csv", action="store_true", help="CSV output")
    _add_link_options(p)
    p.set_defaults(func=cmd_dump)

    p = sub.add_parser(
        "simulate",
        help="serve a simulated device (Modbus TCP or RTU on a serial port/pty)",
        description="Serve MAP as the device would: its limits, exception codes and bad-CRC behaviour (transport.bad_crc).",
    )
    p.add_argument("map", metavar="MAP")
    where = p.add_mutually_exclusive_group()
    where.add_argument("--tcp", metavar="HOST:PORT", help="listen on TCP (default 127.0.0.1:5020)")
    where.add_argument("--serial", metavar="DEVICE", help="serve RTU on a serial device or pseudo-terminal")
    p.add_argument("--rtu-over-tcp", action="store_true", help="RTU framing on the TCP socket (serial gateways)")
    p.add_argument("--slave", type=int, default=1, help="slave id (default 1; must be in the map's slave id range)")
    p.add_argument("--state", metavar="FILE", help="persist saved parameters here (atomic writes; its directory must exist)")
    p.add_argument("--log", metavar="FILE", help="append every request and answer, decoded with the map's names, to FILE")
    p.add_argument("-v", "--verbose", action="store_true", help="print the request log on stderr")
    p.add_argument(
        "--rtu-gap",
        type=float,
        metavar="MS",
        help="silence that ends an RTU frame (default 3.5 characters at the baud; 20 ms on a pty, 50 ms over TCP)",
    )
    p.add_argument(
        "--fault",
        default="none",
        metavar="KIND",
        help="inject a fault: no_answer, bad_crc, truncated, exception, wrong_slave, wrong_function, delay",
    )
    p.add_argument("--fault-count", type=int, default=None, metavar="N", help="only the next N answers (default: all)")
    p.add_argument("--fault-after", type=int, default=0, metavar="N", help="answer N requests normally before the faults start")
    p.add_argument("--fault-delay", type=float, default=2.0, metavar="S", help="seconds for --fault delay")
    p.add_argument("--fault-exception", type=lambda v: int(v, 0), default=0x04, metavar="CODE", help="code for --fault exception")
    p.set_defaults(func=cmd_simulate)

    p = sub.add_parser(
        "diff",
        help="what changed between two versions of a map, what it breaks, and the version bump it needs",
        description="Compare two maps: registers are matched by name, then parameter id, then address, so a rename or a move is one change. Each change is breaking or compatible; the report suggests the map_version bump.",
        epilog="OLD and NEW are map files; PATH@GITREV reads the map at a git revision (maps/idm_rs.yaml@HEAD~1). " + _diff_exit_help(),
    )
    p.add_argument("old", metavar="OLD", help="the earlier map: PATH or PATH@GITREV")
    p.add_argument("new", metavar="NEW", help="the later map: PATH or PATH@GITREV")
    p.add_argument("--format", choices=["text", "markdown", "json"], default="text", help="text (default), markdown (a changelog) or json")
    p.set_defaults(func=cmd_diff)

    return parser


def _diff_exit_help() -> str:
    from regmap.diff import EXIT_HELP

    return EXIT_HELP


def cmd_diff(args: argparse.Namespace) -> int:
    from regmap import diff

    report = diff.compare(diff.load_spec(args.old), diff.load_spec(args.new))
    sys.stdout.write(diff.render(report, args.format))
    return report.exit_status


def _target_choices() -> list[str]:
    from regmap.generate import target_names

    return target_names()


def main(argv: Sequence[str] | None = None) -> int:
    # pymodbus logs transport trouble itself; regmap reports it once, as one line of its own.
    logging.getLogger("pymodbus").setLevel(logging.CRITICAL)
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        result: int = args.func(args)
        return result
    except MapError as exc:
        for diag in exc.diagnostics:
            print(diag, file=sys.stderr)
        return 1
    except UsageError as exc:
        print(f"regmap {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except LinkError as exc:
        print(f"regmap {args.command}: bus error: {exc}", file=sys.stderr)
        return 4
    except KeyboardInterrupt:
        print("regmap: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        return 0
    except Exception as exc:  # a bug in regmap, not bad input: one line unless asked for more
        if os.environ.get("REGMAP_DEBUG"):
            traceback.print_exc()
        print(f"regmap {args.command}: internal error: {type(exc).__name__}: {exc} (set REGMAP_DEBUG=1 for the traceback)", file=sys.stderr)
        return 70
