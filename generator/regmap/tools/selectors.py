"""How a person names registers on the command line: name, manual parameter id or address, and how many.

Names and ids are matched case-insensitively where that is unambiguous; a typo gets suggestions
(the same number zero-padded first: Pr5.0 -> Pr5.00). An address is the 0-based protocol address
(0x0191, 0191h, 401) and names the register listed there in the data space given (`--space`/`-t`),
or in the one space that lists a register there; where several do (a coil and a holding register
at 0x0013), the space must be given. mbpoll's 1-based `-r 402` and Modicon reference numbers
(`--modicon 40402`) are opted into and said (a note per conversion).

One grammar for every command that reads (`parse_items`): SELECTOR [COUNT] [SELECTOR [COUNT] ...],
where a plain decimal number right after a selector is that selector's COUNT, as mbpoll's `-c`.
"""

from __future__ import annotations

import difflib
import re
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import Any

from regmap.core.text import article, space_label
from regmap.diagnostics import UsageError
from regmap.model import Device, Register
from regmap.runtime_bridge import runtime_specs
from regmap_runtime.spaces import DEFAULT_SPACE, SPACES
from regmap_runtime.spec import RegisterSpec

# mbpoll's -t numbers (0 coils, 1 discrete inputs, 3 input registers, 4 holding registers) and the map's names.
SPACE_ALIASES = {"0": "coil", "1": "discrete_input", "3": "input", "4": "holding", **{name: name for name in SPACES}}


def parse_space(text: str) -> str:
    """A data space as the command line names it: the map's name or mbpoll's -t number."""
    name = SPACE_ALIASES.get(text.strip().lower())
    if name is None:
        raise UsageError(f"--space {text!r}: one of {', '.join(SPACES)}, or mbpoll's 0 (coil), 1 (discrete_input), 3 (input), 4 (holding)")
    return name


def _number_shape(text: str) -> tuple[tuple[str, ...], tuple[int, ...]] | None:
    """`Pr5.00` -> (('pr', '.'), (5, 0)): the text between the numbers and the numbers' values, or None without digits."""
    parts = re.split(r"([0-9]+)", text.lower())
    if len(parts) == 1:
        return None
    return tuple(parts[0::2]), tuple(int(n) for n in parts[1::2])


def suggest(wrong: str, candidates: Iterable[str]) -> str:
    """` (did you mean peak_current?)` for a typo, or nothing. The ids that are the same numbers
    zero-padded come first (Pr5.0 -> Pr5.00, P12-2 -> P12-02), then the closest spellings."""
    pool = list(dict.fromkeys(candidates))
    folded = {c.lower(): c for c in pool}
    shape = _number_shape(wrong)
    padded = [c for c in folded if shape is not None and _number_shape(c) == shape]
    close = [c for c in difflib.get_close_matches(wrong.lower(), list(folded), n=3, cutoff=0.75) if c not in padded]
    chosen = (padded + close)[:3]
    if not chosen:
        return ""
    return f" (did you mean {' or '.join(folded[c] for c in chosen)}?)"


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


# Modicon reference numbers: the leading digit names the space, the rest counts from 1 (40001 = holding 0).
MODICON_DIGITS = {"0": "coil", "1": "discrete_input", "3": "input", "4": "holding"}
MBPOLL_T = {space: number for number, space in SPACE_ALIASES.items() if number.isdigit()}


def modicon_reference(text: str) -> tuple[str, int] | None:
    """The space and 0-based address a Modicon number names (40402 and 400402: holding 401), or None."""
    text = text.strip()
    if not re.fullmatch(r"[0-9]{5,6}", text) or text[0] not in MODICON_DIGITS:
        return None
    offset = int(text[1:])
    limit = 9999 if len(text) == 5 else 0x10000
    if not 1 <= offset <= limit:
        return None
    return MODICON_DIGITS[text[0]], offset - 1


def mbpoll_spelling(space: str, address: int) -> str:
    return f"mbpoll -t {MBPOLL_T[space]} -r {address + 1}"


@dataclass(frozen=True)
class Located:
    """An address as the command line gave it: 0-based, its space when the notation or -t says it,
    and how a notation was read (said on stderr)."""

    address: int
    space: str | None = None
    note: str | None = None


def _same_space(given: str | None, implied: str, what: str) -> str:
    if given is not None and given != implied:
        raise UsageError(f"{what} is {article(space_label(implied))}, but -t/--space says {given}: give one of them")
    return implied


def locate(text: str, *, modicon: bool = False, space: str | None = None) -> Located | None:
    """An address selector: with `modicon`, a decimal one is a Modicon number (its space checked against
    -t); else (and hex always) the 0-based protocol address. None when `text` is no address."""
    text = text.strip()
    if modicon and re.fullmatch(r"[0-9]+", text):
        found = modicon_reference(text)
        if found is None:
            raise UsageError(
                f"--modicon: {text} is no Modicon number: 5 or 6 digits, 0xxxx coils, 1xxxx discrete inputs, "
                "3xxxx input registers, 4xxxx holding registers, counting from 1 (40402 is holding register 401)"
            )
        implied, address = found
        implied = _same_space(space, implied, f"Modicon {text}")
        note = f"Modicon {text} is {space_label(implied)} {address} (0x{address:04X}; {mbpoll_spelling(implied, address)})"
        return Located(address, implied, note)
    protocol = parse_address(text)
    return None if protocol is None else Located(protocol, space)


def locate_reference(text: str, *, modicon: bool = False, space: str | None = None) -> Located:
    """mbpoll's `-r REF`: the 1-based reference (-r 402 is address 401); with `modicon` a Modicon number."""
    if modicon:
        located = locate(text, modicon=True, space=space)
        if located is None:
            raise UsageError(f"-r {text}: with --modicon, -r takes a Modicon number (40402)")
        return located
    reference = parse_int(text, "-r")
    if not 1 <= reference <= 0x10000:
        raise UsageError(f"-r {text}: mbpoll's references count from 1 (-r 1 is address 0) up to 65536")
    address = reference - 1
    return Located(address, space, f"-r {text} is address {address} (0x{address:04X}): mbpoll's references count from 1")


@dataclass(frozen=True)
class Item:
    """One SELECTOR [COUNT] of a command line: what was typed, how many from it on (None: the
    register alone), and the address `-r` gave (already read)."""

    selector: str
    count: int | None = None
    located: Located | None = None


COUNT_RULE = "a plain decimal number right after a selector is its COUNT"


def parse_items(
    tokens: Sequence[str], *, count: str | None = None, start: str | None = None, modicon: bool = False, space: str | None = None
) -> list[Item]:
    """The selector grammar of every reading command: SELECTOR [COUNT] [SELECTOR [COUNT] ...], or
    mbpoll's `-r REF [-c N]`; `-c N` is the COUNT of a single SELECTOR."""
    if start is not None:
        if tokens:
            raise UsageError(f"-r {start} names the start: give either -r or SELECTORs ({' '.join(tokens)}), not both")
        items = [Item(f"-r {start}", located=locate_reference(start, modicon=modicon, space=space))]
    else:
        if not tokens:
            raise UsageError("give SELECTOR [COUNT] ... (a name, a parameter id or an address), or -r REF [-c N]")
        items = []
        for token in tokens:
            if items and items[-1].count is None and re.fullmatch(r"[0-9]+", token.strip()):
                items[-1] = Item(items[-1].selector, _count(token.strip(), items[-1].selector))
            else:
                items.append(Item(token))
    if count is not None:
        if len(items) > 1:
            raise UsageError(
                f"-c {count} counts from one start: give one SELECTOR (or a COUNT after each: {items[0].selector} {count} ...)"
            )
        if items[0].count is not None:
            raise UsageError(f"two counts: {items[0].selector} {items[0].count} and -c {count}; give one")
        items = [Item(items[0].selector, _count(count, "-c"), items[0].located)]
    return items


def _count(text: str, after: str) -> int:
    value = parse_int(text, "COUNT")
    if value < 1:
        raise UsageError(f"COUNT {value} after {after}: give at least 1")
    return value


class Registers:
    """Look-ups by selector and by address over one device's registers."""

    def __init__(self, device: Device, space: str | None = None, *, modicon: bool = False) -> None:
        self.device = device
        self.space = space  # the space an address selector names (None: the one space that lists a register there)
        self.modicon = modicon  # decimal address selectors are Modicon numbers
        self.notes: list[str] = []  # how -r and Modicon numbers were read, in order, to be said on stderr
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
        located = locate(text, modicon=self.modicon, space=self.space)
        return None if located is None else self.at(located, selector)

    def at(self, located: Located, selector: str) -> Register | None:
        """The register listed at an address: in its space, or in the one space that lists one there."""
        if located.note is not None and located.note not in self.notes:
            self.notes.append(located.note)
        if located.space is not None:
            return self.by_address.get((located.space, located.address))
        order = list(SPACES)
        listed = sorted((reg for (_, at), reg in self.by_address.items() if at == located.address), key=lambda r: order.index(r.space))
        if len(listed) > 1:
            named = ", ".join(f"{space_label(r.space)} {r.label}" for r in listed)
            raise UsageError(f"{selector!r} is the address of {named}; give --space (-t) or the register's name")
        return listed[0] if listed else None

    def resolve(self, selector: str) -> Register:
        reg = self.find(selector)
        if reg is None:
            raise UsageError(f"unknown register {selector!r}{self.hint(selector)}")
        return reg

    def resolve_item(self, item: Item) -> Register:
        if item.located is None:
            return self.resolve(item.selector)
        reg = self.at(item.located, item.selector)
        if reg is None:
            where = f" among the {SPACES[item.located.space].title}" if item.located.space is not None else ""
            raise UsageError(
                f"{item.selector}: no register at {item.located.address} = 0x{item.located.address:04X}{where}; --words reads any address"
            )
        return reg

    def expand(self, item: Item) -> list[Register]:
        """The register an item names, or with a COUNT that many of the map's readable registers of its space from it on."""
        reg = self.resolve_item(item)
        if not reg.access.readable:
            raise UsageError(f"{reg.label} is write-only")
        if item.count is None:
            return [reg]
        chosen = self.from_on(reg.space, reg.address)[: item.count]
        if len(chosen) < item.count:
            what = "registers" if reg.space == DEFAULT_SPACE else SPACES[reg.space].title
            raise UsageError(
                f"only {len(chosen)} readable {what} from {reg.label} onwards, asked for {item.count} ({COUNT_RULE}{self._count_as_address(item)})"
            )
        return chosen

    def select(self, items: Sequence[Item]) -> list[Register]:
        """Every register the items name, in their order, each once."""
        chosen = {reg.name: reg for item in items for reg in self.expand(item)}
        return list(chosen.values())

    def from_on(self, space: str, address: int) -> list[Register]:
        """The map's readable registers of `space` at or after `address`, by address."""
        return sorted(
            (r for r in self.device.registers if r.space == space and r.access.readable and r.address >= address), key=lambda r: r.address
        )

    def _count_as_address(self, item: Item) -> str:
        """Where a COUNT is also an address of the map: how to name that register instead."""
        assert item.count is not None
        try:
            reg = self.find(str(item.count)) if not self.modicon else None
        except UsageError:  # an address two spaces list: no one register to name
            reg = None
        return f"; for {reg.label} at {item.count} as well, write its address in hex: 0x{reg.address:04X}" if reg is not None else ""

    def hint(self, selector: str) -> str:
        try:
            located = locate(selector, modicon=self.modicon, space=self.space)
        except UsageError:
            located = None
        if located is None:
            return self._field_hint(selector) or suggest(selector, [*self.by_name, *self.by_param])
        address = located.address
        spaces = [located.space] if located.space is not None else list(SPACES)
        owners = [o for o in (self.device.covering(address, space) for space in spaces) if o is not None]
        if owners:
            return f" (0x{address:04X} lies inside {owners[0].label}; --words writes single words)"
        where = f" among the {SPACES[located.space].title}" if located.space is not None else ""
        typed, at = selector.strip(), f"0x{address:04X}"
        if typed.isdigit():  # say the number as typed too: 40402 = 0x9DD2
            at = f"{'Modicon ' if self.modicon else ''}{typed} = {at}"
        return f" (no register at {at}{where}{self._nearby(located, selector)}; --words reads and writes any address)"

    def _field_hint(self, selector: str) -> str:
        """REGISTER.FIELD (a struct member's spelling) names one field of a bitfield register: say how regmap names it."""
        head, dot, field = selector.strip().rpartition(".")
        try:
            reg = self.find(head) if dot else None
        except UsageError:
            reg = None
        if reg is None or not any(f.name == field for f in reg.bitfields):
            return ""
        return f" ({field} is a field of {reg.label}: name the register; a write of one field is {reg.name}={field}:VALUE, the other bits kept)"

    def _nearby(self, located: Located, selector: str | None = None) -> str:
        """The notations a field engineer may have meant by a decimal address: a Modicon number, or mbpoll's 1-based -r."""
        if selector is None or not re.fullmatch(r"[0-9]+", selector.strip()) or self.modicon:
            return ""
        found = modicon_reference(selector)
        if found is not None and found in self.by_address and located.space in (None, found[0]):
            space, address = found
            return (
                f"; as a Modicon number {selector.strip()} is {space_label(space)} {address} ({self.by_address[found].label}): "
                f"add --modicon, or write 0x{address:04X}"
            )
        spaces = [located.space] if located.space is not None else list(SPACES)
        below = [self.by_address[(s, located.address - 1)] for s in spaces if (s, located.address - 1) in self.by_address]
        if below:
            return f"; mbpoll's -r {located.address} is address {located.address - 1} ({below[0].label})"
        return ""

    def spec(self, reg: Register) -> RegisterSpec[Any]:
        return self.specs[reg.name]


def dump_range(
    device: Device, start: str | None, count: str | None, space: str | None, *, modicon: bool = False
) -> tuple[list[Register] | None, list[str]]:
    """What `dump -t SPACE` or `dump -r REF [-c N]` reads (None: every readable register), and how -r was read."""
    if start is None:
        if count is not None:
            raise UsageError(f"-c {count} counts from a start: give -r REF too")
        return (None if space is None else Registers(device).from_on(space, 0)), []
    (item,) = parse_items([], count=count, start=start, modicon=modicon, space=space)
    assert item.located is not None
    start_space = item.located.space or space or DEFAULT_SPACE
    chosen = Registers(device).from_on(start_space, item.located.address)[: item.count]
    if not chosen:
        raise UsageError(f"{item.selector}: no readable {SPACES[start_space].title} from 0x{item.located.address:04X} on")
    return chosen, [item.located.note] if item.located.note else []


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
