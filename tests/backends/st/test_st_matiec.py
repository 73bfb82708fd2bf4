"""matiec (OpenPLC's and Beremiz's IEC 61131-3 compiler) compiles every map's plain-standard ST.

The `iec/` dialect says "IEC 61131-3 (OpenPLC / matiec)": its types, functions and constants (in a
resource) must pass `iec2c` with no error, for the seed maps and for every fixture map. The CODESYS
dialect shares every line but its pragmas, enum base types and qualified enum values
(tests/backends/st/test_st_backend.py holds it to that), so its conversions are checked here too.

Without a built matiec (`make tools`, from ../shared/tools) the test skips; under CI=true it fails.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from regmap.frontend import load_map

from conftest import FIXTURE_MAPS, MAPS, ROOT, built_tool
from support.st_matiec import decoding_program, iec2c, program_text, st_files


@pytest.fixture(scope="session")
def matiec() -> Path:
    return built_tool("matiec")


@pytest.mark.parametrize("map_path", [*MAPS, *FIXTURE_MAPS], ids=lambda p: p.stem)
def test_matiec_compiles_the_plain_standard_st(map_path: Path, matiec: Path, tmp_path: Path) -> None:
    device = load_map(map_path, display_name=map_path.relative_to(ROOT).as_posix())
    files = st_files(device)
    source = program_text(files, decoding_program(files, f"ST_{device.id.upper()}_VALUES"), "P_DECODE_ALL")
    compiled = iec2c(matiec, source, tmp_path, device.id)
    lines = source.splitlines()
    shown = [f"{e}\n    {lines[int(e.split(':')[0]) - 1].strip()}" for e in compiled.errors[:20]]
    assert compiled.returncode == 0 and not compiled.errors, (
        f"iec2c: {len(compiled.errors)} errors in {device.id}:\n" + "\n".join(shown) + "\n" + compiled.output[-2000:]
    )
    assert sorted(p.name for p in compiled.c_dir.glob("*.c")), "iec2c wrote no C"


def test_matiec_reports_an_error_it_is_shown() -> None:
    """The error parser reads iec2c's message form (a parse that found none would pass any output)."""
    from support.st_matiec import ERROR

    text = "x.st:12: error: ')' missing.\nx.st:7-9..7-20: error: invalid.\nx.st:3-1..y.st:4-2: error: w.\n3 error(s) found.\n"
    assert [m["line"] for m in ERROR.finditer(text)] == ["12", "7", "3"]
