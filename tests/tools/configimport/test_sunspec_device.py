"""A simulated SunSpec device (the maps of models 1, 103 and 160, chained) answers pysunspec2's own client scan as a
real inverter would: the marker, each model at its address with its length, the repeating groups, the values."""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

from conftest import ROOT, SimulatorFactory
from support.sunspec_models import chain_map, pysunspec_python


def test_pysunspec2_scans_the_simulated_chain(simulator: SimulatorFactory, tmp_path: Path) -> None:
    python = pysunspec_python()
    values = {"m1_mn": "regmap", "m1_sn": "SIM-0001", "m103_w": 1234, "m103_w_sf": -1, "m103_st": 4}
    map_path = chain_map(python, [1, 103, 160], tmp_path / "inverter.yaml", repeats=2, values=values)
    sim = simulator(map_path)
    run = subprocess.run(
        [str(python), str(ROOT / "tests" / "support" / "sunspec_scan.py"), "127.0.0.1", str(sim.port), "1"],
        capture_output=True,
        text=True,
        check=False,
        timeout=60,
    )
    assert run.returncode == 0, run.stderr
    scan = json.loads(run.stdout)
    assert scan["base"] == 40000
    assert [(m["id"], m["addr"], m["len"]) for m in scan["models"]] == [(1, 40002, 66), (103, 40070, 50), (160, 40122, 48)]
    common, inverter, mppt = scan["models"]
    assert (common["points"]["Mn"], common["points"]["SN"]) == ("regmap", "SIM-0001")
    assert (inverter["points"]["W"], inverter["points"]["W_SF"], inverter["points"]["St"]) == (1234, -1, 4)
    assert mppt["groups"] == {"module": 2} and mppt["points"]["N"] == 2
