"""The repository as a newcomer meets it: no file a shell would take for an option, scripts that honour --help."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from conftest import ROOT


def test_no_tracked_file_looks_like_an_option() -> None:
    tracked = subprocess.run(["git", "ls-files", "-z"], cwd=ROOT, capture_output=True, check=True).stdout.decode().split("\0")
    assert [name for name in tracked if Path(name).name.startswith("-")] == []


def test_the_table_script_answers_help_and_writes_nothing(tmp_path: Path) -> None:
    script = ROOT / "tests" / "support" / "c630s_table.py"
    for argv in (["--help"], ["write", "--help"]):
        result = subprocess.run([sys.executable, str(script), *argv], cwd=tmp_path, capture_output=True, text=True, check=False)
        assert result.returncode == 0, result.stderr
        assert "usage:" in result.stdout
    refused = subprocess.run([sys.executable, str(script), "--report"], cwd=tmp_path, capture_output=True, text=True, check=False)
    assert refused.returncode == 2 and "usage:" in refused.stderr
    assert list(tmp_path.iterdir()) == []
