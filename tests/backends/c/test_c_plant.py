"""The C plant header: compiles warning-free as C99 and C++, and a program walking its poll table prints the
shared schedule (runtime_bridge.plant_schedule), row for row, with the line's settings and timing."""

from __future__ import annotations

import subprocess
from pathlib import Path

import pytest

from regmap.backends.c.plant import plant_header
from regmap.frontend.plant import load_plant
from regmap.runtime_bridge import plant_schedule, read_plan
from regmap_runtime.line import interleave
from regmap_runtime.spaces import SPACES

from conftest import ROOT, require_tool
from support.plants import METER_VARIANTS, write_meter_plant

CELL1 = ROOT / "examples" / "plants" / "cell1.yaml"
WARNINGS = ("-Wall", "-Wextra", "-Wpedantic", "-Werror", "-Wconversion", "-Wsign-conversion")
COMPILERS = {"c99": ("gcc", "-std=c99", "-Wstrict-prototypes"), "c++17": ("g++", "-x", "c++", "-std=c++17")}

WALK = """\
#define CELL1_PLANT_IMPLEMENTATION
#include "cell1_plant.h"
#include <stdio.h>

int main(void)
{
    unsigned i;
    printf("devices %u slaves %u %u %u\\n", (unsigned)CELL1_DEVICE_COUNT, (unsigned)CELL1_AXIS_X_SLAVE,
           (unsigned)CELL1_AXIS_Y_SLAVE, (unsigned)CELL1_SPINDLE_SLAVE);
    printf("line %lu %c silence %lu cycle %lu\\n", (unsigned long)CELL1_LINE1_BAUD, CELL1_LINE1_PARITY,
           (unsigned long)CELL1_LINE1_SILENCE_US, (unsigned long)CELL1_LINE1_CYCLE_US);
    for (i = 0u; i < CELL1_LINE1_POLL_LEN; i++) {
        const cell1_poll *row = &cell1_line1_poll[i];
        printf("%u %u %u %u %u\\n", (unsigned)row->device, (unsigned)row->slave, (unsigned)row->function,
               (unsigned)row->start, (unsigned)row->count);
    }
    return 0;
}
"""


@pytest.mark.parametrize("standard", sorted(COMPILERS))
def test_the_poll_table_walks_as_the_shared_schedule(standard: str, tmp_path: Path) -> None:
    tool, *flags = COMPILERS[standard]
    compiler = require_tool(tool)
    plant = load_plant(CELL1)
    (tmp_path / "cell1_plant.h").write_text(plant_header(plant), encoding="utf-8")
    source = tmp_path / "walk.c"
    source.write_text(WALK, encoding="utf-8")
    build = subprocess.run(
        [compiler, *flags, "-O2", *WARNINGS, f"-I{tmp_path}", str(source), "-o", str(tmp_path / "walk")],
        capture_output=True,
        text=True,
        check=False,
    )
    assert build.returncode == 0 and not build.stderr.strip(), build.stderr
    lines = subprocess.run([str(tmp_path / "walk")], capture_output=True, text=True, check=True).stdout.splitlines()
    (schedule,) = plant_schedule(plant)
    index = {dev.name: n for n, dev in enumerate(plant.devices)}
    assert lines[0] == "devices 3 slaves 1 2 3"
    assert lines[1] == f"line 38400 E silence 1750 cycle {round((schedule.cycle_s or 0) * 1e6)}"
    rows = [tuple(int(x) for x in line.split()) for line in lines[2:]]
    assert rows == [(index[e.device.name], e.slave, e.function, e.start, e.count) for e in schedule.entries]


METERS_WALK = """\
#define METERS_PLANT_IMPLEMENTATION
#include "meters_plant.h"
#include <stdio.h>

int main(void)
{
    unsigned i;
    for (i = 0u; i < METERS_LINE1_POLL_LEN; i++) {
        const meters_poll *row = &meters_line1_poll[i];
        printf("%u %u %u %u %u\\n", (unsigned)row->device, (unsigned)row->slave, (unsigned)row->function,
               (unsigned)row->start, (unsigned)row->count);
    }
    return 0;
}
"""


def test_each_device_of_a_variant_polls_that_variants_plan(tmp_path: Path) -> None:
    """Two float meters on one bus, single- and three-phase: the compiled poll table is each meter's own variant's
    read plan (runtime_bridge.read_plan(variants=...)), interleaved; only the three-phase one reads voltage_l2."""
    compiler = require_tool("gcc")
    plant = load_plant(write_meter_plant(tmp_path, "meters", "tcp: {host: 127.0.0.1, port: 502}"))
    (tmp_path / "meters_plant.h").write_text(plant_header(plant), encoding="utf-8")
    (tmp_path / "walk.c").write_text(METERS_WALK, encoding="utf-8")
    build = subprocess.run(
        [compiler, "-std=c99", "-O2", *WARNINGS, f"-I{tmp_path}", str(tmp_path / "walk.c"), "-o", str(tmp_path / "walk")],
        capture_output=True,
        text=True,
        check=False,
    )
    assert build.returncode == 0 and not build.stderr.strip(), build.stderr
    lines = subprocess.run([str(tmp_path / "walk")], capture_output=True, text=True, check=True).stdout.splitlines()
    rows = [tuple(int(x) for x in line.split()) for line in lines]
    devices = plant.devices
    plans = [read_plan(dev.device, variants=(METER_VARIANTS[dev.name][1],)) for dev in devices]
    expected = [(i, devices[i].slave, SPACES[b.space].read, b.address, b.count) for i, b in interleave(plans)]
    assert rows == expected
    l2 = devices[0].device.register("voltage_l2")
    reads_l2 = {slave for _, slave, fc, start, count in rows if fc == 0x04 and start <= l2.address < start + count}
    assert reads_l2 == {3}
