"""The layers of docs/architecture.md, read from the imports themselves (parsed with `ast`, so a
comment or a string naming a module does not count, and an import inside a function does).

Back ends and field tools are two wings that never import each other; what both need lives in the
core below them, which imports neither.
"""

from __future__ import annotations

import ast
import tomllib
from pathlib import Path

import pytest

from conftest import ROOT

PACKAGE = ROOT / "generator" / "regmap"


def imported_modules(path: Path) -> set[str]:
    """Every module a file imports, relative imports resolved against its own package."""
    package = path.relative_to(ROOT / "generator").parts[:-1]
    found: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"), str(path))):
        if isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = list(package[: len(package) - node.level + 1]) if node.level else []
            module = ".".join([*base, *([node.module] if node.module else [])])
            found.add(module)
            found.update(f"{module}.{alias.name}" for alias in node.names)  # `from regmap import tools`
    return found


def crossings(layer: str, forbidden: tuple[str, ...]) -> list[str]:
    """`file: module` for every import under `layer` of a module inside one of `forbidden`."""
    out = []
    for path in sorted((PACKAGE / layer).rglob("*.py")):
        for module in sorted(imported_modules(path)):
            if any(module == f or module.startswith(f + ".") for f in forbidden):
                out.append(f"{path.relative_to(ROOT)}: {module}")
    return out


@pytest.mark.parametrize(
    ("layer", "forbidden"),
    [
        ("backends", ("regmap.tools",)),
        ("tools", ("regmap.backends",)),
        ("core", ("regmap.backends", "regmap.tools", "regmap.cli", "regmap.generate", "regmap.homeauto")),
        ("homeauto", ("regmap.tools", "regmap.cli")),
    ],
)
def test_a_layer_imports_nothing_of_the_layers_beside_or_above_it(layer: str, forbidden: tuple[str, ...]) -> None:
    assert crossings(layer, forbidden) == []


def test_the_import_reader_sees_imports_at_the_top_and_in_functions() -> None:
    """The check above passes on a file that imports nothing only if the reader can see imports at all."""
    assert {"regmap.tools.decode", "regmap.tools.decode.decode_frame"} <= imported_modules(PACKAGE / "tools" / "simulator" / "log.py")
    assert "regmap.generate" in imported_modules(PACKAGE / "tools" / "diff" / "changelog.py")  # imported inside a function


def test_backends_holds_only_back_ends() -> None:
    """Every module directly under backends/ is a target registered in pyproject.toml's `regmap.targets`;
    shared helpers live in the core or in the package of the back ends that share them."""
    pyproject = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    registered = {value.split(":")[0] for value in pyproject["project"]["entry-points"]["regmap.targets"].values()}
    present = {
        f"regmap.backends.{path.stem if path.is_file() else path.name}"
        for path in (PACKAGE / "backends").iterdir()
        if path.name != "__init__.py" and (path.suffix == ".py" or (path / "__init__.py").exists())
    }
    assert present == registered


MAX_FILE_LINES = 600
MAX_FUNCTION_LINES = 100


def test_no_product_file_or_function_grows_past_what_a_reader_takes_in() -> None:
    """Files ≤ 600 lines, functions ≤ 100: past that a module or a function does more than one thing."""
    too_long = []
    for path in sorted((ROOT / "generator").rglob("*.py")):
        source = path.read_text(encoding="utf-8")
        where = path.relative_to(ROOT)
        if len(source.splitlines()) > MAX_FILE_LINES:
            too_long.append(f"{where}: {len(source.splitlines())} lines")
        for node in ast.walk(ast.parse(source)):
            if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef) and node.end_lineno is not None:
                length = node.end_lineno - node.lineno + 1
                if length > MAX_FUNCTION_LINES:
                    too_long.append(f"{where}:{node.lineno}: {node.name}() is {length} lines")
    assert too_long == []
