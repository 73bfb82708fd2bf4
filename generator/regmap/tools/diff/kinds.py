"""Change kinds and their rules, one change (`Change`) and the whole report (`Report`): classification,
suggested version bump and exit status."""

from __future__ import annotations

import enum
import re
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from regmap.diagnostics import ExitCode
from regmap.model import Device
from regmap.tools.diff.text import _fields, _json

FORMATS = ("text", "markdown", "json")
JSON_FORMAT = "regmap-diff/1"
EXIT_SAME, EXIT_COMPATIBLE, EXIT_BREAKING = ExitCode.OK, ExitCode.DIFF_COMPATIBLE, ExitCode.DIFF_BREAKING


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
    "firmware_register_changed": Kind(
        "setting",
        "Firmware register changed",
        "breaking when removed or changed (register or format): an old client would read another version; minor when added",
    ),
    "register_removed": Kind("register", "Registers removed", "breaking"),
    "register_renamed": Kind("register", "Registers renamed", "breaking: generated names change (wire unchanged)"),
    "register_moved": Kind("register", "Registers moved", "breaking: another address on the wire"),
    "register_space_changed": Kind("register", "Register spaces changed", "breaking: another table, other function codes"),
    "register_type_changed": Kind("register", "Register types changed", "breaking: width, signedness or kind (integer, float, text, bit)"),
    "register_string_changed": Kind("register", "String registers changed", "breaking: length in words, encoding or padding"),
    "register_word_order_changed": Kind("register", "Register word order changed", "breaking"),
    "register_byte_order_changed": Kind("register", "Register byte order changed", "breaking: every word reads byte-swapped"),
    "register_paired_changed": Kind("register", "Register pairing changed", "breaking: block reads start elsewhere"),
    "register_access_changed": Kind(
        "register", "Register access changed", "breaking when read or write is lost (RW->R, RW->W, R<->W); minor when gained (R->RW, W->RW)"
    ),
    "register_unit_changed": Kind(
        "register", "Register units changed", "breaking when changed or removed; patch when given where there was none"
    ),
    "register_scale_changed": Kind("register", "Register scales changed", "breaking"),
    "register_offset_changed": Kind("register", "Register offsets changed", "breaking: the same raw value means another value"),
    "register_range_changed": Kind(
        "register", "Register ranges changed", "breaking when narrowed; minor when only widened; patch when the effective range is the same"
    ),
    "register_enum_changed": Kind("register", "Register enums changed", "breaking: the generated value type changes"),
    "register_firmware_changed": Kind(
        "register",
        "Register firmware gates changed",
        "breaking when firmware versions lose the register (a gate added or narrowed); minor when only widened or removed",
    ),
    "register_default_changed": Kind("register", "Register defaults changed", "patch: factory state, never sent by generated code"),
    "register_param_changed": Kind("register", "Parameter ids changed", "patch: the manual's label only"),
    "register_na_changed": Kind(
        "register", "Register 'not available' markers changed", "breaking: a read gives None where it gave a value, or the other way round"
    ),
    "register_zone_changed": Kind(
        "register",
        "Timestamp zones changed",
        "breaking: the same seconds read as another time (UTC, or the device's zone-less local clock)",
    ),
    "register_poll_changed": Kind("register", "Register poll classes changed", "patch: how often a poller reads it, not what it reads"),
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


class Changes(list[Change]):
    """Changes as a comparison finds them; `old` and `new` are stored as JSON values."""

    def add(
        self, kind: str, subject: str, bump: Bump, before: str = "", after: str = "", old: Any = None, new: Any = None, note: str = ""
    ) -> None:
        self.append(Change(kind, subject, bump, before, after, _json(old), _json(new), note))

    def doc(self, kind: str, subject: str, o: object, n: object, fields: Sequence[str]) -> None:
        """At most one patch-level change listing every documentation field that differs."""
        diffs = [(f, getattr(o, f), getattr(n, f)) for f in fields if getattr(o, f) != getattr(n, f)]
        if diffs:
            before, after = _fields(diffs)
            self.add(kind, subject, PATCH, before, after, {f: a for f, a, _ in diffs}, {f: b for f, _, b in diffs})
