"""The committed generated/ tree must be exactly what the maps and the example plants produce now
(`make generate`: `regmap generate`, then `regmap generate PLANT` for each plant in examples/plants/)."""

from __future__ import annotations

import difflib
import subprocess
import sys
from pathlib import Path

from regmap.frontend.plant import load_plant

from conftest import GENERATED, ROOT
from support.trees import tree

PLANTS = sorted((ROOT / "examples" / "plants").glob("*.yaml"))


def _generate(*args: str) -> None:
    result = subprocess.run([sys.executable, "-m", "regmap", "generate", *args], cwd=ROOT, capture_output=True, text=True, check=False)
    assert result.returncode == 0, result.stderr


def test_generated_tree_matches_the_maps(tmp_path: Path) -> None:
    out = tmp_path / "generated"
    _generate("--out", str(out))
    (out / "plants").mkdir()
    for plant in PLANTS:
        _generate(plant.relative_to(ROOT).as_posix(), "--out", str(out / "plants" / load_plant(plant).id))
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
    assert not problems, "generated/ has drifted from the maps or plants; run `make generate` and commit:\n" + "\n".join(problems)


def test_generation_is_deterministic(tmp_path: Path) -> None:
    trees = []
    for name in ("a", "b"):
        out = tmp_path / name
        subprocess.run([sys.executable, "-m", "regmap", "generate", "--out", str(out)], cwd=ROOT, check=True, capture_output=True)
        trees.append(tree(out))
    assert trees[0] == trees[1]
