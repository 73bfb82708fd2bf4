"""Structured Text has no f16 helpers yet: the float helpers go by width (32 or 64 bits), so a map with a half
float is refused by the st target with one line per register at file:line:col, not generated wrong."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from regmap.backends.st import check
from regmap.frontend import load_map

from support.half_map import write_half_map


def test_a_half_float_is_named_not_generated(tmp_path: Path) -> None:
    path = write_half_map(tmp_path)
    problems = check(load_map(path))
    halves = [r for r in load_map(path).registers if r.type.value == "f16"]
    assert [p.message.split(":")[0] for p in problems] == [r.name for r in halves]
    assert all(p.file == str(path) and p.line > 0 and "f16 (half float)" in p.message for p in problems)
    run = subprocess.run(
        [sys.executable, "-m", "regmap", "generate", "--target", "st", "--out", str(tmp_path / "out"), str(path)],
        capture_output=True,
        text=True,
        check=False,
    )
    assert run.returncode != 0 and "Traceback" not in run.stderr
    assert f"{path}:" in run.stderr and "setpoint: an f16 (half float)" in run.stderr
    assert not (tmp_path / "out" / "st").exists()
