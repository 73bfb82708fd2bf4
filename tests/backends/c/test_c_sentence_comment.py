"""A comment made by `sentences` is escaped by `sentence_comment` exactly as `c_comment` escapes it."""

from __future__ import annotations

from regmap.backends.c.names import sentence_comment
from regmap.core.text import sentences
from regmap.render import c_comment

TEXTS = (
    ("Peak current (峰值电流)", "raw 0..100, scale 0.1", "Manual 4.2."),
    ("ends */ here", "/* opens", None),
    ("a\\b", "why??", "one\n  two\tthree"),
    ("  spaced  out  ", "", "\u3000ideographic\u3000space"),
    ("slash / alone", "x\x1cy", "done."),
)


def test_sentence_comment_escapes_as_c_comment() -> None:
    for parts in TEXTS:
        text = sentences(*parts)
        assert sentence_comment(text) == c_comment(text), parts


def test_plain_sentences_are_their_own_escape() -> None:
    text = sentences("Peak current (峰值电流)", "raw 0..100")
    assert sentence_comment(text) is text
