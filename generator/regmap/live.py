"""`regmap read`, `write` and `dump`: talk to a drive by register name, straight from its map.

The client is the same runtime the generated modules use, built from the map at run time; the
answers are shown through the same decoder as `regmap decode`.
"""

from __future__ import annotations

import csv
import io
import json
import sys
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

from regmap.backends.common import read_plan, runtime_device
from regmap.diagnostics import LinkError, UsageError
from regmap.frames import DecodedValue, Registers, check_slave, decode_words, parse_assignments, write_blocks
from regmap.model import Device, Register
from regmap_runtime.client import SyncClient
from regmap_runtime.errors import RegmapError


@dataclass(frozen=True)
class Link:
    tcp: str | None = None
    serial: str | None = None
    slave: int = 1
    baud: int | None = None
    parity: str | None = None
    stop_bits: int | None = None
    timeout: float = 1.0
    retries: int = 2
    rtu_over_tcp: bool = False


def connect(device: Device, link: Link) -> SyncClient:
    check_slave(device, link.slave)
    client_class: type[SyncClient] = type(f"{device.id}_live", (SyncClient,), {"DEVICE": runtime_device(device)})
    if link.serial:
        client = client_class.rtu(
            link.serial,
            link.slave,
            baud=link.baud,
            parity=link.parity,
            stop_bits=link.stop_bits,
            timeout=link.timeout,
            retries=link.retries,
        )
    elif link.tcp:
        host, _, port = link.tcp.rpartition(":")
        if not port.isdigit():
            raise UsageError(f"--tcp wants HOST:PORT, got {link.tcp!r}")
        client = client_class.tcp(
            host or "127.0.0.1", int(port), link.slave, timeout=link.timeout, retries=link.retries, rtu_over_tcp=link.rtu_over_tcp
        )
    else:
        raise UsageError("say where the drive is: --serial DEVICE or --tcp HOST:PORT")
    try:
        client.connect()
    except RegmapError as exc:
        raise LinkError(f"cannot open {link.serial or link.tcp}: {exc}") from None
    return client


@dataclass
class ReadResult:
    values: list[DecodedValue]
    unread: list[Register]
    error: str | None = None


def read_registers(
    client: SyncClient, device: Device, registers: Sequence[Register], progress: Callable[[int, int], None] | None = None
) -> ReadResult:
    """Read by the plan; on a bus failure keep what was read and name what was not."""
    wanted = {r.name for r in registers}
    blocks = read_plan(device, registers)
    values: list[DecodedValue] = []
    done: set[str] = set()
    for number, block in enumerate(blocks, 1):
        try:
            words = client.read_raw(block.address, block.count)
        except RegmapError as exc:
            unread = [r for r in registers if r.name not in done]
            return ReadResult(
                values, unread, f"{type(exc).__name__}: {exc} (request {number} of {len(blocks)}, 0x{block.address:04X} x {block.count})"
            )
        for value in decode_words(device, block.address, words):
            if value.register in wanted and value.raw is not None:
                values.append(value)
                done.add(value.register)
        if progress is not None:
            progress(number, len(blocks))
    return ReadResult(values, [])


def show_value(value: DecodedValue) -> str:
    label = " ".join(x for x in (value.param, value.register) if x)
    return f"{label} = {value.text}"


def cmd_read(device: Device, link: Link, selectors: Sequence[str], as_json: bool) -> int:
    regs = Registers(device)
    registers = [regs.resolve(s) for s in selectors]
    for reg in registers:
        if not reg.access.readable:
            raise UsageError(f"{reg.label} is write-only")
    client = connect(device, link)
    try:
        result = read_registers(client, device, registers)
    finally:
        client.close()
    _print_values(result.values, "json" if as_json else "text")
    return _finish(result)


def cmd_write(device: Device, link: Link, assignments: Sequence[str], raw: bool, verify: bool) -> int:
    parsed = parse_assignments(device, assignments, raw)  # every value is checked before anything is sent
    blocks = write_blocks(device, parsed.values)
    client = connect(device, link)
    try:
        for address, words in parsed.raw_writes:
            client.write_raw(address, words)
        for block in blocks:
            client.write_raw(block.address, block.words, multiple=not block.single)
        if not verify or client.broadcast or not parsed.registers:
            print(f"wrote {len(parsed.values) + len(parsed.raw_writes)} value(s) in {len(blocks) + len(parsed.raw_writes)} request(s)")
            return 0
        readable = [r for r in parsed.registers if r.access.readable]
        result = read_registers(client, device, readable)
    except RegmapError as exc:
        raise LinkError(f"{type(exc).__name__}: {exc}") from None
    finally:
        client.close()
    expected = {spec.name: raw_value for spec, raw_value in parsed.values}
    mismatches = [v for v in result.values if v.register in expected and v.raw != expected[v.register]]
    for value in result.values:
        print(
            f"{show_value(value)}  (verified)"
            if value not in mismatches
            else f"{show_value(value)}  (MISMATCH: wrote raw {expected[value.register or '']})"
        )
    if result.error:
        raise LinkError(f"written, but the read-back failed: {result.error}")
    if mismatches:
        print(f"regmap write: {len(mismatches)} register(s) read back different values", file=sys.stderr)
        return 5
    return 0


def cmd_dump(device: Device, link: Link, output: str) -> int:
    registers = [r for r in device.registers if r.access.readable]
    client = connect(device, link)
    progress = _progress_bar if sys.stderr.isatty() else None
    try:
        result = read_registers(client, device, registers, progress)
    finally:
        client.close()
        if progress is not None:
            sys.stderr.write("\n")
    _print_values(result.values, output)
    return _finish(result)


def _finish(result: ReadResult) -> int:
    if result.error is None:
        return 0
    names = ", ".join(r.name for r in result.unread[:10]) + (f" and {len(result.unread) - 10} more" if len(result.unread) > 10 else "")
    print(f"regmap: the bus failed after {len(result.values)} register(s) were read: {result.error}; not read: {names}", file=sys.stderr)
    return 4


def _progress_bar(done: int, total: int) -> None:
    width = 30
    filled = width * done // total
    sys.stderr.write(f"\r[{'#' * filled}{'.' * (width - filled)}] {done}/{total} requests")
    sys.stderr.flush()


def _print_values(values: Sequence[DecodedValue], output: str) -> None:
    if output == "json":
        json.dump([_row(v) for v in values], sys.stdout, ensure_ascii=False, indent=2)
        sys.stdout.write("\n")
    elif output == "csv":
        buffer = io.StringIO()
        writer = csv.DictWriter(buffer, fieldnames=["register", "param", "address", "raw", "value", "unit", "text"], lineterminator="\n")
        writer.writeheader()
        for v in values:
            row = _row(v)
            writer.writerow({k: row[k] for k in writer.fieldnames})
        sys.stdout.write(buffer.getvalue())
    else:
        for v in values:
            print(show_value(v))


def _row(v: DecodedValue) -> dict[str, Any]:
    return {
        "register": v.register,
        "param": v.param,
        "address": f"0x{v.address:04X}",
        "raw": v.raw,
        "value": v.value,
        "unit": v.unit,
        "text": v.text,
    }
