"""A register's range and default are worked out once per page and shown the same in its quick-reference row and its
facts; the engineering values behind them are kept by the ratios' integers, the same as worked out afresh."""

from __future__ import annotations

from fractions import Fraction

from regmap.backends.markdown.page import device_page
from regmap.backends.markdown.registers import _value_cells
from regmap.backends.markdown.views import Context, RegisterView
from regmap.core.text import _scaled_number, _scaled_text
from regmap.frontend import load_map

from conftest import ROOT


def test_a_registers_row_and_facts_show_the_same_range_and_default() -> None:
    device = load_map(ROOT / "maps" / "c630s.yaml")
    page = device_page(device)
    checked = 0
    for group in page.groups:
        sections = {item.anchor: item for item in group.items if isinstance(item, RegisterView)}
        for row in group.quick:
            name = row.name[row.name.index("(#") + 2 : -1]
            if name not in sections:
                continue
            facts = dict(sections[name].facts)
            assert facts["Default"].startswith(row.default.split(" = ")[0]), (name, row.default, facts["Default"])
            if "Range" in facts:
                assert facts["Range"].startswith(row.range), (name, row.range, facts["Range"])
                checked += 1
    assert checked >= 10


def test_the_cells_are_kept_per_device() -> None:
    one, other = (load_map(ROOT / "maps" / name) for name in ("c630s.yaml", "id243pro.yaml"))
    ctx, other_ctx = Context(one), Context(other)
    reg = one.registers[0]
    assert _value_cells(ctx, reg) is _value_cells(ctx, reg)
    assert reg.name not in other_ctx.value_cells


def test_scaled_values_by_integers_are_the_fractions_values() -> None:
    assert 0 < (_scaled_text.cache_info().maxsize or 0) <= 1 << 16
    for raw, scale, offset in (
        (15, Fraction(1, 10), Fraction(0)),
        (-400, Fraction(1, 10), Fraction(-40)),
        (7, Fraction(3, 7), Fraction(1, 3)),
    ):
        spelled = _scaled_text(raw, scale.numerator, scale.denominator, offset.numerator, offset.denominator)
        assert spelled == _scaled_number(raw, scale, offset)
    assert _scaled_text(15, 1, 10, 0, 1) == "1.5"
    assert _scaled_text(-400, 1, 10, -40, 1) == "-80"
