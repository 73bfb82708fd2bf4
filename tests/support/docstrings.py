"""The docstrings of a generated Python module, read from its source (attribute docstrings exist only there)."""

from __future__ import annotations

import ast
import itertools
from collections import Counter
from pathlib import Path
from types import ModuleType


def _tree(module: ModuleType) -> ast.Module:
    return ast.parse(Path(str(module.__file__)).read_text(encoding="utf-8"))


def constant_docs(module: ModuleType) -> dict[str, str]:
    """Each module-level constant's docstring: the string right after its assignment."""
    docs = {}
    for node, after in itertools.pairwise(_tree(module).body):
        if not (isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name) and isinstance(after, ast.Expr)):
            continue
        if isinstance(after.value, ast.Constant) and isinstance(after.value.value, str):
            docs[node.target.id] = after.value.value
    return docs


def written(module: ModuleType) -> Counter[str]:
    """How often each docstring text occurs in the module (module, class, function and attribute docstrings)."""
    strings = (n.value.value for n in ast.walk(_tree(module)) if isinstance(n, ast.Expr) and isinstance(n.value, ast.Constant))
    return Counter(s for s in strings if isinstance(s, str))
