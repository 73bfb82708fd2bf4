"""A timestamp register in the generated Python client: reads are typed `datetime` (`| None` where the device
has a "not available" marker), writes take a `datetime`, and mypy --strict holds users to it (the float
meter fixture: `clock`, local, and `last_reset`, UTC)."""

from __future__ import annotations

import re
from pathlib import Path

from conftest import fixture_maps_generated, mypy_strict

CORRECT = """
from datetime import datetime
from typing import assert_type

from fixture_float_meter import FixtureFloatMeter


def use(meter: FixtureFloatMeter) -> datetime | None:
    assert_type(meter.read_clock(), datetime)
    meter.write_clock(datetime(2024, 1, 1))
    snapshot = meter.read_all()
    clock: datetime = snapshot["clock"]
    print(clock.isoformat())
    assert_type(meter.read_last_reset(), datetime | None)
    return snapshot["last_reset"]
"""

# Each line marked `# refused` must be an error of mypy --strict, and no other line.
MISUSE = """
from datetime import datetime

from fixture_float_meter import FixtureFloatMeter


def misuse(meter: FixtureFloatMeter) -> None:
    meter.write_clock(1704067200)  # refused: the typed write takes a datetime, not seconds
    seconds: int = meter.read_clock()  # refused: a read is a datetime
    when: datetime = meter.read_last_reset()  # refused: None for the 'not available' marker
    print(seconds, when)
"""


def _run(tmp_path: Path, text: str) -> tuple[int, str, Path]:
    program = tmp_path / "use_timestamps.py"
    program.write_text(text, encoding="utf-8")
    result = mypy_strict(str(program), cwd=fixture_maps_generated() / "python")
    return result.returncode, result.stdout + result.stderr, program


def test_a_correct_use_of_timestamps_passes_mypy_strict(tmp_path: Path) -> None:
    code, out, _ = _run(tmp_path, CORRECT)
    assert code == 0, out


def test_each_misuse_of_a_timestamp_fails_mypy_strict(tmp_path: Path) -> None:
    code, out, program = _run(tmp_path, MISUSE)
    refused = {number for number, line in enumerate(MISUSE.splitlines(), 1) if "# refused" in line}
    assert code == 1, out
    assert {int(m.group(1)) for m in re.finditer(rf"{re.escape(program.name)}:(\d+): error:", out)} == refused, out
