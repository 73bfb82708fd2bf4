"""Words read from (or written to) a device, named with the map's registers: the decoder `regmap decode`,
`regmap read` and the manual's annotated frames share.

The words go through the runtime's codec (`words_to_raw`, `raw_to_value`), the same code that
decodes what the generated clients read. The bit functions (0x01/0x02/0x05/0x0F) carry bits
(`carried`), a bit response as many as its request asked for (`trim_bits`: the rest of its last
byte is padding, which must be zero).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from typing import Any, Protocol

from regmap.core.text import BIT_NAMES, na_mark, number_text
from regmap.model import Device, Register
from regmap.records import dataclass
from regmap.runtime_bridge import wire_specs
from regmap_runtime.codec import raw_to_value, words_to_raw
from regmap_runtime.rtu import Frame
from regmap_runtime.scaling import scaled
from regmap_runtime.spaces import COIL, DEFAULT_SPACE, DISCRETE_INPUT, HOLDING, INPUT, SPACES
from regmap_runtime.spec import Raw, RegisterSpec
from regmap_runtime.timestamps import time_text

# The Modbus names of the public function codes; the data spaces' codes come from the space table.
FUNCTION_NAMES = {
    COIL.read: "read coils",
    DISCRETE_INPUT.read: "read discrete inputs",
    HOLDING.read: "read holding registers",
    INPUT.read: "read input registers",
    COIL.write_single: "write single coil",
    HOLDING.write_single: "write single register",
    0x08: "diagnostics",
    COIL.write_multiple: "write multiple coils",
    HOLDING.write_multiple: "write multiple registers",
    0x11: "report server id",
    0x16: "mask write register",
    0x17: "read/write multiple registers",
    0x2B: "read device identification",
}


def carried(frame: Frame) -> tuple[int, ...]:
    """The values a frame carries, one per address: register words, or in a bit space its bits."""
    return frame.bits if frame.space is not None and SPACES[frame.space].bits else frame.words


def trim_bits(frame: Frame, count: int) -> Frame:
    """A bit read response cut to the `count` bits its request asked for. A byte count other than
    ceil(count/8), or padding bits that are not zero (§6.1, §6.2 pad with zeros), is a problem."""
    if frame.kind != "read_response" or frame.space is None or not SPACES[frame.space].bits:
        return frame
    problems = list(frame.problems)
    need = (count + 7) // 8
    if frame.byte_count is not None and frame.byte_count != need:
        problems.append(f"{count} bits take {need} data byte(s), the byte count says {frame.byte_count}")
    if any(frame.bits[count:]):
        problems.append(f"the bits after the last of {count} are not zero (a response pads with zeros)")
    return dataclasses.replace(frame, bits=frame.bits[:count], problems=tuple(problems))


class SpecSource(Protocol):
    """Anything that gives a register's runtime spec (`RegisterSpecs`, the tools' `Registers`)."""

    def spec(self, reg: Register) -> RegisterSpec[Any]: ...


class RegisterSpecs:
    """Every register's wire spec by name, built once per device: decoding scales and orders words by the spec and
    takes enum members from the model, so the runtime's enum classes are not built for it."""

    def __init__(self, device: Device) -> None:
        self.specs: dict[str, RegisterSpec[Any]] = {s.name: s for s in wire_specs(device)}

    def spec(self, reg: Register) -> RegisterSpec[Any]:
        return self.specs[reg.name]


def _json_number(value: Any) -> Any:
    """JSON has no NaN or infinity: a float that is not finite becomes null (its text still says it)."""
    return None if isinstance(value, float) and not math.isfinite(value) else value


@dataclass
class DecodedValue:
    address: int
    register: str | None
    param: str | None
    raw: Raw | None  # an integer, a float, text, or 0/1 for a bit
    words: list[int]  # register words, or for a coil or discrete input its one bit
    value: Any = None  # engineering value: number, enum member name, text, True/False
    unit: str | None = None
    text: str = ""
    in_range: bool = True
    fields: dict[str, Any] | None = None  # a bitfield register's fields (enum fields by member name)
    space: str = DEFAULT_SPACE

    def as_json(self) -> dict[str, Any]:
        out: dict[str, Any] = {
            "address": self.address,
            "address_hex": f"0x{self.address:04X}",
            "space": self.space,
            "register": self.register,
            "param": self.param,
            "words": self.words,
            "raw": _json_number(self.raw),
            "value": _json_number(self.value),
            "unit": self.unit,
            "text": self.text,
            "in_range": self.in_range,
        }
        if self.fields is not None:
            out["fields"] = self.fields
        return out


def _eng_text(reg: Register, spec: RegisterSpec[Any], raw: int | float) -> str:
    number = raw_to_value(spec, raw)
    return number_text(number, None if reg.scaled or reg.offset_set else reg.type.value)


def describe_value(device: Device, reg: Register, raw: Raw, regs: SpecSource | None = None) -> tuple[Any, str, bool, dict[str, Any] | None]:
    """Engineering value, a human text (`2.2 A`, `save_ok (0x5555)`, `fault=0 enabled=1 ...`, `"PM-3000"`,
    `on`), whether the map's range and enum admit it, and a bitfield register's fields."""
    regs = regs or RegisterSpecs(device)
    spec = regs.spec(reg)
    if isinstance(raw, str):
        readable = "\ufffd" not in raw
        quoted = '"' + raw.replace("\\", "\\\\").replace('"', '\\"') + '"'
        return raw, quoted + ("" if readable else f"  [NOT valid {reg.encoding}: unreadable bytes shown as U+FFFD]"), readable, None
    if reg.type.is_bool:
        return bool(raw), BIT_NAMES[1 if raw else 0], True, None
    if reg.is_na(raw):
        return None, f"not available (raw {na_mark(reg, raw)}, the device's marker)", True, None
    if reg.scale_from is not None:  # its value needs the scale factor: apply_scale_factors gives it where that was read
        return None, f"raw {raw}; no value without its scale factor {reg.scale_from}", reg.raw_min <= raw <= reg.raw_max, None
    if isinstance(raw, float) and math.isnan(raw):
        return raw, "NaN  [NOT a number: no value the map admits]", False, None
    in_range = reg.raw_min <= raw <= reg.raw_max
    outside = "" if in_range else f"  [OUTSIDE the map's range {_eng_text(reg, spec, reg.raw_min)}..{_eng_text(reg, spec, reg.raw_max)}]"
    if reg.bitfields and isinstance(raw, int):
        parts = []
        fields: dict[str, Any] = {}
        for b in reg.bitfields:
            field_value = (raw & b.mask) >> b.lsb
            member = b.enum.by_value(field_value) if b.enum else None
            if b.enum is not None and member is None:
                in_range = False
            shown: Any = member.name if member else field_value
            fields[b.name] = shown
            parts.append(f"{b.name}={shown}")
        return raw, f"0x{raw:04X}: " + " ".join(parts) + outside, in_range, fields
    if reg.enum is not None and isinstance(raw, float):  # a setting coded as a float: a member, exactly, or not a value
        member = reg.enum.by_value(int(raw)) if raw.is_integer() else None
        shown = number_text(raw, reg.type.value)
        if member is None:
            return raw, f"{shown}  [NOT a value of {reg.enum.name}]", False, None
        return member.name, f"{member.name} ({shown})" + outside, in_range, None
    if reg.enum is not None and isinstance(raw, int):
        member = reg.enum.by_value(raw)
        if member is None:
            return raw, f"{raw} = 0x{raw & 0xFFFFFFFF:X}  [NOT a value of {reg.enum.name}]", False, None
        return member.name, f"{member.name} ({raw} = 0x{raw & 0xFFFFFFFF:X})" + outside, in_range, None
    if reg.zone is not None and isinstance(raw, int):  # a timestamp: the seconds, shown as the time on its clock
        return raw, f"{time_text(raw, reg.zone)} ({raw} s, {'UTC' if reg.zone == 'utc' else 'local clock, no zone'})", True, None
    number = raw_to_value(spec, raw)
    unit = f" {reg.unit}" if reg.unit else ""
    scaled = reg.scaled or reg.offset_set
    shown_number = number_text(number, None if scaled else reg.type.value)
    raw_text = f" (raw {number_text(raw, reg.type.value)})" if scaled else ""
    return number, f"{shown_number}{unit}" + raw_text + outside, in_range, None


def decode_words(
    device: Device,
    start: int,
    words: Sequence[int],
    *,
    word_order: str | None = None,
    space: str = DEFAULT_SPACE,
    regs: SpecSource | None = None,
) -> list[DecodedValue]:
    """Split words read from (or written to) `start` of `space` into the registers they carry
    (for coils and discrete inputs: bits, one per address). `regs`: the device's specs where the caller has them."""
    out: list[DecodedValue] = []
    regs = regs or RegisterSpecs(device)
    address = start
    end = start + len(words)
    bits = SPACES[space].bits

    def one(text: str, reg: Register | None = None) -> None:
        word = words[address - start]
        shown = str(word) if bits else f"0x{word:04X}"
        name, param = (reg.name, reg.param) if reg is not None else (None, None)
        out.append(DecodedValue(address, name, param, None, [word], text=f"{shown}, {text}", space=space))

    while address < end:
        reg = device.covering(address, space)
        if reg is None:
            one("not documented in the map" if space == DEFAULT_SPACE else f"not documented in the map's {SPACES[space].title}")
            address += 1
            continue
        if reg.paired and address == reg.first_address:
            one(f"the unused high word of {reg.label}", reg)
            address += 1
            continue
        own = list(range(reg.address, reg.last_address + 1))
        if own[0] < start or own[-1] >= end:
            one(f"part of {reg.label} (not all of its words are here)", reg)
            address += 1
            continue
        own_words = [words[a - start] for a in own]
        try:
            raw = words_to_raw(regs.spec(reg).in_word_order(word_order), own_words)
        except ValueError as exc:  # a bit that is neither 0 nor 1: the frame is wrong, not the decoder
            one(f"not a value of {reg.label} ({exc})", reg)
            address = reg.last_address + 1
            continue
        value, text, in_range, fields = describe_value(device, reg, raw, regs)
        out.append(DecodedValue(reg.address, reg.name, reg.param, raw, own_words, value, reg.unit, text, in_range, fields, space))
        address = reg.last_address + 1
    return apply_scale_factors(device, out, out, "its scale factor {sf} is not in these words")


def apply_scale_factors(device: Device, values: list[DecodedValue], among: Sequence[DecodedValue], missing: str) -> list[DecodedValue]:
    """Each `scale_from` register of `values` scaled (value = raw x 10^sf) by its scale factor's value found `among`
    the values decoded with it; where the scale factor is not there, no value: the raw number and why (`missing`,
    with `{sf}` for its name). Returns `values`, changed in place."""
    factors = {v.register: v for v in among if v.register is not None}
    for v in values:
        reg = device.register(v.register) if v.register is not None else None
        if reg is None or reg.scale_from is None or v.raw is None or isinstance(v.raw, str):
            continue
        point = None if reg.is_na(v.raw) else int(v.raw)
        sf = factors.get(reg.scale_from)
        raw_text = "not available (raw its marker)" if point is None else f"raw {v.raw}"
        if sf is None or sf.raw is None:
            v.value, v.text = None, f"{raw_text}; no value: " + missing.format(sf=reg.scale_from)
            continue
        factor = None if device.register(reg.scale_from).is_na(sf.raw) else int(sf.raw)
        v.value = scaled(point, factor)
        unit = f" {reg.unit}" if reg.unit else ""
        if v.value is None:
            why = raw_text if point is None else f"{reg.scale_from} reads its 'not available' marker"
            v.text = f"not available ({why})"
        else:
            v.text = (
                f"{number_text(v.value)}{unit} (raw {v.raw} x 10^{factor}, {reg.scale_from})"
                + v.text.partition("  [")[1]
                + v.text.partition("  [")[2]
            )
    return values
