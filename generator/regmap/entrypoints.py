"""Entry points of one group, read from the installed distributions' entry_points.txt files as importlib.metadata
reads them, without importing it: importlib.metadata brings email, zipfile and csv along, about 30 ms of a cold
`regmap generate` (issue #36). Only the usual layout is read here: directories on sys.path holding `*.dist-info` and
`*.egg-info` folders, found through the standard path finder. Anything else (a zip or an egg on the path, another
distribution finder, a line the format does not allow) is left to importlib.metadata itself: `read` returns None.
"""

from __future__ import annotations

import functools
import importlib
import importlib.machinery
import os
import re
import sys
from typing import Any

# importlib.metadata.EntryPoint.pattern: `module[:attr.attr][ [extras]]`
_VALUE = re.compile(r"(?P<module>[\w.]+)\s*(:\s*(?P<attr>[\w.]+)\s*)?((?P<extras>\[.*\])\s*)?$")
_INFO_SUFFIXES = (".dist-info", ".egg-info")


class EntryPoint:
    """One `name = value` line of a group's section; `load()` imports what it names, as importlib.metadata's does."""

    __slots__ = ("group", "name", "value")

    def __init__(self, name: str, value: str, group: str) -> None:
        self.name = name
        self.value = value
        self.group = group

    def load(self) -> Any:
        match = _VALUE.match(self.value)
        if match is None:  # malformed: importlib.metadata's own EntryPoint fails it with its own words
            from importlib.metadata import EntryPoint as Standard

            return Standard(self.name, self.value, self.group).load()
        module = importlib.import_module(match.group("module"))
        return functools.reduce(getattr, filter(None, (match.group("attr") or "").split(".")), module)


def read(group: str) -> list[EntryPoint] | None:
    """The group's entry points in the order importlib.metadata.entry_points(group=...) gives them (one distribution
    per normalized name: the first on sys.path), or None when the layout is one only importlib.metadata reads."""
    finders = [finder for finder in sys.meta_path if hasattr(finder, "find_distributions")]
    if finders != [importlib.machinery.PathFinder]:
        return None
    seen: set[str] = set()
    found: list[EntryPoint] = []
    for root in sys.path:
        if not isinstance(root, str) or os.path.basename(root).lower().endswith(".egg"):
            return None
        try:
            children = os.listdir(root or ".")
        except OSError:
            if os.path.isfile(root):
                return None  # a zip on the path
            continue
        for child in children:
            stem, suffix = os.path.splitext(child)
            if not child.lower().endswith(_INFO_SUFFIXES):
                continue
            if suffix not in _INFO_SUFFIXES:
                return None  # `X.DIST-INFO`: importlib.metadata names it from its METADATA file
            name = re.sub(r"[-_.]+", "-", stem.partition("-")[0]).lower().replace("-", "_")
            if name in seen:
                continue
            seen.add(name)
            points = _section(os.path.join(root, child, "entry_points.txt"), group)
            if points is None:
                return None
            found.extend(points)
    return found


def _section(path: str, group: str) -> list[EntryPoint] | None:
    """The group's lines of one entry_points.txt (none if there is no such file); None for a line without `=`."""
    try:
        with open(path, encoding="utf-8") as file:
            text = file.read()
    except (FileNotFoundError, IsADirectoryError, NotADirectoryError, PermissionError):
        return []
    points: list[EntryPoint] = []
    section = None
    for line in (line.strip() for line in text.splitlines()):
        if not line or line.startswith("#"):
            continue
        if line.startswith("[") and line.endswith("]"):
            section = line.strip("[]")
        elif section is not None:
            name, equals, value = line.partition("=")
            if not equals:
                return None
            if section == group:
                points.append(EntryPoint(name.strip(), value.strip(), group))
    return points
