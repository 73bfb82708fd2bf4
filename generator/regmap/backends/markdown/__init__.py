"""Markdown back end: a reference page per map, an index page, and a bitfield diagram (SVG) per bitfield register.

The views compute every cell; the templates only print. Map text reaches a page in one of two ways:
a plain `str` field goes through the template's `md` filter, and an `Md` field is a cell a view
assembled from `md_text`-escaped map text and validated identifiers (`DocId`), printed as is.
Anchors are explicit `<a id="...">` tags: a register's anchor is its name, every other anchor has a
hyphenated prefix (`array-`, `enum-`, `example-`, `erratum-` ...), and every generated heading has a
hyphen in its slug, so no two ids on a page can collide.

Modules: `text` (text types, escaping, links, numbers), `views` (the view classes and the per-device
context), `registers`, `frames` (frame annotation of the examples), `page` (the page and the index),
`diagrams` (wavedrom's bitfield drawing) and `hook` (the mkdocs hook that mkdocs.yml names).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from regmap.backends.markdown.diagrams import bitfield_svg, diagram_path
from regmap.backends.markdown.page import INDEX_PAGE, device_page, render_device, render_shared
from regmap.target import Files, Target

if TYPE_CHECKING:
    from regmap.plant import Plant


def render_plant(plant: Plant) -> Files:
    """The plant's page (backends/markdown/plant.py): imported only when a plant is rendered."""
    from regmap.backends.markdown.plant import render_plant as render

    return render(plant)


TARGET = Target(
    name="markdown", subdir="docs", per_device=render_device, shared=render_shared, order=30, plant=render_plant, scale_from=True
)

__all__ = ["INDEX_PAGE", "TARGET", "bitfield_svg", "device_page", "diagram_path", "render_device", "render_shared"]
