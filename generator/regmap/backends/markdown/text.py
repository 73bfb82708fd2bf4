"""Markdown text types and helpers: validated identifiers (`DocId`), assembled Markdown (`Md`),
escaping, links, anchors and the spelling of numbers in the docs.

The views use it as one module (`from regmap.backends.markdown import text as md`: `md.code(name)`,
`md.link(...)`, `md.escaped(text)`), so the helpers a view needs are not an import list to keep in step.
"""

from __future__ import annotations

import functools
import re
from collections.abc import Iterable, Sequence

from regmap import render
from regmap.core.text import number
from regmap.diagnostics import UsageError
from regmap.model import EnumType, Register
from regmap.render import TEXT_CACHE_SIZE

# `md_text` for the views: a page escapes the same titles, units and names again and again (quick reference, sections,
# tables), and every map's text again for each page of a plant. Each text is escaped once.
md_text = functools.lru_cache(maxsize=TEXT_CACHE_SIZE)(render.md_text)

DASH = "—"

# ---------------------------------------------------------------------------------------------- text types

# Compiled on first use (re's cache), not at import: the test in DocId answers nearly every name without it.
_DOC_ID = r"^[A-Za-z][A-Za-z0-9_]*$"


class DocId(str):
    """A map identifier (register, enum, example, erratum ...) that is safe as an HTML id, inside a
    Markdown code span and as a file name."""

    def __new__(cls, name: str) -> DocId:
        # An ASCII identifier not starting with _ is what _DOC_ID matches, told without the regex (thousands a page).
        if not (name.isascii() and name.isidentifier() and name[0] != "_") and not re.match(_DOC_ID, name):
            raise UsageError(f"{name!r} cannot name an anchor or a file in the docs; use letters, digits and _")
        return super().__new__(cls, name)


class Md(str):
    """Markdown a view assembled from escaped map text and validated identifiers: printed as is."""


_EMPTY = Md("")


def escaped(text: str | None) -> Md:
    return Md(md_text(text))


@functools.lru_cache(maxsize=TEXT_CACHE_SIZE)  # a page names each register and enum several times: each is checked once
def code(name: str) -> Md:
    return Md(f"`{DocId(name)}`")


def link(label: str, anchor: str, page: str = "") -> Md:
    return Md(f"[{label}]({page}#{anchor})")


@functools.lru_cache(maxsize=TEXT_CACHE_SIZE)
def anchor(prefix: str, *names: str) -> str:
    return "-".join([prefix, *(DocId(n) for n in names)])


_BLOCK_START = re.compile(r"^(?:[#>+\-]|\d+[.)])")


def paragraph(text: str | None) -> Md:
    """Escaped text that stays one paragraph: a leading `#`, `>`, `-`, `+`, `1.` or `~~~` would start
    a block (`md_text` already folds the text onto one line and escapes everything inline)."""
    if not text:  # most registers have no notes, many no description
        return _EMPTY
    inline = md_text(text)
    match = _BLOCK_START.match(inline)
    if match:
        marker = match.group(0)
        inline = (marker[:-1] + "\\" + marker[-1] if marker[0].isdigit() else "\\" + marker) + inline[len(marker) :]
    elif inline.startswith("~"):
        inline = "&#126;" + inline[1:]
    return Md(inline)


def html_comment(line: str) -> str:
    """A header line that cannot end the HTML comment it sits in."""
    return line.replace("--", "- -").replace(">", "&gt;")


def sources(source: Sequence[str]) -> str:
    return ", ".join(source) if source else DASH


def join(parts: Iterable[str], sep: str = ", ") -> Md:
    return Md(sep.join(parts))


# ---------------------------------------------------------------------------------------------- numbers


def hex_value(value: int, words: int = 1) -> str:
    return f"0x{value:04X}" if words == 1 else f"0x{value:0{4 * words}X}"  # one word: most values, without the nested width


def address(value: int) -> Md:
    return Md(f"`{hex_value(value)}`")


def unit_suffix(reg: Register) -> Md:
    return Md(f" {md_text(reg.unit)}") if reg.unit else Md("")


def raw_literal(reg: Register, raw: int | float | str) -> str:
    """Bit words read best in hex, integers in decimal, floats as the docs print numbers, text quoted
    (and escaped: it came from a frame or a map)."""
    if isinstance(raw, str):
        return '"' + md_text(raw) + '"'
    if isinstance(raw, float):
        return number(raw)
    if reg.bitfields and raw >= 0:
        return hex_value(raw, reg.words)
    return str(raw)


def enum_label(e: EnumType, raw: int) -> Md | None:
    member = e.by_value(raw)
    return None if member is None else code(member.name)


# ---------------------------------------------------------------------------------------------- links


def _reg_anchor(reg: Register) -> str:
    return anchor("array", reg.array.array) if reg.array is not None else DocId(reg.name)


def reg_link(reg: Register, *, param: bool = True) -> Md:
    label = link(code(reg.name), _reg_anchor(reg))
    if param and reg.param:
        return Md(f"{label} ({md_text(reg.param)})")
    return label


def errata_links(ids: Iterable[str]) -> Md:
    unique = dict.fromkeys(ids)  # an array member's errata repeat once per element: kept once each, in order
    return join(link(md_text(i), anchor("erratum", i)) for i in unique)
