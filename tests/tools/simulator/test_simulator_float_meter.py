"""Issue #34's float meter (tests/maps/fixtures/float_meter.yaml) served by `regmap simulate` and read by both
flavours of its Python client: "not available" markers read as None and are never written."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest

from conftest import ROOT, SimulatorFactory
from support.fixture_clients import FLAVOURS, flavour, read, write

FLOAT_METER = ROOT / "tests" / "maps" / "fixtures" / "float_meter.yaml"
METER = "fixture_float_meter"


def _state(tmp_path: Path, registers: dict[str, Any]) -> str:
    """A state file that puts these raw values into the simulated device (input registers included)."""
    path = tmp_path / "meter.json"
    path.write_text(json.dumps({"device": METER, "map_version": "0.1.0", "registers": registers}), encoding="utf-8")
    return str(path)


@pytest.mark.parametrize("name", FLAVOURS)
def test_not_available_markers_read_as_none(name: str, simulator: SimulatorFactory, tmp_path: Path) -> None:
    state = _state(tmp_path, {"temperature": -32768, "humidity": 0xFFFF, "pulse_count": 0xFFFFFFFF, "current_l1": 5.0, "ct_ratio": 0xFFFF})
    sim = simulator(FLOAT_METER, "--state", state)
    assert sim.port is not None
    f = flavour(name, METER)
    client, _ = f.client(sim.port)
    with client:
        values = client.read_all()
        assert values["temperature"] is None and values["humidity"] is None and values["pulse_count"] is None
        assert values["ct_ratio"] is None  # 0xFFFF: not set yet
        assert values["current_l1"] == 5.0 and values["voltage_l1"] == 0.0 and values["voltage_alarm"] == 0.0
        assert read(f, client, "pulse_count") is None


@pytest.mark.parametrize("name", FLAVOURS)
def test_a_marker_is_never_written(name: str, simulator: SimulatorFactory) -> None:
    sim = simulator(FLOAT_METER)
    assert sim.port is not None
    f = flavour(name, METER)
    client, recorder = f.client(sim.port)
    with client:
        for register, marker in (("ct_ratio", 0xFFFF), ("voltage_alarm", -1.0)):
            with pytest.raises(ValueError, match="not available"):
                write(f, client, register, marker)
            with pytest.raises(ValueError, match="None is no value"):
                write(f, client, register, None)
        assert recorder.sent == []  # refused before anything went out
        write(f, client, "ct_ratio", 100)
        assert read(f, client, "ct_ratio") == 100
        # The device refuses the marker too: the simulator answers 0x03 when a raw write sends it.
        with pytest.raises(f.errors.DeviceException) as refused:
            client.write_raw(0x0104, [0xFFFF])
        assert refused.value.code == 0x03
        assert read(f, client, "ct_ratio") == 100
