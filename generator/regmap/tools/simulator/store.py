"""The device's register memory and rules: what a read or a write does, and which exception it earns.

`DeviceStore` knows nothing of frames: it is given a space, an address and a count (or words, or
bits) and returns the words, or the Modbus exception code the real device answers (an address the
map does not document in that space, a register the simulated firmware lacks, half of a wide value,
read-only register, value out of range). The four tables (holding, input, coil, discrete input) are
one memory keyed on (space, address); a coil's or discrete input's "word" is its bit, 0 or 1.
Commands with a declared `effect` act (save to the state file, restore defaults, clear a register).

The firmware it plays is `--firmware` (`Quirks.firmware`), else the default of the map's firmware
register, else the newest version the map's gates name; the map's firmware register reports it, and
registers whose `firmware` gate does not admit it are absent (0x02, as undocumented addresses are).
A map without gates or firmware register plays no particular firmware: every register is present.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from regmap.diagnostics import UsageError
from regmap.model import Device, Register, WordOrder
from regmap.runtime_bridge import runtime_alignment, runtime_device, runtime_specs
from regmap.tools.output import write_output
from regmap_runtime.codec import RangeError, check_raw, raw_to_words, words_to_raw
from regmap_runtime.spaces import DEFAULT_SPACE
from regmap_runtime.spec import Raw, parse_version

from .faults import FaultPlan
from .quirks import Quirks

ILLEGAL_FUNCTION = 0x01
ILLEGAL_ADDRESS = 0x02
ILLEGAL_VALUE = 0x03
READ_CHECKS_KEPT = 4096  # reads whose address check is remembered


def slave_refusal(device: Device, slave: int) -> str | None:
    """Why `slave` cannot be this device's slave id (outside its map's range, or its broadcast id), else None."""
    t = device.transport
    if slave == t.broadcast_id or not t.slave_min <= slave <= t.slave_max:
        broadcast = f" ({t.broadcast_id} is the broadcast id)" if slave == t.broadcast_id else ""
        return f"{slave} is outside {t.slave_min}..{t.slave_max}, the slave ids of {device.info.model}{broadcast}"
    return None


class DeviceStore:
    """Register memory of one simulated device, with the map's rules."""

    def __init__(self, device: Device, slave: int, state_file: Path | None = None, quirks: Quirks | None = None) -> None:
        self.device = device
        self.quirks = quirks or Quirks()
        self.slave = slave
        self.state_file = state_file
        self.specs = {s.name: s for s in runtime_specs(device)}
        self.firmware = firmware_played(device, self.quirks.firmware)
        self.firmware_text = firmware_text(device, self.firmware, self.quirks.firmware) if self.firmware is not None else None
        # Registers the simulated firmware has (every register when no firmware is played).
        self.present = [
            r
            for r in device.registers
            if (self.firmware is None or r.firmware is None or r.firmware.admits(self.firmware[0])) and r.on_variant(self.quirks.variant)
        ]
        self.registers = {r.name: r for r in self.present}
        self.words: dict[tuple[str, int], int] = {}  # by (space, address)
        # Counts the changes of `words`: an answer worked out at one generation holds while it stays (the answer cache).
        self.generation = 0
        self.word_order = device.transport.word_order.value
        self.pending_after_read: dict[tuple[str, int], int] = {}
        self.alignment = runtime_alignment(device)
        self._unreadable: dict[tuple[str, int, int], int | None] = {}  # (space, address, count) -> what unreadable() says
        self.faults = FaultPlan()
        self.load_defaults()
        if state_file is not None and state_file.exists():
            self.load_state(state_file)

    # -- memory ------------------------------------------------------------------------------

    def spec(self, reg: Register) -> Any:
        """The register's codec in the word order the device uses right now (the map's word-order register can change it)."""
        return self.specs[reg.name].in_word_order(self.word_order)

    def follow_word_order_register(self) -> None:
        """Re-lay every 32-bit value when the word-order parameter changes: values stay, words swap."""
        control = self.device.transport.word_order_register
        if control is None or control.swaps:  # a swap acts on the write itself (swap_if_magic), not on what the register holds
            return
        setting = self.raw_of(control.register)
        wanted = "high_first" if setting == control.high_first else "low_first" if setting == control.low_first else self.word_order
        self.relay(wanted)

    def swap_if_magic(self, reg: Register, raw: Raw) -> None:
        """The map's swap value written to its word-order register: from now on the words of every float go the other way."""
        control = self.device.transport.word_order_register
        if control is not None and control.swaps and reg.name == control.register.name and isinstance(raw, int | float):
            self.relay(control.order_after(WordOrder(self.word_order), raw).value)

    def relay(self, wanted: str) -> None:
        """Lay every 32-bit value that follows the device's order in `wanted`: values stay, words swap."""
        if wanted == self.word_order:
            return
        moving = [r for r in self.present if r.wide and not r.word_order_fixed]
        values = {r.name: self.raw_of(r) for r in moving}
        self.word_order = wanted
        for reg in moving:
            self.store_raw(reg, values[reg.name])

    def covering(self, address: int, space: str) -> Register | None:
        """The register that owns `address` in `space`, if the simulated firmware has it."""
        reg = self.device.covering(address, space)
        return reg if reg is not None and reg.name in self.registers else None

    def store_raw(self, reg: Register, raw: Raw) -> None:
        words = raw_to_words(self.spec(reg), raw, with_pair=True)
        self.generation += 1
        for offset, word in enumerate(words):
            self.words[reg.space, reg.first_address + offset] = word

    def raw_of(self, reg: Register) -> Raw:
        spec = self.spec(reg)
        return words_to_raw(spec, [self.words.get((reg.space, reg.address + i), 0) for i in range(reg.words)])

    def load_defaults(self) -> None:
        self.words.clear()
        self.word_order = self.device.transport.word_order.value
        for reg in self.present:
            self.store_raw(reg, reg.default if reg.default is not None else self.rest_value(reg))
        fw = self.device.info.firmware_register
        if self.firmware is not None and self.firmware[1] is not None and fw is not None:
            self.store_raw(fw.register, self.firmware[1])
        control = self.device.transport.word_order_register
        if self.quirks.word_order is not None and control is not None and not control.swaps:
            setting = control.high_first if self.quirks.word_order == "high_first" else control.low_first
            assert setting is not None  # a register with a value per order
            self.store_raw(control.register, setting)
        elif self.quirks.word_order is not None:
            self.relay(self.quirks.word_order)
        self.follow_word_order_register()

    @staticmethod
    def rest_value(reg: Register) -> Raw:
        """What a register the map gives no default holds: 0 (0.0, empty text, off) where the map admits it, else its lowest admitted value."""
        if reg.type.is_string:
            return ""
        if reg.type.is_bool:
            return 0
        if reg.type.is_float and reg.enum is not None:  # a setting coded as a float: a member
            values = sorted(m.value for m in reg.enum.members)
            return 0.0 if 0 in values else float(values[0])
        if reg.type.is_float:
            return 0.0 if reg.raw_min <= 0 <= reg.raw_max else float(reg.raw_min)
        members = sorted(m.value for m in reg.enum.members) if reg.enum is not None and not reg.bitfields else []
        admitted = [v for v in members if reg.raw_min <= v <= reg.raw_max] if members else []
        if (not members or 0 in admitted) and reg.raw_min <= 0 <= reg.raw_max:
            return 0
        return admitted[0] if admitted else int(reg.raw_min)

    def persistent(self) -> list[Register]:
        return [r for r in self.present if r.access.readable and r.access.writable]

    def save_state(self) -> None:
        if self.state_file is None:
            return
        data = {r.name: self.raw_of(r) for r in self.persistent()}
        text = json.dumps(
            {"device": self.device.id, "map_version": self.device.info.map_version, "registers": data}, indent=1, sort_keys=True
        )
        write_output(self.state_file, text.encode("utf-8"), "--state")  # the state file is never left half-written

    def load_state(self, path: Path) -> None:
        try:
            data = json.loads(path.read_text(encoding="utf-8"))
            saved = data["registers"]
            if not isinstance(saved, dict):
                raise TypeError("registers is not an object")
        except (OSError, ValueError, KeyError, TypeError) as exc:
            raise UsageError(f"{path}: not a regmap simulator state file ({exc})") from None
        control = self.device.transport.word_order_register
        if control is not None and isinstance(saved.get(control.register.name), int):
            self.store_raw(control.register, saved[control.register.name])
            self.follow_word_order_register()
        for name, raw in saved.items():
            reg = self.registers.get(name)
            if reg is not None and self._storable(reg, raw):
                self.store_raw(reg, raw)

    def _storable(self, reg: Register, raw: object) -> bool:
        """A saved value of the register's kind that its words can hold (a state file edited by hand may hold anything)."""
        if reg.type.is_string:
            kind_ok = isinstance(raw, str)
        elif reg.type.is_float:
            kind_ok = isinstance(raw, int | float) and not isinstance(raw, bool)
        elif reg.type.is_bool:
            kind_ok = raw in (0, 1)  # 0/1 or true/false
        else:
            kind_ok = isinstance(raw, int) and not isinstance(raw, bool)
        if not kind_ok:
            return False
        assert isinstance(raw, int | float | str)
        try:
            raw_to_words(self.spec(reg), raw)
        except RangeError:
            return False
        return True

    # -- the rules ---------------------------------------------------------------------------

    def failing(self) -> bool:
        """The injected `exception` fault takes this request (`--fault exception`: device failure, 0x04 unless told)."""
        return self.faults.kind != "none" and self.faults.take(("exception",)) == "exception"

    def unreadable(self, address: int, count: int, space: str = DEFAULT_SPACE) -> int | None:
        """The exception code a read of these addresses gets (an undocumented or write-only one), or None.
        The answer never changes while the simulator runs (the firmware played is fixed), so the latest are kept."""
        key = (space, address, count)
        if key in self._unreadable:
            return self._unreadable[key]
        gaps = self.device.transport.tolerates_gaps or self.quirks.answer_gaps
        refused = None
        if self.alignment is not None and not self.alignment.allows(space, address, count):
            refused = self.alignment.exception or ILLEGAL_ADDRESS  # the code the map records; else the address error
        for a in range(address, address + count if refused is None else address):
            reg = self.covering(a, space)
            if (reg is None and not gaps) or (reg is not None and not reg.access.readable):
                refused = ILLEGAL_ADDRESS
                break
        if len(self._unreadable) >= READ_CHECKS_KEPT:  # a client sweeping addresses keeps memory bounded
            self._unreadable.clear()
        self._unreadable[key] = refused
        return refused

    def read(self, address: int, count: int, space: str = DEFAULT_SPACE) -> list[int] | int:
        """The words at `address` of `space`, or the exception code the device answers."""
        refused = self.unreadable(address, count, space)
        if refused is not None:
            return refused
        if self.failing():  # the spec's order: the address is checked before the device fails to carry the request out
            return self.faults.exception_code
        words = self.words
        values = [words.get((space, a), 0) for a in range(address, address + count)]
        if self.pending_after_read:
            for a in range(address, address + count):
                if (space, a) in self.pending_after_read:
                    self.generation += 1
                    self.words[space, a] = self.pending_after_read.pop((space, a))
        return values

    def write(self, address: int, words: list[int], space: str = DEFAULT_SPACE) -> int | None:
        """Store `words` from `address` of `space` (all or nothing); None when done, else the exception code."""
        end = address + len(words)
        touched: list[Register] = []
        for a in range(address, end):
            reg = self.covering(a, space)
            if reg is None:
                if self.device.transport.tolerates_gaps:
                    continue
                return ILLEGAL_ADDRESS
            if reg not in touched:
                touched.append(reg)
        if self.failing():
            return self.faults.exception_code
        updates: list[tuple[Register, Raw]] = []
        for reg in touched:
            own = range(reg.address, reg.last_address + 1)
            covered = [a for a in own if address <= a < end]
            if not covered:
                continue  # only the unused high word of a pair was written
            if len(covered) != len(own):
                return ILLEGAL_ADDRESS  # half of a wide value (32/64 bits, a string)
            if not reg.access.writable:
                return ILLEGAL_VALUE
            spec = self.spec(reg)
            try:
                raw = words_to_raw(spec, [words[a - address] for a in own])
            except ValueError:  # a bit that is neither 0 nor 1 (the PDU layer sends only 0/1)
                return ILLEGAL_VALUE
            if isinstance(raw, str) and "\ufffd" in raw:
                return ILLEGAL_VALUE  # bytes that are no text in the register's encoding: nothing a device could store as text
            if not self._is_command(reg, raw) and not self._acceptable(reg, spec, raw):
                return ILLEGAL_VALUE
            updates.append((reg, raw))
        for reg, raw in updates:
            self.store_raw(reg, raw)
            self._act(reg, raw)
            self.swap_if_magic(reg, raw)
        self.follow_word_order_register()
        return None

    @staticmethod
    def _acceptable(reg: Register, spec: Any, raw: Raw) -> bool:
        """The one validation path shared with the client and the CLI: `check_raw` (range, enum)."""
        try:
            check_raw(spec, raw)
        except RangeError:
            return False
        # Until runtime specs carry enums for every register, the map's enum is checked here too.
        return reg.enum is None or bool(reg.bitfields) or (isinstance(raw, int | float) and reg.enum.by_value(raw) is not None)

    def _is_command(self, reg: Register, raw: Raw) -> bool:
        return any(
            c.register.name == reg.name
            and (c.value == raw or (isinstance(raw, int) and c.argument and c.value + c.argument.min <= raw <= c.value + c.argument.max))
            for c in self.device.commands
        )

    def _act(self, reg: Register, raw: Raw) -> None:
        for command in self.device.commands:
            if command.register.name != reg.name or command.value != raw or command.effect is None:
                continue
            effect = command.effect
            if effect.kind == "save":
                self.save_state()
                if effect.register is not None:
                    self.store_raw(effect.register, effect.value)
                    if effect.after_read is not None:
                        self.pending_after_read[effect.register.space, effect.register.address] = effect.after_read
            elif effect.kind == "restore_defaults":
                self.load_defaults()
            elif effect.kind == "clear" and effect.register is not None:
                self.store_raw(effect.register, effect.value)


def firmware_raw(device: Device, version: str) -> Raw:
    """The raw value of the map's firmware register that reports `version` (its format: decimal with
    N decimals, major_minor, string); a version the register cannot report is a UsageError."""
    fw = device.info.firmware_register
    assert fw is not None
    spec = runtime_device(device)
    wanted = parse_version(version)
    raw: Raw
    if fw.format == "string":
        raw = version
    elif fw.format == "major_minor":
        if len(wanted) != 2 or not all(0 <= part <= 0xFF for part in wanted):
            raise UsageError(f"--firmware {version}: {fw.register.label} reports MAJOR.MINOR, each 0..255 (major_minor)")
        raw = wanted[0] << 8 | wanted[1]
    elif fw.decimals == 0:
        if len(wanted) != 1:
            raise UsageError(f"--firmware {version}: {fw.register.label} reports a whole number (decimal, no decimals)")
        raw = wanted[0]
    else:
        scale = 10**fw.decimals
        if len(wanted) != 2 or wanted[1] >= scale:
            raise UsageError(
                f"--firmware {version}: {fw.register.label} reports MAJOR.MINOR with MINOR below {scale} (decimal, {fw.decimals} decimals)"
            )
        raw = wanted[0] * scale + wanted[1]
    reg_spec = next(s for s in spec.registers if s.name == fw.register.name)
    try:
        check_raw(reg_spec, raw)
    except RangeError as exc:
        raise UsageError(f"--firmware {version}: {exc}") from None
    if spec.firmware_version(raw) != wanted:
        raise UsageError(f"--firmware {version}: {fw.register.label} cannot report it ({fw.format})")
    return raw


def newest_firmware(device: Device) -> str | None:
    """The newest firmware version the map's gates name (a `from` or an `until`), as written; None without gates."""
    named = {v for r in device.registers if r.firmware is not None for v in (r.firmware.first, r.firmware.until) if v is not None}
    return max(named, key=parse_version) if named else None


def firmware_played(device: Device, version: str | None) -> tuple[tuple[int, ...], Raw | None] | None:
    """(version, the firmware register's raw value) the simulator plays: `--firmware`; else the default
    of the map's firmware register; else the newest firmware the map's gates name (the device as it
    ships today: every `from` register present, every `until` one gone); None for a map without
    gates and without a firmware register default (every register is present)."""
    fw = device.info.firmware_register
    if version is not None:
        try:
            wanted = parse_version(version)
        except ValueError:
            raise UsageError(f"--firmware {version!r} is not a version (numbers with dots: 2, 2.10, 1.2.3)") from None
        return wanted, firmware_raw(device, version) if fw is not None else None
    if fw is not None and fw.register.default is not None:
        return runtime_device(device).firmware_version(fw.register.default), fw.register.default
    newest = newest_firmware(device)
    if newest is None:
        return None
    try:
        raw = firmware_raw(device, newest) if fw is not None else None
    except UsageError:
        raw = None  # a gate the firmware register cannot report (a map to fix): the gates still apply
    return parse_version(newest), raw


def firmware_text(device: Device, played: tuple[tuple[int, ...], Raw | None], given: str | None) -> str:
    """The version played as the device's documents write it (its firmware register's raw value as the
    runtime reads it: 2 decimals give "2.00", major_minor "2.3"), else as given."""
    version, raw = played
    if raw is not None:
        return runtime_device(device).firmware_text(raw)
    return given if given is not None else ".".join(str(part) for part in version)
