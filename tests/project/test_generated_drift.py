"""The committed generated/ tree must be exactly what the maps produce now."""

from __future__ import annotations

import difflib
import subprocess
import sys
from pathlib import Path

from conftest import GENERATED, ROOT
from support.trees import tree


def test_generated_tree_matches_the_maps(tmp_path: Path) -> None:
    out = tmp_path / "generated"
    result = subprocess.run(
        [sys.executable, "-m", "regmap", "generate", "--out", str(out)], cwd=ROOT, capture_output=True, text=True, check=False
    )
    assert result.returncode == 0, result.stderr
    fresh, committed = tree(out), tree(GENERATED)
    problems = []
    for name in sorted(set(fresh) | set(committed)):
        if name not in committed:
            problems.append(f"missing from generated/: {name}")
        elif name not in fresh:
            problems.append(f"stale file in generated/ (no map produces it): {name}")
        elif fresh[name] != committed[name]:
            diff = difflib.unified_diff(
                committed[name].decode("utf-8", "replace").splitlines(),
                fresh[name].decode("utf-8", "replace").splitlines(),
                f"generated/{name} (committed)",
                f"generated/{name} (from the maps now)",
                lineterm="",
                n=2,
            )
            problems.append("\n".join(list(diff)[:40]))
    assert not problems, "generated/ has drifted from the maps; run `make generate` and commit:\n" + "\n".join(problems)


def test_generation_is_deterministic(tmp_path: Path) -> None:
    trees = []
    for name in ("a", "b"):
        out = tmp_path / name
        subprocess.run([sys.executable, "-m", "regmap", "generate", "--out", str(out)], cwd=ROOT, check=True, capture_output=True)
        trees.append(tree(out))
    assert trees[0] == trees[1]
