"""Building request frames for field engineers: `regmap frame`, and the values `regmap write` sends.

Everything goes through the runtime's codec, checks and planner, so a frame printed here is byte
for byte the frame the generated client sends, and a value the client refuses is refused here.
"""

from __future__ import annotations

import dataclasses
import itertools
import struct
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from regmap.core.decoding import FUNCTION_NAMES
from regmap.core.text import article, space_label
from regmap.diagnostics import UsageError
from regmap.model import ByteOrder, Device, Register
from regmap.runtime_bridge import read_plan, runtime_alignment
from regmap.tools.selectors import Item, Located, Registers, check_slave, locate, parse_int, parse_items, suggest
from regmap_runtime.codec import RangeError, check_raw, merge_fields, parse_fields, raw_to_words, value_to_raw
from regmap_runtime.plan import WriteBlock, plan_writes
from regmap_runtime.rtu import (
    DEVICE_ID_CODES,
    DIAGNOSTICS,
    ENCAPSULATED_INTERFACE,
    READ_WRITE_MULTIPLE,
    REPORT_SERVER_ID,
    FrameError,
    build_echo,
    build_mask_write,
    build_read,
    build_read_device_id,
    build_read_write,
    build_report_server_id,
    build_write_multiple,
    build_write_single,
)
from regmap_runtime.spaces import DEFAULT_SPACE, MASK_WRITE_REGISTER, SPACES
from regmap_runtime.spec import Raw, RegisterSpec
from regmap_runtime.types import swap_bytes

# -- reads -------------------------------------------------------------------------------


def read_frames(device: Device, regs: Registers, items: Sequence[Item], slave: int) -> list[bytes]:
    """Read the registers the items name (a COUNT: that many of the map's readable registers of its space
    from the selector on), with the fewest requests."""
    check_slave(device, slave, reading=True)
    blocks = read_plan(device, regs.select(items))
    for block in blocks:
        _function(device, SPACES[block.space].read)
    return [build_read(slave, b.address, b.count, space=b.space) for b in blocks]


def _function(device: Device, function: int) -> None:
    """A function the device's map does not list is refused: the device would answer exception 0x01."""
    if function not in device.transport.function_codes:
        listed = " ".join(f"0x{c:02X}" for c in device.transport.function_codes)
        raise UsageError(f"{device.info.model} has no function 0x{function:02X} ({FUNCTION_NAMES[function]}); its map lists {listed}")


@dataclass(frozen=True)
class WordRead:
    """`read --words ADDR [COUNT]`: one read of COUNT words (bits, in a bit space) of `space`, documented or not."""

    address: int
    count: int
    space: str = DEFAULT_SPACE
    note: str | None = None  # how a -r or Modicon address was read


def word_reads(device: Device, items: Sequence[Item], space: str | None = None, *, modicon: bool = False) -> list[WordRead]:
    """One read per ADDR [COUNT] item (one word without a COUNT), in the item's space (Modicon's, -t's, else holding)."""
    t = device.transport
    alignment = runtime_alignment(device)
    reads = []
    for item in items:
        located = item.located or word_location(item.selector, modicon=modicon, space=space)
        read = WordRead(located.address, 1 if item.count is None else item.count, located.space or space or DEFAULT_SPACE, located.note)
        facts = SPACES[read.space]
        _function(device, facts.read)
        limit = t.max_read_coils if facts.bits else t.max_read_registers
        unit = "bits" if facts.bits else "registers"
        if not 1 <= read.count <= limit:
            raise UsageError(f"COUNT {read.count} is outside 1..{limit} ({device.info.model} reads at most {limit} {unit} per request)")
        if read.address + read.count > 0x10000:
            raise UsageError(f"{read.count} {unit} from 0x{read.address:04X} run past 0xFFFF")
        why = None if alignment is None else alignment.refusal(read.space, read.address, read.count)
        if why is not None:
            raise UsageError(f"{device.info.model}: {why}")
        reads.append(read)
    return reads


def read_words_frame(device: Device, address_text: str, count: int, slave: int, space: str = DEFAULT_SPACE) -> bytes:
    """`read --words ADDR COUNT`: one read of COUNT words (bits, in a bit space) of `space`, documented or not."""
    (built,) = word_read_frames(device, word_reads(device, [Item(address_text, count)], space), slave)
    return built


def word_read_frames(device: Device, reads: Sequence[WordRead], slave: int) -> list[bytes]:
    check_slave(device, slave, reading=True)
    return [build_read(slave, r.address, r.count, space=r.space) for r in reads]


def word_location(text: str, *, modicon: bool = False, space: str | None = None) -> Located:
    located = locate(text, modicon=modicon, space=space)
    if located is None:
        raise UsageError(f"{text!r} is not a Modbus address (0x0191, 0191h or decimal 401)")
    return located


# -- writes ------------------------------------------------------------------------------


@dataclass(frozen=True)
class Assignment:
    """One SELECTOR=VALUE argument, checked: either a register's complete raw value, or (for a
    bitfield register given some fields) the fields to merge into the word the drive holds."""

    argument: str
    register: Register
    spec: RegisterSpec[Any]
    raw: Raw | None  # None until the named fields are merged into a base word
    fields: dict[str, int] | None = None  # named bitfields, when not every field is named
    note: str | None = None  # what the bits nobody named were set to
    located: str | None = None  # how a Modicon address selector was read

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
    """`--words ADDR=WORD[,WORD...]`: words (bits, in a bit space) at a Modbus address of `space`."""

    argument: str
    address: int
    words: tuple[int, ...]
    space: str = DEFAULT_SPACE
    located: str | None = None  # how a Modicon address was read


def _split(item: str) -> tuple[str, str]:
    selector, sep, value_text = item.partition("=")
    if not sep or not selector.strip() or not value_text.strip():
        raise UsageError(f"write wants SELECTOR=VALUE, got {item!r}")
    return selector.strip(), value_text.strip()


def read_only(reg: Register) -> str | None:
    """Why a register cannot be written, or None: its space has no write function, or the map says read-only."""
    facts = reg.space_info
    if not facts.writable:
        return (
            f"{reg.label} is {article(space_label(reg.space))}: {facts.title} are read-only "
            f"(function 0x{facts.read:02X} reads them, no function writes them)"
        )
    if not reg.access.writable:
        return f"{reg.label} is read-only"
    return None


def _unquoted(text: str) -> str:
    """Text given as "abc" or 'abc' (quoted so that spaces or an empty text survive the shell)."""
    if len(text) >= 2 and text[0] == text[-1] and text[0] in "\"'":
        return text[1:-1]
    return text


def parse_raw(spec: RegisterSpec[Any], text: str, label: str) -> Raw:
    """A raw register value from the command line (`--raw`): an integer, a float for a float
    register, text for a string, 0/1 (on/off) for a bit."""
    info = spec.type_info
    if info.is_string:
        return _unquoted(text)
    if info.is_bool:
        return value_to_raw(spec, text)
    if info.is_float:
        try:
            return float(text)
        except ValueError:
            raise UsageError(f"{label}: {text!r} is not a number") from None
    return parse_int(text, label)


def parse_assignment(regs: Registers, item: str, raw: bool, *, replace: bool = False) -> Assignment:
    """Check one SELECTOR=VALUE through the runtime's one validation path (range, resolution, enum,
    bitfield widths and enums, text that fits, access) before anything is built or sent."""
    selector, value_text = _split(item)
    said = len(regs.notes)
    reg = regs.resolve(selector)
    refused = read_only(reg)
    if refused is not None:
        raise UsageError(refused)
    spec = regs.spec(reg)
    located = regs.notes[said] if len(regs.notes) > said else None
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
                return Assignment(item, reg, spec, None, named, located=located)
            return dataclasses.replace(Assignment(item, reg, spec, None, named).with_base(base or 0), note=note, located=located)
        if raw:
            number = parse_raw(spec, value_text, reg.label)
        elif reg.scale_from is not None:
            raise RangeError(f"{reg.label}: value = raw x 10^{reg.scale_from}, read at run time; give the raw value (--raw)")
        else:
            number = value_to_raw(spec, _unquoted(value_text) if spec.type_info.is_string else value_text)
        check_raw(spec, number)
    except RangeError as exc:
        raise UsageError(str(exc)) from None
    return Assignment(item, reg, spec, number, located=located)


_BIT_WORDS = {"0": 0, "1": 1, "off": 0, "on": 1, "false": 0, "true": 1}


def parse_word_write(item: str, space: str | None = DEFAULT_SPACE, *, modicon: bool = False) -> WordWrite:
    selector, value_text = _split(item)
    located = word_location(selector, modicon=modicon, space=space)
    address, space = located.address, located.space or DEFAULT_SPACE
    bits = SPACES[space].bits
    if bits:
        try:
            words = tuple(_BIT_WORDS[w.strip().lower()] for w in value_text.split(","))
        except KeyError:
            raise UsageError(f"{item}: a {space_label(space)} is 0 or 1 (on/off), as in {selector}=1,0,1") from None
    else:
        words = tuple(parse_int(w, selector) for w in value_text.split(","))
        if any(not 0 <= w <= 0xFFFF for w in words):
            raise UsageError(f"{item}: a word is 0..0xFFFF (0..65535)")
    if address + len(words) > 0x10000:
        raise UsageError(f"{item}: {len(words)} {'bits' if bits else 'words'} from 0x{address:04X} run past 0xFFFF")
    return WordWrite(item, address, words, space, located.note)


def _words_touched(item: Assignment | WordWrite) -> list[tuple[str, int]]:
    if isinstance(item, WordWrite):
        return [(item.space, a) for a in range(item.address, item.address + len(item.words))]
    return [(item.register.space, a) for a in range(item.register.first_address, item.register.last_address + 1)]


def check_conflicts(items: Sequence[Assignment | WordWrite]) -> None:
    """Two arguments that set the same word would build two frames that disagree: refuse them."""
    owner: dict[tuple[str, int], Assignment | WordWrite] = {}
    for item in items:
        for key in _words_touched(item):
            other = owner.get(key)
            if other is not None:
                what = "word" if key[0] == DEFAULT_SPACE else space_label(key[0])
                raise UsageError(
                    f"{other.argument!r} and {item.argument!r} both set the {what} at 0x{key[1]:04X}; give one value per {what}"
                )
            owner[key] = item


def parse_assignments(
    device: Device, items: Sequence[str], raw: bool, *, replace: bool = False, space: str | None = None, modicon: bool = False
) -> list[Assignment]:
    if not items:
        raise UsageError("write wants SELECTOR=VALUE [SELECTOR=VALUE ...]")
    regs = Registers(device, space, modicon=modicon)
    parsed = [parse_assignment(regs, item, raw, replace=replace) for item in items]
    check_conflicts(parsed)
    return parsed


def parse_word_writes(items: Sequence[str], space: str | None = DEFAULT_SPACE, *, modicon: bool = False) -> list[WordWrite]:
    """`--words` writes of one space: -t's, or the one the Modicon numbers name (holding by default)."""
    if not items:
        raise UsageError("write --words wants ADDR=WORD[,WORD...] ...")
    if space is not None:
        _writable(space)
    parsed = [parse_word_write(item, space, modicon=modicon) for item in items]
    spaces = list(dict.fromkeys(w.space for w in parsed))
    if len(spaces) > 1:
        raise UsageError(f"--words writes one data space at a time; these name {' and '.join(SPACES[s].title for s in spaces)}")
    _writable(spaces[0])
    check_conflicts(parsed)
    return parsed


def _writable(space: str) -> None:
    facts = SPACES[space]
    if not facts.writable:
        raise UsageError(f"{facts.title} are read-only: no function writes them (function 0x{facts.read:02X} reads them)")


def write_function(device: Device, space: str, count: int) -> bool:
    """Whether `count` values of `space` go out with the single-write function (0x06/0x05): one value,
    and the device has it; else the multiple write (0x10/0x0F), which the device must have."""
    facts = SPACES[space]
    single, multiple = facts.write_single, facts.write_multiple
    assert single is not None and multiple is not None
    codes = device.transport.function_codes
    if count == 1 and (single in codes or multiple not in codes):
        _function(device, single)
        return True
    _function(device, multiple)
    return False


def write_blocks(device: Device, assignments: Sequence[Assignment], word_order: str | None = None) -> list[WriteBlock]:
    """The requests that write these values: contiguous values of one space share a request, space by space."""
    t = device.transport
    by_space: dict[str, list[tuple[RegisterSpec[Any], Raw]]] = {}
    for a in assignments:
        assert a.raw is not None, "fields must be merged into a base word first"
        by_space.setdefault(a.register.space, []).append((a.spec.in_word_order(word_order), a.raw))
    blocks: list[WriteBlock] = []
    try:
        for space in (s for s in SPACES if s in by_space):
            multiple = SPACES[space].write_multiple in t.function_codes
            blocks += plan_writes(by_space[space], t.max_write_registers, multiple, max_bits=t.max_write_coils)
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    return blocks


def word_runs(device: Device, writes: Sequence[WordWrite]) -> list[tuple[int, tuple[int, ...]]]:
    """Contiguous words become one run (one 0x10, as mbpoll sends them; bits: one 0x0F); a lone word goes out as 0x06 (0x05)."""
    space = writes[0].space if writes else DEFAULT_SPACE
    facts = SPACES[space]
    words = sorted((w.address + i, word) for w in writes for i, word in enumerate(w.words))
    runs: list[tuple[int, list[int]]] = []
    for address, word in words:
        if runs and runs[-1][0] + len(runs[-1][1]) == address:
            runs[-1][1].append(word)
        else:
            runs.append((address, [word]))
    t = device.transport
    limit = t.max_write_coils if facts.bits else t.max_write_registers
    unit = "coils" if facts.bits else "words"
    for address, run in runs:
        if len(run) > 1 and facts.write_multiple not in t.function_codes:
            raise UsageError(
                f"{device.info.model} has no function 0x{facts.write_multiple:02X}: write the {unit} at 0x{address:04X} one by one"
            )
        if len(run) > limit:
            raise UsageError(f"{len(run)} contiguous {unit} from 0x{address:04X}: {device.info.model} writes at most {limit} per request")
        write_function(device, space, len(run))
    return [(address, tuple(run)) for address, run in runs]


def block_frame(slave: int, address: int, words: Sequence[int], single: bool, space: str = DEFAULT_SPACE) -> bytes:
    """The request of one write block: 0x06/0x10 for registers, 0x05 (FF 00 / 00 00) / 0x0F (packed bits) for coils."""
    try:
        if single:
            return build_write_single(slave, address, words[0], space=space)
        return build_write_multiple(slave, address, list(words), space=space)
    except FrameError as exc:
        raise UsageError(str(exc)) from None


def unnamed_fields(a: Assignment) -> list[str]:
    return [b.name for b in a.register.bitfields if a.fields is not None and b.name not in a.fields]


def write_frames(
    device: Device,
    items: Sequence[str],
    slave: int,
    raw: bool,
    *,
    replace: bool = False,
    word_order: str | None = None,
    space: str | None = None,
    modicon: bool = False,
) -> tuple[list[bytes], list[str]]:
    """Frames for SELECTOR=VALUE assignments (contiguous registers share one 0x10 frame, contiguous
    coils one 0x0F), and notes that say how Modicon addresses were read and what bits nobody named were set to."""
    check_slave(device, slave)
    parsed = parse_assignments(device, items, raw, replace=replace, space=space, modicon=modicon)
    for a in parsed:
        if a.raw is None:
            raise UsageError(
                f"{a.argument}: `frame` has no drive to read the other fields from; name every field "
                f"(missing: {', '.join(unnamed_fields(a))}), give a base word first ({a.register.name}=0x0000,...), or --replace (they become 0)"
            )
    notes = [n for a in parsed for n in (a.located, a.note) if n]
    blocks = write_blocks(device, parsed, word_order)
    return [block_frame(slave, b.address, b.words, write_function(device, b.space, len(b.words)), b.space) for b in blocks], notes


def write_words_frames(device: Device, items: Sequence[str], slave: int, space: str = DEFAULT_SPACE) -> list[bytes]:
    return word_write_frames(device, parse_word_writes(items, space), slave)


def word_write_frames(device: Device, writes: Sequence[WordWrite], slave: int) -> list[bytes]:
    """The frames of parsed `--words` writes (one space)."""
    check_slave(device, slave)
    space = writes[0].space
    runs = word_runs(device, writes)
    return [block_frame(slave, address, run, write_function(device, space, len(run)), space) for address, run in runs]


# -- commands ----------------------------------------------------------------------------


def find_command(device: Device, name: str) -> Any:
    wanted = name.strip().lower()
    command = next((c for c in device.commands if c.name == wanted), None)
    if command is None:
        known = ", ".join(c.name for c in device.commands) or "none"
        raise UsageError(f"unknown command {name!r}{suggest(name, [c.name for c in device.commands])} (commands: {known})")
    return command


def command_words(
    device: Device, name: str, argument: str | None, word_order: str | None = None, confirm: str | None = None
) -> tuple[Any, list[int]]:
    """The command and the words it writes; a destructive one only with `confirm` repeating its name."""
    command = find_command(device, name)
    if confirm is not None and confirm != command.name:
        raise UsageError(f"--confirm {confirm} does not name the command sent ({command.name})")
    if command.destructive and confirm is None:
        raise UsageError(
            f"{command.name} is destructive ({command.title}: the map marks it as losing data or state); "
            f"to send it, repeat its name: --confirm {command.name}"
        )
    takes = command.argument
    if takes is None and argument is not None:
        raise UsageError(f"command {command.name} takes no argument, got {argument!r}")
    if takes is not None and argument is None:
        raise UsageError(f"command {command.name} needs an argument: {takes.name} ({takes.min}..{takes.max})")
    try:
        raw = command.raw_value(None if argument is None else parse_int(argument, command.name))
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    spec = Registers(device).spec(command.register).in_word_order(word_order)
    return command, raw_to_words(spec, raw)


def command_frames(
    device: Device, name: str, argument: str | None, slave: int, word_order: str | None = None, confirm: str | None = None
) -> list[bytes]:
    check_slave(device, slave)
    command, words = command_words(device, name, argument, word_order, confirm)
    return [block_frame(slave, command.register.address, words, len(words) == 1, command.register.space)]


# -- functions beyond reads and writes: 0x08, 0x11, 0x16, 0x17, 0x2B/0x0E ----------------


def echo_frame(device: Device, slave: int, word: str | None = None) -> bytes:
    """Diagnostics 0x08 sub-function 0x0000 (return query data) with one word of data (A5 37 unless given)."""
    _function(device, DIAGNOSTICS)
    check_slave(device, slave, reading=True)
    value = 0xA537 if word is None else parse_int(word, "the query data")
    return _built(lambda: build_echo(slave, value))


def server_id_frame(device: Device, slave: int) -> bytes:
    _function(device, REPORT_SERVER_ID)
    check_slave(device, slave, reading=True)
    return _built(lambda: build_report_server_id(slave))


def identification_frame(device: Device, slave: int, what: str | None = None) -> bytes:
    """Read device identification: a stream (basic, regular, extended) from object 0, or one object by its id."""
    _function(device, ENCAPSULATED_INTERFACE)
    check_slave(device, slave, reading=True)
    wanted = (what or "basic").strip().lower()
    if wanted in DEVICE_ID_CODES and wanted != "individual":
        return _built(lambda: build_read_device_id(slave, DEVICE_ID_CODES[wanted]))
    object_id = parse_int(wanted, "identification")
    return _built(lambda: build_read_device_id(slave, DEVICE_ID_CODES["individual"], object_id))


def mask_frames(device: Device, items: Sequence[str], slave: int, *, words: bool = False, modicon: bool = False) -> list[bytes]:
    """Mask write register (0x16): SELECTOR=FIELD:VALUE,... sets the named bitfields of a one-word holding
    register and keeps every other bit (the device applies it); --words ADDR=AND,OR sends the masks as given."""
    _function(device, MASK_WRITE_REGISTER)
    check_slave(device, slave)
    if not items:
        raise UsageError("mask wants SELECTOR=FIELD:VALUE,... (or --words ADDR=AND,OR)")
    out = []
    for item in items:
        if words:
            write = parse_word_write(item, DEFAULT_SPACE, modicon=modicon)
            if len(write.words) != 2:
                raise UsageError(f"{item}: mask --words wants ADDR=AND,OR (two words)")
            masks = (write.words[0], write.words[1])
            address = write.address
        else:
            a = parse_assignment(Registers(device, DEFAULT_SPACE, modicon=modicon), item, raw=False)
            address, masks = a.register.address, _field_masks(a)
        out.append(_built(lambda address=address, masks=masks: build_mask_write(slave, address, *masks)))
    return out


def _field_masks(a: Assignment) -> tuple[int, int]:
    """The AND and OR masks that set the assignment's named fields (all of them when every field was given)."""
    reg = a.register
    if reg.space != DEFAULT_SPACE or reg.words != 1 or not reg.bitfields:
        raise UsageError(f"{a.argument}: a mask write changes fields of a one-word holding register with bitfields; {reg.label} is none")
    named_fields = a.fields if a.fields is not None else {b.name: 0 for b in reg.bitfields}
    named = sum(b.mask for b in reg.bitfields if b.name in named_fields)
    raw = merge_fields(a.spec, 0, a.fields) if a.fields is not None else int(a.raw or 0)
    and_mask, or_mask = ~named & 0xFFFF, raw & named
    if reg.byte_order is not ByteOrder.HIGH_FIRST:  # the device applies the masks to the word as it travels
        and_mask, or_mask = swap_bytes([and_mask, or_mask])
    return and_mask, or_mask


def read_write_frame(
    device: Device,
    items: Sequence[str],
    slave: int,
    raw: bool,
    *,
    words: bool = False,
    modicon: bool = False,
    word_order: str | None = None,
) -> tuple[bytes, list[str]]:
    """Read/write multiple registers (0x17): the items without `=` name the read (SELECTOR [COUNT], or with
    --words ADDR COUNT), the assignments the write, checked as `write` checks them; both one run of holding registers."""
    _function(device, READ_WRITE_MULTIPLE)
    check_slave(device, slave)
    reading = [item for item in items if "=" not in item]
    writing = [item for item in items if "=" in item]
    if not reading or not writing:
        raise UsageError("write-read wants what to read (SELECTOR [COUNT]) and what to write (SELECTOR=VALUE ...)")
    notes: list[str] = []
    parsed = parse_items(reading, modicon=modicon, space=DEFAULT_SPACE)
    if words:
        if len(parsed) != 1:
            raise UsageError("write-read --words reads one ADDR COUNT")
        (read,) = word_reads(device, parsed, DEFAULT_SPACE, modicon=modicon)
        read_at, read_count = read.address, read.count
        write_at, written = _one_run(writing, modicon)
    else:
        regs = Registers(device, DEFAULT_SPACE, modicon=modicon)
        blocks = read_plan(device, regs.select(parsed))
        if len(blocks) != 1:
            raise UsageError(f"write-read reads one block: these registers need {len(blocks)} requests")
        read_at, read_count = blocks[0].address, blocks[0].count
        assignments = parse_assignments(device, writing, raw, space=DEFAULT_SPACE, modicon=modicon)
        incomplete = [a for a in assignments if a.raw is None]
        if incomplete:
            raise UsageError(f"{incomplete[0].argument}: name every field of a bitfield register in a write-read (nothing is read first)")
        planned = write_blocks(device, assignments, word_order)
        if len(planned) != 1:
            raise UsageError("write-read writes one run of adjacent holding registers; these are not adjacent")
        write_at, written = planned[0].address, tuple(planned[0].words)
        notes = regs.notes + [n for a in assignments for n in (a.located, a.note) if n]
    return _built(lambda: build_read_write(slave, read_at, read_count, write_at, list(written))), notes


def _one_run(items: Sequence[str], modicon: bool) -> tuple[int, tuple[int, ...]]:
    """--words writes of a write-read: contiguous words, one run."""
    writes = parse_word_writes(items, DEFAULT_SPACE, modicon=modicon)
    flat = sorted((w.address + i, word) for w in writes for i, word in enumerate(w.words))
    if any(b[0] != a[0] + 1 for a, b in itertools.pairwise(flat)):
        raise UsageError("write-read --words writes one run of adjacent words")
    return flat[0][0], tuple(word for _, word in flat)


def _built(build: Any) -> bytes:
    try:
        frame: bytes = build()
    except FrameError as exc:
        raise UsageError(str(exc)) from None
    return frame


def mbap_adu(frame: bytes, transaction: int) -> bytes:
    """The Modbus TCP ADU that carries an RTU frame's request: MBAP header (unit = the slave id), PDU, no CRC."""
    return struct.pack(">HHHB", transaction & 0xFFFF, 0, len(frame) - 2, frame[0]) + frame[1:-2]
