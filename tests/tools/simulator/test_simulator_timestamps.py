"""The float meter's timestamps served by `regmap simulate`: the clock starts at its default (the map gives it
as ISO text; the simulator holds the seconds), a write of a time is stored and read back as that time, a
time of the other kind is refused before anything is sent, and a state file's seconds read as UTC times."""

from __future__ import annotations

import json
from datetime import UTC, datetime, timedelta, timezone
from pathlib import Path

import pytest

from conftest import ROOT, SimulatorFactory
from support.fixture_clients import FLAVOURS, flavour, read, write

FLOAT_METER = ROOT / "tests" / "maps" / "fixtures" / "float_meter.yaml"
METER = "fixture_float_meter"


@pytest.mark.parametrize("name", FLAVOURS)
def test_the_clock_serves_its_default_and_takes_a_time(name: str, simulator: SimulatorFactory) -> None:
    sim = simulator(FLOAT_METER)
    assert sim.port is not None
    f = flavour(name, METER)
    client, recorder = f.client(sim.port)
    with client:
        assert client.read_raw(0x0108, 2) == [0x6592, 0x0080]  # default "2024-01-01T00:00:00": 1704067200 s
        assert read(f, client, "clock") == datetime(2024, 1, 1)  # naive: the meter's own clock has no zone
        assert read(f, client, "last_reset") is None  # 0 until the first reset: its 'not available' marker
        sent = len(recorder.sent)
        with pytest.raises(ValueError, match="has a zone"):
            write(f, client, "clock", datetime(2024, 6, 1, tzinfo=UTC))
        with pytest.raises(ValueError, match="outside"):
            write(f, client, "clock", datetime(2106, 2, 7, 6, 28, 16))
        assert len(recorder.sent) == sent  # refused before anything went out
        write(f, client, "clock", datetime(2106, 2, 7, 6, 28, 15))  # the last second 32 bits hold
        assert client.read_raw(0x0108, 2) == [0xFFFF, 0xFFFF]
        write(f, client, "clock", datetime(1970, 1, 1))
        assert client.read_raw(0x0108, 2) == [0x0000, 0x0000] and read(f, client, "clock") == datetime(1970, 1, 1)


@pytest.mark.parametrize("name", FLAVOURS)
def test_a_state_files_seconds_read_as_the_utc_time(name: str, simulator: SimulatorFactory, tmp_path: Path) -> None:
    state = tmp_path / "meter.json"
    state.write_text(json.dumps({"device": METER, "map_version": "0.1.0", "registers": {"last_reset": 1709294400}}), encoding="utf-8")
    sim = simulator(FLOAT_METER, "--state", str(state))
    assert sim.port is not None
    f = flavour(name, METER)
    client, _ = f.client(sim.port)
    with client:
        assert client.read_raw(0x000C, 2, space="input") == [0xC340, 0x65E1]  # low word first
        got = read(f, client, "last_reset")
        assert got == datetime(2024, 3, 1, 12, 0, tzinfo=UTC) and got.utcoffset() == timedelta(0)
        assert got == datetime(2024, 3, 1, 13, 0, tzinfo=timezone(timedelta(hours=1)))  # one instant, in any zone
