"""The bitfield diagrams call wavedrom's `reg` renderer directly (regmap/backends/markdown/diagrams.py, issue #36:
without `wavedrom.render`'s YAML round trip of the JSON source): every diagram of every valid map is the very SVG
that `wavedrom.render` draws."""

from __future__ import annotations

import pytest
import wavedrom  # type: ignore[import-untyped,import-not-found,unused-ignore]

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
