"""A running Home Assistant (the hass tool env's 2024.3, offline) for the tests that let it poll the simulator."""

from __future__ import annotations

import os
import re
import signal
import subprocess
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from conftest import ROOT, built_tool

HASS_OFFLINE = ROOT / "tests" / "support" / "hass_offline.py"
SERIAL_KEYS = ("method", "port", "baudrate", "bytesize", "parity", "stopbits")


def hass_python() -> Path:
    """The hass tool env's Python (skips, or fails under CI=true, without it)."""
    return Path(built_tool("hass").parent / "python")


@contextmanager
def running_hass(config: Path, output: Path) -> Iterator[subprocess.Popen[bytes]]:
    """Home Assistant on the configuration directory `config`, its stdout and stderr into `output`; stopped
    (SIGTERM, then killed after 60 s) on leaving. It runs outside this venv: PYTHON* and VIRTUAL_ENV are not passed."""
    env = {k: v for k, v in os.environ.items() if not k.startswith(("PYTHON", "VIRTUAL_ENV"))}
    with output.open("wb") as out:
        process = subprocess.Popen(
            [str(hass_python()), str(HASS_OFFLINE), "-c", str(config)], stdout=out, stderr=subprocess.STDOUT, env=env
        )
        try:
            yield process
        finally:
            process.send_signal(signal.SIGTERM)
            try:
                process.wait(timeout=60)
            except subprocess.TimeoutExpired:
                process.kill()
                process.wait()


def hub_on_tcp(package: dict[str, Any], port: int) -> dict[str, Any]:
    """The package with its one hub moved from the serial line to the simulator at 127.0.0.1:`port`: only the
    connection keys change."""
    (hub,) = package["modbus"]
    for key in SERIAL_KEYS:
        hub.pop(key, None)
    hub.update(type="tcp", host="127.0.0.1", port=port)
    return package


def check_config(hass: Path, directory: Path, package: str, *info: str) -> str:
    """HA's own config check of `package` (one package in an otherwise empty configuration under `directory`),
    with `--info` for each domain in `info`; its output, colour codes removed. Exit 0 is not enough: HA disables
    a script or template it cannot validate with one logged ERROR line."""
    (directory / "device.yaml").write_text(package, encoding="utf-8")
    (directory / "configuration.yaml").write_text("homeassistant:\n  packages:\n    device: !include device.yaml\n", encoding="utf-8")
    command = [str(hass), "--script", "check_config", "-c", str(directory), *(a for domain in info for a in ("--info", domain))]
    result = subprocess.run(command, capture_output=True, text=True, timeout=300, check=False)
    out = re.sub(r"\x1b\[[0-9;]*m", "", result.stdout + result.stderr)
    assert result.returncode == 0, out[-4000:]
    assert "Incorrect config" not in out and "Failed config" not in out, out[-4000:]
    assert "components.modbus" not in out, out[-4000:]  # the integration's validators warn, e.g. "... is duplicate, not loaded!"
    assert "ERROR" not in out and "WARNING" not in out, out[-4000:]
    return out
