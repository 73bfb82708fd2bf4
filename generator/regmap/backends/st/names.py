"""Structured Text identifiers and literals: the validated name (`StIdentifier`), the scopes that refuse
two map items generating one name (compared case-insensitively, as ST compares names), and the ST
spelling of numbers and strings."""

from __future__ import annotations

import functools
import re
from collections.abc import Callable
from dataclasses import field
from fractions import Fraction

from regmap.diagnostics import Diagnostic, at
from regmap.keywords import IEC_KEYWORDS
from regmap.model import Device, SourcePos
from regmap.records import dataclass
from regmap.render import TEXT_CACHE_SIZE

# Both dialects: CODESYS / TwinCAT accept long names, but matiec (OpenPLC) and several IDE views
# truncate past 64 characters; IEC 61131-3 guarantees only the first 6 significant, which no real
# project relies on. 64 keeps every generated name whole in both.
MAX_LENGTH = 64
# IEC 61131-3 6.1.2: a letter or an underscore first, no two underscores in a row, none at the end.
_IDENTIFIER = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")
# A name `_problem` finds nothing wrong with, in one match (most names): its checks below say why each part is there.
_SOUND = re.compile(rf"(?!.*__)[A-Za-z_][A-Za-z0-9_]{{0,{MAX_LENGTH - 1}}}(?<!_)")
_SUFFIX = re.compile(r"[A-Z0-9]+(?:_[A-Z0-9]+)*")  # appended to a sound name after an underscore, it keeps it sound
# Names the generated functions declare for their own parameters and locals; an enum member printed
# bare (the plain-standard dialect) or a map name must not shadow them.
LOCALS = frozenset(
    name.upper()
    for name in (
        "nRaw",
        "rRaw",
        "eValue",
        "fValue",
        "nValue",
        "bValue",
        "nWord",
        "aWords",
        "dw",
        "stRaw",
        "stValues",
        "bHighWordFirst",
        "bOk",
    )
)
KEYWORD_SUFFIX = "KW"  # `return` -> RETURN_KW: ST has no trailing-underscore escape as C and Python do
_ESCAPED = IEC_KEYWORDS | LOCALS  # the names that get the suffix


class StIdentifier(str):
    """A Structured Text identifier joined from parts (upper case): valid in IEC 61131-3 and in
    CODESYS / TwinCAT, never a keyword, at most `MAX_LENGTH` characters. A part that is a keyword on
    its own gets `_KW` (`return` -> `RETURN_KW`); a problem is kept in `problem`, so that one run
    reports every name of a map."""

    problem: str = ""  # set on the instance only when there is one: most names then need no instance dict

    def __new__(cls, *parts: str) -> StIdentifier:
        name, problem = _spelled(parts)
        made = str.__new__(cls, name)
        if problem:
            made.problem = problem
        return made

    @staticmethod
    def stem(*parts: str) -> Stem:
        """The first parts of a family of names (`<DEV>_<REG>` of a register's constants), joined and checked once."""
        return Stem(parts)


class Stem:
    """The parts a family of names begins with. `stem(suffix)` is `StIdentifier(*parts, suffix)`: when the joined
    parts have no problem and the suffix is upper-case words joined by single underscores, the name can only be
    too long or a keyword, so it checks just those two and skips the whole spelling (a register has up to 16
    constants); any other name is spelled and checked in full."""

    def __init__(self, parts: tuple[str, ...]) -> None:
        self.parts = parts
        self.joined = "_".join(filter(None, parts)).upper()
        self.sound = bool(self.joined) and not _problem(self.joined)

    def __call__(self, suffix: str) -> StIdentifier:
        name = f"{self.joined}_{suffix}"
        if self.sound and _sound_suffix(suffix) and len(name) <= MAX_LENGTH and name not in _ESCAPED:
            return str.__new__(StIdentifier, name)
        return StIdentifier(*self.parts, suffix)

    def declared_in(self, scope: Scope, what: str, pos: SourcePos | None) -> Callable[[str], StIdentifier]:
        """`suffix -> scope.add(self(suffix), what, pos)` in one call for a sound name (a register declares up to 16)."""
        joined, sound, seen = self.joined, self.sound, scope.seen

        def declare(suffix: str) -> StIdentifier:
            name = f"{joined}_{suffix}"
            if sound and _sound_suffix(suffix) and len(name) <= MAX_LENGTH and name not in _ESCAPED:
                made = str.__new__(StIdentifier, name)
                if seen.setdefault(made, what) == what:
                    return made
            return scope.add(self(suffix), what, pos)  # a problem to report, or a name some other item took

        return declare


@functools.cache  # a few dozen suffixes (ADDR, RAW_MIN ...), each asked for by every register
def _sound_suffix(suffix: str) -> bool:
    return _SUFFIX.fullmatch(suffix) is not None


@functools.lru_cache(maxsize=TEXT_CACHE_SIZE)  # the same names are spelled in every dialect and for every constant of a register
def _spelled(parts: tuple[str, ...]) -> tuple[str, str]:
    """The identifier joined from `parts` and its problem ("" when none)."""
    name = "_".join(filter(None, parts)).upper()
    if name in _ESCAPED:
        name = f"{name}_{KEYWORD_SUFFIX}"
    return name, "" if _SOUND.fullmatch(name) else _problem(name)


def _problem(name: str) -> str:
    if not _IDENTIFIER.match(name):
        return f"{name!r} is not a Structured Text identifier"
    if "__" in name:
        return f"{name!r} has two underscores in a row, which IEC 61131-3 forbids in a name; rename it in the map"
    if name.endswith("_"):
        return f"{name!r} ends with an underscore, which IEC 61131-3 forbids in a name; rename it in the map"
    if len(name) > MAX_LENGTH:
        return f"{name!r} is longer than {MAX_LENGTH} characters (the limit kept for OpenPLC/matiec); shorten the name in the map"
    return ""


@dataclass
class Scope:
    """The names one ST scope declares (the global names of a device, the members of one struct or
    enum): two map items generating names that differ only by case collide, as ST sees them."""

    device: Device
    what: str
    problems: list[Diagnostic]
    seen: dict[str, str] = field(default_factory=dict)

    def add(self, name: StIdentifier, what: str, pos: SourcePos | None = None) -> StIdentifier:
        if name.problem:
            self._report(pos, f"generated Structured Text name of {what}: {name.problem}")
        first = self.seen.setdefault(name, what)  # an StIdentifier is upper-case: as ST compares names
        if first != what:
            self._report(
                pos,
                f"generated Structured Text name {name} ({self.what}) is used by both {first} and {what}"
                " (ST names ignore case); rename one in the map",
            )
        return name

    def _report(self, pos: SourcePos | None, message: str) -> None:
        self.problems.append(at(self.device.source_path, pos, message))


# -- literals ----------------------------------------------------------------------------------


# An integer's ST literal is its decimal text: `str` itself, no call of ours around it (thousands a device).
st_int: Callable[[int], str] = str


def st_hex(value: int, digits: int = 4) -> str:
    return f"16#{value:0{digits}X}"


def st_real(value: Fraction | int | float) -> str:
    """An LREAL literal of an exact integer, ratio part or float (always with a point, as ST requires)."""
    text = f"{float(value):.17g}"
    return text if "." in text or "e" in text else text + ".0"


def st_string(text: str) -> str:
    """An ST STRING literal: `$` and `'` escaped, everything outside printable ASCII as `$hh` bytes."""
    out = []
    for byte in text.encode("utf-8"):
        char = chr(byte)
        if char in "$'":
            out.append("$" + char)
        elif 0x20 <= byte < 0x7F:
            out.append(char)
        else:
            out.append(f"${byte:02X}")
    return "'" + "".join(out) + "'"
