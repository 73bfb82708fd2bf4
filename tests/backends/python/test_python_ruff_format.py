"""The generated Python goes through ruff format, run as a child process: its files are rewritten in place, the
vendored runtime is left as it is, and a file ruff cannot read stops the run with ruff's own words."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

from regmap.backends.python.package import _ruff_bin, _run, ruff_format
from regmap.diagnostics import UsageError

UNFORMATTED = "x = {  'a':1 }\n"
FORMATTED = 'x = {"a": 1}\n'


def test_the_generated_modules_are_formatted_and_the_runtime_is_not(tmp_path: Path) -> None:
    (tmp_path / "drive").mkdir()
    (tmp_path / "runtime").mkdir()
    (tmp_path / "drive" / "__init__.py").write_text(UNFORMATTED)
    (tmp_path / "runtime" / "codec.py").write_text(UNFORMATTED)
    ruff_format(tmp_path, skip="runtime")
    assert (tmp_path / "drive" / "__init__.py").read_text() == FORMATTED
    assert (tmp_path / "runtime" / "codec.py").read_text() == UNFORMATTED


def test_a_file_ruff_cannot_parse_stops_the_run(tmp_path: Path) -> None:
    (tmp_path / "broken.py").write_text("def (:\n")
    with pytest.raises(UsageError, match="ruff could not format"):
        ruff_format(tmp_path, skip="runtime")


def test_the_child_s_status_and_standard_error_come_back_and_its_output_is_dropped(capfd: pytest.CaptureFixture[str]) -> None:
    child = "import sys; print('dropped'); sys.stderr.write('said'); sys.exit(3)"
    assert _run([sys.executable, "-c", child]) == (3, "said")
    assert capfd.readouterr() == ("", "")


def test_the_binary_is_the_one_ruff_itself_finds() -> None:
    from ruff import find_ruff_bin

    assert _ruff_bin() == find_ruff_bin()
