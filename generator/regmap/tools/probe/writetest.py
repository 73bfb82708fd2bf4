"""`--write-test`: for chosen registers, write back the value the drive holds and read it again (the
drive is left as it was), then send one value outside the map's range and check the drive refuses
it with the exception the manual gives for a bad value (0x03 where the map lists no exceptions).
Should the drive take that value, the value it held is written back at once."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from regmap.diagnostics import UsageError
from regmap.model import Device, Register
from regmap.tools.selectors import Registers
from regmap_runtime.codec import raw_to_words, words_to_raw
from regmap_runtime.spec import Raw

from .bus import ProbeBus
from .registers import exception_text
from .report import Note

ILLEGAL_VALUE = 0x03


@dataclass
class WriteTest:
    register: str
    held: Raw | None = None
    written_back: str = "not tried"
    out_of_range: Raw | None = None
    refused_with: str = "not tried"

    def as_json(self) -> dict[str, Any]:
        return {
            "register": self.register,
            "held": self.held,
            "write_back": self.written_back,
            "out_of_range_value": self.out_of_range,
            "out_of_range_answer": self.refused_with,
        }


def chosen(device: Device, selectors: Sequence[str]) -> list[Register]:
    """The registers to write-test, checked before the port is opened."""
    regs = Registers(device)
    out = []
    for selector in selectors:
        reg = regs.resolve(selector)
        if not (reg.access.readable and reg.access.writable):
            raise UsageError(f"--write-test {selector}: {reg.label} is not readable and writable")
        if any(c.register.name == reg.name for c in device.commands):
            raise UsageError(f"--write-test {selector}: {reg.label} takes commands; writing it back could act")
        out.append(reg)
    return out


def outside_value(reg: Register) -> Raw | None:
    """A raw value the register's type can carry but the map does not admit, or None (text and bits
    have none: every text that fits and both states of a coil are values)."""
    if not reg.type.numeric:
        return None
    if reg.type.is_float:
        # Well clear of the limit, so that rounding to the register's float width cannot bring it back inside.
        if reg.max is not None:
            return reg.max + max(1.0, abs(reg.max))
        if reg.min is not None:
            return reg.min - max(1.0, abs(reg.min))
        return None
    low, high = int(reg.raw_min), int(reg.raw_max)
    if high < reg.type.raw_max:
        return high + 1
    if low > reg.type.raw_min:
        return low - 1
    if reg.enum is not None and not reg.bitfields:
        members = {m.value for m in reg.enum.members}
        return next((v for v in range(low, low + len(members) + 1) if v not in members), None)
    return None


def expected_refusal(device: Device) -> int:
    known = device.transport.exception(ILLEGAL_VALUE)
    return known.code if known is not None else ILLEGAL_VALUE


@dataclass
class WriteTests:
    tests: list[WriteTest]

    def as_json(self) -> list[dict[str, Any]]:
        return [t.as_json() for t in self.tests]


def write_test(bus: ProbeBus, device: Device, registers: Sequence[Register], word_order: str) -> tuple[WriteTests, list[Note]]:
    regs = Registers(device)
    results, notes = WriteTests([]), []
    for reg in registers:
        spec = regs.spec(reg).in_word_order(word_order)
        result = WriteTest(reg.name)
        results.tests.append(result)

        def write(raw: Raw, reg: Register = reg, spec: Any = spec) -> str:
            return bus.write(reg.first_address, raw_to_words(spec, raw, with_pair=True), reg.space).text

        current = bus.read(reg.address, reg.words, reg.space)
        if current.words is None:
            notes.append(Note("write_test", reg.label, "write_back", f"could not read it first: {current.text}", True))
            continue
        result.held = held = words_to_raw(spec, current.words)
        result.written_back = write(held)
        again = bus.read(reg.address, reg.words, reg.space)
        same = again.words is not None and words_to_raw(spec, again.words) == held
        if result.written_back != "answered" or not same:
            text = f"writing back raw {held}: {result.written_back}; read again: {again.text if again.words is None else words_to_raw(spec, again.words)}"
            notes.append(Note("write_test", reg.label, "write_back", text, True))
        else:
            notes.append(Note("write_test", reg.label, "write_back", f"raw {held} written back and read again", False))
        result.out_of_range = outside = outside_value(reg)
        if outside is None:
            notes.append(
                Note("write_test", reg.label, "out_of_range_write", "the map admits every value its type carries: nothing to refuse", False)
            )
            continue
        code = expected_refusal(device)
        answer = bus.write(reg.first_address, raw_to_words(spec, outside, with_pair=True), reg.space)
        result.refused_with = answer.text
        if answer.exception == code:
            notes.append(
                Note("write_test", reg.label, "out_of_range_write", f"raw {outside} refused with {exception_text(device, code)}", False)
            )
        elif answer.ok:
            restored = write(held)
            text = f"the drive took raw {outside}, outside the map's range; raw {held} written back ({restored})"
            notes.append(Note("write_test", reg.label, "out_of_range_write", text, True))
        else:
            text = f"raw {outside} refused with {answer.text}; the manual gives {exception_text(device, code)}"
            notes.append(Note("write_test", reg.label, "out_of_range_write", text, True))
    return results, notes
