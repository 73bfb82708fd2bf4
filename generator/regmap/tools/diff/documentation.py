"""Changes of the items that only document the manual: examples, errata and groups (all patch)."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

from regmap.model import Device, Erratum, Example, Group
from regmap.tools.diff.kinds import PATCH, Changes
from regmap.tools.diff.match import T, _match
from regmap.tools.diff.text import _clip, _fields, _plain


def documentation_changes(old: Device, new: Device, rename: Callable[[str], str]) -> Changes:
    """Examples, errata and groups added, removed or changed; `rename` maps an old register name to the new one."""
    out = Changes()
    for part in (_examples, _errata, _groups):
        part(out, old, new, rename)
    return out


def _examples(out: Changes, old: Device, new: Device, rename: Callable[[str], str]) -> None:
    def facts(e: Example, is_old: bool) -> dict[str, Any]:
        name_of = rename if is_old else (lambda name: name)
        return {
            "direction": e.direction,
            "frame": e.frame.hex(" ").upper(),
            "corrected_frame": None if e.corrected_frame is None else e.corrected_frame.hex(" ").upper(),
            "request": e.request,
            "erratum": e.erratum,
            "values": [(name_of(v.register.name), v.raw, v.words, v.value) for v in e.values],
            "meaning": e.meaning,
            "meaning_zh": e.meaning_zh,
            "notes": e.notes,
            "source": e.source,
        }

    _by_id(out, "example", old.examples, new.examples, lambda e: e.id, facts, lambda e: f"{e.direction} {e.frame.hex(' ').upper()}")


def _errata(out: Changes, old: Device, new: Device, rename: Callable[[str], str]) -> None:
    def facts(e: Erratum, is_old: bool) -> dict[str, Any]:
        name_of = rename if is_old else (lambda name: name)
        return {
            "title": e.title,
            "readings": [(r.source, r.says) for r in e.readings],
            "choice": e.choice,
            "reason": e.reason,
            "registers": [name_of(r) for r in e.registers],
        }

    _by_id(out, "erratum", old.errata, new.errata, lambda e: e.id, facts, lambda e: f'"{_clip(_plain(e.title))}"')


def _groups(out: Changes, old: Device, new: Device, rename: Callable[[str], str]) -> None:
    def facts(g: Group, is_old: bool) -> dict[str, Any]:
        return {"title": g.title, "title_zh": g.title_zh, "description": g.description, "source": g.source}

    _by_id(out, "group", old.groups, new.groups, lambda g: g.id, facts, lambda g: f'"{_clip(_plain(g.title))}"')


def _by_id(
    out: Changes,
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
        out.add(f"{what}_removed", ident(item), PATCH, summary(item), "", ident(item), None)
    for item in added:
        out.add(f"{what}_added", ident(item), PATCH, "", summary(item), None, ident(item))
    for o, n, _ in pairs:
        a, b = facts(o, True), facts(n, False)
        fields = [k for k in a if a[k] != b[k]]
        if fields:
            out.add(
                f"{what}_changed",
                ident(n),
                PATCH,
                *_fields([(k, a[k], b[k]) for k in fields]),
                {k: a[k] for k in fields},
                {k: b[k] for k in fields},
            )
