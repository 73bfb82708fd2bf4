"""`regmap import` of a Home Assistant `modbus:` config: hubs and slaves, every platform, input and data types, the
swaps, scale/offset, count and virtual_count; one map per distinct device; errors at file:line:col."""

from __future__ import annotations

import subprocess
import sys
from fractions import Fraction
from pathlib import Path

import pytest

from regmap.diagnostics import ExitCode
from regmap.frontend import load_map
from regmap.model import Device, Register

COMMUNITY = Path(__file__).parent / "community" / "sdm72d_m_homeassistant.yaml"


def _regmap(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([str(Path(sys.executable).with_name("regmap")), *args], capture_output=True, text=True, check=False)


@pytest.fixture(scope="module")
def plant(tmp_path_factory: pytest.TempPathFactory) -> tuple[subprocess.CompletedProcess[str], dict[str, Device]]:
    out = tmp_path_factory.mktemp("ha") / "plant"
    run = _regmap("import", str(COMMUNITY), "--into", str(out))
    assert run.returncode == ExitCode.OK, run.stderr + run.stdout
    return run, {p.stem: load_map(p) for p in sorted(out.glob("*.yaml"))}


def _at(device: Device, address: int, space: str = "holding") -> Register:
    return next(r for r in device.registers if (r.address, r.space) == (address, space))


def test_one_map_per_distinct_device_and_the_slaves_that_share_one(
    plant: tuple[subprocess.CompletedProcess[str], dict[str, Device]],
) -> None:
    run, maps = plant
    assert sorted(maps) == ["heatpump_slave_3", "meters_slave_1"]
    assert "meters_slave_1.yaml: 3 registers from homeassistant meters slave 1 (slave 1), meters slave 2 (slave 2)" in run.stdout
    meter = maps["meters_slave_1"]
    power = _at(meter, 0x34, "input")
    assert (power.type.value, power.scale, power.unit) == ("f32", Fraction(1, 1000), "kW")
    assert _at(meter, 0x48, "input").poll.value == "slow" and power.poll.value == "normal"


def test_swaps_data_types_scale_offset_and_counts(plant: tuple[subprocess.CompletedProcess[str], dict[str, Device]]) -> None:
    _, maps = plant
    pump = maps["heatpump_slave_3"]
    outdoor = _at(pump, 10, "input")
    reading: tuple[object, ...] = (outdoor.type.value, outdoor.scale, outdoor.offset, outdoor.unit)
    assert reading == ("s16", Fraction(1, 10), -40, "°C")
    assert outdoor.na == (0x7FFF,)  # HA's nan_value "0x7FFF": the device's "not available" marker
    hours = _at(pump, 12)
    assert (hours.type.value, hours.word_order.value, hours.byte_order.value) == ("u32", "low_first", "high_first")
    swapped = _at(pump, 40)
    assert (swapped.type.value, swapped.word_order.value, swapped.byte_order.value) == ("s32", "low_first", "low_first")
    text = _at(pump, 30)
    assert (text.type.value, text.words) == ("string", 4)
    flows = [r for r in pump.registers if r.array is not None]
    assert [r.address for r in flows] == [20, 21, 22, 23] and {r.scale for r in flows} == {Fraction(1, 100)}


def test_switches_fans_lights_climates_and_covers(plant: tuple[subprocess.CompletedProcess[str], dict[str, Device]]) -> None:
    _, maps = plant
    pump = maps["heatpump_slave_3"]
    assert _at(pump, 4, "coil").access.writable and _at(pump, 6, "coil").access.writable
    assert _at(pump, 2, "discrete_input").type.value == "bool"
    boost = _at(pump, 60)
    assert boost.enum is not None and sorted((m.value, m.name) for m in boost.enum.members) == [(0, "off"), (5, "on")]
    alarm = _at(pump, 50)
    assert [(f.lsb, f.width) for f in alarm.bitfields] == [(0, 1)]  # HA reads value & 1
    target = _at(pump, 101)
    assert target.access.writable and (target.raw_min, target.raw_max, target.scale) == (150, 300, Fraction(1, 10))
    mode = _at(pump, 102)
    assert mode.enum is not None and [m.value for m in mode.enum.members] == [0, 1, 2, 3]
    assert _at(pump, 103).enum is not None
    cover = _at(pump, 120)
    assert cover.enum is not None and {m.name: m.writable for m in cover.enum.members} == {
        "closed": True,
        "open": True,
        "opening": False,
        "closing": False,
    }
    status = _at(pump, 121, "input")
    assert status.enum is not None and not any(m.writable for m in status.enum.members)


def test_what_a_map_cannot_hold_is_reported(plant: tuple[subprocess.CompletedProcess[str], dict[str, Device]]) -> None:
    run, _ = plant
    assert "Panel light: Home Assistant does not read it back (no verify)" in run.stdout
    assert "Float16" not in run.stdout  # a half float is an f16 now (below), nothing to report


def test_a_float16_sensor_is_an_f16(plant: tuple[subprocess.CompletedProcess[str], dict[str, Device]]) -> None:
    _, maps = plant
    half = _at(maps["heatpump_slave_3"], 44)
    assert (half.type.value, half.words, half.title) == ("f16", 1, "Float16 sensor")


def test_a_single_device_goes_into_a_file_and_several_refuse_one(tmp_path: Path) -> None:
    run = _regmap("import", str(COMMUNITY), "--into", str(tmp_path / "one.yaml"))
    assert run.returncode == ExitCode.USAGE and "several distinct devices; give a directory" in run.stderr
    single = tmp_path / "ha.yaml"
    single.write_text(
        "modbus:\n  - name: hub\n    type: tcp\n    host: x\n    port: 502\n    sensors:\n      - {name: T, address: 3}\n", encoding="utf-8"
    )
    run = _regmap("import", str(single), "--into", str(tmp_path / "meter.yaml"))
    assert run.returncode == ExitCode.OK, run.stderr
    reg = load_map(tmp_path / "meter.yaml").registers[0]
    assert (reg.address, reg.type.value, reg.space) == (3, "s16", "holding")  # HA's defaults: int16 holding register


BAD = [
    ("data_type: int16\n        scale: 0.1", "data_type: int17\n        scale: 0.1", "data_type 'int17'"),
    ("swap: word\n", "swap: words\n", "swap 'words'"),
    ("        count: 4\n", "        count: 0\n", "a string needs count"),
    ("        slave: 3\n        address: 10\n", "        slave: 3\n        address: -1\n", "address -1"),
]


@pytest.mark.parametrize(("old", "new", "message"), BAD, ids=[b[2] for b in BAD])
def test_errors_name_file_line_and_column_without_a_traceback(tmp_path: Path, old: str, new: str, message: str) -> None:
    text = COMMUNITY.read_text(encoding="utf-8")
    changed = text.replace(old, new, 1)
    assert changed != text
    config = tmp_path / "configuration.yaml"
    config.write_text(changed, encoding="utf-8")
    run = _regmap("import", str(config), "--into", str(tmp_path / "out"))
    assert run.returncode == ExitCode.INVALID_MAP and "Traceback" not in run.stderr
    line = next(i for i, (a, b) in enumerate(zip(text.splitlines(), changed.splitlines(), strict=False), 1) if a != b)
    assert f"configuration.yaml:{line}:" in run.stderr and message in run.stderr, run.stderr
    assert not (tmp_path / "out").exists()
