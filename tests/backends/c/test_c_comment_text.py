"""`comment_text` escapes any text, `sentence_comment` any text `sentences` made, exactly as `c_comment` does (they only
skip the work where there is none)."""

from __future__ import annotations

from regmap.backends.c.names import comment_text, sentence_comment
from regmap.core.text import sentences
from regmap.render import c_comment

TEXTS = (
    ("Peak current (峰值电流)", "raw 0..100, scale 0.1", "Manual 4.2."),
    ("ends */ here", "/* opens", None),
    ("a\\b", "why??", "one\n  two\tthree"),
    ("  spaced  out  ", "", "\u3000ideographic\u3000space"),
    ("slash / alone", "x\x1cy", "done."),
)
RAW = ("", " ", "a  b", " lead", "trail ", "tab\there", "x\ny", "nbsp\u00a0here", "a*/b", "??=", "m/s", "plain text")


def test_comment_text_escapes_as_c_comment() -> None:
    for parts in TEXTS:
        text = sentences(*parts)
        assert comment_text(text) == sentence_comment(text) == c_comment(text), parts
        for part in parts:
            assert comment_text(part or "") == c_comment(part), part
    for raw in RAW:
        assert comment_text(raw) == c_comment(raw), raw


def test_plain_text_is_its_own_escape() -> None:
    text = sentences("Peak current (峰值电流)", "raw 0..100")
    assert comment_text(text) is sentence_comment(text) is text
