"""Request planning: the fewest Modbus requests that read or write a set of registers.

Reads: registers sorted by (space, address) are cut greedily into blocks of at most `max_registers`
words. A block never mixes register spaces, never splits a register, never crosses an address the
device does not document (unless it tolerates gaps), and starts at the high word of a paired register. For intervals on a
line, taking as many as fit before cutting is optimal (an exchange argument: any optimal plan's
first cut can be moved right to the greedy cut without adding a request).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from typing import Any

from .align import Alignment, padded
from .spaces import DEFAULT_SPACE, MAX_READ_BITS, MAX_WRITE_BITS, SPACES
from .spec import Raw, RegisterSpec


@dataclass(frozen=True)
class ReadBlock:
    address: int
    count: int
    registers: tuple[RegisterSpec[Any], ...]
    space: str = DEFAULT_SPACE

    def words_of(self, spec: RegisterSpec[Any], words: Sequence[int]) -> list[int]:
        """Slice one register's own words out of the words this block returned."""
        start = spec.address - self.address
        own = words[start : start + spec.words]
        return own if isinstance(own, list) else list(own)  # a list's slice is already a copy


def _block(regs: list[RegisterSpec[Any]], alignment: Alignment | None, readable: Callable[[str, Iterable[int]], bool]) -> ReadBlock:
    if len(regs) == 1:
        # A lone register reads just its own words (a lone pair reads its listed low word, as the maps' `paired` rule says).
        reg = regs[0]
        start, end = reg.address, reg.address + reg.words
    else:
        start, end = regs[0].first_address, regs[-1].address + regs[-1].words
    space = regs[0].space
    if alignment is not None and not alignment.allows(space, start, end - start):
        widened = padded(alignment, space, regs[0].first_address, end, lambda words: readable(space, words))
        if widened is None:
            raise ValueError(
                f"{regs[0].label}: no read of it is aligned to {alignment.words} words without reading an address the device refuses"
            )
        start, end = widened
    return ReadBlock(start, end - start, tuple(regs), space)


_SPACE_ORDER = {name: index for index, name in enumerate(SPACES)}


def _in_order(spec: RegisterSpec[Any]) -> tuple[int, int]:
    return _SPACE_ORDER[spec.space], spec.first_address


def plan_reads(
    registers: Iterable[RegisterSpec[Any]],
    max_registers: int,
    documented: frozenset[tuple[str, int]] | None = None,
    *,
    max_bits: int = MAX_READ_BITS,
    alignment: Alignment | None = None,
) -> list[ReadBlock]:
    """Blocks covering every register, space by space. `documented` is the set of (space, address)
    the device answers; None means the device tolerates reads of undocumented addresses.
    `max_registers` limits a 0x03/0x04 request, `max_bits` a 0x01/0x02 request. With an `alignment`, every
    block of a space it covers starts and ends on whole units, padded over readable words only; a register
    it exempts whose padding is not readable is read alone, as the manual allows."""
    regs = sorted({r.name: r for r in registers if r.readable}.values(), key=_in_order)

    def readable(space: str, words: Iterable[int]) -> bool:
        return documented is None or all((space, a) in documented for a in words)

    def alone(reg: RegisterSpec[Any]) -> bool:
        end = reg.address + reg.words
        if alignment is None or alignment.aligned(reg.space, reg.first_address, end - reg.first_address):
            return False
        exempt = alignment.allows(reg.space, reg.address, reg.words)
        return exempt and padded(alignment, reg.space, reg.first_address, end, lambda words: readable(reg.space, words)) is None

    blocks: list[ReadBlock] = []
    current: list[RegisterSpec[Any]] = []
    for reg in regs:
        if current and (alone(reg) or alone(current[0])):
            blocks.append(_block(current, alignment, readable))
        elif current:
            start = current[0].first_address
            prev_end = current[-1].address + current[-1].words
            gap = range(prev_end, reg.first_address)
            limit = max_bits if SPACES[reg.space].bits else max_registers
            end = reg.address + reg.words
            if alignment is not None:
                start, end = alignment.extent(reg.space, start, end)
                limit = alignment.limit(reg.space, limit)
            fits = end - start <= limit
            if reg.space == current[0].space and fits and readable(reg.space, gap) and reg.first_address >= prev_end:
                current.append(reg)
                continue
            blocks.append(_block(current, alignment, readable))
        current = [reg]
    if current:
        blocks.append(_block(current, alignment, readable))
    return blocks


@dataclass(frozen=True)
class WriteBlock:
    address: int
    words: tuple[int, ...]
    registers: tuple[RegisterSpec[Any], ...]
    space: str = DEFAULT_SPACE

    @property
    def single(self) -> bool:
        """Sent with the single-write function (0x06 for one register, 0x05 for one coil) rather than 0x10/0x0F."""
        return len(self.words) == 1


def plan_writes(
    values: Iterable[tuple[RegisterSpec[Any], Raw]],
    max_registers: int,
    use_write_multiple: bool = True,
    *,
    max_bits: int = MAX_WRITE_BITS,
) -> list[WriteBlock]:
    """Group raw writes into the fewest requests: contiguous registers share one 0x10 request
    (a paired register contributes its high word too, as a `paired` map's block writes do); a lone
    16-bit register goes out as 0x06 at its listed address."""
    from .codec import raw_to_words

    items = sorted(values, key=lambda item: _in_order(item[0]))
    names = [spec.name for spec, _ in items]
    if len(set(names)) != len(names):
        raise ValueError("the same register is written twice in one request")
    groups: list[list[tuple[RegisterSpec[Any], Raw]]] = []
    for spec, raw in items:
        if groups and use_write_multiple:
            last_spec = groups[-1][-1][0]
            start = groups[-1][0][0].first_address
            contiguous = spec.space == last_spec.space and spec.first_address == last_spec.address + last_spec.words
            limit = max_bits if SPACES[spec.space].bits else max_registers
            if contiguous and spec.address + spec.words - start <= limit:
                groups[-1].append((spec, raw))
                continue
        groups.append([(spec, raw)])
    blocks = []
    for group in groups:
        if len(group) == 1 and group[0][0].words == 1:
            spec, raw = group[0]
            blocks.append(WriteBlock(spec.address, tuple(raw_to_words(spec, raw)), (spec,), spec.space))
            continue
        words: list[int] = []
        for spec, raw in group:
            words.extend(raw_to_words(spec, raw, with_pair=True))
        blocks.append(WriteBlock(group[0][0].first_address, tuple(words), tuple(s for s, _ in group), group[0][0].space))
    return blocks
