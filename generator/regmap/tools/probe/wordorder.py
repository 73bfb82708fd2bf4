"""The drive's 32-bit word order, decided from the values where they decide it, and the word-order register.

A 32-bit register votes for an order when only that order gives a value the map admits (range and
enum), or, when both do, when only that order gives the map's default. Registers whose words read
the same either way (0, or equal halves) say nothing. The order is decided when every vote agrees.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from regmap.model import Device, Register
from regmap.tools.selectors import Registers
from regmap_runtime.codec import words_to_raw
from regmap_runtime.spec import HIGH_FIRST, LOW_FIRST, Raw

from .registers import RegisterRead
from .report import Note

ORDERS = (HIGH_FIRST, LOW_FIRST)


@dataclass
class WordOrder:
    map_order: str
    votes: dict[str, list[str]] = field(default_factory=lambda: {HIGH_FIRST: [], LOW_FIRST: []})
    register: str | None = None  # the word-order register's label
    register_order: str | None = None  # what it says (None: no register, or not read, or an unknown setting)

    @property
    def inferred(self) -> str | None:
        high, low = self.votes[HIGH_FIRST], self.votes[LOW_FIRST]
        return HIGH_FIRST if high and not low else LOW_FIRST if low and not high else None

    @property
    def effective(self) -> str:
        """The order to decode with: the register's, else the values', else the map's."""
        return self.register_order or self.inferred or self.map_order

    def as_json(self) -> dict[str, Any]:
        return {
            "map": self.map_order,
            "inferred": self.inferred,
            "votes": {order: len(names) for order, names in self.votes.items()},
            "register": self.register,
            "register_says": self.register_order,
            "used": self.effective,
        }


def _admits(reg: Register, raw: Raw) -> bool:
    if isinstance(raw, str) or not reg.raw_min <= raw <= reg.raw_max:
        return False
    return reg.enum is None or bool(reg.bitfields) or reg.enum.by_value(int(raw)) is not None


def infer(device: Device, reads: dict[str, RegisterRead]) -> tuple[WordOrder, list[Note]]:
    regs = Registers(device)
    result = WordOrder(device.transport.word_order.value)
    for read in reads.values():
        reg = read.register
        if reg.words != 2 or reg.type.kind != "int" or reg.word_order_fixed or read.words is None or read.words[0] == read.words[1]:
            continue
        raws = {order: words_to_raw(regs.spec(reg).in_word_order(order), read.words) for order in ORDERS}
        plausible = [order for order in ORDERS if _admits(reg, raws[order])]
        if len(plausible) == 2 and reg.default is not None:
            plausible = [order for order in ORDERS if raws[order] == reg.default] or plausible
        if len(plausible) == 1:
            result.votes[plausible[0]].append(reg.name)
    control = device.transport.word_order_register
    if control is not None and not control.swaps:  # a swap register holds no order to read
        result.register = control.register.label
        held = reads.get(control.register.name)
        if held is not None and held.words is not None:
            setting = held.words[0]
            result.register_order = HIGH_FIRST if setting == control.high_first else LOW_FIRST if setting == control.low_first else None
    return result, _notes(result)


def _notes(result: WordOrder) -> list[Note]:
    inferred = result.inferred
    votes = f"{len(result.votes[HIGH_FIRST])} register(s) read as high_first, {len(result.votes[LOW_FIRST])} as low_first"
    if inferred is None:
        both = result.votes[HIGH_FIRST] and result.votes[LOW_FIRST]
        text = f"not decided from the values ({votes})" if both else "not decided: no 32-bit value tells the orders apart"
        return [Note("word_order", "transport", "word_order", text, bool(both))]
    if result.register is not None:
        if result.register_order is None:
            return [
                Note("word_order", "transport", "word_order", f"the values say {inferred} ({votes}); {result.register} was not read", False)
            ]
        agrees = result.register_order == inferred
        text = f"the values say {inferred} ({votes}); {result.register} says {result.register_order}"
        return [Note("word_order", "transport", "word_order", text, not agrees)]
    if inferred != result.map_order:
        return [
            Note("word_order", "transport", "word_order", f"the map says {result.map_order}; the values say {inferred} ({votes})", True)
        ]
    return [Note("word_order", "transport", "word_order", f"{inferred}, as the map says ({votes})", False)]
