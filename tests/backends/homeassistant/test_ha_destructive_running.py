"""A destructive command's script, run by a running Home Assistant (the hass tool env's 2024.3, offline) against
`regmap simulate maps/idm_rs.yaml` over Modbus TCP: called without `confirm`, or with a word that is not the
command's name, it sends nothing; called with the command's name it sends the command once. HA's own config
check passing is not enough: a script whose field HA cannot validate is disabled with one ERROR line and exit 0
(a `selector: {text: {}}` was), so the calls here must reach the simulator."""

from __future__ import annotations

import re
import time
from pathlib import Path
from typing import Any

import pytest
import yaml

from regmap.backends.homeassistant import render_device
from regmap.frontend import load_map

from conftest import ROOT, SimulatorFactory
from support.hass_running import hub_on_tcp, running_hass
from support.homeauto_yaml import load

MAP = ROOT / "maps" / "idm_rs.yaml"
STARTUP_S = 300
COMMAND = "reset_history_alarms"
SCRIPT = f"script.idm_rs_{COMMAND}"
CALLS = (None, "yes", COMMAND)  # no confirm, a wrong one, the command's name: only the last one sends
_WRITE = re.compile(r"> MBAP transaction \d+, unit (?P<unit>\d+), PDU (?P<pdu>(?:06|10)(?: [0-9a-fA-F]{2})+)$", re.MULTILINE)
_DONE = "regmap test: every call made"


def _writes(log: Path) -> list[bytes]:
    text = log.read_text(encoding="utf-8") if log.exists() else ""
    return [bytes.fromhex(m["pdu"]) for m in _WRITE.finditer(text)]


def _package_on_tcp(port: int) -> dict[str, Any]:
    """The generated package (the command and one sensor selected), its hub moved to the simulator's TCP port."""
    (text,) = render_device(load_map(MAP), (COMMAND, "peak_current")).values()
    package = load(text)
    hub_on_tcp(package, port)
    assert isinstance(package, dict) and SCRIPT.removeprefix("script.") in package["script"]
    return package


@pytest.mark.timeout(STARTUP_S + 180)
def test_a_destructive_script_sends_only_when_confirmed_by_name(simulator: SimulatorFactory, tmp_path: Path) -> None:
    sim_log = tmp_path / "simulator.log"
    sim = simulator(MAP, "--log", str(sim_log))
    assert sim.port is not None
    config = tmp_path / "config"
    config.mkdir()
    package = _package_on_tcp(sim.port)
    (config / "drive.yaml").write_text(yaml.safe_dump(package, sort_keys=False, allow_unicode=True), encoding="utf-8")
    (sensor,) = package["modbus"][0]["sensors"]
    entity = "sensor." + re.sub(r"[^a-z0-9]+", "_", sensor["name"].lower()).strip("_")  # the id HA gives it
    calls: list[dict[str, Any]] = [{"service": SCRIPT, "data": {} if c is None else {"confirm": c}} for c in CALLS]
    automation = {
        "id": "regmap_destructive_calls",
        "alias": "regmap test: call the destructive script",
        "trigger": [{"platform": "homeassistant", "event": "start"}],
        "action": [
            {"wait_template": f"{{{{ has_value('{entity}') }}}}", "timeout": STARTUP_S, "continue_on_timeout": False},
            *calls,
            {"service": "system_log.write", "data": {"message": _DONE, "level": "warning"}},
        ],
    }
    basics = {"name": "regmap destructive test", "latitude": 0, "longitude": 0, "elevation": 0, "unit_system": "metric", "time_zone": "UTC"}
    rest = {"automation": [automation], "logger": {"default": "info"}, "system_log": {}}
    head = yaml.safe_dump({"homeassistant": basics}, sort_keys=False) + "  packages:\n    drive: !include drive.yaml\n"
    (config / "configuration.yaml").write_text(head + yaml.safe_dump(rest, sort_keys=False), encoding="utf-8")
    home_log = config / "home-assistant.log"
    with running_hass(config, tmp_path / "hass.log") as process:
        started = time.monotonic()
        while time.monotonic() - started < STARTUP_S and process.poll() is None:
            text = home_log.read_text(errors="replace") if home_log.exists() else ""
            if _DONE in text or "could not be validated" in text:
                break
            time.sleep(1)
        time.sleep(2)  # a write after the last call would be in the simulator's log by now
        text = home_log.read_text(errors="replace") if home_log.exists() else ""
        assert _DONE in text, text[-4000:]
        assert "could not be validated" not in text, text[-4000:]
    command = next(c for c in load_map(MAP).commands if c.name == COMMAND)  # the map's register and value, once
    assert _writes(sim_log) == [bytes([0x06]) + command.register.address.to_bytes(2, "big") + command.raw_value().to_bytes(2, "big")]
