"""`regmap read`, `write`, `dump` and `command`: talk to a drive by register name, straight from its map.

The client is the same runtime the generated modules use, built from the map at run time; the
answers are shown through the same decoder as `regmap decode`, and every value written passes
the same checks as in the generated clients before anything is sent. Every data space is read and
written with its own functions (`SyncClient.read_raw`/`write_raw` with `space=`). Where the map
names a firmware register and some of the registers asked for are gated by firmware, the version is
read first: `dump` leaves out what that firmware lacks, `read` and `write` refuse it.
"""

from __future__ import annotations

import socket
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

from regmap.core.decoding import DecodedValue, apply_scale_factors, decode_words
from regmap.diagnostics import LinkError, UsageError
from regmap.model import Device, Register
from regmap.runtime_bridge import documented_addresses, read_plan, runtime_alignment, runtime_device, runtime_specs
from regmap.tools.frames import (
    Assignment,
    WordRead,
    command_words,
    parse_assignments,
    parse_word_writes,
    word_runs,
    write_blocks,
    write_function,
)
from regmap.tools.link import Link, parse_endpoint, port_reason, serial_line
from regmap.tools.selectors import Item, Registers, check_slave
from regmap.tools.wordcheck import check_word_runs
from regmap_runtime.client import SyncClient
from regmap_runtime.codec import raw_to_words, words_to_raw
from regmap_runtime.errors import OutcomeUnknown, RegmapError
from regmap_runtime.plan import ReadBlock, plan_reads
from regmap_runtime.profile import DeviceProfile
from regmap_runtime.spaces import DEFAULT_SPACE, SPACES
from regmap_runtime.spec import Raw
from regmap_runtime.wire import PARITY

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
    declared = [v.name for v in device.info.variants]
    if link.variant is not None and link.variant not in declared:
        raise UsageError(f"--variant {link.variant}: {device.id} declares {', '.join(declared) if declared else 'no variants'}")
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
            variant=link.variant,
        )
    elif link.tcp:
        host, port = parse_endpoint(link.tcp)
        client = client_class.tcp(
            host,
            port,
            link.slave,
            timeout=link.timeout,
            retries=link.retries,
            rtu_over_tcp=link.rtu_over_tcp,
            profile=profile,
            variant=link.variant,
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
    if control.swaps:  # a swap register tells nothing when read: the map's order (the device's default) is assumed
        return None
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


def refuse_off_variant(registers: Sequence[Register], variant: str | None, doing: str) -> None:
    """A UsageError naming the registers the device's variant lacks, before the port is opened."""
    missing = [r for r in registers if not r.on_variant(variant)]
    if missing:
        only = "; ".join(f"{r.label} exists only on variant {', '.join(r.variants)}" for r in missing)
        raise UsageError(f"{only}; the device is {variant}: nothing was {doing}")


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


def plan(
    device: Device, registers: Sequence[Register], profile: DeviceProfile | None, known: Firmware | None, variant: str | None = None
) -> list[ReadBlock]:
    """The read plan (`read_plan`); with a firmware that lacks some registers, or a variant, the addresses
    of what they lack are not read across either (the drive answers 0x02 for them)."""
    variants = () if variant is None else (variant,)
    if known is None or not known.absent:
        return read_plan(device, registers, profile, variants=variants)
    absent = {
        (r.space, a)
        for r in device.registers
        if r.firmware is not None and not r.firmware.admits(known.version)
        for a in range(r.first_address, r.last_address + 1)
    }
    t = device.transport
    documented = None if t.tolerates_gaps else documented_addresses(device, variants) - absent
    limit = t.max_read_registers
    if profile is not None:
        profile.check(device.id, device.fingerprint)
        limit, documented = profile.plan_limits(limit, documented)
    names = {r.name for r in registers}
    specs = [s for s in runtime_specs(device) if s.name in names]
    return plan_reads(specs, limit, documented, max_bits=t.max_read_coils, alignment=runtime_alignment(device))


@dataclass
class ReadResult:
    """The values read, in the order asked for; what was not read, and why (a bus failure or Ctrl-C)."""

    values: list[DecodedValue]
    unread: list[Register]
    error: str | None = None
    interrupted: bool = False
    notes: list[str] = field(default_factory=list)  # how addresses were read (-r, Modicon numbers)


def read_registers(
    client: SyncClient,
    device: Device,
    registers: Sequence[Register],
    progress: Callable[[int, int], None] | None = None,
    order: str | None = None,
    profile: DeviceProfile | None = None,
    known: Firmware | None = None,
    variant: str | None = None,
) -> ReadResult:
    """Read by the plan (with a device profile: the plan it allows; with a firmware or a variant: around the
    registers they lack); on a bus failure or Ctrl-C keep what was read and name what was not. Values come
    back in the order `registers` names them."""
    wanted = [r.name for r in registers]
    factors = [device.register(sf) for sf in dict.fromkeys(r.scale_from for r in registers if r.scale_from) if sf not in wanted]
    blocks = plan(device, [*registers, *factors], profile, known, variant)
    found: dict[str, DecodedValue] = {}
    decoded: list[DecodedValue] = []  # every value read, the scale factors of `scale_from` registers among them

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
        these = decode_words(device, block.address, words, word_order=order, space=block.space)
        decoded += these
        for value in these:
            if value.register in wanted and value.raw is not None:
                found[value.register] = value
        apply_scale_factors(device, list(found.values()), decoded, "its scale factor {sf} could not be read")
        if progress is not None:
            progress(number, len(blocks))
    return result()


def profiled_order(device: Device, client: SyncClient, link: Link, profile: DeviceProfile | None) -> str | None:
    """The word order to decode with: the one given or the map's register (`word_order`), else the one a profile observed."""
    order = word_order(device, client, link)
    if order is None and profile is not None and profile.word_order != device.transport.word_order.value:
        return profile.word_order
    return order


def read(
    device: Device,
    link: Link,
    items: Sequence[Item],
    profile: DeviceProfile | None = None,
    space: str | None = None,
    *,
    modicon: bool = False,
) -> ReadResult:
    """Read what the items name (parse_items: SELECTOR [COUNT] ..., as `frame read` builds it), with
    the notes on how addresses were read."""
    regs = Registers(device, space, modicon=modicon)
    registers = regs.select(items)
    refuse_off_variant(registers, link.variant, "read")

    def refuse_absent(known: Firmware) -> list[Register]:
        known.refuse(registers, "read")
        return registers

    result = _read_as_the_drive_runs(device, link, registers, profile, refuse_absent)
    result.notes = list(regs.notes)
    return result


def _read_as_the_drive_runs(
    device: Device,
    link: Link,
    registers: list[Register],
    profile: DeviceProfile | None,
    on_firmware: Callable[[Firmware], list[Register]],
    progress: Callable[[int, int], None] | None = None,
) -> ReadResult:
    """Connect, learn the word order and (where registers are gated) the firmware, then read what
    `on_firmware` makes of `registers` for that firmware."""
    client = connect(device, link, reading=True, profile=profile)
    try:
        order = profiled_order(device, client, link, profile)
        known = firmware(device, client, registers, order)
        if known is not None:
            registers = on_firmware(known)
        return read_registers(client, device, registers, progress, order=order, profile=profile, known=known, variant=link.variant)
    finally:
        client.close()


@dataclass(frozen=True)
class Word:
    """One word (a bit, in a bit space) as `read --words` got it."""

    space: str
    address: int
    word: int


@dataclass
class WordsRead:
    words: list[Word]
    notes: list[str]
    error: str | None = None  # the bus failure that ended the reads


def read_words(device: Device, link: Link, reads: Sequence[WordRead], profile: DeviceProfile | None = None) -> WordsRead:
    """`read --words` (`frames.word_reads`): COUNT words (bits) at each address, documented or not, one request per ADDR [COUNT]."""
    client = connect(device, link, reading=True, profile=profile)
    got = WordsRead([], [r.note for r in reads if r.note])
    try:
        for read in reads:
            try:
                answer = client.read_raw(read.address, read.count, space=read.space)
            except RegmapError as exc:
                got.error = f"{_bus(exc)} (0x{read.address:04X} x {read.count})"
                break
            got.words += [Word(read.space, read.address + i, int(w)) for i, w in enumerate(answer)]
    finally:
        client.close()
    return got


@dataclass
class WriteLog:
    """What went out, for the message when a later request fails."""

    done: list[str] = field(default_factory=list)

    def before(self) -> str:
        return f"; written before it: {', '.join(self.done)}" if self.done else "; nothing was written before it"

    def failed(self, what: str, exc: RegmapError) -> LinkError:
        went = self.before() if self.done else "; nothing was written"
        return LinkError(f"writing {what} failed: {_bus(exc)}{went}")

    def unknown(self, exc: OutcomeUnknown, unit: str) -> Written:
        """What a write that went out once and lost its answer returns: the requests answered, and what is not known."""
        return Written(len(self.done), unit, len(self.done) + 1, unknown=f"{exc}{self.before()}")


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


@dataclass(frozen=True)
class WritePlan:
    """What `write` will send, parsed and checked (range, enum, fields, conflicts) before the port is opened."""

    words: bool  # --words: word runs at any address, not values by register
    space: str  # the data space of the word runs
    runs: list[tuple[int, tuple[int, ...]]]
    assignments: list[Assignment]
    notes: list[str]  # how addresses were read
    order_pending: bool = False  # --words on 32-bit registers that follow the drive's word order: checked once it is read

    @property
    def unit(self) -> str:
        return "bit" if self.space != DEFAULT_SPACE and SPACES[self.space].bits else "word"


def plan_write(
    device: Device, items: Sequence[str], *, raw: bool, replace: bool, words: bool, space: str | None = None, modicon: bool = False
) -> WritePlan:
    word_writes = parse_word_writes(items, space, modicon=modicon) if words else []
    assignments = [] if words else parse_assignments(device, items, raw, replace=replace, space=space, modicon=modicon)
    runs = word_runs(device, word_writes) if words else []
    run_space = word_writes[0].space if word_writes else DEFAULT_SPACE
    order_pending = check_word_runs(device, run_space, runs) if words else False
    return WritePlan(
        words,
        run_space,
        runs,
        assignments,
        [n for n in (*(w.located for w in word_writes), *(a.located for a in assignments)) if n],
        order_pending,
    )


@dataclass(frozen=True)
class Checked:
    """One value written, as read back: `verified`, `mismatch` (the drive holds another value than
    `wrote`), or `write-only` (shown as sent: it cannot be read back)."""

    value: DecodedValue
    outcome: str
    wrote: Raw | None = None


@dataclass
class Written:
    """What a write sent: `count` values (words, bits) in `requests` requests, and the read-back
    (None where nothing was read back: --no-verify, --words, a broadcast)."""

    count: int
    unit: str  # value, word or bit
    requests: int
    checked: list[Checked] | None = None
    mismatches: int = 0
    read_back_error: str | None = None
    unknown: str | None = None  # a command or trigger write went out once and lost its answer: it may have acted


def write(device: Device, link: Link, plan: WritePlan, *, verify: bool) -> Written:
    assignments = plan.assignments
    refuse_off_variant([a.register for a in assignments], link.variant, "written")
    client = connect(device, link, reading=any(a.raw is None for a in assignments))  # a broadcast may write, not read
    log = WriteLog()
    try:
        if plan.order_pending:  # as a named write does: the drive's word order read (or given), then checked
            check_word_runs(device, plan.space, plan.runs, word_order(device, client, link), order_read=True)
        for address, run in plan.runs:
            single = write_function(device, plan.space, len(run))
            try:
                client.write_raw(address, run, multiple=not single, space=plan.space)
            except OutcomeUnknown as exc:
                return log.unknown(exc, plan.unit)
            except RegmapError as exc:
                raise log.failed(f"{len(run)} {plan.unit}(s) at 0x{address:04X}", exc) from None
            log.done.append(f"{len(run)} {plan.unit}(s) at 0x{address:04X}")
        if plan.words:
            return Written(sum(len(r) for _, r in plan.runs), plan.unit, len(plan.runs))
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
            except OutcomeUnknown as exc:
                return log.unknown(exc, "value")
            except RegmapError as exc:
                raise log.failed(names, exc) from None
            log.done.append(names)
        written = Written(len(complete), "value", len(log.done))
        if not verify or client.broadcast:
            return written
        readable = [a.register for a in complete if a.register.access.readable]
        result = read_registers(client, device, readable, order=order, known=known)
    finally:
        client.close()
    expected = {a.register.name: _as_written(a) for a in complete}
    mismatches = [v for v in result.values if v.register in expected and v.raw != expected[v.register]]
    read_back = {v.register: v for v in result.values}
    written.checked = []
    for a in complete:  # in the order given
        value = read_back.get(a.register.name)
        if value is None:
            if not a.register.access.readable:
                written.checked.append(Checked(_written_value(device, a, order), "write-only"))
            continue
        mismatch = value in mismatches
        written.checked.append(Checked(value, "mismatch" if mismatch else "verified", expected[value.register or ""] if mismatch else None))
    written.mismatches, written.read_back_error = len(mismatches), result.error
    return written


@dataclass(frozen=True)
class CommandSent:
    name: str
    words: list[int]
    register: Register
    unknown: str | None = None  # the write went out once and its answer was lost: the drive may or may not have acted


def send_command(device: Device, link: Link, name: str, argument: str | None, confirm: str | None = None) -> CommandSent:
    command, _ = command_words(device, name, argument, confirm=confirm)  # checked before the port is opened
    refuse_off_variant([command.register], link.variant, "sent")
    client = connect(device, link, reading=False)
    try:
        order = word_order(device, client, link) if command.register.wide else None
        _, words = command_words(device, name, argument, order, confirm)
        try:
            client.write_raw(command.register.address, words, multiple=len(words) > 1, space=command.register.space)
        except OutcomeUnknown as exc:
            return CommandSent(command.name, list(words), command.register, unknown=str(exc))
        except RegmapError as exc:
            raise LinkError(f"command {command.name} failed: {_bus(exc)}") from None
    finally:
        client.close()
    return CommandSent(command.name, list(words), command.register)


def dump(
    device: Device,
    link: Link,
    profile: DeviceProfile | None = None,
    chosen: Sequence[Register] | None = None,
    *,
    progress: Callable[[int, int], None] | None = None,
    lacking: Callable[[Firmware], None] | None = None,
) -> ReadResult:
    """Every readable register (or the `chosen` ones: -t, -r/-c) with the read plan. `progress` is told
    of each request done; `lacking` of a firmware that lacks some of the registers (left out), before they are read."""
    registers = [r for r in device.registers if r.access.readable] if chosen is None else list(chosen)
    registers = [r for r in registers if r.on_variant(link.variant)]  # what the variant lacks is not there to read

    def leave_out_absent(known: Firmware) -> list[Register]:
        if known.absent and lacking is not None:
            lacking(known)
        return [r for r in registers if r not in known.absent]

    return _read_as_the_drive_runs(device, link, registers, profile, leave_out_absent, progress)
