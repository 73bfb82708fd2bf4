"""A `scale_from` register's page says how its value is computed, value = raw × 10^<scale factor>, linking the
scale-factor register; its range and default are given as raw numbers (the scale is only known at run time)."""

from __future__ import annotations

import re

from regmap.frontend import load_map
from regmap.generate import render

from conftest import ROOT

MAP = ROOT / "tests" / "maps" / "scaled_from" / "inverter.yaml"


def _section(page: str, name: str) -> str:
    start = page.index(f"`{name}` —")
    end = page.find("\n#### ", start)
    return page[start : end if end != -1 else len(page)]


def test_each_scaled_register_links_its_scale_factor() -> None:
    device = load_map(MAP)
    page = render([device], ["markdown"])["markdown"]["sf_inverter.md"]
    assert "Not generated" not in page
    for reg in (r for r in device.registers if r.scale_from is not None):
        section = _section(page, reg.name)
        assert re.search(rf"value = raw × 10\^\[`{reg.scale_from}`\]\(#{reg.scale_from}\)", section), section
        assert f"raw {reg.default}" in section  # the default, raw: its value depends on the factor read
    limit = device.register("wmax_lim_pct")
    assert f"raw {limit.raw_min} … {limit.raw_max}" in _section(page, "wmax_lim_pct")
