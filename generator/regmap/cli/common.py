"""What several subcommands share: loading maps, the bus options, argument types."""

from __future__ import annotations

import argparse
import dataclasses
import math
import sys
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from regmap.diagnostics import MapError, UsageError

if TYPE_CHECKING:
    from regmap.model import Device
    from regmap.plant import Plant
    from regmap.tools.link import Link

DEFAULT_MAPS_DIR = Path("maps")
VALUE_SYNTAX = (
    "VALUE is in engineering units (1.5 for 1.5 A), an enum member name (save_all_parameters), text for a string register "
    '(label=abc, or label="two words"), on/off (true/false, 1/0) for a coil, or for a bitfield register '
    "field:value,field:value (function:path_address_0,normally_closed:1), optionally after a base word (0x00A8,function:ctrg)"
)

SELECTOR_SYNTAX = (
    "SELECTOR is a register name, the manual's parameter id (Pr5.00, P05-02, 0302) or a register's 0-based protocol address "
    "(0x0191, 0191h, 401; mbpoll's -r 402, Modicon's 40402 with --modicon); a plain decimal number right after a SELECTOR "
    "is its COUNT: that many of the map's readable registers from it on (with --words: words), as mbpoll's -c"
)


def say_notes(command: str, notes: Iterable[str]) -> None:
    """How addresses were read (-r, Modicon numbers) and other notes the tools return, each once, on stderr."""
    for note in dict.fromkeys(notes):
        print(f"regmap {command}: note: {note}", file=sys.stderr)


def load_map(path: str | Path) -> Device:
    """The front end, imported when a command needs a map (so `--help` and argument errors stay fast)."""
    from regmap.frontend import load_map as front_end

    if is_plant(path):
        raise UsageError(
            f"{path} is a plant file, not a map: give one of its maps, or pick a device with --bus NAME --device NAME "
            "(read, write, command, dump, probe)"
        )
    return front_end(path)


def load_plant(path: str | Path) -> Plant:
    """A plant file and every map it names (imported when a command needs it)."""
    from regmap.frontend.plant import load_plant as front_end

    return front_end(path)


def is_plant(path: str | Path) -> bool:
    from regmap.frontend.plantfile import is_plant_file

    return is_plant_file(path)


def plant_argument(paths: Sequence[str]) -> str | None:
    """The plant file among a command's MAP arguments, if one is given: a plant comes alone."""
    plants = [p for p in paths if is_plant(p)]
    if plants and len(paths) > 1:
        raise UsageError(f"a plant file ({plants[0]}) comes alone, without other maps or plants")
    return plants[0] if plants else None


def map_paths(paths: Sequence[str]) -> list[Path]:
    if paths:
        return [Path(p) for p in paths]
    found = sorted(DEFAULT_MAPS_DIR.glob("*.yaml"))
    if not found:
        raise UsageError(f"no maps given and none found in {DEFAULT_MAPS_DIR}/")
    return found


def load_all(paths: Sequence[str]) -> list[Device]:
    """Load every map, reporting the problems of all of them before failing."""
    devices, errors = [], []
    for path in map_paths(paths):
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


def _positive(text: str, unit: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number of {unit}") from None
    if not 0 < value < math.inf:
        raise argparse.ArgumentTypeError(f"{text} must be a positive number of {unit}")
    return value


def positive_float(text: str) -> float:
    return _positive(text, "seconds")


def requests_per_second(text: str) -> float:
    return _positive(text, "requests per second")


def seconds_or_zero(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not 0 <= value < math.inf:
        raise argparse.ArgumentTypeError(f"{text} is not a number of seconds, 0 or more")
    return value


def count(text: str) -> int:
    try:
        value = int(text, 0)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a whole number") from None
    if value < 0:
        raise argparse.ArgumentTypeError(f"{text} must be 0 or more")
    return value


def positive_count(text: str) -> int:
    value = count(text)
    if value == 0:
        raise argparse.ArgumentTypeError(f"{text} must be 1 or more")
    return value


def baud_rate(text: str) -> int:
    """A baud rate as mbpoll's -b takes it: decimal, positive (whether the map's drive talks at it: `tools.link.serial_line`)."""
    if not (text.isascii() and text.isdigit()) or int(text) == 0:
        raise argparse.ArgumentTypeError(f"{text} is not a baud rate (a positive whole number: 9600, 38400 ...)")
    return int(text)


def slave_id(text: str) -> int:
    try:
        value = int(text, 0)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a slave id") from None
    if not 0 <= value <= 255:
        raise argparse.ArgumentTypeError(f"{text} is outside 0..255")
    return value


def add_map(p: argparse.ArgumentParser) -> None:
    p.add_argument("map", metavar="MAP", help="the device's map (maps/idm_rs.yaml)")


def add_word_order(p: Any, *, live: bool) -> None:
    choices = ["auto", "high_first", "low_first"] if live else ["high_first", "low_first"]
    p.add_argument(
        "--word-order",
        choices=choices,
        help=(
            "word order of 32-bit values on a drive whose map has a word-order register (C630S P0C-26): "
            + ("auto (the default) reads that register first" if live else "the drive's setting, when it is not the map's default")
        ),
    )


SPACE_HELP = (
    "data space of --words addresses and of address selectors: holding, input, coil, discrete_input, or mbpoll's -t numbers "
    "4, 3, 0, 1 (default: holding for --words; for an address, the one space that lists a register there)"
)


def add_space(p: Any) -> None:
    p.add_argument("-t", "--space", metavar="SPACE", help=SPACE_HELP)


MODICON_HELP = (
    "decimal addresses are Modicon reference numbers, which name the space and count from 1: 0xxxx coils, 1xxxx discrete "
    "inputs, 3xxxx input registers, 4xxxx holding registers (40402 and 400402 are holding register 401); hex ones stay addresses"
)


def add_addressing(p: Any, *, start: bool) -> None:
    """--modicon, and where a command reads from a start: mbpoll's -r (1-based start reference) and -c (count)."""
    if start:
        p.add_argument("-r", dest="start", metavar="REF", help="mbpoll's -r: the start reference, counting from 1 (-r 402 is address 401)")
        p.add_argument(
            "-c", dest="count", metavar="N", help="mbpoll's -c: how many from the start (registers of the map; with --words, words)"
        )
    p.add_argument("--modicon", action="store_true", help=MODICON_HELP)


def space_from(args: argparse.Namespace) -> str | None:
    """The data space -t/--space names (checked: a one-line error for a wrong one), or None."""
    from regmap.tools.selectors import parse_space

    return parse_space(args.space) if args.space is not None else None


def add_link_options(p: argparse.ArgumentParser) -> None:
    where = p.add_argument_group("where the drive is (one of)").add_mutually_exclusive_group()
    where.add_argument("--serial", metavar="DEVICE", help="serial port (RTU); settings default to the map's")
    where.add_argument("--tcp", metavar="HOST:PORT", help="Modbus TCP gateway or simulator")
    bus = p.add_argument_group("bus settings")
    bus.add_argument("--rtu-over-tcp", action="store_true", help="RTU framing on the TCP connection (transparent serial servers)")
    bus.add_argument("--slave", type=slave_id, help="slave id (default 1; a plant's device: its slave id in the plant)")
    bus.add_argument("--baud", type=baud_rate, help="override the map's default baud rate")
    bus.add_argument("--parity", choices=["none", "even", "odd"], help="override the map's parity")
    bus.add_argument("--stop-bits", type=int, choices=[1, 2], help="override the map's stop bits")
    bus.add_argument("--timeout", type=positive_float, default=1.0, help="seconds to wait for an answer (default 1)")
    bus.add_argument(
        "--retries",
        type=count,
        default=2,
        help="retries of a read or a setting after a lost answer (default 2); commands and trigger writes go out once",
    )
    add_word_order(bus, live=True)


def link_from(args: argparse.Namespace) -> Link:
    from regmap.tools.link import Link  # here: generate, validate and the other commands without a bus skip it

    return Link(
        tcp=args.tcp,
        serial=args.serial,
        slave=1 if args.slave is None else args.slave,
        baud=args.baud,
        parity=args.parity,
        stop_bits=args.stop_bits,
        timeout=args.timeout,
        retries=args.retries,
        rtu_over_tcp=args.rtu_over_tcp,
        word_order=args.word_order,
        variant=getattr(args, "variant", None),
    )


def add_plant_device(p: argparse.ArgumentParser) -> None:
    """--bus and --device: MAP may be a plant file, and the command then talks to one of its devices."""
    plant = p.add_argument_group("a device of a plant (MAP is a plant file, docs/plants.md)")
    plant.add_argument("--bus", metavar="NAME", help="the plant's bus: its line settings unless --serial/--tcp/--baud/... override them")
    plant.add_argument("--device", metavar="NAME", help="the device on that bus: its map and its slave id (unless --slave overrides it)")


def device_and_link(args: argparse.Namespace) -> tuple[Device, Link]:
    """The device and the link a command talks to: MAP's and the options', or, for a plant file, the map and the
    slave id of --device and the line settings of --bus, each overridable on the command line."""
    if not is_plant(args.map):
        if args.bus is not None or args.device is not None:
            raise UsageError(f"--bus and --device pick a device of a plant file; {args.map} is a map")
        return load_map(args.map), link_from(args)
    if args.bus is None or args.device is None:
        raise UsageError(f"{args.map} is a plant file: name the device with --bus NAME --device NAME")
    plant = load_plant(args.map)
    try:
        bus = plant.bus(args.bus)
    except KeyError:
        raise UsageError(f"--bus {args.bus}: {args.map} has no such bus (buses: {', '.join(b.name for b in plant.buses)})") from None
    try:
        member = bus.device(args.device)
    except KeyError:
        raise UsageError(
            f"--device {args.device}: bus {bus.name} has no such device (devices: {', '.join(d.name for d in bus.devices)})"
        ) from None
    link = link_from(args)
    given = link.serial is not None or link.tcp is not None
    serial, tcp = link.serial, link.tcp
    baud, parity, stop_bits = link.baud, link.parity, link.stop_bits
    if bus.serial is not None and tcp is None:  # a --tcp gateway in front of the line has its own serial settings
        serial = serial if given else bus.serial.port
        baud = bus.serial.baud if baud is None else baud
        parity = bus.serial.parity if parity is None else parity
        stop_bits = bus.serial.stop_bits if stop_bits is None else stop_bits
    elif bus.tcp is not None and not given:
        tcp = f"{bus.tcp.host}:{bus.tcp.port}"
    slave = member.slave if args.slave is None else args.slave
    if link.variant is not None and member.variant is not None and link.variant != member.variant:
        raise UsageError(f"--variant {link.variant}: the plant says {member.name} is {member.variant}")
    variant = link.variant or member.variant
    return member.device, dataclasses.replace(
        link, serial=serial, tcp=tcp, slave=slave, baud=baud, parity=parity, stop_bits=stop_bits, variant=variant
    )


def examples(*lines: str) -> str:
    return "examples:\n" + "\n".join(f"  {line}" for line in lines)


WHERE = "--serial /dev/ttyUSB0"


def live_parser(
    sub: argparse._SubParsersAction[argparse.ArgumentParser],
    name: str,
    help: str,
    description: str,
    *example: str,
    variant: bool = True,
) -> argparse.ArgumentParser:
    p = sub.add_parser(
        name, help=help, description=description, epilog=examples(*example), formatter_class=argparse.RawDescriptionHelpFormatter
    )
    add_map(p)
    add_link_options(p)
    add_plant_device(p)
    if variant:  # the probe finds the variant out instead
        p.add_argument(
            "--variant",
            metavar="NAME",
            help="the device's model or option (one of the map's device.variants; a plant device: the plant's): "
            "a register it lacks is refused, nothing sent, and left out of dump",
        )
    return p


def add_output(p: argparse.ArgumentParser) -> None:
    fmt = p.add_mutually_exclusive_group()
    fmt.add_argument("--json", action="store_true", help="JSON output (addresses as integers, plus address_hex)")
    fmt.add_argument("--csv", action="store_true", help="CSV output (a bitfield: its raw word plus one column per field)")


def add_profile(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--profile",
        metavar="FILE",
        help="a device profile from `regmap probe --profile`: read with the limit and the gaps it proved (refused for another map)",
    )


def add_read_options(p: argparse.ArgumentParser) -> None:
    """What `read` and `dump` share: the space, mbpoll's -r/-c, --modicon, the output format, --profile."""
    add_space(p)
    add_addressing(p, start=True)
    add_output(p)
    add_profile(p)


def profile_from(args: argparse.Namespace, device: Device) -> Any:
    """The device profile named by --profile, checked against the map (a UsageError for another map), or None."""
    if not args.profile:
        return None
    from regmap.runtime_bridge import runtime_device
    from regmap_runtime.profile import ProfileError, load_profile

    try:
        return load_profile(args.profile, runtime_device(device))
    except ProfileError as exc:
        raise UsageError(f"--profile {exc}") from None


def output_format(args: argparse.Namespace) -> str:
    return "json" if args.json else "csv" if args.csv else "text"
