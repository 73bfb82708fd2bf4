"""What a `regmap generate` process imports (issue #36: its CPU against the import floor): a map's targets never
need pymodbus, which only a plant's bus schedule (regmap_runtime.line) and the live tools use, nor jsonschema, which
only words the problems of a map that fails the compiled schema check (fastschema)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from conftest import ROOT

PROBE = """
import sys
from regmap.cli import main
status = main(["generate", sys.argv[1], "--out", sys.argv[2]])
print(status, sorted(name for name in sys.modules if name.split(".")[0] in ("pymodbus", "jsonschema")))
"""


def test_generating_a_valid_map_imports_no_pymodbus_nor_jsonschema(tmp_path: Path) -> None:
    result = subprocess.run(
        [sys.executable, "-c", PROBE, str(ROOT / "maps" / "idm_rs.yaml"), str(tmp_path / "out")],
        cwd=ROOT,
        capture_output=True,
        text=True,
        check=False,
    )
    assert result.stdout.splitlines()[-1] == "0 []", result.stdout + result.stderr
    assert (tmp_path / "out" / "python" / "idm_rs" / "__init__.py").is_file()  # every target ran, Python's included
