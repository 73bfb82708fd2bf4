"""The README's examples work as printed."""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

from conftest import GENERATED, ROOT, mypy_strict, require_tool

README = (ROOT / "README.md").read_text(encoding="utf-8")


def _block(language: str, contains: str) -> str:
    for match in re.finditer(rf"```{language}\n(.*?)```", README, re.S):
        if contains in match.group(1):
            return match.group(1)
    raise AssertionError(f"no {language} block with {contains!r} in the README")


def test_c_example_compiles(tmp_path: Path) -> None:
    cc = require_tool("gcc")
    source = tmp_path / "readme.c"
    source.write_text(_block("c", "idm_rs.h"), encoding="utf-8")
    flags = ["-std=c99", "-Wall", "-Wextra", "-Wpedantic", "-Werror", "-Wconversion", "-Wno-missing-prototypes"]
    result = subprocess.run(
        [cc, *flags, "-I", str(GENERATED / "c"), "-c", str(source), "-o", str(tmp_path / "readme.o")],
        capture_output=True,
        text=True,
        check=False,
    )
    assert result.returncode == 0, result.stderr


def test_python_example_type_checks(tmp_path: Path) -> None:
    code = _block("python", "from idm_rs import").replace('sys.path.insert(0, "generated/python")', "pass")
    program = tmp_path / "readme_example.py"
    program.write_text(code, encoding="utf-8")
    result = mypy_strict(str(program))
    assert result.returncode == 0, result.stdout


def test_map_table_matches_the_maps() -> None:
    from regmap.frontend import load_map

    from conftest import MAPS

    for path in MAPS:
        device = load_map(path)
        row = re.search(rf"^\| `maps/{path.name}` \|[^|]*\| (\d+) \| (\d+) \| (\d+) \|$", README, re.M)
        assert row is not None, f"README has no row for maps/{path.name}"
        assert tuple(int(x) for x in row.groups()) == (len(device.registers), len(device.examples), len(device.errata)), (
            f"README row of {path.name} is stale"
        )


def test_the_tour_prints_what_the_readme_says() -> None:
    """Each `regmap ...` line of the tour followed by a `# output` line prints that output."""
    import itertools
    import shlex
    import sys

    lines = _block("sh", "regmap validate maps/idm_rs.yaml").splitlines()
    checked = 0
    for command, expected in itertools.pairwise(lines):
        if not command.startswith("regmap ") or not expected.startswith("# "):
            continue
        argv = shlex.split(command.split("  #", 1)[0])
        result = subprocess.run([sys.executable, "-m", "regmap", *argv[1:]], cwd=ROOT, capture_output=True, text=True, check=False)
        shown = expected[2:].strip()
        if shown.endswith("..."):
            assert any(line.strip().startswith(shown[:-3].strip()) for line in result.stdout.splitlines()), (command, result.stdout)
        else:
            assert shown in [line.strip() for line in result.stdout.splitlines()], (command, result.stdout, result.stderr)
        checked += 1
    assert checked >= 5
