"""The C plant header: compiles warning-free as C99 and C++, and a program walking its poll table prints the
shared schedule (runtime_bridge.plant_schedule), row for row, with the line's settings and timing."""

from __future__ import annotations

import subprocess
from pathlib import Path

import pytest

from regmap.backends.c.plant import plant_header
from regmap.frontend.plant import load_plant
from regmap.runtime_bridge import plant_schedule

from conftest import ROOT, require_tool

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
