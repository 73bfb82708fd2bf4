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


@pytest.mark.parametrize("name", FLAVOURS)
def test_a_setting_coded_as_a_float_reads_and_writes_only_members(name: str, simulator: SimulatorFactory, tmp_path: Path) -> None:
    sim = simulator(FLOAT_METER)
    assert sim.port is not None
    f = flavour(name, METER)
    client, recorder = f.client(sim.port)
    with client:
        assert read(f, client, "baud_code").name == "B9600"  # the default 2.0 is member b9600
        write(f, client, "baud_code", "b19200")
        assert recorder.pdus()[-1] == bytes.fromhex("10 0100 0002 04 40400000")  # code 3 as the f32 3.0
        member = read(f, client, "baud_code")
        assert member.name == "B19200" and int(member) == 3
        sent = len(recorder.sent)
        for refused in (2.5, 7, "b115200", float("nan")):
            with pytest.raises(ValueError):
                write(f, client, "baud_code", refused)
        assert len(recorder.sent) == sent  # nothing went out
        # The device refuses a float no member is (0x03); a value the map does not list reads as it is.
        with pytest.raises(f.errors.DeviceException) as refused_by_device:
            client.write_raw(0x0100, [0x4020, 0x0000])  # 2.5
        assert refused_by_device.value.code == 0x03


def test_a_float_code_no_member_has_reads_as_its_number(simulator: SimulatorFactory, tmp_path: Path) -> None:
    f = flavour("generated", METER)
    assert f.module is not None
    for raw, expected in ((7.0, 7), (2.5, 2.5)):
        sim = simulator(FLOAT_METER, "--state", _state(tmp_path, {"baud_code": raw}))
        assert sim.port is not None
        client, _ = f.client(sim.port)
        with client:
            got = read(f, client, "baud_code")
        assert got == expected and type(got) is (float if raw == 2.5 else f.module.Unlisted), got
        sim.stop()


@pytest.mark.parametrize("name", FLAVOURS)
def test_a_variant_knows_which_registers_it_has(name: str, simulator: SimulatorFactory) -> None:
    f = flavour(name, METER)
    sim = simulator(FLOAT_METER, "--variant", "single_phase")
    assert sim.port is not None
    client, recorder = f.client(sim.port, variant="single_phase")
    with client:
        values = client.read_all()
        assert "voltage_l2" not in values and "voltage_l1" in values  # read_all() leaves out what the variant lacks
        sent = len(recorder.sent)
        with pytest.raises(f.errors.AccessError, match="three_phase"):
            read(f, client, "voltage_l2")
        assert len(recorder.sent) == sent  # refused before anything went out
        with pytest.raises(f.errors.DeviceException) as absent:  # the simulated single-phase model lacks it: 0x02
            client.read_raw(0x000A, 2, space="input")
        assert absent.value.code == 0x02
    three = simulator(FLOAT_METER, "--variant", "three_phase")
    assert three.port is not None
    client, _ = f.client(three.port, variant="three_phase")
    with client:
        assert client.read_all()["voltage_l2"] == 0.0
    with pytest.raises(ValueError, match="no variant 'two_phase'"):
        f.client(three.port, variant="two_phase")
