"""How a person names a register on the command line: name, manual parameter id or address.

Names and ids are matched case-insensitively where that is unambiguous; a typo gets suggestions.
An address names the register listed there in the data space given (`--space`/`-t`), or in the one
space that lists a register there; where several do (a coil and a holding register at 0x0013), the
space must be given.
"""

from __future__ import annotations

import difflib
import re
from collections.abc import Iterable
from typing import Any

from regmap.diagnostics import UsageError
from regmap.model import Device, Register
from regmap.runtime_bridge import runtime_specs
from regmap_runtime.spaces import SPACES
from regmap_runtime.spec import RegisterSpec

# mbpoll's -t numbers (0 coils, 1 discrete inputs, 3 input registers, 4 holding registers) and the map's names.
SPACE_ALIASES = {"0": "coil", "1": "discrete_input", "3": "input", "4": "holding", **{name: name for name in SPACES}}


def parse_space(text: str) -> str:
    """A data space as the command line names it: the map's name or mbpoll's -t number."""
    name = SPACE_ALIASES.get(text.strip().lower())
    if name is None:
        raise UsageError(f"--space {text!r}: one of {', '.join(SPACES)}, or mbpoll's 0 (coil), 1 (discrete_input), 3 (input), 4 (holding)")
    return name


def article(noun: str) -> str:
    """`an input register`, `a coil`."""
    return f"{'an' if noun[:1] in 'aeiou' else 'a'} {noun}"


def space_label(space: str) -> str:
    """`coil`, `input register`: how a message names one address of a space."""
    return {"holding": "holding register", "input": "input register", "coil": "coil", "discrete_input": "discrete input"}[space]


def suggest(wrong: str, candidates: Iterable[str]) -> str:
    """` (did you mean peak_current?)` for a typo, or nothing."""
    pool = list(dict.fromkeys(candidates))
    folded = {c.lower(): c for c in pool}
    close = difflib.get_close_matches(wrong.lower(), list(folded), n=3, cutoff=0.75)
    if not close:
        return ""
    return f" (did you mean {' or '.join(folded[c] for c in close)}?)"


def parse_address(text: str) -> int | None:
    """0x0191, 0191h or decimal 401; None when `text` is not an address."""
    text = text.strip()
    value: int | None = None
    if re.fullmatch(r"0[xX][0-9a-fA-F]+", text):
        value = int(text, 16)
    elif re.fullmatch(r"[0-9a-fA-F]+[hH]", text):
        value = int(text[:-1], 16)
    elif re.fullmatch(r"[0-9]+", text):
        value = int(text, 10)
    if value is None or not 0 <= value <= 0xFFFF:
        return None
    return value


def parse_int(text: str, what: str) -> int:
    try:
        return int(text.strip(), 0)
    except ValueError:
        raise UsageError(f"{what}: {text!r} is not an integer") from None


class Registers:
    """Look-ups by selector and by address over one device's registers."""

    def __init__(self, device: Device, space: str | None = None) -> None:
        self.device = device
        self.space = space  # the space an address selector names (None: the one space that lists a register there)
        self.specs: dict[str, RegisterSpec[Any]] = {s.name: s for s in runtime_specs(device)}
        self.by_name = {r.name: r for r in device.registers}
        self.by_param = {r.param: r for r in device.registers if r.param}
        self.by_address = {(r.space, r.address): r for r in device.registers}
        folded: dict[str, list[Register]] = {}
        for reg in device.registers:
            for key in {reg.name.lower(), (reg.param or reg.name).lower()}:
                folded.setdefault(key, []).append(reg)
        self.folded = folded

    def find(self, selector: str) -> Register | None:
        """A register by name, manual parameter id, or address (0x0191 or decimal 401)."""
        text = selector.strip()
        if text in self.by_name:
            return self.by_name[text]
        if text in self.by_param:
            return self.by_param[text]
        matches = self.folded.get(text.lower(), [])
        if len(matches) == 1:
            return matches[0]
        if len(matches) > 1:
            raise UsageError(f"{selector!r} is ambiguous: {', '.join(r.label for r in matches)}; spell it exactly")
        address = parse_address(text)
        if address is None:
            return None
        if self.space is not None:
            return self.by_address.get((self.space, address))
        order = list(SPACES)
        listed = sorted((reg for (_, at), reg in self.by_address.items() if at == address), key=lambda r: order.index(r.space))
        if len(listed) > 1:
            named = ", ".join(f"{space_label(r.space)} {r.label}" for r in listed)
            raise UsageError(f"{selector!r} is the address of {named}; give --space (-t) or the register's name")
        return listed[0] if listed else None

    def resolve(self, selector: str) -> Register:
        reg = self.find(selector)
        if reg is None:
            raise UsageError(f"unknown register {selector!r}{self.hint(selector)}")
        return reg

    def hint(self, selector: str) -> str:
        address = parse_address(selector)
        if address is not None:
            spaces = [self.space] if self.space is not None else list(SPACES)
            owners = [o for o in (self.device.covering(address, space) for space in spaces) if o is not None]
            if owners:
                return f" (0x{address:04X} lies inside {owners[0].label}; --words writes single words)"
            where = f" among the {SPACES[self.space].title}" if self.space is not None else ""
            return f" (no register at 0x{address:04X}{where}; --words reads and writes any address)"
        return suggest(selector, [*self.by_name, *self.by_param])

    def spec(self, reg: Register) -> RegisterSpec[Any]:
        return self.specs[reg.name]


def check_slave(device: Device, slave: int, *, reading: bool = False) -> None:
    """The slave id must be one the device can have; a broadcast only where nothing is read back."""
    t = device.transport
    if slave == t.broadcast_id:
        if reading:
            raise UsageError(f"--slave {slave} is the broadcast id: a broadcast gets no answer, so it cannot read")
        return
    if t.slave_min <= slave <= t.slave_max:
        return
    broadcast = f", or {t.broadcast_id} to broadcast a write" if t.broadcast_id is not None else ""
    raise UsageError(f"--slave {slave} is outside {t.slave_min}..{t.slave_max}{broadcast} for {device.info.model}")
