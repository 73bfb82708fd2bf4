"""What the ESPHome and Home Assistant back ends share: entity facts computed from the model, and YAML output.

Both files are emitted as PyYAML's safe dumper writes them (`yamltext`) from plain data the views computed,
never from a template: a string from a map is always a quoted-or-plain *string* scalar (anything that would
read back as another type, a tag `!lambda`/`!secret`/`!include`, an anchor or an alias is quoted), so map
text cannot become YAML structure. The only tagged nodes are `Lambda`s, which the ESPHome
views build from integers and validated identifiers alone.
"""

from __future__ import annotations

import enum
import math
import re
from collections.abc import Callable
from fractions import Fraction
from typing import TYPE_CHECKING, Any

from regmap.diagnostics import MapError, at
from regmap.homeauto.selection import Selection
from regmap.homeauto.yamltext import yaml_text
from regmap.model import Bitfield, ByteOrder, Command, Device, EnumMember, EnumType, FirmwareGate, PollClass, Register
from regmap.records import dataclass
from regmap.render import header_lines
from regmap.runtime_bridge import documented_addresses, runtime_alignment, wire_specs
from regmap_runtime.plan import ReadBlock, plan_reads

if TYPE_CHECKING:  # only a plant's run imports the plant model (tests/project/test_generate_imports.py)
    from regmap.plant import Bus, Plant, PlantDevice

# -- entity facts ------------------------------------------------------------------------------

# Home Assistant device classes (ESPHome uses the same names) implied by a map's unit.
DEVICE_CLASS = {
    "A": "current",
    "mA": "current",
    "V": "voltage",
    "mV": "voltage",
    "W": "power",
    "kW": "power",
    "°C": "temperature",
    "Hz": "frequency",
    "kHz": "frequency",
    "s": "duration",
    "ms": "duration",
    "min": "duration",
    "h": "duration",
}

# Units of a quantity that only accumulates: the Energy dashboard reads these (device_class energy) as totals.
ENERGY_UNITS = {"Wh": "energy", "kWh": "energy", "MWh": "energy", "varh": None, "kvarh": None}
DURATION_UNITS = frozenset({"s", "ms", "min", "h"})
# Title words (the last resort: the map format has no `counter` key) that make a duration or a plain
# count a running total, e.g. "Total power-on time", "Running hours", "Faults since power-on".
COUNTER_WORDS = re.compile(r"\b(total|cumulative|accumulated|counter|count|since|running|operating|power-on)\b", re.IGNORECASE)
# Title words of a register or field the manual gives no meaning ("Reserved", "Invalid (no meaning; ...)").
RESERVED_TITLE = re.compile(r"^\s*reserved\b|\bno meaning\b", re.IGNORECASE)


class Kind(enum.Enum):
    """What a register is to a home-automation user; its classes and category follow from it."""

    SETTING = "setting"  # writable: someone sets it (a control, when a write makes the device act)
    IDENTITY = "identity"  # the firmware register, text, values read once (nameplate, limits)
    STATE = "state"  # an enum, bit flags or a coil: shown with the map's labels
    CODE = "code"  # a unitless, unscaled integer that is none of those: a status word, fault code, version word
    COUNTER = "counter"  # a running total: energy, power-on time, a count of events
    MEASUREMENT = "measurement"  # a quantity the device measures now


def kind(device: Device, reg: Register) -> Kind:
    """The register's kind, from the model: access, type, poll class, enum/bitfields, unit; title words
    (`COUNTER_WORDS`) only to tell a running total from a duration or count measured now."""
    if reg.access.writable:
        return Kind.SETTING
    firmware = device.info.firmware_register
    if reg.type.is_string or reg.poll is PollClass.STATIC or (firmware is not None and firmware.register.name == reg.name):
        return Kind.IDENTITY
    if reg.enum is not None or reg.bitfields or reg.type.is_bool:
        return Kind.STATE
    if is_counter(reg):
        return Kind.COUNTER
    if reg.unit is None and not reg.type.is_float and not reg.scaled and not reg.offset_set:
        return Kind.CODE
    return Kind.MEASUREMENT


def is_counter(reg: Register) -> bool:
    """Energy always accumulates; a duration or a plain count does when its title says it is a total."""
    if reg.unit in ENERGY_UNITS:
        return True
    if reg.signed or not COUNTER_WORDS.search(reg.title):
        return False
    return reg.unit in DURATION_UNITS or (reg.unit is None and not reg.type.is_float and not reg.scaled)


def state_class(device: Device, reg: Register) -> str | None:
    """`measurement` for quantities only; a counter `total_increasing` (`total` when signed: a net
    value can fall); none for settings, codes, states and identity (statistics of them mean nothing)."""
    k = kind(device, reg)
    if k is Kind.COUNTER:
        return "total" if reg.signed else "total_increasing"
    return "measurement" if k is Kind.MEASUREMENT else None


def device_class(reg: Register) -> str | None:
    if reg.unit in ENERGY_UNITS:
        return ENERGY_UNITS[reg.unit]
    return DEVICE_CLASS.get(reg.unit or "")


def entity_category(device: Device, reg: Register, raw: bool = False) -> str | None:
    """`config` for settings (a write that makes the device act is a control: none), `diagnostic` for
    identity and codes (and `raw`: a register's number shown beside its labelled fields)."""
    k = kind(device, reg)
    if k is Kind.SETTING:
        return None if device.is_trigger(reg) else "config"
    return "diagnostic" if raw or k in (Kind.IDENTITY, Kind.CODE) else None


def command_category(command: Command) -> str | None:
    """A destructive command, and one that saves or restores the configuration, is `config`; a control
    (motion, a reset of an alarm) is a primary entity."""
    effect = command.effect.kind if command.effect is not None else None
    return "config" if command.destructive or effect in ("save", "restore_defaults") else None


MAX_PRESSES_PER_COMMAND = 16  # a command with an argument gets a button (or script) per value, up to this many


@dataclass(frozen=True)
class Press:
    """One thing to press for a command: a command without an argument, or one of its argument's values."""

    title: str
    raw: int
    key: tuple[str, ...]  # the parts of its id


def presses(command: Command) -> tuple[Press, ...] | None:
    """The presses of `command`, or None when its argument has more than MAX_PRESSES_PER_COMMAND values."""
    arg = command.argument
    if arg is None:
        return (Press(command.title, command.raw_value(), (command.name,)),)
    if arg.max - arg.min + 1 > MAX_PRESSES_PER_COMMAND:
        return None
    return tuple(
        Press(f"{command.title} {arg.name} {value}", command.raw_value(value), (command.name, arg.name, str(value)))
        for value in range(arg.min, arg.max + 1)
    )


def too_many_presses(command: Command) -> str:
    return f"command {command.name} (its argument has more than {MAX_PRESSES_PER_COMMAND} values)"


def reserved(title: str) -> bool:
    """The manual gives it no meaning: not exposed as an entity."""
    return bool(RESERVED_TITLE.search(title))


def turnaround_ms(device: Device) -> float | None:
    """How long the device takes to answer, from the map: its timing row at the line's baud rate, else
    its response delay; None when the map gives neither."""
    t = device.transport
    row = next((r for r in t.timing if r.baud == t.baud and r.total_ms is not None), None)
    if row is not None and row.total_ms is not None:
        return row.total_ms
    return t.response_delay_ms


def command_throttle_ms(device: Device, floor: int) -> int:
    """A pause between two requests to one device: `floor`, or the device's documented turnaround when longer."""
    documented = turnaround_ms(device)
    return max(floor, math.ceil(documented)) if documented is not None else floor


class Ids:
    """Entity ids unique within one file: a clash (a register named like another's field) gets `_2`, `_3`, ..."""

    def __init__(self, taken: tuple[str, ...] = ()) -> None:
        self.seen = set(taken)

    def id(self, *parts: str) -> str:
        base = "_".join(parts)
        text, n = base, 2
        while text in self.seen:
            text, n = f"{base}_{n}", n + 1
        self.seen.add(text)
        return text


ON_NAMES = frozenset({"on", "enabled", "enable", "yes", "true"})
OFF_NAMES = frozenset({"off", "disabled", "disable", "no", "false"})
MAX_DECIMALS = 6


def decimals(scale: Fraction) -> int:
    """Digits after the point that show every raw step: 0.1 -> 1, 0.125 -> 3 (capped for 1/3)."""
    for digits in range(MAX_DECIMALS + 1):
        if (scale * 10**digits).denominator == 1:
            return digits
    return MAX_DECIMALS


def scale_float(scale: Fraction) -> float | int:
    return scale.numerator if scale.denominator == 1 else float(scale)


def on_off(enum: EnumType | None) -> tuple[int, int] | None:
    """(on value, off value) of a two-valued on/off enum, which a switch can show; else None. A switch
    writes both values and reads them back, so both must be members that may be written and are reported."""
    if enum is None or len(enum.members) != 2 or not all(m.writable and m.readable for m in enum.members):
        return None
    on = [m.value for m in enum.members if m.name.lower() in ON_NAMES]
    off = [m.value for m in enum.members if m.name.lower() in OFF_NAMES]
    return (on[0], off[0]) if on and off and on[0] >= 0 and off[0] >= 0 else None


def writable_members(enum: EnumType) -> tuple[EnumMember, ...]:
    """The members a write may send (a state the device only reports is never offered)."""
    return tuple(m for m in enum.members if m.writable)


def flags(reg: Register) -> tuple[Bitfield, ...]:
    """The one-bit fields of a register (what a binary sensor or switch shows)."""
    return tuple(b for b in reg.bitfields if b.width == 1)


def single_flag(reg: Register) -> Bitfield | None:
    """The flag of a register whose only field is one bit: writing the mask or 0 then clobbers nothing."""
    return reg.bitfields[0] if len(reg.bitfields) == 1 and reg.bitfields[0].width == 1 else None


def is_parameter(reg: Register) -> bool:
    """A setting: it changes only when someone writes it, so it is polled less often than status values.
    A register whose enum has states the device reports (a trigger register's progress) changes by itself."""
    reports = reg.enum is not None and any(not m.writable for m in reg.enum.members)
    return reg.access.writable and not reports


FLOAT_DECIMALS = 3  # decimals shown for an unscaled float register (its resolution is not a fixed step)


def shown_decimals(reg: Register) -> int:
    return max(FLOAT_DECIMALS, decimals(reg.scale)) if reg.type.is_float else decimals(reg.scale)


def swapped(reg: Register) -> bool:
    """The device sends the register's words with their bytes exchanged."""
    return reg.byte_order is ByteOrder.LOW_FIRST and not reg.type.is_bool


def swap_word(value: int) -> int:
    return ((value & 0xFF) << 8) | (value >> 8)


def gate_key(reg: Register) -> tuple[str, str, tuple[str, ...]]:
    """What decides whether the register answers: its firmware gate (from, until) and the variants that
    have it (() every variant). Registers of two keys never share a read: one may answer, the other not."""
    gate = reg.firmware
    first, until = (gate.first or "", gate.until or "") if gate is not None else ("", "")
    return (first, until, variant_set(reg))


def variant_set(reg: Register) -> tuple[str, ...]:
    """The variants that have the register, sorted (() every variant): one set however the map orders it."""
    return tuple(sorted(reg.variants))


def planned(
    device: Device, registers: list[Register], max_bits: int | None = None
) -> list[tuple[ReadBlock, PollClass, FirmwareGate | None]]:
    """The read plan of `registers` split by poll class and `gate_key` (a read never mixes polling rates,
    and never holds a register the connected firmware or variant may lack beside one it has), in (space,
    address) order. One class, no gates and no variants (the seed maps): the plain read plan."""
    t = device.transport
    documented = None if t.tolerates_gaps else documented_addresses(device)
    bits = t.max_read_coils if max_bits is None else min(t.max_read_coils, max_bits)
    keyed = [((r.poll._value_, gate_key(r)), r.name) for r in registers]  # _value_: .value is a Python-level property in 3.11
    out: list[tuple[ReadBlock, PollClass, FirmwareGate | None]] = []
    for poll, key in sorted({both for both, _ in keyed}):
        chosen = {name for both, name in keyed if both == (poll, key)}
        first, until, variants = key
        gate = FirmwareGate(first or None, until or None) if first or until else None
        specs = [spec for spec in wire_specs(device) if spec.name in chosen]
        bridged = None if documented is None else documented - _other_variants_words(device, variants)
        blocks = plan_reads(specs, t.max_read_registers, bridged, max_bits=bits, alignment=runtime_alignment(device))
        out += [(block, PollClass(poll), gate) for block in blocks]
    spaces = ("holding", "input", "coil", "discrete_input")
    out.sort(key=lambda item: (spaces.index(item[0].space), item[0].address))
    return out


def _other_variants_words(device: Device, variants: tuple[str, ...]) -> frozenset[tuple[str, int]]:
    """The words of the registers only other variants have: a read of registers on `variants` never bridges them."""
    return frozenset(
        (r.space, a)
        for r in device.registers
        if r.variants and variant_set(r) != variants
        for a in range(r.first_address, r.last_address + 1)
    )


ABSENT = "answers them with an exception: the entities become unavailable"


def gate_notes(device: Device, registers: tuple[Register, ...] | list[Register], variant: str | None = None) -> list[str]:
    """One line per firmware gate and per set of variants: which selected registers only that firmware or
    those variants have, and what the others do (the registers not named answer always). A device known to
    be one `variant` (a plant's): no variant lines, its registers are that variant's."""
    by_gate: dict[str, list[str]] = {}
    by_variants: dict[tuple[str, ...], list[str]] = {}
    for reg in registers:
        if reg.firmware is not None:
            by_gate.setdefault(reg.firmware.text, []).append(reg.name)
        if reg.variants and variant is None:
            by_variants.setdefault(variant_set(reg), []).append(reg.name)
    notes = [f"Needs {gate}: {', '.join(names)} (older or newer firmware {ABSENT})." for gate, names in by_gate.items()]
    declared = [v.name for v in device.info.variants]
    for having, names in by_variants.items():
        others = [name for name in declared if name not in having]
        if others:  # a register every declared variant has answers always
            notes.append(f"Only on variant {', '.join(having)}: {', '.join(names)} (on {', '.join(others)} the device {ABSENT}).")
    return notes


class Names:
    """Entity names, unique within one generated file (a repeated title gets the register's name), and
    at most `MAX_NAME_BYTES` long (ESPHome refuses longer names; a long title is cut with an ellipsis)."""

    def __init__(self, clean: Callable[[str], str] = str, limit: int = 0) -> None:
        self.seen: set[str] = set()
        self.clean = clean  # the target's own escaping, applied before the length is measured
        self.limit = limit or MAX_NAME_BYTES

    def name(self, title: str, qualifier: str) -> str:
        text = _cut(self.clean(" ".join(title.split()) or qualifier), self.limit)
        if text in self.seen:
            suffix = f" ({self.clean(qualifier)})"
            text = _cut(text, self.limit - len(suffix.encode())) + suffix
        self.seen.add(text)
        return text


MAX_NAME_BYTES = 120
MAX_UNIT_BYTES = 63  # ESPHome's limit for unit_of_measurement


def unit_text(unit: str) -> str:
    return _cut(" ".join(unit.split()), MAX_UNIT_BYTES)


def _cut(text: str, limit: int) -> str:
    if len(text.encode()) <= limit:
        return text
    while len((text + "…").encode()) > limit:
        text = text[:-1]
    return text.rstrip() + "…"


# -- YAML -----------------------------------------------------------------------------------


def dump(device: Device, about: list[str], data: dict[str, Any]) -> str:
    """The YAML file: the do-not-edit header and `about` as comments, then `data` (keys in the order given)."""
    return dump_commented([*header_lines(device, "regmap generate"), *about], data)


def plant_header_lines(plant: Plant) -> list[str]:
    """The do-not-edit header of a plant's file: the plant file, and each map it uses with its fingerprint."""
    maps = "; ".join(f"{d.source_path} version {d.info.map_version}, fingerprint {d.fingerprint}" for d in plant.maps)
    return [
        f"Generated by regmap from {plant.source_path} - do not edit.",
        f"Plant {plant.id}, fingerprint {plant.fingerprint}; regenerate with `regmap generate {plant.source_path}`.",
        f"Maps: {maps}.",
    ]


def plant_device_line(bus: Bus, dev: PlantDevice, selection: Selection) -> str:
    """One line of a plant file's header per device: where it is and what of its map is generated."""
    info = dev.device.info
    line = (
        f"{dev.name} ({' '.join(dev.title.split())}): {info.vendor} {info.model} at slave {dev.slave} on {bus.name}"
        f" ({len(selection.registers)} registers, {len(selection.commands)} commands selected)."
    )
    if dev.variant is not None:
        left = (
            f"left out, as that variant lacks them: {', '.join(selection.left_out)}" if selection.left_out else "it has every one selected"
        )
        line += f" Variant {dev.variant}: {left}."
    return line


def refuse_shared_ids(plant: Plant, ids: list[tuple[PlantDevice, list[str]]], tool: str) -> None:
    """Two devices whose generated ids meet (device `a` with a register `b_c` and device `a_b` with `c` both
    give `a_b_c`): refused at the second device's line, one problem per device, naming the id."""
    owners: dict[str, PlantDevice] = {}
    problems = []
    for dev, dev_ids in ids:
        for made in dev_ids:
            first = owners.setdefault(made, dev)
            if first is not dev:
                message = f"devices {first.name!r} and {dev.name!r} give {tool} the same id {made}; rename one of them"
                problems.append(at(plant.source_path, dev.pos, message))
                break
    if problems:
        raise MapError(problems)


def dump_commented(comments: list[str], data: dict[str, Any]) -> str:
    """`data` as YAML under `comments` (each one `#` line; an empty one a bare `#`)."""
    head = "".join("# " + " ".join(line.split()) + "\n" if line else "#\n" for line in comments)
    return head + yaml_text(data)
