"""A third-party back end, shipped as its own package, found through the `regmap.targets` entry points and
written against the documented contract (`regmap.target`, docs/plugins.md): its files, its checks, its
order and its reserved words; and the built-in targets' reserved words (IEC 61131-3 for st)."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from regmap.diagnostics import MapError
from regmap.frontend import load_map
from regmap.generate import check, render

from conftest import ROOT

BUILT_IN = "python, c, markdown, st, esphome, homeassistant"
IEC_ID_MAP = ROOT / "tests" / "maps" / "invalid" / "device_id_iec_keyword.yaml"

PLUGINS_DOC = ROOT / "docs" / "plugins.md"


def documented_plugin() -> str:
    """The example plugin of docs/plugins.md, its first Python block: the test installs what the page shows."""
    text = PLUGINS_DOC.read_text(encoding="utf-8")
    start = text.index("```python\n") + len("```python\n")
    return text[start : text.index("```", start)]


@pytest.fixture(scope="module")
def plugin_env(tmp_path_factory: pytest.TempPathFactory) -> dict[str, str]:
    """The environment of a `regmap` that has the plugin installed (in a directory of its own, on PYTHONPATH;
    regmap comes from the project's environment)."""
    tmp_path = tmp_path_factory.mktemp("plugin")
    source = tmp_path / "plugin"
    (source / "regmap_registers").mkdir(parents=True)
    (source / "regmap_registers" / "__init__.py").write_text(documented_plugin(), encoding="utf-8")
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
    # Kept in front of any PYTHONPATH already set (the mutation gate points it at its mutated copy of regmap).
    return {**os.environ, "PYTHONPATH": os.pathsep.join(p for p in (str(plugins), os.environ.get("PYTHONPATH")) if p)}


def _regmap(*args: str, env: dict[str, str] | None = None) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "regmap", *args], cwd=ROOT, capture_output=True, text=True, check=False, env=env)


def _id_position(map_path: Path) -> tuple[int, int]:
    """Line and column of the device id's value, read from the map text itself."""
    for number, line in enumerate(map_path.read_text(encoding="utf-8").splitlines(), start=1):
        if line.startswith("  id: "):
            return number, len("  id: ") + 1
    raise AssertionError(f"{map_path} has no device id line")


def test_a_plugin_package_adds_a_target(plugin_env: dict[str, str], tmp_path: Path) -> None:
    out = tmp_path / "out"
    result = _regmap("generate", "maps/idm_rs.yaml", "--target", "registers", "--out", str(out), env=plugin_env)
    assert result.returncode == 0, result.stderr
    assert (out / "registers" / "idm_rs.csv").read_text(encoding="utf-8").splitlines()[:2] == [
        "address,name",
        "0x0001,pulses_per_revolution",
    ]
    validate = _regmap("validate", "maps/c630s.yaml", env=plugin_env)
    long_names = [line for line in validate.stderr.splitlines() if "refuses names over 30 characters" in line]
    assert validate.returncode == 1 and long_names, validate.stderr
    assert long_names[0].split(":")[0] == "maps/c630s.yaml" and long_names[0].split(":")[1].isdigit()
    # Without the plugin the same map is valid: the check is the plugin's own.
    assert _regmap("validate", "maps/c630s.yaml").returncode == 0


def test_a_plugin_declares_its_order(plugin_env: dict[str, str]) -> None:
    """Targets are listed (and run) by the order each declares: the plugin's 5 puts it before python's 10."""
    with_plugin = _regmap("generate", "--target", "nosuch", env=plugin_env)
    assert with_plugin.returncode == 2, with_plugin.stderr
    assert with_plugin.stderr.strip().endswith(f"(targets: registers, {BUILT_IN})"), with_plugin.stderr
    alone = _regmap("generate", "--target", "nosuch")
    assert alone.stderr.strip().endswith(f"(targets: {BUILT_IN})"), alone.stderr


def test_a_plugin_declares_its_reserved_words(plugin_env: dict[str, str], tmp_path: Path) -> None:
    """The plugin reserves C630S (case-insensitively): `validate` and `generate --target registers` refuse the id
    c630s at its map line; with the plugin not chosen, or not installed, the map is fine."""
    line, column = _id_position(ROOT / "maps" / "c630s.yaml")
    refusal = (
        f"maps/c630s.yaml:{line}:{column}: device id 'c630s' is a reserved word of the registers target "
        "(a name the registers plugin keeps); choose another (e.g. c630s_drive)"
    )
    validate = _regmap("validate", "maps/c630s.yaml", env=plugin_env)
    assert validate.returncode == 1 and refusal in validate.stderr.splitlines(), validate.stderr
    out = tmp_path / "out"
    generate = _regmap("generate", "maps/c630s.yaml", "--target", "registers", "--out", str(out), env=plugin_env)
    assert (generate.returncode, generate.stderr.splitlines()) == (1, [refusal])
    assert not out.exists()
    assert "reserved word" not in _regmap("validate", "maps/c630s.yaml").stderr


def test_st_refuses_an_iec_word_as_device_id_only_when_chosen() -> None:
    """END_IF is no Python or C word: only the st target reserves it (IEC 61131-3 compares case-insensitively)."""
    device = load_map(IEC_ID_MAP)
    line, column = _id_position(IEC_ID_MAP)
    [problem] = check([device], ["st"])
    assert (problem.line, problem.column) == (line, column)
    assert problem.message.startswith("device id 'end_if' is a reserved word of the st target (an IEC 61131-3")
    assert check([device], ["python", "c"]) == []
    with pytest.raises(MapError) as refused:
        render([device], ["c", "st"])
    assert [str(d) for d in refused.value.diagnostics] == [str(problem)]
    assert "end_if.h" in render([device], ["c"])["c"]
