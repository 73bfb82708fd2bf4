"""The plant page: buses with their line settings and wiring notes, devices with slave ids and working links to
their pages, the poll order as the shared schedule has it and the line's timing budget computed from it."""

from __future__ import annotations

import re

from regmap.backends.markdown.plant import render_plant
from regmap.frontend.plant import load_plant
from regmap.runtime_bridge import plant_schedule

from conftest import ROOT

CELL1 = ROOT / "examples" / "plants" / "cell1.yaml"


def test_the_plant_page_shows_buses_devices_and_links_that_resolve() -> None:
    plant = load_plant(CELL1)
    files = render_plant(plant)
    page = files["cell1_plant.md"]
    assert "## Bus `line1`" in page
    assert "| Baud rate | 38400 |" in page and "| Parity | even |" in page
    assert "| Inter-frame silence | 1.75 ms" in page
    assert "120 ohm termination at the master" in page  # the bus's wiring notes
    for dev in plant.devices:
        row = re.search(rf"^\| `{dev.name}` \| (.*)$", page, re.M)
        assert row is not None, dev.name
        cells = [c.strip() for c in row.group(1).split(" | ")]
        assert cells[2] == str(dev.slave)
        assert f"[{dev.device.id}]({dev.device.id}.md)" in cells[1]
    for target in re.findall(r"\]\(([^)#]+\.md)\)", page):
        assert target in files, f"the plant page links {target}, which is not written beside it"


def test_the_poll_order_and_the_budget_are_the_schedules() -> None:
    plant = load_plant(CELL1)
    page = render_plant(plant)["cell1_plant.md"]
    (schedule,) = plant_schedule(plant)
    rows = re.findall(r"^\| (\d+) \| `(\w+)` \| (\d+) \| 0x([0-9A-F]{2}) [^|]* \| 0x([0-9A-F]{4}) \| (\d+) \| ([\d.]+) ms \|$", page, re.M)
    assert [(int(n), d, int(s), int(f, 16), int(a, 16), int(c)) for n, d, s, f, a, c, _ in rows] == [
        (n, e.device.name, e.slave, e.function, e.start, e.count) for n, e in enumerate(schedule.entries, start=1)
    ]
    assert [float(t) for *_, t in rows] == [round((schedule.exchange_s(e) or 0) * 1000, 2) for e in schedule.entries]
    assert f"take at most **{(schedule.cycle_s or 0) * 1000:.2f} ms** of line time" in page
    # The budget of one exchange: request and answer on the wire, the device's turnaround, the silence.
    first = schedule.entries[0]
    line = plant.buses[0].serial
    assert line is not None
    wire = (8 + 5 + 2 * first.count) * line.character_bits / line.baud
    assert schedule.exchange_s(first) == wire + first.device.turnaround_s(line.baud) + line.silence_s
