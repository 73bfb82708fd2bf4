"""What a `regmap generate` process imports (issue #36: its CPU against the import floor): a map's targets never
need pymodbus, which only a plant's bus schedule (regmap_runtime.line) and the live tools use, nor jsonschema, which
only words the problems of a map that fails the compiled schema check (fastschema), nor any plant module (the plant
model, its front end, a back end's plant renderer), which only a plant's run uses, nor importlib.resources (regmap's
package data is read beside its code)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

from conftest import ROOT

PROBE = """
import json, sys
from regmap.cli import main
status = main(sys.argv[1:])
print(json.dumps([status, sorted(sys.modules)]))
"""


def _imported(*argv: str) -> list[str]:
    """The modules a process running `regmap ARGV` has imported at its end (after checking it succeeded)."""
    result = subprocess.run([sys.executable, "-c", PROBE, *argv], cwd=ROOT, capture_output=True, text=True, check=False)
    status, modules = json.loads(result.stdout.splitlines()[-1])
    assert status == 0, result.stdout + result.stderr
    return list(modules)


def _plant_modules(modules: list[str]) -> list[str]:
    return [name for name in modules if name.split(".")[-1] == "plant"]


def test_generating_a_valid_map_imports_no_pymodbus_nor_jsonschema_nor_a_plant_module(tmp_path: Path) -> None:
    modules = _imported("generate", str(ROOT / "maps" / "idm_rs.yaml"), "--out", str(tmp_path / "out"))
    assert [name for name in modules if name.split(".")[0] in ("pymodbus", "jsonschema")] == []
    assert [name for name in modules if name.startswith("importlib.resources")] == []
    assert _plant_modules(modules) == []
    assert (tmp_path / "out" / "python" / "idm_rs" / "__init__.py").is_file()  # every target ran, Python's included


def test_a_plant_run_imports_the_plant_modules(tmp_path: Path) -> None:
    modules = _imported("generate", str(ROOT / "examples" / "plants" / "cell1.yaml"), "--out", str(tmp_path / "plant"))
    assert {"regmap.plant", "regmap.frontend.plant", "regmap.backends.c.plant", "regmap.backends.st.plant"} <= set(_plant_modules(modules))
