"""The tool environments: built by `make tools` before pytest, looked up (never installed) by the tests."""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

import pytest

from conftest import ROOT, built_tool, skip_or_fail
from support import tool_envs


def test_an_environment_without_its_stamp_is_not_taken_for_a_built_one(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("REGMAP_TOOLS_DIR", str(tmp_path))
    half_built = tool_envs.location("esphome")
    (half_built / "bin").mkdir(parents=True)
    (half_built / "bin" / "esphome").write_text("#!/bin/sh\n", encoding="utf-8")
    with pytest.raises(tool_envs.ToolUnavailable, match="make tools"):
        tool_envs.find("esphome")
    (half_built / tool_envs.STAMP).write_text("esphome", encoding="utf-8")
    assert tool_envs.find("esphome") == half_built / "bin" / "esphome"


def test_new_pins_mean_a_new_environment(monkeypatch: pytest.MonkeyPatch) -> None:
    before = tool_envs.location("hass")
    tool = tool_envs.VENV_TOOLS["hass"]
    monkeypatch.setitem(tool_envs.VENV_TOOLS, "hass", tool_envs.VenvTool(tool.name, tool.executable, (*tool.pins, "extra==1"), tool.why))
    assert tool_envs.location("hass") != before


def test_no_test_installs_a_tool() -> None:
    """pip runs in tests/support/tool_envs.py (`make tools`) alone; a test that installed would race pytest-timeout."""
    installers = re.compile(r"[\"']pip[\"'],\s*[\"']install[\"']|[\"']-m[\"'],\s*[\"'](venv|ensurepip)[\"']")
    offenders = [
        f"{path.name}:{number}"
        for path in sorted((ROOT / "tests").rglob("*.py"))
        if path.name not in ("tool_envs.py", "test_tool_envs.py")
        for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1)
        if installers.search(line)
    ]
    assert offenders == []


def test_matiec_compiles_structured_text(tmp_path: Path) -> None:
    matiec = built_tool("matiec")
    program = tmp_path / "smoke.st"
    program.write_text(
        "FUNCTION scaled : DINT\n  VAR_INPUT raw : UINT; END_VAR\n  scaled := UINT_TO_DINT(raw) * 10;\nEND_FUNCTION\n\n"
        "PROGRAM main\n  VAR value : DINT; END_VAR\n  value := scaled(raw := 22);\nEND_PROGRAM\n\n"
        "CONFIGURATION config\n  RESOURCE res ON PLC\n    TASK cycle(INTERVAL := T#10ms, PRIORITY := 0);\n"
        "    PROGRAM instance WITH cycle : main;\n  END_RESOURCE\nEND_CONFIGURATION\n",
        encoding="utf-8",
    )
    out = tmp_path / "c"
    out.mkdir()
    result = subprocess.run(
        [str(matiec / "iec2c"), "-I", str(matiec / "lib"), "-T", str(out), str(program)], capture_output=True, text=True, check=False
    )
    assert result.returncode == 0, result.stdout + result.stderr
    assert "SCALED" in (out / "POUS.c").read_text(encoding="utf-8")


def test_a_missing_tool_skips_here_and_fails_under_ci(monkeypatch: pytest.MonkeyPatch) -> None:
    # pytest.raises(BaseException): a skip raised where a failure is due must fail this test, not skip it.
    outcomes = []
    for ci in (None, "true"):
        if ci is None:
            monkeypatch.delenv("CI", raising=False)
        else:
            monkeypatch.setenv("CI", ci)
        with pytest.raises(BaseException, match="no such tool") as caught:
            skip_or_fail("no such tool")
        outcomes.append(caught.type)
    assert outcomes == [pytest.skip.Exception, pytest.fail.Exception]
