"""Which of the map's variants the device is: each register only some variants have (`variants: [...]`)
is read by itself; exception 0x02 (illegal data address) says the device lacks it, a value that it has
it. A declared variant agrees when it has exactly the registers that answered among those read."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from regmap.model import Device

from .bus import ProbeBus
from .registers import RegisterRead, read_alone
from .report import Note

ABSENT_EXCEPTION = 0x02  # what a device answers for an address it does not have


@dataclass(frozen=True)
class VariantCheck:
    present: tuple[str, ...]  # registers that answered
    absent: tuple[str, ...]  # registers answered with ABSENT_EXCEPTION
    unclear: tuple[str, ...]  # registers whose answer says neither (no answer, another exception)
    matches: tuple[str, ...]  # the declared variants that have exactly the present registers of those read
    declared: tuple[str, ...]

    @property
    def text(self) -> str:
        heard = [f"{name} answered" for name in self.present] + [f"{name} is absent (exception 0x02)" for name in self.absent]
        heard += [f"{name} gave no clear answer" for name in self.unclear]
        seen = "; ".join(heard)
        if not self.present and not self.absent:
            return f"no register only some variants have answered clearly ({seen}): the variant is unknown"
        if not self.matches:
            return f"no declared variant ({', '.join(self.declared)}) has these registers: {seen}"
        if len(self.matches) == len(self.declared):
            return f"every declared variant ({', '.join(self.declared)}) agrees: {seen}"
        return f"the device is {' or '.join(self.matches)} (of {', '.join(self.declared)}): {seen}"

    def as_json(self) -> dict[str, Any]:
        return {"present": self.present, "absent": self.absent, "unclear": self.unclear, "matches": self.matches}


def gated(device: Device) -> list[RegisterRead]:
    """A fresh read of every readable register only some declared variants have."""
    return [RegisterRead(r) for r in device.registers if r.variants and r.access.readable]


def check(bus: ProbeBus, device: Device) -> tuple[VariantCheck, list[Note]]:
    """Read each register only some variants have (one request each) and name the variants that agree."""
    present, absent, unclear = [], [], []
    for read in gated(device):
        answer = read_alone(bus, device, read)
        name = read.register.name
        if answer.ok:
            present.append(name)
        elif answer.exception == ABSENT_EXCEPTION:
            absent.append(name)
        else:
            unclear.append(name)
    declared = tuple(v.name for v in device.info.variants)
    matches = tuple(
        variant
        for variant in declared
        if all(device.register(name).on_variant(variant) for name in present)
        and not any(device.register(name).on_variant(variant) for name in absent)
    )
    result = VariantCheck(tuple(present), tuple(absent), tuple(unclear), matches, declared)
    return result, [Note("variants", "transport", "variants", result.text, not result.matches)]
