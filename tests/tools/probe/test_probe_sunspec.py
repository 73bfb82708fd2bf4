"""`regmap probe --sunspec` walks a SunSpec device's chain (the SunS marker, then model id + length) and reports its
models; a model where the map has another is a disagreement."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from regmap.diagnostics import ExitCode

from conftest import SimulatorFactory
from support.sunspec_models import chain_map, pysunspec_python


def _probe(map_path: Path, port: int | None) -> subprocess.CompletedProcess[str]:
    regmap = str(Path(sys.executable).with_name("regmap"))
    return subprocess.run(
        [regmap, "probe", str(map_path), "--tcp", f"127.0.0.1:{port}", "--sunspec", "--budget", "60"],
        capture_output=True,
        text=True,
        check=False,
    )


def test_the_chain_is_walked_and_reported(simulator: SimulatorFactory, tmp_path: Path) -> None:
    python = pysunspec_python()
    device = chain_map(python, [1, 103, 160], tmp_path / "inverter.yaml", repeats=2)
    sim = simulator(device)
    run = _probe(device, sim.port)
    assert run.returncode == ExitCode.OK, run.stdout + run.stderr
    assert "ok  SunSpec: SunSpec chain at 40000: models 1 at 40002 (L 66), 103 at 40070 (L 50), 160 at 40122 (L 48)" in run.stdout


def test_a_model_the_map_does_not_expect_disagrees(simulator: SimulatorFactory, tmp_path: Path) -> None:
    python = pysunspec_python()
    served = chain_map(python, [1, 103, 160], tmp_path / "inverter.yaml", repeats=2)
    expected = chain_map(python, [1, 101, 160], tmp_path / "single_phase.yaml", repeats=2)  # 101 and 103 have the same length
    sim = simulator(served)
    run = _probe(expected, sim.port)
    assert run.returncode == ExitCode.PROBE_DISAGREES, run.stdout + run.stderr
    assert "DISAGREES  SunSpec: 40070: model 103 at 40070, where the map has model 101" in run.stdout
