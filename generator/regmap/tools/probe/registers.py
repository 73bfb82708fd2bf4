"""Every documented register: read by the map's read-plan blocks, one register at a time only where a
block fails, then judged once the word order is known: answered or not, in range, an enum member,
the map's default or not (the last is only information: drives are configured)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from regmap.core.decoding import describe_value
from regmap.model import Device, Register
from regmap.runtime_bridge import read_plan
from regmap.tools.selectors import Registers
from regmap_runtime.codec import words_to_raw
from regmap_runtime.plan import ReadBlock
from regmap_runtime.rtu import STANDARD_EXCEPTIONS
from regmap_runtime.spaces import SPACES
from regmap_runtime.spec import Raw

from .bus import Answer, ProbeBus
from .report import Note


@dataclass
class RegisterRead:
    register: Register
    answer: Answer | None = None  # None: not read (the probe stopped first)
    words: list[int] | None = None
    raw: Raw | None = None
    value: Any = None
    text: str = ""
    in_range: bool = True
    member: bool = True
    default_differs: bool = False

    def as_json(self) -> dict[str, Any]:
        reg = self.register
        status = (
            "not_read" if self.answer is None else "answered" if self.answer.ok else "exception" if self.answer.exception else "no_answer"
        )
        out: dict[str, Any] = {"register": reg.name, "param": reg.param, "address": reg.address, "status": status}
        if self.answer is not None and self.answer.exception is not None:
            out["exception"] = self.answer.exception
        if self.answer is not None and self.answer.failure is not None:
            out["failure"] = self.answer.failure
        if self.raw is not None:
            out.update(raw=self.raw, value=self.value, text=self.text, in_range=self.in_range, enum_member=self.member)
            out["default"] = reg.default
            out["differs_from_default"] = self.default_differs
        return out


def exception_text(device: Device, code: int) -> str:
    known = device.transport.exception(code)
    meaning = known.title if known is not None else STANDARD_EXCEPTIONS.get(code, "unknown exception code")
    return f"exception 0x{code:02X} ({meaning})"


def read_registers(bus: ProbeBus, device: Device, reads: dict[str, RegisterRead], progress: Callable[[str], None] | None = None) -> None:
    """Fill `reads` (every readable register, in address order) as the answers come: a stop keeps what was read."""
    for reg in device.registers:
        if reg.access.readable:
            reads[reg.name] = RegisterRead(reg)
    blocks = probe_plan(device)
    for number, block in enumerate(blocks, 1):
        if progress is not None:
            progress(f"registers: request {number} of {len(blocks)}")
        answer = bus.read(block.address, block.count, block.space)
        if answer.ok and answer.words is not None:
            for spec in block.registers:
                reads[spec.name].answer, reads[spec.name].words = answer, block.words_of(spec, answer.words)
            continue
        if len(block.registers) == 1:
            reads[block.registers[0].name].answer = answer
            continue
        for spec in block.registers:  # the block failed: which of its registers does the drive refuse?
            read_alone(bus, device, reads[spec.name])


def probe_plan(device: Device) -> list[ReadBlock]:
    """The map's read plan, split by the variants that have each register: a block never holds a register some
    variant lacks beside one that variant has, nor reads across its words, so on any variant only the reads of
    what it lacks fail (the device's variant is what the probe finds out)."""
    if not device.info.variants:
        return read_plan(device)
    every = tuple(v.name for v in device.info.variants)
    readable = [r for r in device.registers if r.access.readable]
    blocks: list[ReadBlock] = []
    for having in sorted({tuple(sorted(r.variants)) for r in readable}):
        # variants=: only words every one of those variants answers are read across
        chosen = [r for r in readable if tuple(sorted(r.variants)) == having]
        blocks += read_plan(device, chosen, variants=having or every)
    spaces = list(SPACES)
    return sorted(blocks, key=lambda b: (spaces.index(b.space), b.address))


def read_alone(bus: ProbeBus, device: Device, read: RegisterRead) -> Answer:
    """Read one register by itself, as the read plan would (widened to whole units where the map's reads
    must be aligned), and keep its own words."""
    (alone,) = read_plan(device, [read.register])
    answer = bus.read(alone.address, alone.count, alone.space)
    (spec,) = alone.registers
    read.answer, read.words = answer, alone.words_of(spec, answer.words) if answer.words is not None else None
    return answer


def judge(device: Device, reads: dict[str, RegisterRead], word_order: str | None) -> list[Note]:
    """Decode what was read in `word_order` and say where the drive and the map disagree."""
    regs = Registers(device)
    notes = []
    for read in reads.values():
        reg = read.register
        if read.answer is None:
            continue
        if not read.answer.ok:
            what = (
                exception_text(device, read.answer.exception) if read.answer.exception is not None else read.answer.failure or "no answer"
            )
            if reg.firmware is not None:
                # Whether the firmware should have it is the firmware stage's judgement, made with the version read.
                notes.append(Note("registers", reg.label, "not_answered", f"0x{reg.address:04X}: {what} ({reg.firmware.text})", False))
                continue
            if reg.variants:
                # Whether the device should have it is the variants stage's judgement, made with every such register.
                only = f"only on variant {', '.join(reg.variants)}"
                notes.append(Note("registers", reg.label, "not_answered", f"0x{reg.address:04X}: {what} ({only})", False))
                continue
            notes.append(Note("registers", reg.label, "not_answered", f"0x{reg.address:04X}: {what}", True))
            continue
        assert read.words is not None
        read.raw = raw = words_to_raw(regs.spec(reg).in_word_order(word_order), read.words)
        read.value, read.text, admitted, _ = describe_value(device, reg, raw, regs)
        # Text and bits have no range; a float that is NaN is outside any range.
        read.in_range = isinstance(raw, str) or reg.raw_min <= raw <= reg.raw_max
        read.member = admitted or not read.in_range
        read.default_differs = reg.default is not None and read.raw != reg.default
        if not read.in_range:
            notes.append(Note("registers", reg.label, "out_of_range", f"reads {read.text}", True))
        elif not read.member:
            notes.append(Note("registers", reg.label, "not_a_member", f"reads {read.text}", True))
        elif read.default_differs:
            notes.append(
                Note("registers", reg.label, "not_the_default", f"reads {read.text} (the map's default is raw {reg.default})", False)
            )
    return notes
