"""A map full of hostile text cannot inject into generated Python, C or Markdown (issue 12)."""

from __future__ import annotations

import dataclasses
import json
import re
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import ROOT, mypy_strict, require_tool

HOSTILE = ROOT / "tests" / "maps" / "hostile" / "hostile.yaml"


@pytest.fixture(scope="module")
def generated(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("hostile") / "generated"
    result = subprocess.run(
        [sys.executable, "-m", "regmap", "generate", str(HOSTILE), "--out", str(out)], cwd=ROOT, capture_output=True, text=True, check=False
    )
    assert result.returncode == 0, result.stderr
    return out


def test_python_imports_and_runs_nothing_injected(generated: Path, tmp_path: Path) -> None:
    probe = (
        "import hostile_dev as h, pathlib\n"
        "assert not [n for n in dir(h) if 'pwn' in n.lower()], dir(h)\n"
        "assert set(h.Class.__members__) == {'NONE', 'RETURN_', 'DEFAULT'}\n"
        "assert h.DEVICE.registers[0].name == 'import'\n"
        "print(h.HostileDev.read_import_.__doc__)\n"
    )
    result = subprocess.run(
        [sys.executable, "-c", probe],
        cwd=tmp_path,
        env={"PYTHONPATH": str(generated / "python")},
        capture_output=True,
        text=True,
        check=False,
    )
    assert result.returncode == 0, result.stderr
    assert not list(tmp_path.iterdir()), "an injected statement created a file"
    assert '__import__("pathlib")' in result.stdout  # the text survives, as text
    mypy = mypy_strict("-p", "hostile_dev", cwd=generated / "python")
    assert mypy.returncode == 0, mypy.stdout


@pytest.mark.parametrize(("compiler", "flags"), [("gcc", ["-x", "c", "-std=c99"]), ("g++", ["-x", "c++", "-std=c++17"])])
def test_c_compiles_and_holds_no_injected_code(generated: Path, tmp_path: Path, compiler: str, flags: list[str]) -> None:
    cc = require_tool(compiler)
    source = tmp_path / "use.c"
    source.write_text('#include "hostile_dev.h"\nint main(void) { return (int)HOSTILE_DEV_IMPORT_ADDR - 1; }\n', encoding="utf-8")
    include = ["-I", str(generated / "c")]
    result = subprocess.run(
        [cc, *flags, "-Wall", "-Wextra", "-Wpedantic", "-Werror", *include, "-c", str(source), "-o", str(tmp_path / "use.o")],
        capture_output=True,
        text=True,
        check=False,
    )
    assert result.returncode == 0, result.stderr
    expanded = subprocess.run([cc, *flags, "-E", "-P", *include, str(source)], capture_output=True, text=True, check=True).stdout
    assert "pwned" not in expanded.lower(), "text from the map reached the compiler as code"
    header = (generated / "c" / "hostile_dev.h").read_text(encoding="utf-8")
    directives = [line for line in header.splitlines() if line.lstrip().startswith("#include")]
    assert directives == ['#include "regmap_rtu.h"'], directives
    assert (
        "PWNED_DEFINE"
        not in subprocess.run([cc, *flags, "-E", "-dM", *include, str(source)], capture_output=True, text=True, check=True).stdout
    )


def test_markdown_has_no_live_html(generated: Path) -> None:
    for page in (generated / "docs").rglob("*.md"):
        text = page.read_text(encoding="utf-8")
        assert "<script" not in text.lower(), page
        assert not re.search(r"(?<!\\)\]\(javascript:", text), f"{page}: a live link from map text"
    assert "{{ 7\\*7 }}" in (generated / "docs" / "hostile_dev.md").read_text(encoding="utf-8") or "{{ 7*7 }}" in (
        generated / "docs" / "hostile_dev.md"
    ).read_text(encoding="utf-8"), "Jinja delimiters from a map must appear as text, not be evaluated"


def test_validate_summary_is_one_line() -> None:
    result = subprocess.run(
        [sys.executable, "-m", "regmap", "validate", str(HOSTILE)], cwd=ROOT, capture_output=True, text=True, check=False
    )
    assert result.returncode == 0, result.stderr
    assert len(result.stdout.strip().splitlines()) == 1, result.stdout


HOSTILE_TEXT = "<script>alert(1)</script> | `x` [a](javascript:alert(1)) *y*"


def test_markdown_escapes_the_text_of_string_registers() -> None:
    """Issue #19: a string register's default is map text that reaches the page as a value (in the quick
    reference and the details), not through a title: it is escaped like every other text."""
    from regmap.frontend import load_map_text
    from regmap.generate import render

    fixture = ROOT / "tests" / "maps" / "fixtures" / "power_meter.yaml"
    original = 'words: 4, encoding: utf-8, default: "", title: User label (UTF-8)'
    hostile = f"words: 40, encoding: utf-8, default: {json.dumps(HOSTILE_TEXT)}, title: User label"
    text = fixture.read_text(encoding="utf-8").replace(original, hostile)
    assert HOSTILE_TEXT in text
    # The examples are left out: they carry no string default, and their frames are another test's.
    device = dataclasses.replace(load_map_text(text, "tests/maps/fixtures/power_meter.yaml"), examples=())
    page = render([device], ["markdown"])["markdown"][f"{device.id}.md"]
    assert "<script" not in page.lower()
    assert not re.search(r"(?<!\\)\]\(javascript:", page), "a string default must not make a link"
    row = next(line for line in page.splitlines() if "(#meter_label)" in line and line.startswith("| "))
    assert "&lt;script&gt;" in row and "\\|" in row
    assert len(re.findall(r"(?<!\\)\|", row)) == 15, "a pipe in the default must not add a table column"
