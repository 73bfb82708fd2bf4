"""`regmap diff`: what changed between two versions of a map, what it breaks, and the version bump it needs.

How items are matched and every change classified, and why: docs/diff.md.
"""

from __future__ import annotations

from regmap.tools.diff.changelog import changelog_pages
from regmap.tools.diff.compare import compare
from regmap.tools.diff.gitload import load_spec, read_at_revision, split_spec
from regmap.tools.diff.kinds import FORMATS, KINDS, Bump, Change, Report
from regmap.tools.diff.render import render, render_json, render_markdown, render_text

__all__ = [
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
    "render_json",
    "render_markdown",
    "render_text",
    "split_spec",
]
