"""The ST plant files through matiec: the poll tables as ARRAY OF STRUCT constants in a configuration, read by a
program; the table matiec builds from them (its C initialiser) is the shared schedule, row for row."""

from __future__ import annotations

import re
from pathlib import Path

from regmap.backends.st.plant import render_plant
from regmap.frontend.plant import load_plant
from regmap.plant import Plant
from regmap.runtime_bridge import plant_schedule, read_plan
from regmap_runtime.line import interleave
from regmap_runtime.spaces import SPACES

from conftest import ROOT, built_tool
from support.plants import METER_VARIANTS, write_meter_plant
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


def _matiec_resource(plant: Plant, walk: str, tmp_path: Path) -> str:
    """The plant's constants and a program reading them, compiled by matiec: the resource's C text."""
    matiec = built_tool("matiec")
    files = render_plant(plant)
    types, constants = files[f"{plant.id}_plant/{plant.id}_plant_types.st"], files[f"{plant.id}_plant/{plant.id}_plant_constants.st"]
    body = constants[constants.index("VAR_GLOBAL CONSTANT") :]
    source = (
        types
        + walk
        + "\nCONFIGURATION C_TEST\nRESOURCE R_TEST ON PLC\n"
        + body
        + "    TASK T_TEST(INTERVAL := T#10ms, PRIORITY := 0);\n    PROGRAM P_TEST WITH T_TEST : P_WALK;\nEND_RESOURCE\nEND_CONFIGURATION\n"
    )
    compiled = iec2c(matiec, source, tmp_path, "plant")
    assert compiled.returncode == 0 and not compiled.errors, compiled.output
    return (compiled.c_dir / "R_TEST.c").read_text(encoding="utf-8")


def _poll_rows(resource: str, table: str) -> list[tuple[int, ...]]:
    initial = re.search(table + r",__INITIAL_VALUE\(\{\{(.*?)\}\}\)", resource)
    assert initial is not None, resource
    return [tuple(int(n, 0) for n in row.split(",")) for row in re.findall(r"\{([0-9x,A-Fa-f]+)\}", initial.group(1))]


def test_matiec_compiles_the_plant_constants_and_builds_the_schedule(tmp_path: Path) -> None:
    plant = load_plant(CELL1)
    resource = _matiec_resource(plant, WALK, tmp_path)
    rows = _poll_rows(resource, "CELL1_LINE1_POLL")
    index = {dev.name: n for n, dev in enumerate(plant.devices)}
    (schedule,) = plant_schedule(plant)
    assert rows == [(index[e.device.name], e.slave, e.function, e.start, e.count) for e in schedule.entries]
    slaves = re.search(r"CELL1_SPINDLE_SLAVE,__INITIAL_VALUE\((\d+)\)", resource)
    assert slaves is not None and int(slaves.group(1)) == 3


METERS_WALK = """
PROGRAM P_WALK
VAR
    nRows : UINT;
END_VAR
VAR_EXTERNAL CONSTANT
    METERS_LINE1_POLL : ST_METERS_LINE1_POLL_TABLE;
    METERS_LINE1_POLL_LEN : UINT;
END_VAR
nRows := METERS_LINE1_POLL_LEN;
END_PROGRAM
"""


def test_each_device_of_a_variant_polls_that_variants_plan(tmp_path: Path) -> None:
    """Two float meters on one bus, single- and three-phase: the table matiec builds is each meter's own variant's
    read plan (runtime_bridge.read_plan(variants=...)), interleaved; only the three-phase one reads voltage_l2."""
    plant = load_plant(write_meter_plant(tmp_path, "meters", "tcp: {host: 127.0.0.1, port: 502}"))
    rows = _poll_rows(_matiec_resource(plant, METERS_WALK, tmp_path), "METERS_LINE1_POLL")
    devices = plant.devices
    plans = [read_plan(dev.device, variants=(METER_VARIANTS[dev.name][1],)) for dev in devices]
    assert rows == [(i, devices[i].slave, SPACES[b.space].read, b.address, b.count) for i, b in interleave(plans)]
    l2 = devices[0].device.register("voltage_l2")
    assert {slave for _, slave, fc, start, count in rows if fc == 0x04 and start <= l2.address < start + count} == {3}
