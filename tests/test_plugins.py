"""A third-party back end, shipped as its own package, found through the `regmap.targets` entry points."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
from pathlib import Path

from conftest import ROOT

PLUGIN = '''
"""A tiny regmap back end: one line per register."""

from regmap.diagnostics import at
from regmap.generate import Target


def per_device(device):
    rows = [f"0x{r.address:04X},{r.name}" for r in device.registers]
    return {f"{device.id}.csv": "address,name\\n" + "\\n".join(rows) + "\\n"}


def check(device):
    return [at(device.source_path, r.pos, f"{r.name}: the registers plugin refuses names over 30 characters") for r in device.registers if len(r.name) > 30]


TARGET = Target(name="registers", subdir="registers", per_device=per_device, shared=lambda devices: {}, check=check)
'''


def test_a_plugin_package_adds_a_target(tmp_path: Path) -> None:
    source = tmp_path / "plugin"
    (source / "regmap_registers").mkdir(parents=True)
    (source / "regmap_registers" / "__init__.py").write_text(PLUGIN, encoding="utf-8")
    (source / "pyproject.toml").write_text(
        textwrap.dedent(
            """
            [build-system]
            requires = ["setuptools>=68"]
            build-backend = "setuptools.build_meta"

            [project]
            name = "regmap-registers"
            version = "1.0"

            [project.entry-points."regmap.targets"]
            registers = "regmap_registers:TARGET"
            """
        ),
        encoding="utf-8",
    )
    # The plugin goes into an environment of its own (a target directory on PYTHONPATH); regmap comes from the project's.
    plugins = tmp_path / "site"
    installed = subprocess.run(
        [
            sys.executable,
            "-m",
            "pip",
            "install",
            "--quiet",
            "--no-deps",
            "--no-build-isolation",
            "--no-index",
            "--target",
            str(plugins),
            str(source),
        ],
        capture_output=True,
        text=True,
        check=False,
    )
    assert installed.returncode == 0, installed.stderr
    python = sys.executable
    env = {**os.environ, "PYTHONPATH": str(plugins)}
    out = tmp_path / "out"
    result = subprocess.run(
        [python, "-m", "regmap", "generate", "maps/idm_rs.yaml", "--target", "registers", "--out", str(out)],
        cwd=ROOT,
        capture_output=True,
        text=True,
        check=False,
        env=env,
    )
    assert result.returncode == 0, result.stderr
    assert (out / "registers" / "idm_rs.csv").read_text(encoding="utf-8").splitlines()[:2] == [
        "address,name",
        "0x0001,pulses_per_revolution",
    ]
    validate = subprocess.run(
        [python, "-m", "regmap", "validate", "maps/c630s.yaml"], cwd=ROOT, capture_output=True, text=True, check=False, env=env
    )
    long_names = [line for line in validate.stderr.splitlines() if "refuses names over 30 characters" in line]
    assert validate.returncode == 1 and long_names, validate.stderr
    assert long_names[0].split(":")[0] == "maps/c630s.yaml" and long_names[0].split(":")[1].isdigit()
    # Without the plugin the same map is valid: the check is the plugin's own.
    assert (
        subprocess.run(
            [sys.executable, "-m", "regmap", "validate", "maps/c630s.yaml"], cwd=ROOT, capture_output=True, check=False
        ).returncode
        == 0
    )
