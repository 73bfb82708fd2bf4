"""Problems found in a map, reported as `file:line:col: message` values rather than exceptions."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True, order=True)
class Diagnostic:
    file: str
    line: int
    column: int
    message: str

    def __str__(self) -> str:
        return f"{self.file}:{self.line}:{self.column}: {self.message}"


class MapError(Exception):
    """Raised once per map with every problem found in it."""

    def __init__(self, diagnostics: list[Diagnostic]) -> None:
        self.diagnostics = sorted(set(diagnostics))
        super().__init__("\n".join(str(d) for d in self.diagnostics))


class UsageError(Exception):
    """A bad command-line argument or runtime input (selector, value, frame); one line for the user."""


class LinkError(Exception):
    """The bus failed (no answer, connection lost, exception response); one line for the user."""
