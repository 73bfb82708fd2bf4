"""An example's decoded table shows, beside what the frame decodes to, the value the map recorded for each register."""

from __future__ import annotations

from regmap.backends.markdown.page import render_device
from regmap.frontend import load_map

from conftest import ROOT


def test_every_recorded_raw_value_is_checked_against_the_frame() -> None:
    device = load_map(ROOT / "maps" / "c630s.yaml")
    text = render_device(device)[f"{device.id}.md"]
    checked = 0
    for example in device.examples:
        section = text[text.index(f'<a id="example-{example.id}"></a>') :]
        for value in example.values:
            if value.raw is None:
                continue
            row = next(line for line in section.splitlines() if line.startswith(f"| [`{value.register.name}`]"))
            assert row.endswith(" ✓ |") or "**differs from the frame**" in row, row
            checked += 1
    assert checked >= 3
