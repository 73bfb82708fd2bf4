"""A directory tree as {relative path: bytes}, to compare generated output."""

from __future__ import annotations

from pathlib import Path

CACHES = {"__pycache__", ".mypy_cache", ".ruff_cache", ".pytest_cache"}  # made by tools run on the tree; git ignores them


def tree(root: Path) -> dict[str, bytes]:
    return {str(p.relative_to(root)): p.read_bytes() for p in sorted(root.rglob("*")) if p.is_file() and not CACHES & set(p.parts)}
