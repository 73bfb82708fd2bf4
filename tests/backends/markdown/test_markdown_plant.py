"""The plant page: buses with their line settings and wiring notes, devices with slave ids and working links to
their pages, the poll order as the shared schedule has it and the line's timing budget computed from it."""

from __future__ import annotations

import re
from pathlib import Path

from regmap.backends.markdown.plant import render_plant
from regmap.frontend.plant import load_plant
from regmap.runtime_bridge import plant_schedule, read_plan
from regmap_runtime.line import interleave

from conftest import ROOT
from support.plants import METER_VARIANTS, write_meter_plant

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


def test_a_device_of_a_variant_is_polled_and_budgeted_for_that_variant_only(tmp_path: Path) -> None:
    """Two float meters on a serial line, single- and three-phase: the page names each one's variant, and its poll
    order and line-time budget are each meter's own variant's read plan, interleaved."""
    plant = load_plant(write_meter_plant(tmp_path, "meters", "serial: {port: /dev/ttyUSB0, baud: 9600, parity: none}"))
    page = render_plant(plant)["meters_plant.md"]
    devices = plant.devices
    plans = [read_plan(dev.device, variants=(METER_VARIANTS[dev.name][1],)) for dev in devices]
    expected = [(devices[i].name, devices[i].slave, b.address, b.count) for i, b in interleave(plans)]
    rows = re.findall(r"^\| \d+ \| `(\w+)` \| (\d+) \| 0x[0-9A-F]{2} [^|]* \| 0x([0-9A-F]{4}) \| (\d+) \| [\d.]+ ms \|$", page, re.M)
    assert [(d, int(s), int(a, 16), int(c)) for d, s, a, c in rows] == expected
    assert len(plans[0]) != len(plans[1])  # the single-phase meter skips voltage_l2's words
    for dev, plan in zip(devices, plans, strict=True):
        row = re.search(rf"^\| `{dev.name}` \| (.*)$", page, re.M)
        assert row is not None
        cells = [c.strip() for c in row.group(1).split(" | ")]
        assert f"variant `{dev.variant}`" in cells[1] and cells[4] == str(len(plan)), cells
    (schedule,) = plant_schedule(plant)
    assert f"{len(expected)} requests a cycle take at most **{(schedule.cycle_s or 0) * 1000:.2f} ms**" in page
