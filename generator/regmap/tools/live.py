"""`regmap read`, `write`, `dump` and `command`: talk to a drive by register name, straight from its map.

The client is the same runtime the generated modules use, built from the map at run time; the
answers are shown through the same decoder as `regmap decode`, and every value written passes
the same checks as in the generated clients before anything is sent. Every data space is read and
written with its own functions (`SyncClient.read_raw`/`write_raw` with `space=`). Where the map
names a firmware register and some of the registers asked for are gated by firmware, the version is
read first: `dump` leaves out what that firmware lacks, `read` and `write` refuse it.
"""

from __future__ import annotations

import csv
import io
import json
import socket
import sys
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

from regmap.core.decoding import DecodedValue, decode_words
from regmap.core.text import space_label
from regmap.diagnostics import ExitCode, LinkError, UsageError
from regmap.model import Device, Register
from regmap.runtime_bridge import documented_addresses, read_plan, runtime_device, runtime_specs
from regmap.tools.frames import (
    Assignment,
    WordRead,
    command_words,
    parse_assignments,
    parse_word_writes,
    word_reads,
    word_runs,
    write_blocks,
    write_function,
)
from regmap.tools.link import Link, port_reason, serial_line
from regmap.tools.selectors import Item, Registers, check_slave, say_notes
from regmap_runtime.client import PARITY, SyncClient
from regmap_runtime.codec import raw_to_words, words_to_raw
from regmap_runtime.errors import RegmapError
from regmap_runtime.plan import ReadBlock, plan_reads
from regmap_runtime.profile import DeviceProfile
from regmap_runtime.spaces import DEFAULT_SPACE, SPACES
from regmap_runtime.spec import Raw

WORD_ORDERS = ("auto", "high_first", "low_first")


def _why_unreachable(link: Link, device: Device) -> str:
    """The operating system's reason a port or socket cannot be opened, for the one-line error: the port
    itself, then the line settings the client asked of it (a pseudo-terminal refuses parity, for one)."""
    if link.serial:
        import serial

        line = serial_line(device, link.serial, link.baud, link.parity, link.stop_bits)
        try:
            serial.Serial(
                link.serial, baudrate=line.baud, parity=PARITY[line.parity], stopbits=line.stop_bits, bytesize=device.transport.data_bits
            ).close()
        except (OSError, ValueError) as exc:  # the port itself: missing, busy, not a tty
            return port_reason(exc)
        except Exception as exc:  # termios.error (no OSError): the port refuses the line settings
            return line.refused(str(exc.args[-1] if exc.args else exc))
        return "the port opened, but the client could not use it"
    host, _, port = (link.tcp or "").rpartition(":")
    try:
        socket.create_connection((host or "127.0.0.1", int(port)), timeout=link.timeout).close()
    except OSError as exc:
        return exc.strerror or str(exc)
    return "the connection opened, but the client could not use it"


def connect(device: Device, link: Link, *, reading: bool, profile: DeviceProfile | None = None) -> SyncClient:
    check_slave(device, link.slave, reading=reading)
    serial_line(device, link.serial, link.baud, link.parity, link.stop_bits)
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
            profile=profile,
        )
    elif link.tcp:
        host, _, port = link.tcp.rpartition(":")
        if not port.isdigit() or not 0 < int(port) < 65536:
            raise UsageError(f"--tcp wants HOST:PORT, got {link.tcp!r}")
        client = client_class.tcp(
            host or "127.0.0.1",
            int(port),
            link.slave,
            timeout=link.timeout,
            retries=link.retries,
            rtu_over_tcp=link.rtu_over_tcp,
            profile=profile,
        )
    else:
        raise UsageError("say where the drive is: --serial DEVICE or --tcp HOST:PORT")
    try:
        client.connect()
    except RegmapError:
        raise LinkError(f"cannot open {link.where}: {_why_unreachable(link, device)}") from None
    return client


def word_order(device: Device, client: SyncClient, link: Link) -> str | None:
    """The word order of the drive's 32-bit values: the one given, or (`auto`) read from the map's
    word-order register. None where the map fixes the word order."""
    control = device.transport.word_order_register
    if control is None:
        if link.word_order not in (None, "auto"):
            raise UsageError(
                f"{device.info.model} has no word-order register: the map fixes its word order ({device.transport.word_order.value})"
            )
        return None
    if link.word_order in ("high_first", "low_first"):
        return link.word_order
    reg = control.register
    if client.broadcast:
        raise UsageError(f"a broadcast cannot read the word-order register {reg.label}: give --word-order high_first|low_first")
    try:
        words = client.read_raw(reg.address, reg.words, space=reg.space)
    except RegmapError as exc:
        raise LinkError(
            f"cannot read the word-order register {reg.label} (--word-order high_first|low_first skips it): {_bus(exc)}"
        ) from None
    setting = words_to_raw(Registers(device).spec(reg), words)
    if setting == control.high_first:
        return "high_first"
    if setting == control.low_first:
        return "low_first"
    raise LinkError(f"the word-order register {reg.label} holds {setting}, which is neither {control.high_first} nor {control.low_first}")


def _bus(exc: RegmapError) -> str:
    return f"{type(exc).__name__}: {exc}"


@dataclass(frozen=True)
class Firmware:
    """The firmware version a drive reported, and the registers asked for that it lacks."""

    version: tuple[int, ...]
    text: str
    absent: tuple[Register, ...]

    def refuse(self, registers: Sequence[Register], doing: str) -> None:
        """A UsageError naming the registers of `registers` this firmware lacks, before anything is sent."""
        missing = [r for r in registers if r in self.absent]
        if missing:
            gates = "; ".join(f"{r.label} exists only with {r.firmware.text if r.firmware else '?'}" for r in missing)
            raise UsageError(f"{gates}; the drive reports firmware {self.text}: nothing was {doing}")


def firmware(device: Device, client: SyncClient, registers: Sequence[Register], order: str | None = None) -> Firmware | None:
    """The drive's firmware, read from the map's firmware register when some of `registers` are gated
    by firmware (None when none is, or the map names no firmware register: every register is asked for)."""
    fw = device.info.firmware_register
    if fw is None or not any(r.firmware is not None for r in registers):
        return None
    reg = fw.register
    if client.broadcast:
        raise UsageError(f"a broadcast cannot read the firmware register {reg.label}, which says which of the registers exist")
    try:
        words = client.read_raw(reg.address, reg.words, space=reg.space)
    except RegmapError as exc:
        raise LinkError(f"cannot read the firmware register {reg.label}: {_bus(exc)}") from None
    raw = words_to_raw(Registers(device).spec(reg).in_word_order(order), words)
    spec = runtime_device(device)
    try:
        version, text = spec.firmware_version(raw), spec.firmware_text(raw)
    except ValueError as exc:
        raise LinkError(f"the firmware register {reg.label} holds {raw!r}, which is not a version ({exc})") from None
    absent = tuple(r for r in registers if r.firmware is not None and not r.firmware.admits(version))
    return Firmware(version, text, absent)


def plan(device: Device, registers: Sequence[Register], profile: DeviceProfile | None, known: Firmware | None) -> list[ReadBlock]:
    """The read plan (`read_plan`); with a firmware that lacks some registers, their addresses are
    not read across either (the drive answers 0x02 for them)."""
    if known is None or not known.absent:
        return read_plan(device, registers, profile)
    absent = {
        (r.space, a)
        for r in device.registers
        if r.firmware is not None and not r.firmware.admits(known.version)
        for a in range(r.first_address, r.last_address + 1)
    }
    t = device.transport
    documented = None if t.tolerates_gaps else documented_addresses(device) - absent
    limit = t.max_read_registers
    if profile is not None:
        profile.check(device.id, device.fingerprint)
        limit, documented = profile.plan_limits(limit, documented)
    names = {r.name for r in registers}
    return plan_reads([s for s in runtime_specs(device) if s.name in names], limit, documented, max_bits=t.max_read_coils)


@dataclass
class ReadResult:
    values: list[DecodedValue]
    unread: list[Register]
    error: str | None = None
    interrupted: bool = False


def read_registers(
    client: SyncClient,
    device: Device,
    registers: Sequence[Register],
    progress: Callable[[int, int], None] | None = None,
    order: str | None = None,
    profile: DeviceProfile | None = None,
    known: Firmware | None = None,
) -> ReadResult:
    """Read by the plan (with a device profile: the plan it allows; with a firmware: around the registers
    it lacks); on a bus failure or Ctrl-C keep what was read and name what was not. Values come back
    in the order `registers` names them."""
    wanted = [r.name for r in registers]
    blocks = plan(device, registers, profile, known)
    found: dict[str, DecodedValue] = {}

    def result(error: str | None = None, interrupted: bool = False) -> ReadResult:
        values = [found[name] for name in dict.fromkeys(wanted) if name in found]
        unread = [r for r in registers if r.name not in found]
        return ReadResult(values, unread, error, interrupted)

    for number, block in enumerate(blocks, 1):
        try:
            words = client.read_raw(block.address, block.count, space=block.space)
        except RegmapError as exc:
            return result(f"{_bus(exc)} (request {number} of {len(blocks)}, 0x{block.address:04X} x {block.count})")
        except KeyboardInterrupt:
            return result("interrupted (Ctrl-C)", interrupted=True)
        for value in decode_words(device, block.address, words, word_order=order, space=block.space):
            if value.register in wanted and value.raw is not None:
                found[value.register] = value
        if progress is not None:
            progress(number, len(blocks))
    return result()


def show_value(value: DecodedValue) -> str:
    label = " ".join(x for x in (value.param, value.register) if x)
    return f"{label} = {value.text}"


def profiled_order(device: Device, client: SyncClient, link: Link, profile: DeviceProfile | None) -> str | None:
    """The word order to decode with: the one given or the map's register (`word_order`), else the one a profile observed."""
    order = word_order(device, client, link)
    if order is None and profile is not None and profile.word_order != device.transport.word_order.value:
        return profile.word_order
    return order


def cmd_read(
    device: Device,
    link: Link,
    items: Sequence[Item],
    output: str,
    profile: DeviceProfile | None = None,
    space: str | None = None,
    *,
    modicon: bool = False,
    words: bool = False,
) -> int:
    """Read what the items name (parse_items: SELECTOR [COUNT] ..., as `frame read` builds it); with
    `words`, COUNT words (bits) at each address, documented or not."""
    if words:
        return _read_words(device, link, word_reads(device, items, space, modicon=modicon), output, profile)
    regs = Registers(device, space, modicon=modicon)
    registers = regs.select(items)
    client = connect(device, link, reading=True, profile=profile)
    try:
        order = profiled_order(device, client, link, profile)
        known = firmware(device, client, registers, order)
        if known is not None:
            known.refuse(registers, "read")
        result = read_registers(client, device, registers, order=order, profile=profile, known=known)
    finally:
        client.close()
    print_values(result.values, output)
    say_notes("read", regs.notes)
    return finish(result, "read")


def _read_words(device: Device, link: Link, reads: Sequence[WordRead], output: str, profile: DeviceProfile | None) -> int:
    """`read --words`: one request per ADDR [COUNT], every word shown as it came (hex, unsigned, signed; bits 0/1)."""
    client = connect(device, link, reading=True, profile=profile)
    rows: list[dict[str, Any]] = []
    error = None
    try:
        for read in reads:
            try:
                got = client.read_raw(read.address, read.count, space=read.space)
            except RegmapError as exc:
                error = f"{_bus(exc)} (0x{read.address:04X} x {read.count})"
                break
            rows += [{"space": read.space, "address": read.address + i, "word": int(w)} for i, w in enumerate(got)]
    finally:
        client.close()
    print_words(rows, output)
    say_notes("read", [r.note for r in reads if r.note])
    if error is not None:
        raise LinkError(f"the bus failed after {len(rows)} word(s) were read: {error}")
    return ExitCode.OK


def print_words(rows: Sequence[dict[str, Any]], output: str) -> None:
    if output == "json":
        out = [{"address": r["address"], "address_hex": f"0x{r['address']:04X}", "space": r["space"], "word": r["word"]} for r in rows]
        json.dump(out, sys.stdout, indent=2)
        sys.stdout.write("\n")
    elif output == "csv":
        buffer = io.StringIO()
        writer = csv.DictWriter(buffer, fieldnames=["space", "address", "address_hex", "word"], lineterminator="\n")
        writer.writeheader()
        writer.writerows({**r, "address_hex": f"0x{r['address']:04X}"} for r in rows)
        sys.stdout.write(buffer.getvalue())
    else:
        for r in rows:
            word = r["word"]
            shown = (
                str(word)
                if SPACES[r["space"]].bits
                else f"0x{word:04X} = {word} unsigned, {word - 0x10000 if word & 0x8000 else word} signed"
            )
            print(f"{space_label(r['space'])} 0x{r['address']:04X} = {shown}")


@dataclass
class WriteLog:
    """What went out, for the message when a later request fails."""

    done: list[str] = field(default_factory=list)

    def failed(self, what: str, exc: RegmapError) -> LinkError:
        went = f"; written before it: {', '.join(self.done)}" if self.done else "; nothing was written"
        return LinkError(f"writing {what} failed: {_bus(exc)}{went}")


def _merge_current(client: SyncClient, device: Device, partial: list[Assignment], order: str | None) -> list[Assignment]:
    """Read-modify-write: one read of the registers whose fields were named, then each named field
    merged into the word the drive holds (every other bit kept)."""
    if not partial:
        return []
    current = read_registers(client, device, [a.register for a in partial], order=order)
    if current.error:
        raise LinkError(
            f"cannot read the current value of {', '.join(a.register.label for a in partial)} to change only the named fields: {current.error}"
        )
    held = {v.register: v.raw for v in current.values}
    return [a.with_base(int(held[a.register.name] or 0)) for a in partial]


def _as_written(a: Assignment) -> Raw | None:
    """The raw value the drive holds after the write: an f32 keeps only float32's precision (0.1 reads
    back as 0.10000000149011612), text only what fits; what the read-back is compared with."""
    if a.raw is None:
        return None
    return words_to_raw(a.spec, raw_to_words(a.spec, a.raw))


def _written_value(device: Device, a: Assignment, order: str | None) -> DecodedValue:
    """What a write sent, decoded as `read` shows a value (for a register that cannot be read back)."""
    assert a.raw is not None
    words = raw_to_words(a.spec.in_word_order(order), a.raw)
    decoded = decode_words(device, a.register.address, words, word_order=order, space=a.register.space)
    return next(v for v in decoded if v.register == a.register.name)


def cmd_write(
    device: Device,
    link: Link,
    items: Sequence[str],
    *,
    raw: bool,
    verify: bool,
    replace: bool,
    words: bool,
    space: str | None = None,
    modicon: bool = False,
) -> int:
    # Every value is parsed and checked (range, enum, fields, conflicts) before the port is opened.
    word_writes = parse_word_writes(items, space, modicon=modicon) if words else []
    word_space = word_writes[0].space if word_writes else DEFAULT_SPACE
    runs = word_runs(device, word_writes) if words else []
    assignments = [] if words else parse_assignments(device, items, raw, replace=replace, space=space, modicon=modicon)
    say_notes("write", [n for n in (*(w.located for w in word_writes), *(a.located for a in assignments)) if n])
    client = connect(device, link, reading=any(a.raw is None for a in assignments))  # a broadcast may write, not read
    log = WriteLog()
    unit = "bit" if word_space != DEFAULT_SPACE and SPACES[word_space].bits else "word"
    try:
        for address, run in runs:
            single = write_function(device, word_space, len(run))
            try:
                client.write_raw(address, run, multiple=not single, space=word_space)
            except RegmapError as exc:
                raise log.failed(f"{len(run)} {unit}(s) at 0x{address:04X}", exc) from None
            log.done.append(f"{len(run)} {unit}(s) at 0x{address:04X}")
        if words:
            print(f"wrote {sum(len(r) for _, r in runs)} {unit}(s) in {len(runs)} request(s)")
            return ExitCode.OK
        order = word_order(device, client, link) if any(a.register.wide for a in assignments) else None
        known = firmware(device, client, [a.register for a in assignments], order)
        if known is not None:
            known.refuse([a.register for a in assignments], "written")
        complete = [a for a in assignments if a.raw is not None]
        complete += _merge_current(client, device, [a for a in assignments if a.raw is None], order)
        for block in write_blocks(device, complete, order):
            names = ", ".join(s.label for s in block.registers)
            single = write_function(device, block.space, len(block.words))
            try:
                client.write_raw(block.address, block.words, multiple=not single, space=block.space)
            except RegmapError as exc:
                raise log.failed(names, exc) from None
            log.done.append(names)
        if not verify or client.broadcast:
            print(f"wrote {len(complete)} value(s) in {len(log.done)} request(s)")
            return ExitCode.OK
        readable = [a.register for a in complete if a.register.access.readable]
        result = read_registers(client, device, readable, order=order, known=known)
    finally:
        client.close()
    expected = {a.register.name: _as_written(a) for a in complete}
    mismatches = [v for v in result.values if v.register in expected and v.raw != expected[v.register]]
    read_back = {v.register: v for v in result.values}
    for a in complete:  # in the order given
        value = read_back.get(a.register.name)
        if value is None:
            if not a.register.access.readable:
                print(f"{show_value(_written_value(device, a, order))}  (written; write-only, not read back)")
            continue
        print(
            f"{show_value(value)}  (verified)"
            if value not in mismatches
            else f"{show_value(value)}  (MISMATCH: wrote raw {expected[value.register or '']!r})"
        )
    if result.error:
        raise LinkError(f"written, but the read-back failed: {result.error}")
    if mismatches:
        print(f"regmap write: {len(mismatches)} register(s) read back different values", file=sys.stderr)
        return ExitCode.VERIFY_MISMATCH
    return ExitCode.OK


def cmd_command(device: Device, link: Link, name: str, argument: str | None) -> int:
    command, _ = command_words(device, name, argument)  # checked before the port is opened
    client = connect(device, link, reading=False)
    try:
        order = word_order(device, client, link) if command.register.wide else None
        _, words = command_words(device, name, argument, order)
        try:
            client.write_raw(command.register.address, words, multiple=len(words) > 1, space=command.register.space)
        except RegmapError as exc:
            raise LinkError(f"command {command.name} failed: {_bus(exc)}") from None
    finally:
        client.close()
    shown = " ".join(f"0x{w:04X}" for w in words)
    print(f"sent {command.name}: {shown} to {command.register.label} (0x{command.register.address:04X})")
    return ExitCode.OK


def cmd_dump(
    device: Device, link: Link, output: str, profile: DeviceProfile | None = None, chosen: Sequence[Register] | None = None
) -> int:
    """Every readable register (or the `chosen` ones: -t, -r/-c) with the read plan."""
    registers = [r for r in device.registers if r.access.readable] if chosen is None else list(chosen)
    client = connect(device, link, reading=True, profile=profile)
    progress = _progress_bar if sys.stderr.isatty() else None
    try:
        order = profiled_order(device, client, link, profile)
        known = firmware(device, client, registers, order)
        if known is not None and known.absent:
            registers = [r for r in registers if r not in known.absent]
            names = ", ".join(r.name for r in known.absent[:10]) + (f" and {len(known.absent) - 10} more" if len(known.absent) > 10 else "")
            print(
                f"regmap dump: firmware {known.text} lacks {len(known.absent)} register(s) of the map, not read: {names}", file=sys.stderr
            )
        result = read_registers(client, device, registers, progress, order=order, profile=profile, known=known)
    finally:
        client.close()
        if progress is not None:
            sys.stderr.write("\n")
    print_values(result.values, output)
    return finish(result, "dump")


def finish(result: ReadResult, command: str) -> int:
    if result.error is None:
        return ExitCode.OK
    names = ", ".join(r.name for r in result.unread[:10]) + (f" and {len(result.unread) - 10} more" if len(result.unread) > 10 else "")
    cause = "stopped" if result.interrupted else "the bus failed"
    print(f"regmap {command}: {cause} after {len(result.values)} register(s) were read: {result.error}; not read: {names}", file=sys.stderr)
    return ExitCode.INTERRUPTED if result.interrupted else ExitCode.BUS


def _progress_bar(done: int, total: int) -> None:
    width = 30
    filled = width * done // total
    sys.stderr.write(f"\r[{'#' * filled}{'.' * (width - filled)}] {done}/{total} requests")
    sys.stderr.flush()


CSV_COLUMNS = ["register", "param", "address", "address_hex", "raw", "value", "unit", "in_range", "text", "space"]


def _csv_cell(value: Any) -> Any:
    """A CSV cell as JSON writes the value: true/false for a bit (and in_range), numbers as numbers, text as text."""
    if isinstance(value, bool):
        return "true" if value else "false"
    return "" if value is None else value


def print_values(values: Sequence[DecodedValue], output: str) -> None:
    if output == "json":
        json.dump([v.as_json() for v in values], sys.stdout, ensure_ascii=False, indent=2)
        sys.stdout.write("\n")
    elif output == "csv":
        fields = list(dict.fromkeys(name for v in values if v.fields for name in v.fields))
        buffer = io.StringIO()
        writer = csv.DictWriter(buffer, fieldnames=CSV_COLUMNS + fields, lineterminator="\n")
        writer.writeheader()
        for v in values:
            row: dict[str, Any] = {k: _csv_cell(val) for k, val in v.as_json().items() if k in CSV_COLUMNS}
            row.update({k: _csv_cell(val) for k, val in (v.fields or {}).items()})
            writer.writerow(row)
        sys.stdout.write(buffer.getvalue())
    else:
        for v in values:
            print(show_value(v))
