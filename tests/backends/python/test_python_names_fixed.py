"""The generated Python's names do not change with the interpreter that runs regmap: keywords escape with a
trailing underscore, and the soft keywords escaped are Python 3.11's (3.12 made `type` one; a field named `type`
stays `type`, as the committed modules have it, on every Python)."""

from __future__ import annotations

import keyword
import sys

import pytest

from regmap.backends.python import PythonIdentifier
from regmap.keywords import PYTHON_KEYWORDS, PYTHON_SOFT_KEYWORDS


def test_a_name_is_escaped_for_keywords_and_311s_soft_keywords_only(monkeypatch: pytest.MonkeyPatch) -> None:
    newer = [*keyword.softkwlist, "type"]  # what Python 3.12 and later list
    monkeypatch.setattr(keyword, "softkwlist", newer)
    monkeypatch.setattr(keyword, "issoftkeyword", frozenset(newer).__contains__)
    names = ("type", "match", "case", "class", "speed")
    assert [PythonIdentifier(name) for name in names] == ["type", "match_", "case_", "class_", "speed"]


def test_the_soft_keywords_are_the_oldest_supported_pythons() -> None:
    assert {"_", "case", "match"} == PYTHON_SOFT_KEYWORDS
    assert {*keyword.kwlist, *PYTHON_SOFT_KEYWORDS} == PYTHON_KEYWORDS
    if sys.version_info[:2] == (3, 11):
        assert frozenset(keyword.softkwlist) == PYTHON_SOFT_KEYWORDS
