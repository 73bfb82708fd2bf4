"""The tests mirror the code: each test file sits in the folder of what it tests (tests/frontend, tests/runtime,
tests/backends/<target>, tests/tools/<tool>, tests/cli, tests/homeauto; tests/project for the repository as a
whole), shared helpers are modules in tests/support, and no test file imports another."""

from __future__ import annotations

import ast
from collections import Counter
from pathlib import Path

from conftest import ROOT

TESTS = ROOT / "tests"
PACKAGE = ROOT / "generator" / "regmap"
TEST_FILES = sorted(TESTS.rglob("test_*.py"))


def _code_folders(parent: Path) -> set[str]:
    """The packages and modules directly under a product folder, by name."""
    return {
        p.stem for p in parent.iterdir() if (p.is_dir() and (p / "__init__.py").is_file()) or (p.suffix == ".py" and p.stem != "__init__")
    }


def _mirrors_the_code(folder: Path) -> bool:
    parts = folder.relative_to(TESTS).parts
    if parts in {("frontend",), ("runtime",), ("cli",), ("homeauto",), ("project",), ("backends",), ("tools",)}:
        return True
    if len(parts) == 2 and parts[0] in ("backends", "tools"):
        return parts[1] in _code_folders(PACKAGE / parts[0])
    return False


def test_every_test_file_sits_in_the_folder_of_what_it_tests() -> None:
    misplaced = [p.relative_to(ROOT).as_posix() for p in TEST_FILES if not _mirrors_the_code(p.parent)]
    assert misplaced == []


def test_basenames_are_unique_and_no_test_folder_is_a_package() -> None:
    """Without __init__.py pytest imports each test file by its basename, so two equal names would collide."""
    assert [name for name, count in Counter(p.name for p in TEST_FILES).items() if count > 1] == []
    assert sorted({p.parent.relative_to(ROOT).as_posix() for p in TEST_FILES if (p.parent / "__init__.py").exists()}) == []


def test_no_test_file_imports_another() -> None:
    """Helpers two test files share live in tests/support/, so moving or deleting a test breaks no other."""
    offenders = []
    for path in sorted(TESTS.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            names = (
                [a.name for a in node.names]
                if isinstance(node, ast.Import)
                else [node.module or ""]
                if isinstance(node, ast.ImportFrom)
                else []
            )
            offenders += [f"{path.relative_to(ROOT).as_posix()}: {name}" for name in names if name.split(".")[-1].startswith("test_")]
    assert offenders == []
