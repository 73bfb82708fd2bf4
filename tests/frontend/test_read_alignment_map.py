"""Issue #34: a float meter answers only reads that start on an even address and cover an even count
(`transport.read_alignment`), and swaps its float word order when a magic float is written
(`word_order_register.swap_value`). The front end keeps the model and the registers consistent with both."""

from __future__ import annotations

from pathlib import Path

import pytest

from regmap.cli import main
from regmap.frontend import load_map
from regmap.model import WordOrder

from conftest import ROOT

FLOAT_METER = ROOT / "tests" / "maps" / "fixtures" / "float_meter.yaml"
TEXT = FLOAT_METER.read_text(encoding="utf-8")


def _variant(tmp_path: Path, *edits: tuple[str, str]) -> Path:
    text = TEXT
    for old, new in edits:
        assert old in text, old
        text = text.replace(old, new)
    path = tmp_path / "float_meter.yaml"
    path.write_text(text, encoding="utf-8")
    return path


def _where(path: Path, needle: str) -> str:
    """file:line:col of the flow mapping that starts the line holding `needle` (a register entry's `{`)."""
    for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
        if needle in line:
            return f"{path}:{number}:{line.index('{') + 1}"
    raise AssertionError(needle)


def _errors(path: Path, capsys: pytest.CaptureFixture[str]) -> list[str]:
    assert main(["validate", str(path)]) == 1
    err = capsys.readouterr().err
    assert "Traceback" not in err
    return err.splitlines()


def test_the_fixture_records_the_rule_its_exemption_and_the_magic_swap() -> None:
    t = load_map(FLOAT_METER).transport
    a = t.read_alignment
    assert a is not None and (a.words, a.spaces, a.exception) == (2, ("holding", "input"), 0x02)
    assert [r.name for r in a.exempt] == ["ct_ratio"] and a.exempt_reads() == (("holding", 0x0104, 1),)
    w = t.word_order_register
    assert w is not None and w.register.name == "word_order_swap" and w.swaps and w.register.trigger
    hi, lo = WordOrder.HIGH_FIRST, WordOrder.LOW_FIRST
    assert (w.value_for(hi, lo), w.value_for(lo, hi), w.value_for(hi, hi)) == (2141.0, 2141.0, None)
    assert (w.order_after(hi, 2141.0), w.order_after(lo, 2141.0), w.order_after(hi, 5.0)) == (lo, hi, hi)


def test_a_float_at_an_odd_address_is_refused_where_it_is_declared(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = _variant(
        tmp_path, ("{name: current_l1, address: 0x0002", "{name: current_l1, address: 0x0003"), ("address: 0x0004,", "address: 0x0010,")
    )
    (line,) = _errors(path, capsys)
    assert line.startswith(_where(path, "name: current_l1") + ": current_l1: its 2 words at 0x0003 cross a 2-word boundary")


def test_the_same_float_is_accepted_when_the_map_records_the_exemption(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = _variant(
        tmp_path,
        ("{name: current_l1, address: 0x0002", "{name: current_l1, address: 0x0003"),
        ("address: 0x0004,", "address: 0x0010,"),
        ("exempt: [ct_ratio]", "exempt: [ct_ratio, current_l1]"),
    )
    assert main(["validate", str(path)]) == 0, capsys.readouterr().err


def test_a_lone_word_with_an_undocumented_neighbour_needs_the_exemption(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = _variant(tmp_path, ("    exempt: [ct_ratio]\n", ""))
    (line,) = _errors(path, capsys)
    assert line.startswith(_where(path, "name: ct_ratio") + ": ct_ratio: an aligned read of it (2 words at 0x0104) covers 0x0105")


def test_the_rules_own_mistakes(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = _variant(
        tmp_path,
        ("exception: 0x02", "exception: 0x04"),
        ("exempt: [ct_ratio]", "exempt: [ct_ratio, baud_code]"),
        ("access: w, trigger: true,", "access: w,"),
        ("swap_value: 2141.0}", "swap_value: 2141.0, high_first: 0}"),
    )
    lines = _errors(path, capsys)
    assert len(lines) == 1 and "word_order_register" in lines[0]  # the schema: swap_value or a value per order, never both
    path = _variant(
        tmp_path,
        ("exception: 0x02", "exception: 0x04"),
        ("exempt: [ct_ratio]", "exempt: [ct_ratio, baud_code]"),
        ("access: w, trigger: true,", "access: w,"),
    )
    lines = _errors(path, capsys)
    assert any(
        "read_alignment answers exception 0x04, which transport.exceptions does not list (listed: 0x01, 0x02, 0x03)" in x for x in lines
    )
    assert any("read_alignment.exempt: baud_code is aligned already" in x for x in lines)
    assert any("word_order_swap must be marked trigger: true" in x for x in lines)
    assert len(lines) == 3
