"""Whether a file is a plant file, told by its text alone: a map's run asks it of each map without importing the
plant front end and the plant model (tests/project/test_generate_imports.py)."""

from __future__ import annotations

import re
from pathlib import Path

_PLANT_LINE = re.compile(r"""^format:[ \t]*["']?regmap-plant/""", re.MULTILINE)


def is_plant_text(text: str) -> bool:
    """Whether a file's text declares the plant format (a top-level `format: regmap-plant/…` line)."""
    return _PLANT_LINE.search(text) is not None


def is_plant_file(path: str | Path) -> bool:
    try:
        with open(path, encoding="utf-8", errors="replace") as handle:
            head = handle.read(64 * 1024)
    except OSError:
        return False
    return is_plant_text(head)
