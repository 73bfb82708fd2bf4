"""What several back ends need from the model in the same form: runtime specs and the read plan.

The read plan is computed once, by the very planner the runtime uses, so the Python client's
`read_all()`, the C read-plan tables and the benchmarks agree request for request.
"""

from __future__ import annotations

import dataclasses
import enum
import weakref
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

from regmap.model import ByteOrder, Device, EnumType, PollClass, Register
from regmap.records import dataclass
from regmap_runtime.align import Alignment
from regmap_runtime.plan import ReadBlock, plan_reads
from regmap_runtime.profile import DeviceProfile
from regmap_runtime.spaces import MAX_READ_BITS, MAX_WRITE_BITS, SPACES
from regmap_runtime.spec import BitfieldSpec, DeviceSpec, RegisterSpec
from regmap_runtime.types import TYPES

if TYPE_CHECKING:  # only a plant's run imports the plant model (tests/project/test_generate_imports.py)
    from regmap.plant import Bus, Plant, PlantDevice

# Worked out once per device while it lives: keyed by its id (hashing a whole model would cost more than the work),
# each entry dropped when its device is freed, so a process that loads many maps keeps only the live ones'.
_SPECS: dict[int, list[RegisterSpec[Any]]] = {}  # wire_specs(): what planning and the wire need
_RUNTIME: dict[int, list[RegisterSpec[Any]]] = {}  # runtime_specs(): the same with the enum classes the checks use
_PLANS: dict[int, tuple[ReadBlock, ...]] = {}  # read_all()'s plan of each device
_EXTRAS: dict[int, dict[str, tuple[dict[str, Any], dict[str, Any]]]] = {}  # register_extras()
_DOCUMENTED: dict[int, frozenset[tuple[str, int]]] = {}  # documented_addresses() of every variant
_MEMOS = (_SPECS, _RUNTIME, _PLANS, _EXTRAS, _DOCUMENTED)


def _kept(device: Device, cache: dict[int, Any], value: Any) -> None:
    key = id(device)
    if all(key not in memo for memo in _MEMOS):
        weakref.finalize(device, _forget, key)
    cache[key] = value


def _forget(key: int) -> None:
    for memo in _MEMOS:
        memo.pop(key, None)


def documented_addresses(device: Device, variants: Sequence[str] = ()) -> frozenset[tuple[str, int]]:
    """(space, address) of every word the device answers reads of: every readable register's, pairs included;
    with `variants`, only the registers every one of them has (a word one of them lacks answers 0x02 there).
    Without variants (the read plans and the ESPHome and HA ranges ask for it) worked out once per device."""
    if variants:
        return frozenset(
            (r.space, a)
            for r in device.registers
            if r.access.readable and all(r.on_variant(v) for v in variants)
            for a in range(r.first_address, r.last_address + 1)
        )
    cached = _DOCUMENTED.get(id(device))
    if cached is None:
        cached = frozenset((r.space, a) for r in device.registers if r.access.readable for a in range(r.first_address, r.last_address + 1))
        _kept(device, _DOCUMENTED, cached)
    return cached


def runtime_enum(e: EnumType) -> type[enum.IntEnum]:
    """The enum as the runtime checks it, built from the model (the generated modules declare the same)."""
    members = [(m.name.upper(), m.value) for m in e.members]
    made: type[enum.IntEnum] = enum.IntEnum("".join(part.capitalize() for part in e.name.split("_")), members)  # type: ignore[misc]
    return made


# Every RegisterSpec field with its default, in the dataclass's order (the four without one are always given).
_SPEC_FIELDS: dict[str, Any] = {f.name: f.default for f in dataclasses.fields(RegisterSpec)}
_new_spec = object.__new__


def _spec(fields: dict[str, Any]) -> RegisterSpec[Any]:
    """RegisterSpec(**fields), made as its __init__ makes it (the fields, in order, in the instance's dict; the class
    has no __post_init__) at a fifth of the cost: a frozen dataclass's __init__ sets each of its 35 fields by a call.
    The three cached facts every planner asks first are filled in as the class works them out: Python 3.11's
    cached_property takes a lock on each first read."""
    spec: RegisterSpec[Any] = _new_spec(RegisterSpec)
    own = spec.__dict__
    own.update(_SPEC_FIELDS)
    own.update(fields)
    info = own["type_info"] = TYPES[own["data_type"]]
    own["words"] = own["string_words"] if info.is_string else info.words
    own["first_address"] = own["address"] - 1 if own["paired"] else own["address"]
    return spec


def wire_specs(device: Device) -> list[RegisterSpec[Any]]:
    """Every register as the runtime plans its reads and puts it on the wire: `runtime_specs` without the enum
    classes, which only the runtime's value checks use (building them cost a generator target a quarter of its
    per-device time). The read plans and the back ends take these. Built once per device."""
    cached = _SPECS.get(id(device))
    if cached is not None:
        return cached
    specs: list[RegisterSpec[Any]] = []
    extras = register_extras(device)
    for r in device.registers:
        fields = {
            "name": r.name,
            "address": r.address,
            "data_type": r.type._value_,  # _value_: an enum's .value is a Python-level property in 3.11
            "access": r.access._value_,
            "word_order": r.word_order._value_,
            "follows_device_order": not r.word_order_fixed,
            "paired": r.paired,
            "scale_num": r.scale.numerator,
            "scale_den": r.scale.denominator,
            "min": r.min,
            "max": r.max,
            "unit": r.unit,
            "param": r.param,
            "bitfields": tuple(BitfieldSpec(b.name, b.lsb, b.width) for b in r.bitfields),
            "space": r.space,
        }
        own, commands = extras[r.name]
        fields.update(own)
        fields.update(commands)
        specs.append(_spec(fields))
    _kept(device, _SPECS, specs)
    return specs


def register_extras(device: Device) -> dict[str, tuple[dict[str, Any], dict[str, Any]]]:
    """Each register's `spec_extras` and `command_extras` by its name: worked out once per device for the wire specs
    and the back ends that print them (the Python modules). Shared: read them, never change them."""
    cached = _EXTRAS.get(id(device))
    if cached is None:
        cached = {r.name: (spec_extras(r), command_extras(device, r)) for r in device.registers}
        _kept(device, _EXTRAS, cached)
    return cached


def runtime_specs(device: Device) -> list[RegisterSpec[Any]]:
    """Every register as the runtime sees it, enums and bitfields included, so that the one
    check (`regmap_runtime.codec.check_raw`) serves the CLI and the simulator as it serves the
    generated clients. Built once per device: a register without an enum is its wire spec."""
    cached = _RUNTIME.get(id(device))
    if cached is not None:
        return cached
    enums = {e.name: runtime_enum(e) for e in device.enums}
    specs: list[RegisterSpec[Any]] = []
    for r, wire in zip(device.registers, wire_specs(device), strict=True):
        if r.enum is None and not any(b.enum for b in r.bitfields):
            specs.append(wire)
            continue
        fields = {name: wire.__dict__[name] for name in _SPEC_FIELDS}
        fields["enum"] = enums[r.enum.name] if r.enum is not None else None
        fields["bitfields"] = tuple(BitfieldSpec(b.name, b.lsb, b.width, enums[b.enum.name] if b.enum else None) for b in r.bitfields)
        specs.append(_spec(fields))
    _kept(device, _RUNTIME, specs)
    return specs


def command_extras(device: Device, r: Register) -> dict[str, Any]:
    """The RegisterSpec fields the device's commands give a register: `trigger` (a write makes the device
    act: sent once) and `destructive` (the values destructive commands write: only those commands, confirmed)."""
    extras: dict[str, Any] = {}
    if device.is_trigger(r):
        extras["trigger"] = True
    destructive = tuple((*c.raw_values, c.name) for c in device.destructive_commands(r))
    if destructive:
        extras["destructive"] = destructive
    return extras


def spec_extras(r: Register) -> dict[str, Any]:
    """The RegisterSpec fields of the wider types, spaces and gates, where they differ from the
    defaults: generated modules print only these, so a seed map's output does not change."""
    extras: dict[str, Any] = {}
    if r.byte_order is not ByteOrder.HIGH_FIRST:
        extras["byte_order"] = r.byte_order.value
    if r.offset_set:
        extras["offset_num"], extras["offset_den"] = r.offset.numerator, r.offset.denominator
    if r.type.is_string:
        extras["string_words"] = r.string_words
        if r.encoding != "ascii":
            extras["encoding"] = r.encoding
        if r.padding != "nul":
            extras["padding"] = r.padding
    if r.firmware is not None:
        if r.firmware.first is not None:
            extras["firmware_from"] = r.firmware.first
        if r.firmware.until is not None:
            extras["firmware_until"] = r.firmware.until
    if r.poll is not PollClass.NORMAL:
        extras["poll"] = r.poll.value
    if r.na:
        extras["na"] = r.na
    if r.na_nan:
        extras["na_nan"] = True
    if r.variants:
        extras["variants"] = r.variants
    if r.zone is not None:
        extras["zone"] = r.zone
    if r.scale_from is not None:
        extras["scale_from"] = r.scale_from
    reported = reported_values(r.enum) if r.enum is not None and not r.bitfields else ()
    if reported:
        extras["reported"] = reported
    fields = tuple((b.name, runs) for b in r.bitfields if b.enum is not None and (runs := reported_values(b.enum)))
    if fields:
        extras["reported_fields"] = fields
    return extras


def reported_values(e: EnumType) -> tuple[tuple[int, int], ...]:
    """The members the device only reports (access r: read, never written) as runs (first, last) of
    consecutive raw values, so that a register with 55 such states declares three runs."""
    runs: list[tuple[int, int]] = []
    for value in sorted(m.value for m in e.members if not m.writable):
        if runs and runs[-1][1] + 1 == value:
            runs[-1] = (runs[-1][0], value)
        elif not runs or runs[-1][1] != value:
            runs.append((value, value))
    return tuple(runs)


def device_extras(device: Device) -> dict[str, Any]:
    """The DeviceSpec fields for coil limits and the firmware register, where they differ from the defaults."""
    t = device.transport
    extras: dict[str, Any] = {}
    if t.max_read_coils != MAX_READ_BITS:
        extras["max_read_coils"] = t.max_read_coils
    if t.max_write_coils != MAX_WRITE_BITS:
        extras["max_write_coils"] = t.max_write_coils
    if device.info.variants:
        extras["variants"] = tuple(v.name for v in device.info.variants)
    alignment = t.read_alignment
    if alignment is not None:
        extras["read_alignment"] = alignment.words
        extras["aligned_spaces"] = alignment.spaces
        if alignment.exempt:
            extras["alignment_exempt"] = alignment.exempt_reads()
        if alignment.exception is not None:
            extras["misaligned_exception"] = alignment.exception
    control = t.word_order_register
    if control is not None:
        extras["word_order_register"] = control.register.name
        extras["word_order_values"] = (control.high_first, control.low_first, control.swap_value)
    firmware = device.info.firmware_register
    if firmware is not None:
        extras["firmware_register"] = firmware.register.name
        extras["firmware_format"] = firmware.format
        if firmware.decimals:
            extras["firmware_decimals"] = firmware.decimals
    return extras


def runtime_device(device: Device) -> DeviceSpec:
    """The runtime's view of the whole device, for clients built from a map at run time."""
    t = device.transport
    return DeviceSpec(
        id=device.id,
        map_version=device.info.map_version,
        fingerprint=device.fingerprint,
        registers=tuple(runtime_specs(device)),
        baud=t.baud,
        parity=t.parity,
        data_bits=t.data_bits,
        stop_bits=t.stop_bits,
        max_read_registers=t.max_read_registers,
        max_write_registers=t.max_write_registers,
        word_order=t.word_order.value,
        broadcast_id=t.broadcast_id,
        function_codes=t.function_codes,
        tolerates_gaps=t.tolerates_gaps,
        exceptions=tuple((e.code, e.name, e.title) for e in t.exceptions),
        **device_extras(device),
    )


def read_plan(
    device: Device,
    registers: Sequence[Register] | None = None,
    profile: DeviceProfile | None = None,
    *,
    poll: PollClass | None = None,
    variants: Sequence[str] = (),
) -> list[ReadBlock]:
    """The requests that read `registers` (default: every readable one, as `read_all()` does), in order;
    with a device profile, the read limit and the readable gaps it observed (as the client uses them);
    with a poll class, only that class's registers (as `read_all(poll=...)` does); with `variants`, only
    the registers every one of them has, bridging only words all of them answer (one variant: as
    `read_all()` of a client made with `variant=` does)."""
    whole = registers is None and profile is None and poll is None and not variants
    if whole:  # every back end asks for read_all()'s plan: planned once per device
        cached = _PLANS.get(id(device))
        if cached is not None:
            return list(cached)
    t = device.transport
    chosen = device.registers if registers is None else registers
    if poll is not None:
        chosen = [r for r in chosen if r.poll is poll]
    names = {r.name for r in chosen if all(r.on_variant(v) for v in variants)} if variants else {r.name for r in chosen}
    specs = [s for s in wire_specs(device) if s.name in names]
    limit, documented = t.max_read_registers, None if t.tolerates_gaps else documented_addresses(device, variants)
    if profile is not None:
        profile.check(device.id, device.fingerprint)
        limit, documented = profile.plan_limits(limit, documented)
    plan = plan_reads(specs, limit, documented, max_bits=t.max_read_coils, alignment=runtime_alignment(device))
    if whole:
        _kept(device, _PLANS, tuple(plan))
    return plan


def runtime_alignment(device: Device) -> Alignment | None:
    """The map's read-alignment rule as the runtime's planner and checks take it (None: reads may start anywhere)."""
    a = device.transport.read_alignment
    return None if a is None else Alignment(a.words, a.spaces, a.exempt_reads(), a.exception)


# -- plants: several devices on one bus ------------------------------------------------------------

READ_REQUEST_BYTES = 8  # slave, function, start (2), count (2), CRC (2)


def microseconds(seconds: float) -> int:
    """A line time as the C and ST plant constants give it."""
    return round(seconds * 1_000_000)


@dataclass(frozen=True)
class PollEntry:
    """One request of a bus's poll cycle: which device, at which slave id, reads which block."""

    device: PlantDevice
    block: ReadBlock

    @property
    def slave(self) -> int:
        return self.device.slave

    @property
    def function(self) -> int:
        return SPACES[self.block.space].read

    @property
    def start(self) -> int:
        return self.block.address

    @property
    def count(self) -> int:
        return self.block.count

    @property
    def reply_bytes(self) -> int:
        """The RTU answer: slave, function, byte count, the data, CRC (2)."""
        data = (self.count + 7) // 8 if SPACES[self.block.space].bits else 2 * self.count
        return 5 + data


@dataclass(frozen=True)
class BusSchedule:
    """A bus's poll cycle in line order, and (on a serial line) what each exchange costs at worst."""

    bus: Bus
    entries: tuple[PollEntry, ...]

    def exchange_s(self, entry: PollEntry) -> float | None:
        """Request, the device's turnaround, its answer, then the inter-frame silence (None on TCP: the gateway's timing)."""
        line = self.bus.serial
        if line is None:
            return None
        from regmap_runtime.line import frame_s  # plants only: the line module brings pymodbus, which maps never need here

        frames = frame_s(READ_REQUEST_BYTES + entry.reply_bytes, line.character_bits, line.baud)
        return frames + entry.device.turnaround_s(line.baud) + line.silence_s

    @property
    def cycle_s(self) -> float | None:
        """The whole cycle's line time at worst (None on TCP)."""
        times = [self.exchange_s(entry) for entry in self.entries]
        return None if any(t is None for t in times) else sum(t for t in times if t is not None)


def bus_schedule(bus: Bus) -> BusSchedule:
    """The bus's poll order: each device's read plan (as its client's `read_all()` plans it: of a device the plant
    names a variant of, only that variant's registers), interleaved round robin block by block, as the plant
    client's `read_all()` runs it (`regmap_runtime.line.interleave`)."""
    from regmap_runtime.line import interleave  # plants only, as in `exchange_s`

    plans = [read_plan(dev.device, variants=dev.variants) for dev in bus.devices]
    order = interleave(plans)
    return BusSchedule(bus, tuple(PollEntry(bus.devices[index], block) for index, block in order))


def plant_schedule(plant: Plant) -> tuple[BusSchedule, ...]:
    """Every bus's poll cycle, in the plant file's order: what the C and ST poll tables and the plant page print."""
    return tuple(bus_schedule(bus) for bus in plant.buses)
