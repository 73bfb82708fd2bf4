"""The bitfield diagrams are written directly (regmap/backends/markdown/diagrams.py, issue #36: importing wavedrom
and svgwrite and drawing through them cost more than the rest of the docs): every diagram of every valid map, and
of any layout of 8 to 64 bits, is the very SVG that `wavedrom.render` draws."""

from __future__ import annotations

import json

import pytest
import wavedrom  # type: ignore[import-untyped,import-not-found,unused-ignore]
from hypothesis import given
from hypothesis import strategies as st

from regmap.backends.markdown import diagrams
from regmap.diagnostics import MapError
from regmap.frontend import load_map
from regmap.model import Device

from conftest import ROOT

MAPS = sorted([*(ROOT / "maps").glob("*.yaml"), *(p for p in (ROOT / "tests" / "maps").rglob("*.yaml") if "invalid" not in p.parts)])


def _through_render(source: str) -> str:
    """The diagram as regmap drew it before: `wavedrom.render` of the JSON text."""
    drawing = wavedrom.render(source)
    drawing.set_desc(title=diagrams._TITLE_SLOT)
    text: str = drawing.tostring()
    return text


def _devices() -> list[Device]:
    devices = []
    for path in MAPS:
        try:
            devices.append(load_map(path))
        except (MapError, ValueError):  # a plant, a diff fixture meant to fail, ...: not a map with diagrams
            continue
    return devices


def test_every_diagram_is_what_wavedrom_render_draws(monkeypatch: pytest.MonkeyPatch) -> None:
    drawn = 0
    for device in _devices():
        for reg in device.registers:
            if not reg.bitfields:
                continue
            direct = diagrams.bitfield_svg(device, reg)
            with monkeypatch.context() as patch:
                patch.setattr(diagrams, "_drawing", _through_render)
                assert direct == diagrams.bitfield_svg(device, reg), f"{device.source_path}: {reg.name}"
            drawn += 1
    assert drawn >= 40  # the seed maps alone hold 24 bitfield registers; the fixtures add their own


@st.composite
def layouts(draw: st.DrawFn) -> str:
    """A register's layout as `bitfield_svg` gives it to the drawing: fields (named, wrapped as the docs wrap them, or
    unused bits) that fill 8 to 64 bits, one lane per 8."""
    bits = draw(st.sampled_from([8, 16, 32, 64]))
    fields, left = [], bits
    while left:
        width = draw(st.integers(1, left))
        named = draw(st.booleans())
        name = draw(st.from_regex(r"[a-z][a-z0-9]{0,7}(_[a-z0-9]{1,9}){0,6}", fullmatch=True))
        fields.append({"bits": width, "name": diagrams._wrap(name, width)} if named else {"bits": width})
        left -= width
    config = {"bits": bits, "lanes": bits // diagrams.LANE_BITS, "hspace": diagrams.DIAGRAM_WIDTH, "vspace": 110}
    return json.dumps({"reg": fields, "config": config}, sort_keys=True)


@given(layouts())
def test_any_layout_is_drawn_as_wavedrom_draws_it(source: str) -> None:
    assert diagrams._drawing(source) == _through_render(source)
