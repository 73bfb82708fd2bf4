"""Read-plan optimality: a dynamic programme, independent of the greedy planner, finds the fewest
requests (and, among those, the fewest words) that read every readable register under the device's
constraints; the planner's plan is compared with it.

Constraints, as the planner states them: a request reads one space (holding, input, coils, discrete
inputs); at most `limit` registers (`max_bits` bits for coils and discrete inputs) per request; a
register is never split; a request of several registers starts at the high word of a paired register
and spans only documented addresses of its space unless the device tolerates gaps; a lone register
reads just its own words. For registers that do not overlap (checked), every request's registers are
a run of consecutive registers in address order within one space, so a DP over runs, space by space,
is exact. The same holds for the registers of one poll class (`read_all(poll=...)`), whose requests
may span the documented addresses of other classes.
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from regmap.model import Device
from regmap.runtime_bridge import documented_addresses, runtime_specs
from regmap_runtime.plan import plan_reads
from regmap_runtime.spaces import MAX_READ_BITS, SPACES
from regmap_runtime.spec import POLL_CLASSES, RegisterSpec

INFINITY = 10**9


@dataclass(frozen=True)
class Optimum:
    requests: int
    words: int  # fewest words read among the plans with the fewest requests


def fewest_requests(
    specs: Sequence[RegisterSpec[Any]], limit: int, documented: frozenset[tuple[str, int]] | None, *, max_bits: int = MAX_READ_BITS
) -> Optimum:
    """The optimum for registers of any spaces: no request mixes spaces, so it is the sum of each space's."""
    requests = words = 0
    for space in SPACES:
        part = fewest_in_space([r for r in specs if r.space == space], max_bits if SPACES[space].bits else limit, documented)
        requests, words = requests + part.requests, words + part.words
    return Optimum(requests, words)


def fewest_in_space(specs: Sequence[RegisterSpec[Any]], limit: int, documented: frozenset[tuple[str, int]] | None) -> Optimum:
    """DP over the registers of one space in address order: best[j] = the best plan for the first j
    registers, minimising (requests, words) lexicographically."""
    assert len({r.space for r in specs}) <= 1, "one space at a time"
    regs = sorted(specs, key=lambda r: (r.first_address, r.address))
    n = len(regs)
    if n == 0:
        return Optimum(0, 0)
    base = min(r.first_address for r in regs)
    top = max(r.address + r.words for r in regs)
    # undocumented[i]: how many addresses in base .. base+i-1 the device does not answer
    undocumented = [0] * (top - base + 1)
    for i in range(top - base):
        undocumented[i + 1] = undocumented[i] + (documented is not None and (regs[0].space, base + i) not in documented)
    best: list[tuple[int, int]] = [(0, 0)] + [(INFINITY, INFINITY)] * n
    for end in range(1, n + 1):
        last = regs[end - 1]
        high = last.address + last.words
        for start in range(end, 0, -1):
            first = regs[start - 1]
            high = max(high, first.address + first.words)
            if start == end:  # a lone register: its own words, pair or not
                low = last.address
            else:
                low = first.first_address
                if high - low > limit:
                    break  # a longer run only gets longer
                if undocumented[high - base] - undocumented[low - base]:
                    break  # the gap stays inside every longer run that starts earlier
            requests, words = best[start - 1]
            candidate = (requests + 1, words + high - low)
            if candidate < best[end]:
                best[end] = candidate
    return Optimum(*best[n])


def overlapping(specs: Sequence[RegisterSpec[Any]]) -> list[tuple[str, str]]:
    """Pairs of readable registers of one space whose words (pair high words included) overlap."""
    regs = sorted(specs, key=lambda r: (r.space, r.first_address))
    return [(a.name, b.name) for a, b in itertools.pairwise(regs) if a.space == b.space and b.first_address < a.address + a.words]


@dataclass(frozen=True)
class PartCheck:
    """The plan of one part of the readable registers (one space, or one poll class) against the DP."""

    part: str  # "holding", "coil", ... or "poll static", "poll fast", ...
    registers: int
    plan_requests: int
    optimum: Optimum
    sweep_mismatches: tuple[int, ...]

    @property
    def optimal(self) -> bool:
        return self.plan_requests == self.optimum.requests and not self.sweep_mismatches


@dataclass(frozen=True)
class PlanCheck:
    device_id: str
    limit: int
    plan_requests: int
    plan_words: int
    optimum: Optimum
    overlaps: int
    sweep_instances: int  # other limits checked: 2..125
    sweep_mismatches: tuple[int, ...]  # limits at which the planner needed more requests than the DP
    tolerant_requests: int  # what the plan would be if the device answered reads across gaps
    parts: tuple[PartCheck, ...] = ()  # per space and per poll class (only where the map has more than one)

    @property
    def optimal(self) -> bool:
        return (
            self.plan_requests == self.optimum.requests
            and not self.sweep_mismatches
            and not self.overlaps
            and all(p.optimal for p in self.parts)
        )


def _part(
    name: str,
    specs: Sequence[RegisterSpec[Any]],
    limit: int,
    max_bits: int,
    documented: frozenset[tuple[str, int]] | None,
    sweep: Sequence[int],
) -> PartCheck:
    """The planner against the DP on `specs`, at the device's limits and at every limit of the sweep
    (the sweep sets the register and the bit limit alike)."""
    mismatches = tuple(
        n for n in sweep if len(plan_reads(specs, n, documented, max_bits=n)) != fewest_requests(specs, n, documented, max_bits=n).requests
    )
    plan = plan_reads(specs, limit, documented, max_bits=max_bits)
    return PartCheck(name, len(specs), len(plan), fewest_requests(specs, limit, documented, max_bits=max_bits), mismatches)


def check(device: Device, sweep: Sequence[int] = range(2, 126)) -> PlanCheck:
    t = device.transport
    specs = [s for s in runtime_specs(device) if s.readable]
    documented = None if t.tolerates_gaps else documented_addresses(device)
    bits = t.max_read_coils
    plan = plan_reads(specs, t.max_read_registers, documented, max_bits=bits)
    optimum = fewest_requests(specs, t.max_read_registers, documented, max_bits=bits)
    mismatches = tuple(
        limit
        for limit in sweep
        if len(plan_reads(specs, limit, documented, max_bits=limit)) != fewest_requests(specs, limit, documented, max_bits=limit).requests
    )
    spaces = [space for space in SPACES if any(s.space == space for s in specs)]
    classes = [poll for poll in POLL_CLASSES if any(s.poll == poll for s in specs)]
    parts: list[PartCheck] = []
    if len(spaces) > 1:
        parts += [_part(space, [s for s in specs if s.space == space], t.max_read_registers, bits, documented, sweep) for space in spaces]
    if len(classes) > 1:
        parts += [
            _part(f"poll {poll}", [s for s in specs if s.poll == poll], t.max_read_registers, bits, documented, sweep) for poll in classes
        ]
    return PlanCheck(
        device_id=device.id,
        limit=t.max_read_registers,
        plan_requests=len(plan),
        plan_words=sum(b.count for b in plan),
        optimum=optimum,
        overlaps=len(overlapping(specs)),
        sweep_instances=len(sweep),
        sweep_mismatches=mismatches,
        tolerant_requests=len(plan_reads(specs, t.max_read_registers, None, max_bits=bits)),
        parts=tuple(parts),
    )
