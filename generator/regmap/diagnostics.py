"""Problems found in a map, reported as `file:line:col: message` values rather than exceptions."""

from __future__ import annotations

import enum

from regmap.records import dataclass


class ExitCode(enum.IntEnum):
    """Exit statuses, one meaning each, the same in every subcommand (README "Exit status")."""

    OK = 0
    INVALID_MAP = 1  # a map is missing, unreadable or invalid (every problem printed as file:line:col)
    USAGE = 2  # a bad command line or a bad value; nothing was sent or written
    BAD_FRAME = 3  # `decode`: a CRC mismatch, a malformed frame, or a line that is no frame
    BUS = 4  # the bus failed: no answer, a bad answer, an exception response, a dead port
    VERIFY_MISMATCH = 5  # `write`: the drive reads back another value than was written
    DIFF_COMPATIBLE = 6  # `diff`: differences, all compatible
    DIFF_BREAKING = 7  # `diff`: breaking differences
    PROBE_DISAGREES = 8  # `probe`: the drive and its map disagree
    OUTCOME_UNKNOWN = 9  # `command`, `write`: a command or trigger write went out once, its answer was lost: it may have acted
    INTERNAL = 70  # a bug in regmap (EX_SOFTWARE): please report it with REGMAP_DEBUG=1
    OUTPUT = 74  # an output could not be written (EX_IOERR): disk full, read-only, permission
    INTERRUPTED = 130  # Ctrl-C


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


class OutputError(Exception):
    """An output could not be written (disk full, read-only, permission); one line naming it, nothing half-written."""


class LinkError(Exception):
    """The bus failed (no answer, connection lost, exception response); one line for the user."""


def at(file: str, pos: tuple[int, int] | None, message: str) -> Diagnostic:
    """A diagnostic at a model item's source position (line 1, column 1 when it has none)."""
    line, column = pos or (1, 1)
    return Diagnostic(file, line, column, message)
