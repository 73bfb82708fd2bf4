"""The read-plan optimality bench (bench/optimal.py) per space and per poll class: the fixture maps of
issue #19, and random registers over every space and class, planned greedily and by the DP."""

from __future__ import annotations

import random
import sys
from typing import Any

import pytest

from regmap.frontend import load_map
from regmap.model import PollClass
from regmap.runtime_bridge import read_plan, runtime_specs
from regmap_runtime.plan import plan_reads
from regmap_runtime.spaces import SPACES
from regmap_runtime.spec import POLL_CLASSES, RegisterSpec

from conftest import FIXTURE_MAPS, ROOT

if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))  # bench/ sits at the top of the repository

from bench import optimal

FIXTURES = {path.stem: load_map(path) for path in FIXTURE_MAPS}


@pytest.mark.parametrize("name", sorted(FIXTURES))
def test_the_fixture_plans_are_optimal_per_space_and_class(name: str) -> None:
    device = FIXTURES[name]
    result = optimal.check(device, sweep=range(2, 126))
    assert result.optimal, result
    specs = [s for s in runtime_specs(device) if s.readable]
    spaces = {s.space for s in specs}
    classes = {s.poll for s in specs}
    expected = (sorted(spaces) if len(spaces) > 1 else []) + (sorted(f"poll {c}" for c in classes) if len(classes) > 1 else [])
    assert sorted(p.part for p in result.parts) == sorted(expected)
    # The class plans are read_plan(poll=...)'s, the ones read_all(poll=...) sends.
    for poll in PollClass:
        part = next((p for p in result.parts if p.part == f"poll {poll.value}"), None)
        if part is not None:
            assert part.plan_requests == len(read_plan(device, poll=poll))


def test_the_fixtures_have_what_the_per_part_check_is_for() -> None:
    """So that the check above cannot pass vacuously: several spaces and several classes among the fixtures."""
    parts = {p.part for d in FIXTURES.values() for p in optimal.check(d, sweep=(125,)).parts}
    assert set(SPACES) <= parts and {f"poll {c}" for c in POLL_CLASSES} <= parts


def _random_specs(rng: random.Random) -> list[RegisterSpec[Any]]:
    specs: list[RegisterSpec[Any]] = []
    for space in SPACES:
        address = rng.randint(0, 20)
        for i in range(rng.randint(0, 25)):
            address += rng.randint(0, 3)
            data_type = "bool" if SPACES[space].bits else rng.choice(["u16", "s32", "u64", "f32"])
            poll = rng.choice(POLL_CLASSES)
            specs.append(RegisterSpec(name=f"{space}{i}", address=address, data_type=data_type, access="r", space=space, poll=poll))
            address += specs[-1].words
    return specs


def test_the_dp_agrees_with_the_planner_over_spaces_and_classes() -> None:
    rng = random.Random(19)
    for _ in range(300):
        specs = _random_specs(rng)
        limit, bits = rng.randint(4, 20), rng.randint(1, 30)  # a u64 needs 4 registers in one request
        documented = (
            None if rng.random() < 0.3 else frozenset((r.space, a) for r in specs for a in range(r.first_address, r.address + r.words))
        )
        for chosen in (specs, *([s for s in specs if s.poll == poll] for poll in POLL_CLASSES)):
            plan = plan_reads(chosen, limit, documented, max_bits=bits)
            assert optimal.fewest_requests(chosen, limit, documented, max_bits=bits).requests == len(plan)
            assert all(len({r.space for r in b.registers}) == 1 for b in plan)
            assert all(b.count <= (bits if SPACES[b.space].bits else limit) for b in plan)


def test_the_dp_never_mixes_spaces() -> None:
    """Two spaces at the same addresses: the optimum is one request each, not one for both."""
    specs: list[RegisterSpec[Any]] = [
        RegisterSpec(name=f"{space}{a}", address=a, data_type="u16" if not SPACES[space].bits else "bool", access="r", space=space)
        for space in ("holding", "coil")
        for a in range(4)
    ]
    assert optimal.fewest_requests(specs, 125, None).requests == 2
    with pytest.raises(AssertionError, match="one space at a time"):
        optimal.fewest_in_space(specs, 125, None)
