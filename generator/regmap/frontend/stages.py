"""What one front-end stage hands the next, and the problem list each stage keeps.

yamlsource + schema -> `MapSource` -> elaborate -> `Elaborated` -> crossrefs -> `model.Device`.
A map the YAML or schema stage refuses goes no further (elaboration relies on its structure). After
that no stage stops at its first problem: elaboration hands its problems on with its result, and the
cross-reference stage raises them with its own as one `MapError`.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from regmap.diagnostics import Diagnostic, MapError
from regmap.frontend.yamlsource import Path, Positions
from regmap.model import EnumType, Group, Register
from regmap.records import dataclass


@dataclass(frozen=True)
class MapSource:
    """A map that passed the schema: its data, where each value is written, and the file it came from."""

    raw: dict[str, Any]
    positions: Positions
    name: str
    fingerprint: str


@dataclass(frozen=True)
class Elaborated:
    """The elaboration stage's model objects, not yet checked against each other, and its problems."""

    source: MapSource
    enums: Mapping[str, EnumType]
    groups: tuple[Group, ...]
    registers: tuple[Register, ...]
    register_paths: tuple[Path, ...]  # where each of `registers` is declared, in step with it
    problems: tuple[Diagnostic, ...]


class Problems:
    """The problems one stage finds, each located at `file:line:col` by its path in the map."""

    def __init__(self, source: MapSource, found: tuple[Diagnostic, ...] = ()) -> None:
        self._source = source
        self._found = list(found)

    def add(self, path: Path, message: str) -> None:
        line, col = self._source.positions.locate(path)
        self._found.append(Diagnostic(self._source.name, line, col, message))

    def count(self) -> int:
        return len(self._found)

    def forget_repeats(self) -> None:
        """An array member's problem is found once per element; it is one mistake."""
        self._found = list(dict.fromkeys(self._found))

    def raise_any(self) -> None:
        if self._found:
            raise MapError(self._found)

    def found(self) -> tuple[Diagnostic, ...]:
        return tuple(self._found)
