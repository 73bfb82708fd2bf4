"""The ST plant files through matiec: the poll tables as ARRAY OF STRUCT constants in a configuration, read by a
program; the table matiec builds from them (its C initialiser) is the shared schedule, row for row."""

from __future__ import annotations

import re
from pathlib import Path

from regmap.backends.st.plant import render_plant
from regmap.frontend.plant import load_plant
from regmap.runtime_bridge import plant_schedule

from conftest import ROOT, built_tool
from support.st_matiec import iec2c

CELL1 = ROOT / "examples" / "plants" / "cell1.yaml"

WALK = """
PROGRAM P_WALK
VAR
    nSlaves : UDINT;
    i : INT;
END_VAR
VAR_EXTERNAL CONSTANT
    CELL1_LINE1_POLL : ST_CELL1_LINE1_POLL_TABLE;
    CELL1_LINE1_POLL_LEN : UINT;
    CELL1_SPINDLE_SLAVE : USINT;
END_VAR
nSlaves := 0;
FOR i := 0 TO UINT_TO_INT(CELL1_LINE1_POLL_LEN) - 1 DO
    IF CELL1_LINE1_POLL[i].SLAVE = CELL1_SPINDLE_SLAVE THEN
        nSlaves := nSlaves + 1;
    END_IF;
END_FOR;
END_PROGRAM
"""


def test_matiec_compiles_the_plant_constants_and_builds_the_schedule(tmp_path: Path) -> None:
    matiec = built_tool("matiec")
    plant = load_plant(CELL1)
    files = render_plant(plant)
    types, constants = files["cell1_plant/cell1_plant_types.st"], files["cell1_plant/cell1_plant_constants.st"]
    body = constants[constants.index("VAR_GLOBAL CONSTANT") :]
    source = (
        types
        + WALK
        + "\nCONFIGURATION C_TEST\nRESOURCE R_TEST ON PLC\n"
        + body
        + "    TASK T_TEST(INTERVAL := T#10ms, PRIORITY := 0);\n    PROGRAM P_TEST WITH T_TEST : P_WALK;\nEND_RESOURCE\nEND_CONFIGURATION\n"
    )
    compiled = iec2c(matiec, source, tmp_path, "plant")
    assert compiled.returncode == 0 and not compiled.errors, compiled.output
    resource = (compiled.c_dir / "R_TEST.c").read_text(encoding="utf-8")
    initial = re.search(r"CELL1_LINE1_POLL,__INITIAL_VALUE\(\{\{(.*?)\}\}\)", resource)
    assert initial is not None, resource
    rows = [tuple(int(n, 0) for n in row.split(",")) for row in re.findall(r"\{([0-9x,A-Fa-f]+)\}", initial.group(1))]
    index = {dev.name: n for n, dev in enumerate(plant.devices)}
    (schedule,) = plant_schedule(plant)
    assert rows == [(index[e.device.name], e.slave, e.function, e.start, e.count) for e in schedule.entries]
    slaves = re.search(r"CELL1_SPINDLE_SLAVE,__INITIAL_VALUE\((\d+)\)", resource)
    assert slaves is not None and int(slaves.group(1)) == 3
