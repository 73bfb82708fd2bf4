"""A plant file: buses and the devices on them. Every rule refuses at the offending line, through the real CLI."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from regmap.diagnostics import MapError
from regmap.frontend.plant import load_plant
from regmap.frontend.plantfile import is_plant_text

from conftest import ROOT

EXAMPLE = ROOT / "examples" / "plants" / "cell1.yaml"
MAPS = ROOT / "maps"
FLOAT_METER = ROOT / "tests" / "maps" / "fixtures" / "float_meter.yaml"

TCP_PLANT = f"""format: regmap-plant/1
plant: {{id: cell1, title: Assembly cell 1}}
buses:
  - name: line1
    tcp: {{host: 127.0.0.1, port: 1502}}
    devices:
      - {{name: axis_x, map: {MAPS}/idm_rs.yaml, slave: 1}}
      - {{name: axis_y, map: {MAPS}/idm_rs.yaml, slave: 2}}
      - {{name: spindle, map: {MAPS}/c630s.yaml, slave: 3}}
"""


def _write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "plant.yaml"
    path.write_text(text, encoding="utf-8")
    return path


def _problems(tmp_path: Path, text: str) -> list[str]:
    with pytest.raises(MapError) as caught:
        load_plant(_write(tmp_path, text))
    return [str(d) for d in caught.value.diagnostics]


def _validate(path: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "regmap", "validate", str(path)], capture_output=True, text=True, timeout=120)


def test_the_example_plant_validates_through_the_cli() -> None:
    result = _validate(EXAMPLE)
    assert result.returncode == 0, result.stderr
    assert "ok: plant cell1, 1 bus(es), 3 device(s), 2 map(s)" in result.stdout
    assert "axis_x@1 (idm_rs), axis_y@2 (idm_rs), spindle@3 (c630s)" in result.stdout


def test_the_tcp_plant_loads_with_two_instances_of_one_map(tmp_path: Path) -> None:
    plant = load_plant(_write(tmp_path, TCP_PLANT))
    bus = plant.bus("line1")
    assert bus.kind == "tcp" and bus.tcp is not None and (bus.tcp.host, bus.tcp.port) == ("127.0.0.1", 1502)
    assert [(d.name, d.slave, d.device.id) for d in plant.devices] == [
        ("axis_x", 1, "idm_rs"),
        ("axis_y", 2, "idm_rs"),
        ("spindle", 3, "c630s"),
    ]
    assert [m.id for m in plant.maps] == ["idm_rs", "c630s"]
    assert plant.device("spindle")[1].slave == 3


def test_two_devices_at_one_slave_id_are_refused_at_the_second(tmp_path: Path) -> None:
    text = TCP_PLANT.replace(
        "name: axis_y, map: " + f"{MAPS}/idm_rs.yaml, slave: 2", "name: axis_y, map: " + f"{MAPS}/idm_rs.yaml, slave: 1"
    )
    path = _write(tmp_path, text)
    result = _validate(path)
    assert result.returncode == 1 and "Traceback" not in result.stderr
    assert f"{path}:8:" in result.stderr and "slave id 1 is used twice on bus 'line1' (also 'axis_x')" in result.stderr


@pytest.mark.parametrize(
    ("change", "line", "message"),
    [
        (("slave: 3", "slave: 0"), 9, "slave id 0 is the broadcast address"),
        (("slave: 3", "slave: 250"), 9, "slave id 250 is outside 1..247, the range the map c630s allows"),
        (("slave: 2", "slave: 40"), 8, "slave id 40 is outside 1..31, the range the map idm_rs allows"),
        (("name: axis_y", "name: axis_x"), 8, "device name 'axis_x' is used twice in the plant"),
        (("name: spindle", "name: struct"), 9, "device name 'struct' is a reserved word of C/C++"),
        (("name: spindle", "name: END_VAR"), 9, "is not a snake_case identifier"),
        (("name: spindle", "name: end_var"), 9, "device name 'end_var' is a reserved word of IEC 61131-3"),
        (("c630s.yaml", "c631s.yaml"), 9, "map '" + f"{MAPS}/c631s.yaml' not found"),
        (("port: 1502}", "port: 1502, baud: 9600}"), 5, "unknown key 'baud'"),
    ],
)
def test_each_rule_refuses_at_its_line(tmp_path: Path, change: tuple[str, str], line: int, message: str) -> None:
    old, new = change
    assert old in TCP_PLANT
    problems = _problems(tmp_path, TCP_PLANT.replace(old, new, 1))
    assert any(p.startswith(f"{tmp_path / 'plant.yaml'}:{line}:") and message in p for p in problems), problems


def test_the_serial_line_must_suit_every_device_on_it(tmp_path: Path) -> None:
    text = EXAMPLE.read_text(encoding="utf-8").replace("../../maps", str(MAPS))
    slow = _problems(tmp_path, text.replace("baud: 38400", "baud: 57600"))
    assert any(":6:" in p and "baud 57600: device 'axis_x' (idm_rs) can be set to 9600, 19200, 38400, 115200 only" in p for p in slow), slow
    assert not any("spindle" in p for p in slow)  # the C630S does 57600
    with_id243 = text.replace("map: ../../maps/c630s.yaml", "map: ../../maps/id243pro.yaml").replace(
        f"{MAPS}/c630s.yaml", f"{MAPS}/id243pro.yaml"
    )
    odd = _problems(tmp_path, with_id243)
    assert any("parity even: device 'spindle' (id243pro) can be set to none only" in p for p in odd), odd


def test_a_broken_map_is_reported_at_its_own_lines(tmp_path: Path) -> None:
    broken = tmp_path / "broken.yaml"
    broken.write_text(
        (MAPS / "id243pro.yaml").read_text(encoding="utf-8").replace("map_version: 1.0.0", "map_version: [1]", 1), encoding="utf-8"
    )
    problems = _problems(tmp_path, TCP_PLANT.replace(f"{MAPS}/c630s.yaml", "broken.yaml"))
    assert any(":9:" in p and "map 'broken.yaml' is invalid" in p for p in problems)
    assert any(p.startswith(f"{broken}:") and "map_version" in p for p in problems), problems


METERS = f"""format: regmap-plant/1
plant: {{id: meters, title: Two meters}}
buses:
  - name: line1
    tcp: {{host: 127.0.0.1, port: 1502}}
    devices:
      - {{name: m1, map: {FLOAT_METER}, slave: 1, variant: single_phase}}
      - {{name: m3, map: {FLOAT_METER}, slave: 3, variant: three_phase}}
      - {{name: axis_x, map: {MAPS}/idm_rs.yaml, slave: 5}}
"""


def test_each_device_is_the_variant_the_plant_names(tmp_path: Path) -> None:
    path = _write(tmp_path, METERS)
    plant = load_plant(path)
    assert [(d.name, d.variant, d.variants) for d in plant.devices] == [
        ("m1", "single_phase", ("single_phase",)),
        ("m3", "three_phase", ("three_phase",)),
        ("axis_x", None, ()),
    ]
    result = _validate(path)
    assert result.returncode == 0, result.stderr
    assert "m1@1 (fixture_float_meter, single_phase), m3@3 (fixture_float_meter, three_phase), axis_x@5 (idm_rs)" in result.stdout


@pytest.mark.parametrize(
    ("change", "line", "message"),
    [
        (
            ("variant: three_phase", "variant: split_phase"),
            8,
            "variant 'split_phase': device 'm3' (fixture_float_meter) declares single_phase, three_phase only",
        ),
        (("slave: 5}", "slave: 5, variant: single_phase}"), 9, "variant 'single_phase': device 'axis_x' (idm_rs) declares no variants"),
    ],
)
def test_a_variant_the_map_does_not_declare_is_refused_at_its_line(
    tmp_path: Path, change: tuple[str, str], line: int, message: str
) -> None:
    old, new = change
    assert old in METERS
    text = METERS.replace(old, new, 1)
    path = _write(tmp_path, text)
    result = _validate(path)
    assert result.returncode == 1 and "Traceback" not in result.stderr
    col = text.splitlines()[line - 1].index("variant: ") + len("variant: ") + 1  # at the value
    assert f"{path}:{line}:{col}: {message}" in result.stderr, result.stderr


def test_a_plant_is_told_from_a_map_by_its_format_line() -> None:
    assert is_plant_text(EXAMPLE.read_text(encoding="utf-8"))
    assert not any(is_plant_text(p.read_text(encoding="utf-8")) for p in MAPS.glob("*.yaml"))


def test_a_plant_comes_alone_on_the_command_line() -> None:
    result = subprocess.run(
        [sys.executable, "-m", "regmap", "validate", str(EXAMPLE), str(MAPS / "c630s.yaml")], capture_output=True, text=True, timeout=120
    )
    assert result.returncode == 2 and "a plant file" in result.stderr and "comes alone" in result.stderr
