"""`regmap simulate`: serve a map as the drive would (Modbus TCP, or RTU on a serial port or pty)."""

from __future__ import annotations

import argparse
import ipaddress
import sys
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING

from regmap.cli.common import add_map, baud_rate, count, examples, is_plant, load_map, load_plant, positive_count, seconds_or_zero, slave_id
from regmap.diagnostics import ExitCode, UsageError
from regmap.tools.link import serial_line
from regmap.tools.simulator.policy import DEFAULT_IDLE_TIMEOUT_S, DEFAULT_MAX_CONNECTIONS

if TYPE_CHECKING:
    from regmap.plant import Bus
    from regmap.tools.simulator import FaultPlan, Quirks
    from regmap.tools.simulator.policy import TcpPolicy
    from regmap.tools.simulator.run import Listening

HELP = "serve a simulated device (Modbus TCP or RTU on a serial port/pty)"
FAULT_HELP = "inject a fault: no_answer, bad_crc, truncated, exception, wrong_slave, wrong_function, delay"


def exception_code(text: str) -> int:
    try:
        code: int | None = int(text, 0)
    except ValueError:
        code = None
    if code is None or not 1 <= code <= 0xFF:
        shown = repr(text) if code is None else text
        raise argparse.ArgumentTypeError(f"{shown} is not a Modbus exception code (1..255, 0x01..0xFF)")
    return code


def read_limit(text: str) -> int:
    limit = count(text)
    if not 1 <= limit <= 125:
        raise argparse.ArgumentTypeError(f"{text} is outside 1..125")
    return limit


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> argparse.ArgumentParser:
    p = sub.add_parser(
        "simulate",
        help=HELP,
        description="Serve the map as the drive: its four tables (holding and input registers, coils, discrete inputs) with "
        "their defaults, word and byte order, limits, exception codes and bad-CRC behaviour (transport.bad_crc); its firmware "
        "(--firmware: the firmware register reports it, gated registers it lacks answer 0x02); commands act (save to the state "
        "file, factory reset, clear alarm); broadcast writes get no reply. Faults can be injected for client tests.",
        epilog=examples(
            "regmap simulate maps/idm_rs.yaml --tcp 127.0.0.1:5020 --state drive.json",
            "regmap simulate maps/c630s.yaml --serial /dev/pts/7",
            "regmap simulate maps/idm_rs.yaml --fault no_answer --fault-after 3 --fault-count 1",
            "regmap simulate maps/idm_rs.yaml --answer-gaps --max-read 20 --word-order low_first   # a drive unlike its map",
            "regmap simulate tests/maps/fixtures/power_meter.yaml --firmware 1.10 -v             # an older firmware, logged",
            "regmap simulate examples/plants/cell1.yaml --bus line1 --tcp 127.0.0.1:5020     # every drive of a plant's bus",
        ),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    add_map(p)
    where = p.add_mutually_exclusive_group()
    where.add_argument(
        "--tcp", metavar="HOST:PORT", help="listen on TCP (default 127.0.0.1:5020; a plant's bus at a loopback address: that address)"
    )
    where.add_argument("--serial", metavar="DEVICE", help="serve RTU on a serial device or pseudo-terminal")
    p.add_argument("--rtu-over-tcp", action="store_true", help="RTU framing on the TCP socket (serial gateways)")
    tcp = p.add_argument_group("Modbus TCP connections (with --tcp)")
    tcp.add_argument(
        "--gateway",
        action="store_true",
        help="play a TCP-to-serial gateway with the device behind it: unit 0 is a broadcast, other units answer 0x0B "
        "(default: the device is addressed by its IP address and also answers units 0xFF and 0)",
    )
    tcp.add_argument(
        "--idle-timeout",
        type=seconds_or_zero,
        default=DEFAULT_IDLE_TIMEOUT_S,
        metavar="S",
        help=f"close a connection that sends nothing for S seconds (default {DEFAULT_IDLE_TIMEOUT_S:g}; 0: never)",
    )
    tcp.add_argument(
        "--max-connections",
        type=positive_count,
        default=DEFAULT_MAX_CONNECTIONS,
        metavar="N",
        help=f"at most N connections; a new one closes the one idle the longest (default {DEFAULT_MAX_CONNECTIONS}, "
        "fewer if the descriptor limit is lower)",
    )
    line = p.add_argument_group("the serial line (with --serial; default: the map's)")
    line.add_argument("--baud", type=baud_rate, help="another of the baud rates the map lists")
    line.add_argument("--parity", choices=["none", "even", "odd"], help="override the map's parity (a pty may need none)")
    line.add_argument("--stop-bits", type=int, choices=[1, 2], help="override the map's stop bits")
    p.add_argument("--slave", type=slave_id, default=None, help="slave id (default 1; must be in the map's slave id range)")
    p.add_argument("--state", metavar="FILE", help="persist saved parameters here (atomic writes; its directory must exist)")
    plant = p.add_argument_group("a plant's bus (MAP is a plant file, docs/plants.md)")
    plant.add_argument(
        "--bus", metavar="NAME", help="serve every device of this bus on one port, each at its slave id (default: the only bus)"
    )
    plant.add_argument("--state-dir", metavar="DIR", help="persist each device's saved parameters in DIR/<device>.json (DIR must exist)")
    p.add_argument("--log", metavar="FILE", help="append every request and answer, decoded with the map's names, to FILE")
    p.add_argument("-v", "--verbose", action="store_true", help="print the request log on stderr")
    p.add_argument(
        "--rtu-gap",
        type=float,
        metavar="MS",
        help="silence that ends an RTU frame (default 3.5 characters at the baud; 20 ms on a pty, 50 ms over TCP)",
    )
    p.add_argument("--fault", default="none", metavar="KIND", help=FAULT_HELP)
    p.add_argument("--fault-count", type=positive_count, default=None, metavar="N", help="only the next N answers (default: all)")
    p.add_argument("--fault-after", type=count, default=0, metavar="N", help="answer N requests normally before the faults start")
    p.add_argument("--fault-delay", type=seconds_or_zero, default=2.0, metavar="S", help="seconds for --fault delay")
    p.add_argument("--fault-exception", type=exception_code, default=0x04, metavar="CODE", help="code for --fault exception (1..255)")
    quirks = p.add_argument_group("a drive that departs from its map (what `regmap probe` finds)")
    quirks.add_argument("--max-read", type=read_limit, metavar="N", help="take reads of at most N registers (1..125), not the map's limit")
    quirks.add_argument("--answer-gaps", action="store_true", help="answer reads over undocumented addresses (they read 0), not 0x02")
    quirks.add_argument(
        "--word-order",
        choices=["high_first", "low_first"],
        help="the drive's 32-bit word order at start-up (with a word-order register, as if that register were set to it)",
    )
    quirks.add_argument(
        "--firmware",
        metavar="VERSION",
        help="the drive's firmware version (2.10): the map's firmware register reports it, registers it lacks (their `firmware` "
        "gate) answer 0x02 (default: the firmware register's default, else the newest version the map's gates name)",
    )
    quirks.add_argument(
        "--variant",
        metavar="NAME",
        help="the model or option played (one of the map's device.variants): registers other variants have answer 0x02 "
        "(default: every register is present)",
    )
    return p


def _say_listening(at: Listening) -> None:
    print(f"regmap simulate: {at.model} (slave {at.slave}) on {at.where} ({at.framing}){at.playing}; Ctrl-C stops", flush=True)


def run(args: argparse.Namespace) -> int:
    from regmap.tools.simulator import FAULT_KINDS, FaultPlan, Quirks, run
    from regmap.tools.simulator.policy import TcpPolicy

    if args.fault not in FAULT_KINDS:
        raise UsageError(f"--fault must be one of {', '.join(FAULT_KINDS)}")
    if args.gateway and (args.serial or args.rtu_over_tcp):
        raise UsageError(
            "--gateway plays a Modbus TCP gateway: it takes neither --serial nor --rtu-over-tcp (RTU keeps the serial line's rules)"
        )
    if args.rtu_gap is not None and not 0 < args.rtu_gap <= 10000:
        raise UsageError(f"--rtu-gap {args.rtu_gap:g} ms is outside 0..10000 ms")
    try:
        quirks = Quirks(max_read=args.max_read, answer_gaps=args.answer_gaps, word_order=args.word_order, firmware=args.firmware)
    except ValueError as exc:
        raise UsageError(f"--max-read/--word-order: {exc}") from None
    faults = FaultPlan(
        kind=args.fault, count=args.fault_count, after=args.fault_after, delay_s=args.fault_delay, exception_code=args.fault_exception
    )
    policy = TcpPolicy(gateway=args.gateway, idle_timeout_s=args.idle_timeout or None, max_connections=args.max_connections)
    if is_plant(args.map):
        return _run_bus(args, faults, quirks, policy)
    if args.bus is not None or args.state_dir is not None:
        raise UsageError(f"--bus and --state-dir serve a plant's bus; {args.map} is a map")
    device = load_map(args.map)
    variants = [v.name for v in device.info.variants]
    if args.variant is not None and args.variant not in variants:
        raise UsageError(f"--variant {args.variant!r}: {device.id} declares {', '.join(variants) if variants else 'no variants'}")
    quirks = replace(quirks, variant=args.variant)
    line = serial_line(device, args.serial, args.baud, args.parity, args.stop_bits)
    served = run(
        device,
        tcp=args.tcp,
        serial=args.serial,
        line=line,
        slave=1 if args.slave is None else args.slave,
        state=Path(args.state) if args.state else None,
        faults=faults,
        rtu_over_tcp=args.rtu_over_tcp,
        log=Path(args.log) if args.log else None,
        echo=sys.stderr if args.verbose else None,
        rtu_gap_s=args.rtu_gap / 1000 if args.rtu_gap is not None else None,
        quirks=quirks,
        listening=_say_listening,
        tcp_policy=policy,
    )
    print(f"regmap simulate: stopped after {served}", flush=True)
    return ExitCode.OK


def _run_bus(args: argparse.Namespace, faults: FaultPlan, quirks: Quirks, policy: TcpPolicy) -> int:
    """`regmap simulate PLANT --bus NAME`: every device of the bus on one port."""
    from regmap.tools.link import Line
    from regmap.tools.simulator.run import run_bus

    per_device = [
        option
        for option, given in (
            ("--slave", args.slave is not None),
            ("--state", args.state is not None),
            ("--firmware", args.firmware is not None),
            ("--word-order", args.word_order is not None),
            ("--max-read", args.max_read is not None),
            ("--answer-gaps", args.answer_gaps),
            ("--variant", args.variant is not None),
        )
        if given
    ]
    if per_device:
        raise UsageError(
            f"{', '.join(per_device)}: one device's setting; a plant's bus takes its devices, slave ids and variants from the plant file"
        )
    plant = load_plant(args.map)
    if args.bus is None and len(plant.buses) > 1:
        raise UsageError(f"{args.map} has {len(plant.buses)} buses: name one with --bus ({', '.join(b.name for b in plant.buses)})")
    try:
        bus = plant.bus(args.bus) if args.bus is not None else plant.buses[0]
    except KeyError:
        raise UsageError(f"--bus {args.bus}: {args.map} has no such bus (buses: {', '.join(b.name for b in plant.buses)})") from None
    state_dir = Path(args.state_dir) if args.state_dir else None
    if state_dir is not None and not state_dir.is_dir():
        raise UsageError(f"--state-dir {state_dir}: not a directory")
    given = [
        option for option, value in (("--baud", args.baud), ("--parity", args.parity), ("--stop-bits", args.stop_bits)) if value is not None
    ]
    if given and args.serial is None:
        raise UsageError(f"{', '.join(given)}: a serial line's settings, given without --serial (a TCP gateway's line is set on it)")
    settings = bus.serial
    line = Line(
        args.baud or (settings.baud if settings else bus.devices[0].device.transport.baud),
        args.parity or (settings.parity if settings else "none"),
        args.stop_bits or (settings.stop_bits if settings else 1),
    )
    served = run_bus(
        bus,
        tcp=args.tcp or _bus_address(bus, args.serial is not None),
        serial=args.serial,
        line=line,
        state_dir=state_dir,
        faults=faults,
        rtu_over_tcp=args.rtu_over_tcp,
        log=Path(args.log) if args.log else None,
        echo=sys.stderr if args.verbose else None,
        rtu_gap_s=args.rtu_gap / 1000 if args.rtu_gap is not None else None,
        listening=_say_bus_listening,
        tcp_policy=policy,
    )
    print(f"regmap simulate: stopped after {served}", flush=True)
    return ExitCode.OK


def _bus_address(bus: Bus, serial: bool) -> str | None:
    """Where a plant's bus simulator listens when not told: the bus's own TCP address when it is this machine's
    (so `regmap read PLANT` talks to the simulator), else the default, with a word that the plant's clients
    talk to the real address, not to this simulator."""
    if serial or bus.tcp is None:
        return None
    host = bus.tcp.host
    try:
        local = ipaddress.ip_address(host).is_loopback
    except ValueError:
        local = host == "localhost"
    if local:
        return f"[{host}]:{bus.tcp.port}" if ":" in host else f"{host}:{bus.tcp.port}"
    print(
        f"regmap simulate: bus {bus.name} is at {host}:{bus.tcp.port} in the plant file: `regmap read/write PLANT` "
        f"talk to that address, not to this simulator (give --tcp to listen elsewhere)",
        file=sys.stderr,
        flush=True,
    )
    return None


def _say_bus_listening(at: Listening) -> None:
    print(f"regmap simulate: {at.model} on {at.where} ({at.framing}); Ctrl-C stops", flush=True)
