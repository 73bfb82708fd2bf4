"""The ESPHome and Home Assistant files are written without PyYAML's emitter (issue #36) but must stay what
`yaml.dump` writes, byte for byte: every quoting decision is a safety decision (map text written plain as
`!secret x`, `*a`, `yes` or `- x` would read back as a tag, an alias, a boolean or a list). The direct writer
is compared with PyYAML on generated strings and structures, and must not leave the seed files to PyYAML."""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import pytest
import yaml
from hypothesis import given
from hypothesis import strategies as st

from regmap.backends.esphome import render_device as esphome_files
from regmap.backends.homeassistant import render_device as hass_files
from regmap.frontend import load_map
from regmap.homeauto import yamltext
from regmap.homeauto.yamltext import Hex, Lambda, direct_text, pyyaml_text

from conftest import MAPS, ROOT

# Words PyYAML reads as another type or as structure, and characters that change the quoting: all written on one line.
# fmt: off
TRICKY = [
    "!secret wifi", "!include x.yaml", "*alias", "&anchor", "- item", "-", "?", "? x", ":", ":x", "a: b", "a:", "# c",
    "a #b", "a#b", "yes", "No", "ON", "off", "y", "n", "true", "False", "null", "Null", "~", "0x10", "0o17", "017",
    "1_000", "1e3", "1.5", ".5", "-.inf", ".NaN", "12:30:45", "2024-01-02", "---", "...", "=", "<<", "%x", "@x", "`x",
    "'x", '"x', "|", ">", "[a]", "{a}", "a,b", "a, b", "it's", "' '", "é", "°C", "µs", "中文", "\u00a0x", "x\u00a0",
    "\U0001f600", " lead", "trail ", "two  spaces", "",
]
# Strings PyYAML double-quotes or writes on several lines: left to it.
SEVERAL_LINES_OR_ESCAPED = ["\ufeffx", "\u2028", "a\u2029b", "\x85", "tab\there", "new\nline", "cr\rx", "\x7f", "a \nb"]
# fmt: on
PIECES = st.sampled_from([*TRICKY, " ", "  ", "word", "ab'cd", "x" * 40])
PRINTABLE = st.characters(codec="utf-8", exclude_categories=("Cc", "Cs", "Zl", "Zp"), exclude_characters="\ufeff")
# Strings PyYAML writes plain or single-quoted on one line: the direct writer must take every one of them.
ONE_LINE = st.one_of(st.text(PRINTABLE, max_size=30), st.lists(PIECES, max_size=8).map("".join), st.sampled_from(TRICKY))
ANY_TEXT = st.one_of(ONE_LINE, st.text(max_size=20), st.sampled_from(SEVERAL_LINES_OR_ESCAPED))
# Long texts: folding at a single space past column 120, in plain and quoted strings, at every depth.
# Code of a `!lambda |-` block: lines of any indentation between a first and a last line of code.
LAMBDAS = st.lists(st.sampled_from(["return x;", "", "  x;", "y: #z 'q'"]), max_size=4).map(
    lambda lines: Lambda("\n".join(["id(a)->b(0x01, 2);", *lines, "return x;"]))
)
# Keys about as long as PyYAML writes as a simple `key:` (else a complex `? key`).
LONG_KEYS = st.text("ab :'", min_size=118, max_size=130)
LONG = st.lists(st.sampled_from(["word", "w", "a:b", "it's", "x" * 30, " ", "  ", "yes", "#"]), min_size=20, max_size=60).map(" ".join)


def scalars(text: st.SearchStrategy[str]) -> st.SearchStrategy[Any]:
    return st.one_of(
        text,
        LONG,
        st.integers(-(2**40), 2**40),
        st.booleans(),
        st.none(),
        st.floats(allow_nan=False, allow_infinity=False),
        st.builds(Hex, st.integers(0, 2**32), st.sampled_from([2, 4, 8])),
        LAMBDAS,
    )


def documents(text: st.SearchStrategy[str], keys: st.SearchStrategy[str]) -> st.SearchStrategy[dict[str, Any]]:
    nodes = st.recursive(
        scalars(text),
        lambda inner: st.one_of(st.lists(inner, max_size=4), st.dictionaries(keys, inner, max_size=4)),
        max_leaves=25,
    )
    return st.dictionaries(keys, nodes, min_size=1, max_size=5)


@given(documents(ONE_LINE, ONE_LINE.filter(lambda k: 0 < len(k) < 123)))
def test_one_line_strings_are_written_directly_as_pyyaml_writes_them(data: dict[str, Any]) -> None:
    direct = direct_text(data)
    assert direct is not None
    assert direct == pyyaml_text(data)


@pytest.mark.parametrize(
    "data",
    [
        {"note": " ".join(["word"] * 40)},  # plain, folded at the first single space past column 120
        {"notes": ["it's  " * 30]},  # single-quoted in a sequence: a run of two spaces is never folded
        {"k" * 122: " a b "},  # single-quoted past column 120 from its start: a first or last space is never folded
        {"deep": [{"x": {"y": "yes " * 40 + "no"}}]},
    ],
)
def test_long_text_is_folded_where_pyyaml_folds_it(data: dict[str, Any]) -> None:
    assert direct_text(data) == pyyaml_text(data)


def test_a_key_pyyaml_writes_as_complex_is_left_to_it() -> None:
    """PyYAML's longest simple `key:` is 122 characters (it counts the `!!str` tag it does not write)."""
    assert direct_text({"k" * 122: "v"}) == pyyaml_text({"k" * 122: "v"})
    assert direct_text({"k" * 123: "v"}) is None
    assert pyyaml_text({"k" * 123: "v"}).startswith("? ")


@pytest.mark.parametrize("code", ["", " x;", "x;\n", "x; \ny;", "a\tb", "a\u2028b"])
def test_lambda_blocks_pyyaml_would_not_write_as_blocks_are_left_to_it(code: str) -> None:
    data = {"then": [{"lambda": Lambda(code)}]}
    assert direct_text(data) is None
    assert yamltext.yaml_text(data) == pyyaml_text(data)


@given(documents(ANY_TEXT, st.one_of(ANY_TEXT, LONG_KEYS)))
def test_any_document_is_written_as_pyyaml_writes_it(data: dict[str, Any]) -> None:
    """A string PyYAML double-quotes or writes on several lines, a long or empty key: left to PyYAML, never guessed."""
    direct = direct_text(data)
    assert direct is None or direct == pyyaml_text(data)
    assert yamltext.yaml_text(data) == pyyaml_text(data)


# PyYAML writes "\x85" (a YAML 1.1 line break) single-quoted on two lines, read back as a space: its own quirk, kept.
@pytest.mark.parametrize("text", TRICKY + [t for t in SEVERAL_LINES_OR_ESCAPED if t != "\x85"])
def test_map_text_reads_back_as_the_same_string(text: str) -> None:
    written = yamltext.yaml_text({"name": text, "list": [text], text or "k": 1})
    assert yaml.safe_load(written) == {"name": text, "list": [text], text or "k": 1}


@pytest.mark.parametrize("path", MAPS, ids=lambda p: p.stem)
def test_the_seed_files_are_written_without_pyyaml(path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    def refuse(data: Any) -> str:
        raise AssertionError("left to PyYAML")

    monkeypatch.setattr(yamltext, "pyyaml_text", refuse)
    device = load_map(path, display_name=path.relative_to(ROOT).as_posix())
    for target, render in (("esphome", esphome_files), ("homeassistant", hass_files)):
        for name, text in render(device).items():
            assert text == (ROOT / "generated" / target / name).read_text(encoding="utf-8")


# The one-pattern spellings the checks replaced (issue #36: compiling them cost a cold run about 5M instructions).
ORDINARY_PATTERN = re.compile(
    r"(?![\s#,\[\]{}&*!|>'\"%@`?:.-])[^\x00-\x1f#:\x7f-\x9f\u2028\u2029\ud800-\udfff\ufeff\ufffe-\U0010ffff]+(?<! )"
)
SPECIAL_PATTERN = re.compile("[\x00-\x09\x0b-\x1f\x7f-\x9f\u2028\u2029\ud800-\udfff\ufeff\ufffe-\U0010ffff]")
EDGES = ["\x9f", "\xa0", "\u2027", "\u2028", "\u2029", "\u202a", "\ud7ff", "\ud800", "\udfff", "\ue000", "\ufefe", "\ufeff"]
EDGES += ["\ufffd", "\ufffe", "\uffff", "\U00010000", "\u3000", "\u1680", "\x85", "\x1c", "\t", "\n", " ", "#", ":", "."]
CHARACTERS = st.one_of(st.characters(), st.sampled_from([*EDGES, "a", "-", "!"]))


@given(st.text(CHARACTERS, max_size=6))
def test_ordinary_text_is_what_the_one_pattern_matched(text: str) -> None:
    assert yamltext._ordinary(text) == bool(ORDINARY_PATTERN.fullmatch(text))


@given(st.text(CHARACTERS, max_size=6))
def test_special_characters_are_what_the_one_pattern_found(text: str) -> None:
    assert yamltext._special(text) == bool(SPECIAL_PATTERN.search(text))


@pytest.mark.parametrize("text", EDGES)
def test_every_edge_character_alone_and_inside_text_is_ordinary_as_before(text: str) -> None:
    for written in (text, "a" + text, text + "a", "a" + text + "a"):
        assert yamltext._ordinary(written) == bool(ORDINARY_PATTERN.fullmatch(written))
        assert yamltext._special(written) == bool(SPECIAL_PATTERN.search(written))
