"""`regmap diff`: what changed between two versions of a map, what it breaks, and the version bump it needs.

The diff compares two `Device` models, never YAML text, so comments, key order, hex-versus-decimal
spelling and group defaults are not changes; only what the model (and so every back end) sees is.

Matching. Registers outside arrays are paired by name, then by the manual's parameter id, then by
address (unless both carry different parameter ids), so a renamed or moved register is one change,
not a removal plus an addition. Arrays are paired by name, then by (base, stride); their members by
name, then by offset; array elements by index. Bitfields are paired by name, then by bits; enums by
name, then by identical (value, name) members; enum values by name, then by value; commands by name,
then by (register, value); faults by name, then by code; examples, errata and groups by id.
References (a command's register, an example's values, a bitfield's enum ...) are compared through
these pairings, so renaming a register does not also "change" every example that names it.

Classification. A change is **breaking** when client code or firmware built from the old map would
now misbehave or stop building, and **compatible** otherwise. Every change carries the version bump it
needs: major when breaking, minor when it adds something a client can use (a register, an enum value,
write access, a wider range ...), patch for the rest (documentation, defaults, examples, errata).
`KINDS` lists every kind with its rule; the README's "regmap diff" section prints the same table.
Decisions beyond the issue's list, and why:

- renamed (register, array, member, bitfield, enum, enum value, command): breaking. The wire is
  unchanged, but generated names (`read_peak_current`, `IDM_RS_PEAK_CURRENT_ADDR`, enum members)
  derive from the map's names, so code written against them no longer builds.
- unit changed or removed: breaking (the same number now means another quantity, e.g. ms -> s);
  a unit given where there was none is documentation: patch.
- default changed: compatible (patch). A default describes the drive's factory state; generated
  code documents it and never sends it, and a client that relies on it reads it back anyway.
- enum of a register or bitfield changed (added, removed, replaced): breaking, because the
  generated value type changes (int <-> enum class), and writes now check membership.
- first bitfield of a register: breaking (its value type becomes a bitfield class); a further
  bitfield is compatible (the generated class gains a field with a default; old bits keep meaning).
- paired changed: breaking (block reads start at another address, spans change).
- parameter id changed at the same address: patch (the manual's label; wire and names unchanged).
- transport: the default baud, parity, data/stop bits, word order and CRC byte order are what an
  old client uses by default, so any change is breaking; lists and limits are breaking when they
  shrink (a baud rate, function code or slave id dropped; a smaller max read/write) and compatible
  when they grow; timing, response delay, the exception table and notes are patch.
- examples, errata, groups, faults' text: documentation, patch. A removed fault or a fault whose
  code or value changed is breaking (the C header defines them as macros).

Exit status: 0 no differences, 1 differences that are all compatible, 3 breaking differences.
"""

from __future__ import annotations

import enum
import json
import os
import re
import subprocess
import unicodedata
from collections.abc import Callable, Hashable, Iterable, Mapping, Sequence
from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path
from typing import Any, TypeVar

from regmap.diagnostics import MapError, UsageError
from regmap.frontend.load import load_map, load_map_bytes
from regmap.model import (
    Access,
    ArrayDef,
    ArrayMember,
    Command,
    Device,
    EnumType,
    Erratum,
    Example,
    Group,
    Register,
    Transport,
)
from regmap.render import header_lines, md_text

FORMATS = ("text", "markdown", "json")
JSON_FORMAT = "regmap-diff/1"
EXIT_SAME, EXIT_COMPATIBLE, EXIT_BREAKING = 0, 1, 3
EXIT_HELP = "exit status: 0 no differences, 1 differences that are all compatible, 3 breaking differences present, 2 bad input (a missing file, an unknown git revision, an invalid map)"


class Bump(enum.IntEnum):
    """The semantic-version bump a change needs; ordered, so the report needs the largest."""

    NONE = 0
    PATCH = 1
    MINOR = 2
    MAJOR = 3

    @property
    def label(self) -> str | None:
        return None if self is Bump.NONE else self.name.lower()


MAJOR, MINOR, PATCH = Bump.MAJOR, Bump.MINOR, Bump.PATCH


@dataclass(frozen=True)
class Kind:
    item: str  # what one row names (the first column of its Markdown table)
    heading: str
    rule: str  # when it is breaking; the README table is printed from these


KINDS: dict[str, Kind] = {
    # Order here is the order of the report within "breaking" and within "compatible".
    "device_id_changed": Kind("field", "Device id changed", "breaking: generated module, class and macro names derive from it"),
    "transport_changed": Kind("setting", "Transport settings changed", "see the transport table"),
    "register_removed": Kind("register", "Registers removed", "breaking"),
    "register_renamed": Kind("register", "Registers renamed", "breaking: generated names change (wire unchanged)"),
    "register_moved": Kind("register", "Registers moved", "breaking: another address on the wire"),
    "register_type_changed": Kind("register", "Register types changed", "breaking: width or signedness"),
    "register_word_order_changed": Kind("register", "Register word order changed", "breaking"),
    "register_paired_changed": Kind("register", "Register pairing changed", "breaking: block reads start elsewhere"),
    "register_access_changed": Kind(
        "register", "Register access changed", "breaking when read or write is lost (RW->R, RW->W, R<->W); minor when gained (R->RW, W->RW)"
    ),
    "register_unit_changed": Kind(
        "register", "Register units changed", "breaking when changed or removed; patch when given where there was none"
    ),
    "register_scale_changed": Kind("register", "Register scales changed", "breaking"),
    "register_range_changed": Kind(
        "register", "Register ranges changed", "breaking when narrowed; minor when only widened; patch when the effective range is the same"
    ),
    "register_enum_changed": Kind("register", "Register enums changed", "breaking: the generated value type changes"),
    "register_default_changed": Kind("register", "Register defaults changed", "patch: factory state, never sent by generated code"),
    "register_param_changed": Kind("register", "Parameter ids changed", "patch: the manual's label only"),
    "register_added": Kind("register", "Registers added", "minor"),
    "register_doc_changed": Kind("register", "Register documentation changed", "patch"),
    "array_removed": Kind("array", "Arrays removed", "breaking"),
    "array_renamed": Kind("array", "Arrays renamed", "breaking: generated names change"),
    "array_layout_changed": Kind("array", "Array layout changed", "breaking: base, stride, index base or member offset; elements move"),
    "array_count_changed": Kind("array", "Array sizes changed", "breaking when fewer elements; minor when more"),
    "array_member_removed": Kind("member", "Array members removed", "breaking"),
    "array_member_renamed": Kind("member", "Array members renamed", "breaking: generated names change"),
    "array_added": Kind("array", "Arrays added", "minor"),
    "array_member_added": Kind("member", "Array members added", "minor"),
    "array_doc_changed": Kind("array", "Array documentation changed", "patch"),
    "bitfield_removed": Kind("bitfield", "Bitfields removed", "breaking"),
    "bitfield_renamed": Kind("bitfield", "Bitfields renamed", "breaking: generated names change"),
    "bitfield_moved": Kind("bitfield", "Bitfields moved", "breaking: other bits"),
    "bitfield_resized": Kind("bitfield", "Bitfields resized", "breaking: other bits"),
    "bitfield_enum_changed": Kind("bitfield", "Bitfield enums changed", "breaking: the generated field type changes"),
    "bitfield_added": Kind("bitfield", "Bitfields added", "minor; breaking when the register had none (its value type changes)"),
    "bitfield_doc_changed": Kind("bitfield", "Bitfield documentation changed", "patch"),
    "enum_removed": Kind("enum", "Enums removed", "breaking"),
    "enum_renamed": Kind("enum", "Enums renamed", "breaking: generated names change"),
    "enum_value_removed": Kind("enum value", "Enum values removed", "breaking"),
    "enum_value_renumbered": Kind("enum value", "Enum values renumbered", "breaking"),
    "enum_value_renamed": Kind("enum value", "Enum values renamed", "breaking: generated names change"),
    "enum_added": Kind("enum", "Enums added", "minor"),
    "enum_value_added": Kind("enum value", "Enum values added", "minor"),
    "enum_doc_changed": Kind("enum", "Enum documentation changed", "patch"),
    "command_removed": Kind("command", "Commands removed", "breaking"),
    "command_renamed": Kind("command", "Commands renamed", "breaking: generated names change"),
    "command_changed": Kind("command", "Commands changed", "breaking: value, register or argument"),
    "command_added": Kind("command", "Commands added", "minor"),
    "command_effect_changed": Kind("command", "Command effects changed", "patch: what the simulator does"),
    "command_doc_changed": Kind("command", "Command documentation changed", "patch"),
    "fault_removed": Kind("fault", "Faults removed", "breaking: the C header defines them"),
    "fault_changed": Kind("fault", "Faults changed", "breaking when the name, code or value changes; patch for kind or resettable"),
    "fault_added": Kind("fault", "Faults added", "minor"),
    "fault_doc_changed": Kind("fault", "Fault documentation changed", "patch"),
    "example_added": Kind("example", "Examples added", "patch: documentation"),
    "example_removed": Kind("example", "Examples removed", "patch: documentation"),
    "example_changed": Kind("example", "Examples changed", "patch: documentation"),
    "erratum_added": Kind("erratum", "Errata added", "patch: documentation"),
    "erratum_removed": Kind("erratum", "Errata removed", "patch: documentation"),
    "erratum_changed": Kind("erratum", "Errata changed", "patch: documentation"),
    "group_added": Kind("group", "Groups added", "patch: documentation"),
    "group_removed": Kind("group", "Groups removed", "patch: documentation"),
    "group_changed": Kind("group", "Groups changed", "patch: documentation"),
    "device_changed": Kind("field", "Device description changed", "patch: vendor, model, manual, firmware notes"),
}
_KIND_ORDER = {k: i for i, k in enumerate(KINDS)}


@dataclass(frozen=True)
class Change:
    """One difference. `before`/`after` are short plain-text renderings; `old`/`new` the same as JSON values."""

    kind: str
    subject: str
    bump: Bump
    before: str = ""
    after: str = ""
    old: Any = None
    new: Any = None
    note: str = ""
    count: int = 1  # array elements this row stands for

    @property
    def breaking(self) -> bool:
        return self.bump is Bump.MAJOR

    def as_json(self) -> dict[str, Any]:
        return {
            "kind": self.kind,
            "item": KINDS[self.kind].item,
            "subject": self.subject,
            "breaking": self.breaking,
            "bump": self.bump.label,
            "before": self.before,
            "after": self.after,
            "old": self.old,
            "new": self.new,
            "note": self.note,
            "count": self.count,
        }


def _semver(text: str) -> tuple[int, int, int] | None:
    m = re.fullmatch(r"(\d+)\.(\d+)\.(\d+)", text)
    return (int(m[1]), int(m[2]), int(m[3])) if m else None


@dataclass(frozen=True)
class Report:
    old: Device
    new: Device
    changes: tuple[Change, ...]

    @property
    def breaking(self) -> tuple[Change, ...]:
        return tuple(c for c in self.changes if c.breaking)

    @property
    def compatible(self) -> tuple[Change, ...]:
        return tuple(c for c in self.changes if not c.breaking)

    @property
    def bump(self) -> Bump:
        return max((c.bump for c in self.changes), default=Bump.NONE)

    def _target(self) -> tuple[int, int, int] | None:
        v = _semver(self.old.info.map_version)
        if v is None:
            return None
        major, minor, patch = v
        return {
            Bump.NONE: v,
            Bump.PATCH: (major, minor, patch + 1),
            Bump.MINOR: (major, minor + 1, 0),
            Bump.MAJOR: (major + 1, 0, 0),
        }[self.bump]

    @property
    def suggested_version(self) -> str | None:
        """OLD's map_version bumped as the changes need (None when it is not X.Y.Z)."""
        target = self._target()
        return None if target is None else ".".join(map(str, target))

    @property
    def version_ok(self) -> bool:
        """NEW's map_version is at least the suggested one (a larger bump than needed is fine)."""
        target, new = self._target(), _semver(self.new.info.map_version)
        return target is not None and new is not None and new >= target

    @property
    def exit_status(self) -> int:
        if not self.changes:
            return EXIT_SAME
        return EXIT_BREAKING if self.breaking else EXIT_COMPATIBLE


# -- reading OLD and NEW ---------------------------------------------------------------------


def split_spec(spec: str) -> tuple[str, str | None]:
    """`PATH` or `PATH@GITREV`. An existing file is a path even if its name has an `@`; otherwise the
    split is at the first `@` after which the path names an existing file or ends in .yaml/.yml (so
    revisions like `HEAD@{1}` keep their own `@`), else at the first `@`."""
    if "@" not in spec or Path(spec).is_file():
        return spec, None
    at = [i for i, ch in enumerate(spec) if ch == "@"]
    for i in at:
        head = spec[:i]
        if Path(head).is_file() or head.endswith((".yaml", ".yml")):
            return head, spec[i + 1 :]
    return spec[: at[0]], spec[at[0] + 1 :]


def _git(where: Path, *args: str) -> subprocess.CompletedProcess[bytes]:
    env = {**os.environ, "LC_ALL": "C", "GIT_OPTIONAL_LOCKS": "0", "GIT_TERMINAL_PROMPT": "0"}
    try:
        return subprocess.run(["git", "-C", str(where), *args], capture_output=True, env=env, timeout=60, check=False)
    except FileNotFoundError:
        raise UsageError("git is not installed; it is needed to read a map at a git revision (PATH@GITREV)") from None
    except subprocess.TimeoutExpired:
        raise UsageError(f"git {' '.join(args)} did not answer within 60 s") from None


def read_at_revision(path: Path, rev: str) -> bytes | None:
    """The bytes of `path` as committed at `rev` (what `git show REV:PATH` prints), or None when the
    file did not exist there. Git runs in the file's directory with a `./`-relative path, which git
    resolves from the repository root, so PATH may be relative to anywhere and the repository may be
    any repository. An unknown revision or a directory outside git is a UsageError."""
    if not rev or rev.startswith("-") or any(ch in rev for ch in "\0\n\r"):
        raise UsageError(f"{rev!r} is not a git revision")
    where = path.parent
    if not where.is_dir():
        raise UsageError(f"{path}: the directory {where} does not exist")
    probe = _git(where, "rev-parse", "--verify", "--quiet", f"{rev}^{{commit}}")
    if probe.returncode != 0:
        if b"not a git repository" in probe.stderr:
            raise UsageError(f"{path} is not inside a git repository (needed for @{rev})")
        raise UsageError(f"unknown git revision {rev!r} in the repository of {path}")
    blob = f"{rev}:./{path.name}"
    if _git(where, "cat-file", "-e", blob).returncode != 0:
        return None
    shown = _git(where, "cat-file", "blob", blob)  # the stored bytes, no filters: the fingerprint matches a checkout
    if shown.returncode != 0:
        message = shown.stderr.decode("utf-8", "replace").strip().splitlines()
        raise UsageError(f"git could not read {path} at {rev}: {message[0] if message else 'unknown error'}")
    return shown.stdout


def _checked(name: str, load: Callable[[], Device]) -> Device:
    """Load a map; an invalid one is bad input for diff (exit 2, one line), since 1 means "compatible"."""
    try:
        return load()
    except MapError as exc:
        more = len(exc.diagnostics) - 1
        first = str(exc.diagnostics[0]) if exc.diagnostics else name
        extra = f" (and {more} more problem{'s' if more > 1 else ''}; see `regmap validate`)" if more else ""
        raise UsageError(f"not a valid map: {first}{extra}") from None


def _load_revision(path: str, rev: str, data: bytes) -> Device:
    return _checked(f"{path}@{rev}", lambda: load_map_bytes(data, f"{path}@{rev}"))


def load_spec(spec: str) -> Device:
    """The `Device` of a diff argument: a map file, or `PATH@GITREV` read from git history."""
    path, rev = split_spec(spec)
    if rev is None:
        if not Path(path).is_file():
            raise UsageError(f"{path}: no such map file")
        return _checked(path, lambda: load_map(path))
    data = read_at_revision(Path(path), rev)
    if data is None:
        raise UsageError(f"{path} does not exist at git revision {rev}")
    return _load_revision(path, rev, data)


# -- display helpers -------------------------------------------------------------------------


def _plain(text: str) -> str:
    """Map text on one line, without control characters (terminals) or runs of whitespace."""
    cleaned = "".join(" " if unicodedata.category(ch) in ("Cc", "Zl", "Zp") else ch for ch in text)
    return " ".join(cleaned.split())


def _clip(text: str, limit: int = 60) -> str:
    return text if len(text) <= limit else text[: limit - 1] + "…"


def _addr(address: int) -> str:
    return f"0x{address:04X}"


def _val(value: int) -> str:
    """An enum or command value as the maps write them: hex from 10 up."""
    return f"0x{value:02X}" if value >= 10 else str(value)


def _show(value: Any) -> str:
    if value is None:
        return "none"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, str):
        return f'"{_clip(_plain(value))}"'
    if isinstance(value, (tuple, list)):
        return "[" + ", ".join(_show(v) for v in value) + "]"
    if isinstance(value, Fraction):
        return _fraction(value)
    if isinstance(value, enum.Enum):
        return str(value.value)
    return _clip(_plain(str(value)))


def _pair(a: Any, b: Any, limit: int = 60) -> tuple[str, str]:
    """Two values for a before/after pair; long texts are shown around their first difference."""
    if not (isinstance(a, str) and isinstance(b, str)):
        return _show(a), _show(b)
    a, b = _plain(a), _plain(b)
    if len(a) <= limit and len(b) <= limit:
        return f'"{a}"', f'"{b}"'
    same = next((i for i, (x, y) in enumerate(zip(a, b, strict=False)) if x != y), min(len(a), len(b)))
    start = max(0, same - limit // 3)

    def window(text: str) -> str:
        part = text[start : start + limit]
        return ("…" if start else "") + part + ("…" if start + limit < len(text) else "")

    return f'"{window(a)}"', f'"{window(b)}"'


def _fields(diffs: Sequence[tuple[str, Any, Any]]) -> tuple[str, str]:
    """`field value; field value` before and after, for the fields that differ."""
    pairs = [(f, *_pair(a, b)) for f, a, b in diffs]
    return "; ".join(f"{f} {a}" for f, a, _ in pairs), "; ".join(f"{f} {b}" for f, _, b in pairs)


def _fraction(value: Fraction) -> str:
    if value.denominator == 1:
        return str(value.numerator)
    as_float = float(value)
    return repr(as_float) if Fraction(repr(as_float)) == value else f"{value.numerator}/{value.denominator}"


def _json(value: Any) -> Any:
    if isinstance(value, (tuple, list)):
        return [_json(v) for v in value]
    if isinstance(value, Fraction):
        return value.numerator if value.denominator == 1 else float(value)
    if isinstance(value, enum.Enum):
        return value.value
    if isinstance(value, bytes):
        return value.hex(" ").upper()
    if isinstance(value, Mapping):
        return {str(k): _json(v) for k, v in value.items()}
    return value


def _range(lo: int | None, hi: int | None) -> str:
    if lo is not None and hi is not None:
        return f"{lo}..{hi}"
    if lo is not None:
        return f">= {lo}"
    if hi is not None:
        return f"<= {hi}"
    return "not given"


ACCESS = {Access.READ: "R", Access.READ_WRITE: "RW", Access.WRITE: "W"}


def _register_summary(r: Register) -> str:
    parts = [_addr(r.address), r.type.value, ACCESS[r.access]]
    if r.param:
        parts.insert(0, r.param)
    if r.unit:
        parts.append(_plain(r.unit))
    return " ".join(parts) + f', "{_clip(_plain(r.title))}"'


def _array_summary(a: ArrayDef) -> str:
    members = ", ".join(m.name for m in a.members)
    return f"{a.count} x {a.stride} words at {_addr(a.base)} ({members})"


def _layout(name: str, value: int) -> str:
    return f"{name} {_addr(value) if name == 'base' else value}"


def _effect(effect: tuple[Any, ...] | None) -> str:
    if effect is None:
        return "none"
    kind, register, value, after_read = effect
    parts = [kind, *([register] if register else []), *([f"value {_val(value)}"] if value else [])]
    return " ".join(parts + ([f"then {_val(after_read)} after a read"] if after_read is not None else []))


def _indices(indices: Sequence[int]) -> str:
    """`[0, 1, 2, 5]` -> `0..2,5`."""
    runs: list[list[int]] = []
    for i in sorted(indices):
        if runs and i == runs[-1][-1] + 1:
            runs[-1].append(i)
        else:
            runs.append([i])
    return ",".join(str(r[0]) if len(r) == 1 else f"{r[0]}..{r[-1]}" for r in runs)


def _natural(text: str) -> list[Any]:
    return [int(t) if t.isdigit() else t for t in re.split(r"(\d+)", text)]


# -- matching --------------------------------------------------------------------------------

T = TypeVar("T")
Key = Callable[[T], Hashable | None]


def _match(
    old: Iterable[T], new: Iterable[T], keys: Sequence[Key[T]], accept: Callable[[T, T], bool] | None = None
) -> tuple[list[tuple[T, T, int]], list[T], list[T]]:
    """Pair items by each key in turn (a key pairs only values unique on both sides, and never None).
    Returns (old, new, index of the key that paired them), the unpaired old and the unpaired new."""
    rest_old, rest_new = list(old), list(new)
    pairs: list[tuple[T, T, int]] = []
    for k, key in enumerate(keys):
        by_old: dict[Hashable, list[T]] = {}
        by_new: dict[Hashable, list[T]] = {}
        for item in rest_old:
            if (value := key(item)) is not None:
                by_old.setdefault(value, []).append(item)
        for item in rest_new:
            if (value := key(item)) is not None:
                by_new.setdefault(value, []).append(item)
        paired_old: set[int] = set()
        paired_new: set[int] = set()
        for value, olds in by_old.items():
            news = by_new.get(value, [])
            if len(olds) == 1 and len(news) == 1 and (k == 0 or accept is None or accept(olds[0], news[0])):
                pairs.append((olds[0], news[0], k))
                paired_old.add(id(olds[0]))
                paired_new.add(id(news[0]))
        rest_old = [i for i in rest_old if id(i) not in paired_old]
        rest_new = [i for i in rest_new if id(i) not in paired_new]
    return pairs, rest_old, rest_new


# -- the comparison --------------------------------------------------------------------------

ELEMENT = "\0"  # stands for an array index in subjects until identical element changes are merged


class _Diff:
    def __init__(self, old: Device, new: Device) -> None:
        self.old, self.new = old, new
        self.changes: list[Change] = []
        self.enum_names: dict[str, str] = {}  # old enum name -> new
        self.register_names: dict[str, str] = {}  # old register name -> new (elements included)

    def add(
        self, kind: str, subject: str, bump: Bump, before: str = "", after: str = "", old: Any = None, new: Any = None, note: str = ""
    ) -> None:
        self.changes.append(_change(kind, subject, bump, before, after, old, new, note))

    def doc(self, kind: str, subject: str, o: object, n: object, fields: Sequence[str]) -> None:
        self.changes.extend(_doc(kind, subject, o, n, fields))

    def run(self) -> tuple[Change, ...]:
        # Enums and registers first: later steps compare references through their pairings.
        self._enums()
        self._registers()
        self._arrays()
        self._device()
        self._transport(self.old.transport, self.new.transport)
        self._commands()
        self._faults()
        self._examples()
        self._errata()
        self._groups()
        return tuple(sorted(self.changes, key=lambda c: (not c.breaking, _KIND_ORDER[c.kind], _natural(c.subject), c.before)))

    def _enum_name(self, e: EnumType | None) -> str | None:
        return None if e is None else self.enum_names.get(e.name, f"(removed) {e.name}")

    def _register_name(self, name: str) -> str:
        return self.register_names.get(name, name)

    # -- device and transport

    def _device(self) -> None:
        o, n = self.old.info, self.new.info
        if o.id != n.id:
            self.add("device_id_changed", "id", MAJOR, o.id, n.id, o.id, n.id)
        for f in (
            "vendor",
            "vendor_zh",
            "model",
            "description",
            "manual_title",
            "manual_version",
            "manual_file",
            "manual_language",
            "firmware",
        ):
            a, b = getattr(o, f), getattr(n, f)
            if a != b:
                self.add("device_changed", f, PATCH, _show(a), _show(b), a, b)

    def _transport(self, o: Transport, n: Transport) -> None:
        def setting(name: str, bump: Bump, a: Any, b: Any, show: Callable[[Any], str] = _show, note: str = "") -> None:
            self.add("transport_changed", name, bump, show(a), show(b), a, b, note)

        def grew_or_shrank(name: str, a: Sequence[int], b: Sequence[int], show: Callable[[Any], str] = _show) -> None:
            if tuple(a) == tuple(b):
                return
            lost, gained = sorted(set(a) - set(b)), sorted(set(b) - set(a))
            note = "; ".join(p for p in (f"removed {show(lost)}" if lost else "", f"added {show(gained)}" if gained else "") if p)
            setting(name, MAJOR if lost else MINOR if gained else PATCH, list(a), list(b), show, note)

        def limit(name: str, a: int | None, b: int | None) -> None:
            if a != b:
                smaller = a is not None and b is not None and b < a
                setting(name, MAJOR if smaller else PATCH, a, b, note="smaller: old requests may be refused" if smaller else "")

        for name in ("baud", "parity", "data_bits", "stop_bits", "word_order", "crc_byte_order"):
            a, b = getattr(o, name), getattr(n, name)
            if a != b:
                note = (
                    "applies to every 32-bit register without its own word order"
                    if name == "word_order"
                    else "an old client uses the old setting by default"
                )
                setting(name, MAJOR, a, b, note=note)
        grew_or_shrank("baud_rates", o.baud_rates, n.baud_rates)
        if (o.slave_min, o.slave_max) != (n.slave_min, n.slave_max):
            narrowed = n.slave_min > o.slave_min or n.slave_max < o.slave_max
            self.add(
                "transport_changed",
                "slave_ids",
                MAJOR if narrowed else MINOR,
                _range(o.slave_min, o.slave_max),
                _range(n.slave_min, n.slave_max),
                {"min": o.slave_min, "max": o.slave_max},
                {"min": n.slave_min, "max": n.slave_max},
                "narrowed" if narrowed else "widened",
            )
        if o.broadcast_id != n.broadcast_id:
            setting("broadcast_id", MINOR if o.broadcast_id is None else MAJOR, o.broadcast_id, n.broadcast_id)
        grew_or_shrank(
            "function_codes",
            o.function_codes,
            n.function_codes,
            lambda v: _show([f"0x{c:02X}" for c in v]) if isinstance(v, list) else _show(v),
        )
        limit("max_read_registers", o.max_read_registers, n.max_read_registers)
        limit("max_write_registers", o.max_write_registers, n.max_write_registers)
        limit("max_message_bytes", o.max_message_bytes, n.max_message_bytes)

        def wor(t: Transport) -> dict[str, Any] | None:
            w = t.word_order_register
            if w is None:
                return None
            name = self._register_name(w.register.name) if t is o else w.register.name
            return {"register": name, "high_first": w.high_first, "low_first": w.low_first}

        a_wor, b_wor = wor(o), wor(n)
        if a_wor != b_wor:
            show = lambda v: "none" if v is None else f"{v['register']} (high first {v['high_first']}, low first {v['low_first']})"  # noqa: E731
            setting("word_order_register", MINOR if a_wor is None else MAJOR, a_wor, b_wor, show)
        if o.undocumented_addresses != n.undocumented_addresses:
            stricter = n.undocumented_addresses == "reject"
            note = "old read plans that bridge gaps are refused now" if stricter else ""
            setting("undocumented_addresses", MAJOR if stricter else PATCH, o.undocumented_addresses, n.undocumented_addresses, note=note)
        if o.response_delay_ms != n.response_delay_ms:
            setting("response_delay_ms", PATCH, o.response_delay_ms, n.response_delay_ms)
        for name, a, b in (
            ("timing", [vars(t) for t in o.timing], [vars(t) for t in n.timing]),
            (
                "exceptions",
                [(e.code, e.name, e.title, e.title_zh, e.source) for e in o.exceptions],
                [(e.code, e.name, e.title, e.title_zh, e.source) for e in n.exceptions],
            ),
        ):
            if a != b:
                codes = name == "exceptions"
                show = (lambda v: _show([f"0x{e[0]:02X} {e[1]}" for e in v])) if codes else (lambda v: f"{len(v)} rows")
                setting(name, PATCH, a, b, show)
        for name in ("source", "notes"):
            a, b = getattr(o, name), getattr(n, name)
            if a != b:
                self.add("transport_changed", name, PATCH, *_pair(a, b), a, b)

    # -- enums

    def _enums(self) -> None:
        def members(e: EnumType) -> frozenset[tuple[int, str]]:
            return frozenset((m.value, m.name) for m in e.members)

        pairs, removed, added = _match(self.old.enums, self.new.enums, [lambda e: e.name, members])
        users_old, users_new = _enum_users(self.old), _enum_users(self.new)
        for e in removed:
            self.add("enum_removed", e.name, MAJOR, f"{len(e.members)} values", "", e.name, None, users_old.get(e.name, ""))
        for e in added:
            self.add("enum_added", e.name, MINOR, "", f"{len(e.members)} values", None, e.name, users_new.get(e.name, ""))
        for o, n, _ in pairs:
            self.enum_names[o.name] = n.name
            if o.name != n.name:
                self.add("enum_renamed", o.name, MAJOR, o.name, n.name, o.name, n.name, users_new.get(n.name, ""))
            self.doc("enum_doc_changed", n.name, o, n, ("title", "title_zh", "description", "source"))
            self._enum_members(o, n, users_old.get(o.name, ""), users_new.get(n.name, ""))

    def _enum_members(self, o: EnumType, n: EnumType, used_old: str, used_new: str) -> None:
        pairs, removed, added = _match(o.members, n.members, [lambda m: m.name, lambda m: m.value])
        for m in removed:
            self.add("enum_value_removed", f"{n.name}.{m.name}", MAJOR, _val(m.value), "", m.value, None, used_old)
        for m in added:
            self.add("enum_value_added", f"{n.name}.{m.name}", MINOR, "", _val(m.value), None, m.value, used_new)
        for a, b, _ in pairs:
            if a.value != b.value:
                self.add("enum_value_renumbered", f"{n.name}.{b.name}", MAJOR, _val(a.value), _val(b.value), a.value, b.value, used_new)
            if a.name != b.name:
                self.add("enum_value_renamed", f"{n.name}.{a.name}", MAJOR, a.name, b.name, a.name, b.name, used_new)
            self.doc("enum_doc_changed", f"{n.name}.{b.name}", a, b, _MEMBER_DOC)

    # -- registers outside arrays

    def _registers(self) -> None:
        old = [r for r in self.old.registers if r.array is None]
        new = [r for r in self.new.registers if r.array is None]
        pairs, removed, added = _match(
            old,
            new,
            [lambda r: r.name, lambda r: r.param, lambda r: r.address],
            accept=lambda a, b: not (a.param and b.param and a.param != b.param),
        )
        for r in removed:
            self.add("register_removed", r.name, MAJOR, _register_summary(r), "", r.name, None)
        for r in added:
            self.add("register_added", r.name, MINOR, "", _register_summary(r), None, r.name)
        for o, n, how in pairs:
            self.register_names[o.name] = n.name
            if o.name != n.name:
                note = ("matched by parameter id" if how == 1 else "matched by address") if how else ""
                self.add("register_renamed", o.name, MAJOR, o.name, n.name, o.name, n.name, note)
            if o.address != n.address:
                params = o.param != n.param
                before = _addr(o.address) + (f" ({o.param})" if params and o.param else "")
                after = _addr(n.address) + (f" ({n.param})" if params and n.param else "")
                self.add("register_moved", n.name, MAJOR, before, after, o.address, n.address)
            elif o.param != n.param:
                self.add("register_param_changed", n.name, PATCH, _show(o.param), _show(n.param), o.param, n.param)
            self.changes.extend(self._register_attributes(o, n, n.name))

    def _register_attributes(self, o: Register, n: Register, subject: str) -> list[Change]:
        """Changes of one register's type, access, unit ..., bitfields and text; name and address are the caller's."""
        out = _Changes()
        add = out.add
        if o.type != n.type:
            note = f"{o.words} -> {n.words} words" if o.words != n.words else ("signedness" if o.signed != n.signed else "")
            add("register_type_changed", subject, MAJOR, o.type.value, n.type.value, o.type, n.type, note)
        # A register that follows the device's word order is reported once, as the transport change.
        device_orders = self.old.transport.word_order, self.new.transport.word_order
        follows = device_orders[0] != device_orders[1] and (o.word_order, n.word_order) == device_orders
        if o.words == 2 and n.words == 2 and o.word_order != n.word_order and not follows:
            add("register_word_order_changed", subject, MAJOR, o.word_order.value, n.word_order.value, o.word_order, n.word_order)
        if o.paired != n.paired:
            add(
                "register_paired_changed",
                subject,
                MAJOR,
                "paired" if o.paired else "single",
                "paired" if n.paired else "single",
                o.paired,
                n.paired,
            )
        if o.access != n.access:
            lost = (o.access.readable and not n.access.readable) or (o.access.writable and not n.access.writable)
            add("register_access_changed", subject, MAJOR if lost else MINOR, ACCESS[o.access], ACCESS[n.access], o.access, n.access)
        if o.unit != n.unit:
            add("register_unit_changed", subject, PATCH if o.unit is None else MAJOR, _show(o.unit), _show(n.unit), o.unit, n.unit)
        if o.scale != n.scale:
            add("register_scale_changed", subject, MAJOR, _fraction(o.scale), _fraction(n.scale), o.scale, n.scale)
        if (o.min, o.max) != (n.min, n.max):
            narrowed = n.raw_min > o.raw_min or n.raw_max < o.raw_max
            widened = n.raw_min < o.raw_min or n.raw_max > o.raw_max
            bump, note = (MAJOR, "narrowed") if narrowed else (MINOR, "widened") if widened else (PATCH, "same effective range")
            add("register_range_changed", subject, bump, _range(o.min, o.max), _range(n.min, n.max), [o.min, o.max], [n.min, n.max], note)
        if o.default != n.default:
            add("register_default_changed", subject, PATCH, _show(o.default), _show(n.default), o.default, n.default)
        a_enum, b_enum = self._enum_name(o.enum), n.enum.name if n.enum else None
        if a_enum != b_enum:
            add(
                "register_enum_changed",
                subject,
                MAJOR,
                _show(o.enum.name if o.enum else None),
                _show(b_enum),
                o.enum.name if o.enum else None,
                b_enum,
            )
        out += self._bitfields(o, n, subject)
        out += _doc("register_doc_changed", subject, o, n, _REGISTER_DOC)
        return out

    def _bitfields(self, o: Register, n: Register, subject: str) -> list[Change]:
        out = _Changes()
        add = out.add
        pairs, removed, added = _match(o.bitfields, n.bitfields, [lambda b: b.name, lambda b: (b.lsb, b.msb)])
        for b in removed:
            add("bitfield_removed", f"{subject}.{b.name}", MAJOR, f"bits {b.bits_text}", "", b.bits_text, None)
        for b in added:
            first = not o.bitfields
            note = "the register had no bitfields: its value type changes" if first else ""
            add("bitfield_added", f"{subject}.{b.name}", MAJOR if first else MINOR, "", f"bits {b.bits_text}", None, b.bits_text, note)
        for a, b, _ in pairs:
            if a.name != b.name:
                add("bitfield_renamed", f"{subject}.{a.name}", MAJOR, a.name, b.name, a.name, b.name)
            if a.width != b.width:
                add(
                    "bitfield_resized", f"{subject}.{b.name}", MAJOR, f"bits {a.bits_text}", f"bits {b.bits_text}", a.bits_text, b.bits_text
                )
            elif a.lsb != b.lsb:
                add("bitfield_moved", f"{subject}.{b.name}", MAJOR, f"bits {a.bits_text}", f"bits {b.bits_text}", a.bits_text, b.bits_text)
            if self._enum_name(a.enum) != (b.enum.name if b.enum else None):
                a_name, b_name = (a.enum.name if a.enum else None), (b.enum.name if b.enum else None)
                add("bitfield_enum_changed", f"{subject}.{b.name}", MAJOR, _show(a_name), _show(b_name), a_name, b_name)
            out += _doc("bitfield_doc_changed", f"{subject}.{b.name}", a, b, ("title", "title_zh", "description"))
        return out

    # -- arrays

    def _arrays(self) -> None:
        pairs, removed, added = _match(self.old.arrays, self.new.arrays, [lambda a: a.name, lambda a: (a.base, a.stride)])
        for a in removed:
            self.add("array_removed", a.name, MAJOR, _array_summary(a), "", a.name, None)
        for a in added:
            self.add("array_added", a.name, MINOR, "", _array_summary(a), None, a.name)
        old_elements = _elements(self.old)
        new_elements = _elements(self.new)
        for o, n, _ in pairs:
            if o.name != n.name:
                self.add("array_renamed", o.name, MAJOR, o.name, n.name, o.name, n.name)
            layout = [(f, getattr(o, f), getattr(n, f)) for f in ("base", "stride", "index_base") if getattr(o, f) != getattr(n, f)]
            if layout:
                self.add(
                    "array_layout_changed",
                    n.name,
                    MAJOR,
                    ", ".join(_layout(f, a) for f, a, _ in layout),
                    ", ".join(_layout(f, b) for f, _, b in layout),
                    {f: a for f, a, _ in layout},
                    {f: b for f, _, b in layout},
                    "every element moves",
                )
            if o.count != n.count:
                fewer = n.count < o.count
                self.add(
                    "array_count_changed",
                    n.name,
                    MAJOR if fewer else MINOR,
                    str(o.count),
                    str(n.count),
                    o.count,
                    n.count,
                    "fewer elements" if fewer else "more elements",
                )
            self.doc("array_doc_changed", n.name, o, n, ("title", "title_zh", "element_title", "description", "group", "source", "notes"))
            member_pairs, gone, new_members = _match(o.members, n.members, [lambda m: m.name, lambda m: m.offset])
            for m in gone:
                self.add("array_member_removed", f"{n.name}.{m.name}", MAJOR, f"offset {m.offset}", "", m.name, None)
            for m in new_members:
                first = new_elements[(n.name, n.first_index, m.name)]
                self.add(
                    "array_member_added", f"{n.name}.{m.name}", MINOR, "", f"offset {m.offset}, {_register_summary(first)}", None, m.name
                )
            common = range(max(o.first_index, n.first_index), min(o.last_index, n.last_index) + 1)
            for om, nm, _ in member_pairs:
                self._array_member(o, n, om, nm, common, old_elements, new_elements)

    def _array_member(
        self,
        o: ArrayDef,
        n: ArrayDef,
        om: ArrayMember,
        nm: ArrayMember,
        common: range,
        old_elements: dict[tuple[str, int, str], Register],
        new_elements: dict[tuple[str, int, str], Register],
    ) -> None:
        if om.name != nm.name:
            self.add("array_member_renamed", f"{n.name}.{om.name}", MAJOR, om.name, nm.name, om.name, nm.name)
        if om.offset != nm.offset:
            self.add(
                "array_layout_changed",
                f"{n.name}.{nm.name}",
                MAJOR,
                f"offset {om.offset}",
                f"offset {nm.offset}",
                om.offset,
                nm.offset,
                "every element moves",
            )
        # Element registers change together; one row per distinct change, naming the elements it covers.
        merged: dict[tuple[Any, ...], tuple[Change, list[int]]] = {}
        template = f"{n.name}[{ELEMENT}].{nm.name}"
        for i in common:
            a, b = old_elements[(o.name, i, om.name)], new_elements[(n.name, i, nm.name)]
            self.register_names[a.name] = b.name
            for c in self._register_attributes(a, b, template):
                key = (c.kind, c.subject, c.bump, c.before, c.after, c.note, json.dumps(c.old), json.dumps(c.new))
                merged.setdefault(key, (c, []))[1].append(i)
        for c, indices in merged.values():
            subject = c.subject.replace(ELEMENT, _indices(indices))
            self.changes.append(Change(c.kind, subject, c.bump, c.before, c.after, c.old, c.new, c.note, len(indices)))

    # -- commands, faults, examples, errata, groups

    def _commands(self) -> None:
        def target(c: Command, old: bool) -> tuple[str, int]:
            return (self._register_name(c.register.name) if old else c.register.name, c.value)

        pairs, removed, added = _match(
            [(c, True) for c in self.old.commands],
            [(c, False) for c in self.new.commands],
            [lambda p: p[0].name, lambda p: target(*p)],
        )

        def what(c: Command) -> str:
            arg = f" + {c.argument.name} {c.argument.min}..{c.argument.max}" if c.argument else ""
            return f"{c.register.name} = {_val(c.value)}{arg}"

        for c, _ in removed:
            self.add("command_removed", c.name, MAJOR, what(c), "", c.name, None)
        for c, _ in added:
            self.add("command_added", c.name, MINOR, "", what(c), None, c.name)
        for (o, _), (n, _), _ in pairs:
            if o.name != n.name:
                self.add("command_renamed", o.name, MAJOR, o.name, n.name, o.name, n.name)
            a_arg = None if o.argument is None else (o.argument.name, o.argument.min, o.argument.max)
            b_arg = None if n.argument is None else (n.argument.name, n.argument.min, n.argument.max)
            if target(o, True) != target(n, False) or a_arg != b_arg:
                self.add(
                    "command_changed",
                    n.name,
                    MAJOR,
                    what(o),
                    what(n),
                    {"register": o.register.name, "value": o.value, "argument": a_arg},
                    {"register": n.register.name, "value": n.value, "argument": b_arg},
                )
            a_eff = (
                None
                if o.effect is None
                else (
                    o.effect.kind,
                    self._register_name(o.effect.register.name) if o.effect.register else None,
                    o.effect.value,
                    o.effect.after_read,
                )
            )
            b_eff = (
                None
                if n.effect is None
                else (n.effect.kind, n.effect.register.name if n.effect.register else None, n.effect.value, n.effect.after_read)
            )
            if a_eff != b_eff:
                self.add("command_effect_changed", n.name, PATCH, _effect(a_eff), _effect(b_eff), a_eff, b_eff)
            self.doc("command_doc_changed", n.name, o, n, ("title", "title_zh", "description", "source"))

    def _faults(self) -> None:
        pairs, removed, added = _match(self.old.faults, self.new.faults, [lambda f: f.name, lambda f: f.code])
        for f in removed:
            self.add("fault_removed", f.name, MAJOR, f"{_plain(f.code)} ({f.kind})", "", f.name, None)
        for f in added:
            self.add("fault_added", f.name, MINOR, "", f"{_plain(f.code)} ({f.kind})", None, f.name)
        for o, n, _ in pairs:
            fields = [
                (k, getattr(o, k), getattr(n, k)) for k in ("name", "code", "value", "kind", "resettable") if getattr(o, k) != getattr(n, k)
            ]
            if fields:
                bump = MAJOR if any(k in ("name", "code", "value") for k, _, _ in fields) else PATCH
                self.add(
                    "fault_changed",
                    o.name,
                    bump,
                    *_fields(fields),
                    {k: a for k, a, _ in fields},
                    {k: b for k, _, b in fields},
                )
            self.doc("fault_doc_changed", n.name, o, n, ("title", "title_zh", "description", "source"))

    def _examples(self) -> None:
        def facts(e: Example, old: bool) -> dict[str, Any]:
            rename = self._register_name if old else (lambda name: name)
            return {
                "direction": e.direction,
                "frame": e.frame.hex(" ").upper(),
                "corrected_frame": None if e.corrected_frame is None else e.corrected_frame.hex(" ").upper(),
                "request": e.request,
                "erratum": e.erratum,
                "values": [(rename(v.register.name), v.raw, v.words, v.value) for v in e.values],
                "meaning": e.meaning,
                "meaning_zh": e.meaning_zh,
                "notes": e.notes,
                "source": e.source,
            }

        self._by_id(
            "example", self.old.examples, self.new.examples, lambda e: e.id, facts, lambda e: f"{e.direction} {e.frame.hex(' ').upper()}"
        )

    def _errata(self) -> None:
        def facts(e: Erratum, old: bool) -> dict[str, Any]:
            rename = self._register_name if old else (lambda name: name)
            return {
                "title": e.title,
                "readings": [(r.source, r.says) for r in e.readings],
                "choice": e.choice,
                "reason": e.reason,
                "registers": [rename(r) for r in e.registers],
            }

        self._by_id("erratum", self.old.errata, self.new.errata, lambda e: e.id, facts, lambda e: f'"{_clip(_plain(e.title))}"')

    def _groups(self) -> None:
        def facts(g: Group, old: bool) -> dict[str, Any]:
            return {"title": g.title, "title_zh": g.title_zh, "description": g.description, "source": g.source}

        self._by_id("group", self.old.groups, self.new.groups, lambda g: g.id, facts, lambda g: f'"{_clip(_plain(g.title))}"')

    def _by_id(
        self,
        what: str,
        old: Sequence[T],
        new: Sequence[T],
        ident: Callable[[T], str],
        facts: Callable[[T, bool], dict[str, Any]],
        summary: Callable[[T], str],
    ) -> None:
        """Items that are documentation: added, removed or changed (every differing field listed), all patch."""
        pairs, removed, added = _match(old, new, [ident])
        for item in removed:
            self.add(f"{what}_removed", ident(item), PATCH, summary(item), "", ident(item), None)
        for item in added:
            self.add(f"{what}_added", ident(item), PATCH, "", summary(item), None, ident(item))
        for o, n, _ in pairs:
            a, b = facts(o, True), facts(n, False)
            fields = [k for k in a if a[k] != b[k]]
            if fields:
                self.add(
                    f"{what}_changed",
                    ident(n),
                    PATCH,
                    *_fields([(k, a[k], b[k]) for k in fields]),
                    {k: a[k] for k in fields},
                    {k: b[k] for k in fields},
                )


class _Changes(list[Change]):
    def add(
        self, kind: str, subject: str, bump: Bump, before: str = "", after: str = "", old: Any = None, new: Any = None, note: str = ""
    ) -> None:
        self.append(_change(kind, subject, bump, before, after, old, new, note))


def _change(
    kind: str, subject: str, bump: Bump, before: str = "", after: str = "", old: Any = None, new: Any = None, note: str = ""
) -> Change:
    return Change(kind, subject, bump, before, after, _json(old), _json(new), note)


def _doc(kind: str, subject: str, o: object, n: object, fields: Sequence[str]) -> list[Change]:
    """At most one patch-level change listing every documentation field that differs."""
    diffs = [(f, getattr(o, f), getattr(n, f)) for f in fields if getattr(o, f) != getattr(n, f)]
    if not diffs:
        return []
    before, after = _fields(diffs)
    return [_change(kind, subject, PATCH, before, after, {f: a for f, a, _ in diffs}, {f: b for f, _, b in diffs})]


_REGISTER_DOC = ("title", "title_zh", "description", "range_text", "takes_effect", "settable", "modes", "group", "source", "notes")
_MEMBER_DOC = ("title", "title_zh", "symbol", "description", "source")


def _elements(device: Device) -> dict[tuple[str, int, str], Register]:
    return {(r.array.array, r.array.index, r.array.member): r for r in device.registers if r.array is not None}


def _enum_users(device: Device, limit: int = 3) -> dict[str, str]:
    """enum name -> "used by a, b, c and 4 more" (array elements named once per member)."""
    users: dict[str, list[str]] = {}

    def use(e: EnumType | None, who: str) -> None:
        if e is not None and who not in users.setdefault(e.name, []):
            users[e.name].append(who)

    for r in device.registers:
        label = f"{r.array.array}[].{r.array.member}" if r.array else r.name
        use(r.enum, label)
        for b in r.bitfields:
            use(b.enum, f"{label}.{b.name}")
    out = {}
    for name, who in users.items():
        more = f" and {len(who) - limit} more" if len(who) > limit else ""
        out[name] = "used by " + ", ".join(who[:limit]) + more
    return out


def compare(old: Device, new: Device) -> Report:
    """Every difference between two maps, classified, breaking first."""
    return Report(old, new, _Diff(old, new).run())


# -- rendering -------------------------------------------------------------------------------


def _summary(report: Report) -> str:
    n = len(report.changes)
    if not n:
        return "no differences"
    return f"{n} change{'s' if n != 1 else ''}: {len(report.breaking)} breaking, {len(report.compatible)} compatible"


def _verdict(report: Report, new_name: str = "NEW") -> str:
    """The suggested bump and whether NEW's map_version already satisfies it."""
    bump, old_v, new_v = report.bump, report.old.info.map_version, report.new.info.map_version
    if bump is Bump.NONE:
        return f"no version bump needed (map_version {old_v} -> {new_v})"
    ok = "satisfies it" if report.version_ok else "does not satisfy it"
    return f"suggested bump: {bump.label} ({old_v} -> {report.suggested_version}); {new_name}'s map_version {new_v} {ok}"


def _line(c: Change) -> str:
    what = f"{c.before} -> {c.after}" if c.before and c.after else c.before or c.after
    note = f"  ({c.note})" if c.note else ""
    return f"  {c.kind:<28} {_plain(c.subject)}: {what}{note}"


def _same_model(report: Report) -> str:
    """Why two different files have no differences."""
    old, new = report.old, report.new
    if report.changes or old.fingerprint == new.fingerprint:
        return ""
    if old.info.map_version != new.info.map_version:
        return " apart from map_version"
    return " (the files differ only in formatting, comments or spelling)"


def render_text(report: Report) -> str:
    old, new = report.old, report.new
    lines = [
        f"old: {_plain(old.source_path)}  {old.id} map {old.info.map_version}  fingerprint {old.fingerprint}",
        f"new: {_plain(new.source_path)}  {new.id} map {new.info.map_version}  fingerprint {new.fingerprint}",
        _summary(report) + _same_model(report),
        _verdict(report),
    ]
    for title, changes in (("breaking:", report.breaking), ("compatible:", report.compatible)):
        if changes:
            lines += ["", title, *(_line(c) for c in changes)]
    return "\n".join(lines) + "\n"


_CODE_SAFE = re.compile(r"^[\w.\[\]\-,/@~^{}:+ ]+$")


def _code(text: str) -> str:
    """An identifier-like value as a code span; anything else as escaped text (a map cannot inject Markdown)."""
    return f"`{text}`" if _CODE_SAFE.match(text) and "`" not in text else md_text(text)


def _html_comment(text: str) -> str:
    """Text that cannot end or nest an HTML comment."""
    return re.sub(r"--(!?>)", r"- -\1", _plain(text)).replace("<!--", "<! --")


def render_markdown(report: Report, header: Sequence[str] = ()) -> str:
    """A changelog page: a summary, then one table per kind, breaking changes first."""
    old, new = report.old, report.new
    title = f"{old.id} → {new.id}" if old.id != new.id else new.id
    lines = [f"# Changelog: {md_text(title)} {md_text(old.info.map_version)} → {md_text(new.info.map_version)}", ""]
    lines += [f"<!-- {_html_comment(h)} -->" for h in header or ["Generated by regmap diff - do not edit."]]
    lines.append("")
    lines += [
        "| | map | version | fingerprint |",
        "|---|---|---|---|",
        f"| old | {_code(old.source_path)} | {md_text(old.info.map_version)} | `{old.fingerprint}` |",
        f"| new | {_code(new.source_path)} | {md_text(new.info.map_version)} | `{new.fingerprint}` |",
        "",
    ]
    summary = _summary(report) + _same_model(report)
    lines.append(f"**{summary[0].upper()}{summary[1:]}.**")
    if report.changes:
        lines.append(
            "Breaking changes make client code or firmware built from the old map misbehave or stop building; compatible ones do not."
        )
    lines.append("")
    if report.bump is Bump.NONE:
        lines.append("No version bump needed.")
    else:
        ok = "already satisfies it" if report.version_ok else "does **not** satisfy it"
        lines.append(
            f"Suggested version bump: **{report.bump.label}** ({md_text(old.info.map_version)} → "
            f"{md_text(report.suggested_version or '?')}); the new map's version {md_text(new.info.map_version)} {ok}."
        )
    for title, changes in (("Breaking changes", report.breaking), ("Compatible changes", report.compatible)):
        if not changes:
            continue
        lines += ["", f"## {title}"]
        for kind in KINDS:
            rows = [c for c in changes if c.kind == kind]
            if rows:
                lines += ["", f"### {KINDS[kind].heading}", "", *_table(KINDS[kind].item, rows)]
    return "\n".join(lines) + "\n"


def _table(item: str, rows: Sequence[Change]) -> list[str]:
    columns: list[tuple[str, Callable[[Change], str]]] = [(item.capitalize(), lambda c: _code(c.subject))]
    if not any(c.before and c.after for c in rows):  # added or removed: what it is, in one column
        columns.append(("Details", lambda c: md_text(c.before or c.after)))
    else:
        columns += [("Before", lambda c: md_text(c.before)), ("After", lambda c: md_text(c.after))]
    if any(c.note for c in rows):
        columns.append(("Note", lambda c: md_text(c.note)))
    out = ["| " + " | ".join(name for name, _ in columns) + " |", "|" + "---|" * len(columns)]
    out += ["| " + " | ".join(cell(c) or " " for _, cell in columns) + " |" for c in rows]
    return out


def render_json(report: Report) -> str:
    def side(d: Device) -> dict[str, Any]:
        return {"map": d.source_path, "device": d.id, "map_version": d.info.map_version, "fingerprint": d.fingerprint}

    doc = {
        "format": JSON_FORMAT,
        "old": side(report.old),
        "new": side(report.new),
        "summary": {
            "changes": len(report.changes),
            "breaking": len(report.breaking),
            "compatible": len(report.compatible),
            "bump": report.bump.label,
            "suggested_version": report.suggested_version,
            "version_ok": report.version_ok,
            "exit_status": report.exit_status,
        },
        "changes": [c.as_json() for c in report.changes],
    }
    return json.dumps(doc, ensure_ascii=False, indent=2) + "\n"


def render(report: Report, fmt: str) -> str:
    if fmt == "markdown":
        return render_markdown(report)
    if fmt == "json":
        return render_json(report)
    return render_text(report)


# -- `regmap generate --since GITREV` ----------------------------------------------------------


def changelog_pages(devices: Sequence[Device], since: str, targets: Sequence[str]) -> dict[str, str]:
    """`docs/<device>-changelog.md` -> page, for every device whose map existed at `since` (paths relative
    to the output directory). Only with the markdown target: the pages belong to the docs. Computed
    before anything is written, so an unknown revision leaves the output untouched."""
    from regmap.backends.markdown import TARGET as DOCS

    if DOCS.name not in targets:
        raise UsageError(f"--since writes changelog pages into the docs: add --target {DOCS.name}")
    pages: dict[str, str] = {}
    for device in devices:
        data = read_at_revision(Path(device.source_path), since)
        if data is None:
            continue  # the map is newer than `since`: no earlier version to compare with
        old = _load_revision(device.source_path, since, data)
        header = header_lines(device, f"regmap generate --since {since}")
        pages[f"{DOCS.subdir}/{device.id}-changelog.md"] = render_markdown(compare(old, device), header)
    return pages


def write_pages(out_dir: Path, pages: Mapping[str, str]) -> list[Path]:
    """Write changelog pages next to the generated docs, each replaced atomically."""
    written: list[Path] = []
    for rel, content in sorted(pages.items()):
        path = out_dir / rel
        path.parent.mkdir(parents=True, exist_ok=True)
        partial = path.with_name(f".{path.name}.partial")
        partial.write_text(content, encoding="utf-8", newline="\n")
        os.replace(partial, path)
        written.append(path)
    return written


__all__ = [
    "EXIT_HELP",
    "FORMATS",
    "KINDS",
    "Bump",
    "Change",
    "Report",
    "changelog_pages",
    "compare",
    "load_spec",
    "read_at_revision",
    "render",
    "split_spec",
    "write_pages",
]
