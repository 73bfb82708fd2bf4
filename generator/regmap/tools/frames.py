"""Building request frames for field engineers: `regmap frame`, and the values `regmap write` sends.

Everything goes through the runtime's codec, checks and planner, so a frame printed here is byte
for byte the frame the generated client sends, and a value the client refuses is refused here.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from regmap.diagnostics import UsageError
from regmap.model import Device, Register
from regmap.runtime_bridge import read_plan
from regmap.tools.selectors import Registers, check_slave, parse_address, parse_int, suggest
from regmap_runtime.codec import RangeError, check_raw, merge_fields, parse_fields, raw_to_words, value_to_raw
from regmap_runtime.plan import WriteBlock, plan_writes
from regmap_runtime.rtu import build_read, build_write_multiple, build_write_single
from regmap_runtime.spaces import DEFAULT_SPACE, HOLDING
from regmap_runtime.spec import RegisterSpec

# -- reads -------------------------------------------------------------------------------


def read_frames(device: Device, selector: str, count: int | None, slave: int) -> list[bytes]:
    """Read one register, or `count` of the map's readable registers from it, with the fewest requests."""
    check_slave(device, slave, reading=True)
    regs = Registers(device)
    reg = regs.resolve(selector)
    if not reg.access.readable:
        raise UsageError(f"{reg.label} is write-only")
    if count is None or count == 1:
        chosen = [reg]
    else:
        readable = [r for r in sorted(device.registers, key=lambda r: r.address) if r.access.readable and r.address >= reg.address]
        chosen = readable[:count]
        if len(chosen) < count:
            raise UsageError(f"only {len(chosen)} readable registers from {reg.label} onwards, asked for {count}")
    return [build_read(slave, b.address, b.count, space=b.space) for b in read_plan(device, chosen)]


def read_words_frame(device: Device, address_text: str, count: int, slave: int) -> bytes:
    """`read --words ADDR COUNT`: one read of COUNT holding-register words, documented or not."""
    check_slave(device, slave, reading=True)
    address = word_address(address_text)
    limit = device.transport.max_read_registers
    if not 1 <= count <= limit:
        raise UsageError(f"COUNT {count} is outside 1..{limit} ({device.info.model} reads at most {limit} registers per request)")
    if address + count > 0x10000:
        raise UsageError(f"{count} words from 0x{address:04X} run past 0xFFFF")
    return build_read(slave, address, count)


def word_address(text: str) -> int:
    address = parse_address(text)
    if address is None:
        raise UsageError(f"{text!r} is not a Modbus address (0x0191, 0191h or decimal 401)")
    return address


# -- writes ------------------------------------------------------------------------------


@dataclass(frozen=True)
class Assignment:
    """One SELECTOR=VALUE argument, checked: either a register's complete raw value, or (for a
    bitfield register given some fields) the fields to merge into the word the drive holds."""

    argument: str
    register: Register
    spec: RegisterSpec[Any]
    raw: int | None  # None until the named fields are merged into a base word
    fields: dict[str, int] | None = None  # named bitfields, when not every field is named
    note: str | None = None  # what the bits nobody named were set to

    def with_base(self, base: int) -> Assignment:
        """The assignment with its named fields merged into `base` (every other bit kept), checked."""
        assert self.fields is not None
        raw = merge_fields(self.spec, base, self.fields)
        try:
            check_raw(self.spec, raw)
        except RangeError as exc:
            raise UsageError(f"{self.argument}: {exc}") from None
        return dataclasses.replace(self, raw=raw, fields=None)


@dataclass(frozen=True)
class WordWrite:
    """`--words ADDR=WORD[,WORD...]`: words at a Modbus address."""

    argument: str
    address: int
    words: tuple[int, ...]


def _split(item: str) -> tuple[str, str]:
    selector, sep, value_text = item.partition("=")
    if not sep or not selector.strip() or not value_text.strip():
        raise UsageError(f"write wants SELECTOR=VALUE, got {item!r}")
    return selector.strip(), value_text.strip()


def parse_assignment(regs: Registers, item: str, raw: bool, *, replace: bool = False) -> Assignment:
    """Check one SELECTOR=VALUE through the runtime's one validation path (range, resolution, enum,
    bitfield widths and enums, access) before anything is built or sent."""
    selector, value_text = _split(item)
    reg = regs.resolve(selector)
    if not reg.access.writable:
        raise UsageError(f"{reg.label} is read-only")
    spec = regs.spec(reg)
    try:
        if reg.bitfields and ":" in value_text:
            base, named = parse_fields(spec, value_text)
            every = {b.name for b in reg.bitfields} <= set(named)
            if base is not None:
                note = f"{reg.label}: the fields not named keep the base word 0x{base:04X}'s bits"
            elif every or replace:
                note = f"{reg.label}: " + (
                    "the bits no field describes are 0"
                    if every
                    else "every field not named, and every bit no field describes, is 0 (--replace)"
                )
            else:
                return Assignment(item, reg, spec, None, named)
            return dataclasses.replace(Assignment(item, reg, spec, None, named).with_base(base or 0), note=note)
        number = parse_int(value_text, reg.label) if raw else value_to_raw(spec, value_text)
        check_raw(spec, number)
    except RangeError as exc:
        raise UsageError(str(exc)) from None
    return Assignment(item, reg, spec, number)


def parse_word_write(item: str) -> WordWrite:
    selector, value_text = _split(item)
    address = word_address(selector)
    words = tuple(parse_int(w, selector) for w in value_text.split(","))
    if any(not 0 <= w <= 0xFFFF for w in words):
        raise UsageError(f"{item}: a word is 0..0xFFFF (0..65535)")
    if address + len(words) > 0x10000:
        raise UsageError(f"{item}: {len(words)} words from 0x{address:04X} run past 0xFFFF")
    return WordWrite(item, address, words)


def _words_touched(item: Assignment | WordWrite) -> range:
    if isinstance(item, WordWrite):
        return range(item.address, item.address + len(item.words))
    return range(item.register.first_address, item.register.last_address + 1)


def check_conflicts(items: Sequence[Assignment | WordWrite]) -> None:
    """Two arguments that set the same word would build two frames that disagree: refuse them."""
    owner: dict[int, Assignment | WordWrite] = {}
    for item in items:
        for address in _words_touched(item):
            other = owner.get(address)
            if other is not None:
                raise UsageError(f"{other.argument!r} and {item.argument!r} both set the word at 0x{address:04X}; give one value per word")
            owner[address] = item


def parse_assignments(device: Device, items: Sequence[str], raw: bool, *, replace: bool = False) -> list[Assignment]:
    if not items:
        raise UsageError("write wants SELECTOR=VALUE [SELECTOR=VALUE ...]")
    regs = Registers(device)
    parsed = [parse_assignment(regs, item, raw, replace=replace) for item in items]
    check_conflicts(parsed)
    return parsed


def parse_word_writes(items: Sequence[str]) -> list[WordWrite]:
    if not items:
        raise UsageError("write --words wants ADDR=WORD[,WORD...] ...")
    parsed = [parse_word_write(item) for item in items]
    check_conflicts(parsed)
    return parsed


def write_blocks(device: Device, assignments: Sequence[Assignment], word_order: str | None = None) -> list[WriteBlock]:
    values = []
    for a in assignments:
        assert a.raw is not None, "fields must be merged into a base word first"
        values.append((a.spec.in_word_order(word_order), a.raw))
    try:
        return plan_writes(values, device.transport.max_write_registers, HOLDING.write_multiple in device.transport.function_codes)
    except ValueError as exc:
        raise UsageError(str(exc)) from None


def word_runs(device: Device, writes: Sequence[WordWrite]) -> list[tuple[int, tuple[int, ...]]]:
    """Contiguous words become one run (one 0x10, as mbpoll sends them); a lone word goes out as 0x06."""
    words = sorted((w.address + i, word) for w in writes for i, word in enumerate(w.words))
    runs: list[tuple[int, list[int]]] = []
    for address, word in words:
        if runs and runs[-1][0] + len(runs[-1][1]) == address:
            runs[-1][1].append(word)
        else:
            runs.append((address, [word]))
    t = device.transport
    for address, run in runs:
        if len(run) > 1 and HOLDING.write_multiple not in t.function_codes:
            raise UsageError(
                f"{device.info.model} has no function 0x{HOLDING.write_multiple:02X}: write the words at 0x{address:04X} one by one"
            )
        if len(run) > t.max_write_registers:
            raise UsageError(
                f"{len(run)} contiguous words from 0x{address:04X}: {device.info.model} writes at most {t.max_write_registers} per request"
            )
    return [(address, tuple(run)) for address, run in runs]


def block_frame(slave: int, address: int, words: Sequence[int], single: bool, space: str = DEFAULT_SPACE) -> bytes:
    if single:
        return build_write_single(slave, address, words[0], space=space)
    return build_write_multiple(slave, address, list(words), space=space)


def unnamed_fields(a: Assignment) -> list[str]:
    return [b.name for b in a.register.bitfields if a.fields is not None and b.name not in a.fields]


def write_frames(
    device: Device, items: Sequence[str], slave: int, raw: bool, *, replace: bool = False, word_order: str | None = None
) -> tuple[list[bytes], list[str]]:
    """Frames for SELECTOR=VALUE assignments (contiguous registers share one 0x10 frame), and notes
    that say what bits nobody named were set to."""
    check_slave(device, slave)
    parsed = parse_assignments(device, items, raw, replace=replace)
    for a in parsed:
        if a.raw is None:
            raise UsageError(
                f"{a.argument}: `frame` has no drive to read the other fields from; name every field "
                f"(missing: {', '.join(unnamed_fields(a))}), give a base word first ({a.register.name}=0x0000,...), or --replace (they become 0)"
            )
    notes = [a.note for a in parsed if a.note]
    frames = [block_frame(slave, b.address, b.words, b.single, b.space) for b in write_blocks(device, parsed, word_order)]
    return frames, notes


def write_words_frames(device: Device, items: Sequence[str], slave: int) -> list[bytes]:
    check_slave(device, slave)
    return [block_frame(slave, address, run, len(run) == 1) for address, run in word_runs(device, parse_word_writes(items))]


# -- commands ----------------------------------------------------------------------------


def find_command(device: Device, name: str) -> Any:
    wanted = name.strip().lower()
    command = next((c for c in device.commands if c.name == wanted), None)
    if command is None:
        known = ", ".join(c.name for c in device.commands) or "none"
        raise UsageError(f"unknown command {name!r}{suggest(name, [c.name for c in device.commands])} (commands: {known})")
    return command


def command_words(device: Device, name: str, argument: str | None, word_order: str | None = None) -> tuple[Any, list[int]]:
    command = find_command(device, name)
    try:
        raw = command.raw_value(None if argument is None else parse_int(argument, command.name))
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    spec = Registers(device).spec(command.register).in_word_order(word_order)
    return command, raw_to_words(spec, raw)


def command_frames(device: Device, name: str, argument: str | None, slave: int, word_order: str | None = None) -> list[bytes]:
    check_slave(device, slave)
    command, words = command_words(device, name, argument, word_order)
    return [block_frame(slave, command.register.address, words, len(words) == 1, command.register.space)]
