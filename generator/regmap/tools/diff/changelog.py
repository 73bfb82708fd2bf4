"""`regmap generate --since GITREV`: a changelog page per map that existed at GITREV."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from regmap.diagnostics import UsageError
from regmap.model import Device
from regmap.render import header_lines
from regmap.tools.diff.compare import compare
from regmap.tools.diff.gitload import _load_revision, read_at_revision
from regmap.tools.diff.render import render_markdown

DOCS_TARGET = "markdown"  # the pages sit beside the manual that back end writes


def changelog_pages(devices: Sequence[Device], since: str, targets: Sequence[str]) -> dict[str, str]:
    """`docs/<device>-changelog.md` -> page, for every device whose map existed at `since` (paths relative
    to the output directory). Only with the markdown target: the pages belong to the docs. Computed
    before anything is written, so an unknown revision leaves the output untouched; `generate` writes
    them into its staged tree, so they are swapped in together with the docs they sit beside."""
    from regmap.generate import target

    if DOCS_TARGET not in targets:
        raise UsageError(f"--since writes changelog pages into the docs: add --target {DOCS_TARGET}")
    docs = target(DOCS_TARGET)
    pages: dict[str, str] = {}
    for device in devices:
        data = read_at_revision(Path(device.source_path), since)
        if data is None:
            continue  # the map is newer than `since`: no earlier version to compare with
        old = _load_revision(device.source_path, since, data)
        header = header_lines(device, f"regmap generate --since {since}")
        pages[f"{docs.subdir}/{device.id}-changelog.md"] = render_markdown(compare(old, device), header)
    return pages
