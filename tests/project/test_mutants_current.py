"""The curated mutants (tests/mutation/mutants.yaml, run by `make mutate`) stay current: each names a line
that is in its file exactly once and tests that exist, so a refactor that moves a line fails here, in
`make test`, rather than only when someone runs the slow mutation gate."""

from __future__ import annotations

import importlib.util
import sys
from typing import Any

from conftest import ROOT


def _gate() -> Any:
    """tests/mutation/run.py, the gate itself, so the list is read as it reads it."""
    spec = importlib.util.spec_from_file_location("mutation_gate", ROOT / "tests" / "mutation" / "run.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # its dataclass looks itself up there
    spec.loader.exec_module(module)
    return module


def test_every_mutant_names_one_line_and_real_tests() -> None:
    mutants = _gate().load()
    stale = [m.id for m in mutants if (ROOT / m.file).read_text(encoding="utf-8").count(m.original) != 1]
    assert not stale, f"mutants whose line is not in the file exactly once: {stale}"
    assert all(m.mutant != m.original for m in mutants)
    missing = [(m.id, t) for m in mutants for t in m.tests if not (ROOT / t.split("::")[0]).is_file()]
    assert not missing, missing
    assert len({m.id for m in mutants}) == len(mutants)
