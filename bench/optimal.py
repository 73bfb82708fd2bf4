"""Read-plan optimality: a dynamic programme, independent of the greedy planner, finds the fewest
requests (and, among those, the fewest words) that read every readable register under the device's
constraints; the planner's plan is compared with it.

Constraints, as the planner states them: at most `limit` registers per request; a register is never
split; a request of several registers starts at the high word of a paired register and spans only
documented addresses unless the device tolerates gaps; a lone register reads just its own words.
For registers that do not overlap (checked), every request's registers are a run of consecutive
registers in address order, so a DP over runs is exact.
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from regmap.model import Device
from regmap.runtime_bridge import documented_addresses, runtime_specs
from regmap_runtime.plan import plan_reads
from regmap_runtime.spec import RegisterSpec

INFINITY = 10**9


@dataclass(frozen=True)
class Optimum:
    requests: int
    words: int  # fewest words read among the plans with the fewest requests


def fewest_requests(specs: Sequence[RegisterSpec[Any]], limit: int, documented: frozenset[tuple[str, int]] | None) -> Optimum:
    """DP over the registers of one space in address order: best[j] = the best plan for the first j
    registers, minimising (requests, words) lexicographically."""
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
    """Pairs of readable registers whose words (pair high words included) overlap."""
    regs = sorted(specs, key=lambda r: r.first_address)
    return [(a.name, b.name) for a, b in itertools.pairwise(regs) if b.first_address < a.address + a.words]


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

    @property
    def optimal(self) -> bool:
        return self.plan_requests == self.optimum.requests and not self.sweep_mismatches and not self.overlaps


def check(device: Device, sweep: Sequence[int] = range(2, 126)) -> PlanCheck:
    t = device.transport
    specs = [s for s in runtime_specs(device) if s.readable]
    documented = None if t.tolerates_gaps else documented_addresses(device)
    plan = plan_reads(specs, t.max_read_registers, documented)
    optimum = fewest_requests(specs, t.max_read_registers, documented)
    mismatches = tuple(
        limit for limit in sweep if len(plan_reads(specs, limit, documented)) != fewest_requests(specs, limit, documented).requests
    )
    return PlanCheck(
        device_id=device.id,
        limit=t.max_read_registers,
        plan_requests=len(plan),
        plan_words=sum(b.count for b in plan),
        optimum=optimum,
        overlaps=len(overlapping(specs)),
        sweep_instances=len(sweep),
        sweep_mismatches=mismatches,
        tolerant_requests=len(plan_reads(specs, t.max_read_registers, None)),
    )
