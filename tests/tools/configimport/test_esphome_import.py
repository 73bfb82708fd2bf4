"""`regmap import` of an ESPHome modbus_controller config: every entity kind, value type and word order read back,
what a map cannot hold kept as notes and reported, the YAML's tags read as data, errors at file:line:col."""

from __future__ import annotations

import subprocess
import sys
from fractions import Fraction
from pathlib import Path

import pytest

from regmap.diagnostics import ExitCode
from regmap.frontend import load_map
from regmap.model import DataType, Device, Register
from regmap.tools.configimport.drafts import read
from regmap.tools.configimport.esphome import VALUE_TYPE, skip_poll_class
from regmap.tools.configimport.reader import ConfigError, Tagged, read_config

CONFIG = """\
substitutions:
  slave: "7"
  prefix: pump
esphome:
  name: ${prefix}-node
wifi:
  ssid: !secret wifi_ssid
  password: !secret wifi_password
packages:
  extra: !include /nonexistent/never-opened.yaml
uart:
  id: bus
  tx_pin: GPIO17
  rx_pin: GPIO16
  baud_rate: 19200
  parity: EVEN
  stop_bits: 1
modbus:
  uart_id: bus
modbus_controller:
  - id: pump
    address: ${slave}
    update_interval: 10s
sensor:
  - platform: modbus_controller
    modbus_controller_id: pump
    id: ${prefix}_speed
    name: Speed
    register_type: read
    address: 0x0010
    value_type: S_WORD
    unit_of_measurement: rpm
    filters:
      - multiply: 0.1
  - platform: modbus_controller
    id: ${prefix}_energy
    name: Energy
    register_type: read
    address: 0x0012
    value_type: U_DWORD_R
    unit_of_measurement: kWh
    skip_updates: 5
    filters:
      - multiply: 0.01
      - offset: 2
  - platform: modbus_controller
    id: power
    name: Power
    register_type: read
    address: 0x0014
    value_type: FP32_R
    force_new_range: true
    filters:
      - multiply: 1000
      - sliding_window_moving_average:
          window_size: 5
  - platform: modbus_controller
    id: voltage
    name: Voltage
    register_type: read
    address: 0x0016
    value_type: FP32
    lambda: !lambda |-
      return x * 2;
  - platform: modbus_controller
    id: hours
    name: Run hours
    register_type: holding
    address: 0x0020
    value_type: U_QWORD_R
    skip_updates: 65535
  - platform: modbus_controller
    id: mode_bits
    name: Mode bits
    register_type: holding
    address: 0x0030
    value_type: U_WORD
    bitmask: 0x0F00
  - platform: wifi_signal
    name: WiFi
binary_sensor:
  - platform: modbus_controller
    id: ready
    name: "Status: Ready"
    register_type: holding
    address: 0x0031
    bitmask: 0x0001
  - platform: modbus_controller
    id: fault
    name: "Status: Fault"
    register_type: holding
    address: 0x0031
    bitmask: 0x0004
  - platform: modbus_controller
    id: door
    name: Door contact
    register_type: discrete_input
    address: 3
switch:
  - platform: modbus_controller
    id: relay
    name: Relay
    register_type: coil
    address: 5
  - platform: modbus_controller
    id: run
    name: "Control: Run"
    register_type: holding
    address: 0x0040
    bitmask: 0x0002
number:
  - platform: modbus_controller
    id: setpoint
    name: Setpoint
    address: 0x0050
    value_type: S_DWORD
    min_value: -100
    max_value: 100
    step: 0.5
    multiply: 10
select:
  - platform: modbus_controller
    id: drive_mode
    name: Drive mode
    address: 0x0060
    value_type: U_WORD
    optionsmap:
      "Off": 0
      Heat: 1
      Cool: 2
text_sensor:
  - platform: modbus_controller
    id: serial
    name: Serial number
    register_type: holding
    address: 0x0070
    register_count: 5
    raw_encode: ANSI
  - platform: modbus_controller
    id: state
    name: State
    register_type: holding
    address: 0x0080
    response_size: 2
    raw_encode: HEXBYTES
    filters:
      - map:
          - 0000 -> Idle
          - 0001 -> Running
"""


def _regmap(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([str(Path(sys.executable).with_name("regmap")), *args], capture_output=True, text=True, check=False)


def _import(tmp_path: Path, text: str, name: str = "pump") -> tuple[subprocess.CompletedProcess[str], Path]:
    config = tmp_path / "node.yaml"
    config.write_text(text, encoding="utf-8")
    out = tmp_path / f"{name}.yaml"
    return _regmap("import", str(config), "--into", str(out)), out


@pytest.fixture(scope="module")
def imported(tmp_path_factory: pytest.TempPathFactory) -> tuple[subprocess.CompletedProcess[str], Device]:
    run, out = _import(tmp_path_factory.mktemp("esphome"), CONFIG)
    assert run.returncode == ExitCode.OK, run.stderr + run.stdout
    return run, load_map(out)


def _reg(device: Device, address: int, space: str) -> Register:
    return next(r for r in device.registers if (r.address, r.space) == (address, space))


def test_types_word_orders_spaces_and_scales_read_as_esphome_reads_them(imported: tuple[subprocess.CompletedProcess[str], Device]) -> None:
    _, device = imported
    seen: dict[tuple[str, int], tuple[object, ...]] = {
        (r.space, r.address): (r.type.value, r.word_order.value if r.wide else None, r.scale, r.offset, r.access.value)
        for r in device.registers
    }
    assert seen[("input", 0x10)] == ("s16", None, Fraction(1, 10), 0, "r")
    assert seen[("input", 0x12)] == ("u32", "low_first", Fraction(1, 100), 2, "r")
    assert seen[("input", 0x14)][:3] == ("f32", "low_first", 1000)  # the multiply before the moving average is the scale
    assert seen[("input", 0x16)] == ("f32", "high_first", 1, 0, "r")
    assert seen[("holding", 0x20)][:2] == ("u64", "low_first")
    assert seen[("holding", 0x50)] == ("s32", "high_first", Fraction(1, 10), 0, "rw")
    assert seen[("coil", 5)] == ("bool", None, 1, 0, "rw")
    assert seen[("discrete_input", 3)] == ("bool", None, 1, 0, "r")
    assert _reg(device, 0x50, "holding").raw_min == -1000 and _reg(device, 0x50, "holding").raw_max == 1000
    assert device.transport.baud == 19200 and device.transport.parity == "even"


def test_every_value_type_is_the_inverse_of_the_back_end() -> None:
    from regmap.backends.esphome.package import VALUE_TYPE as EMITTED

    for (data_type, order), value_type in EMITTED.items():
        kind, read_order = VALUE_TYPE[value_type]
        # ESPHome has no time value type: a timestamp is the u32 of its seconds on the wire, and comes back as one
        assert kind == ("u32" if data_type is DataType.TIMESTAMP else data_type.value)
        assert read_order == order.value or data_type.words == 1


def test_bitmasks_become_fields_and_binary_sensors_of_one_register_merge(imported: tuple[subprocess.CompletedProcess[str], Device]) -> None:
    _, device = imported
    status = _reg(device, 0x31, "holding")
    assert [(f.title, f.lsb, f.width) for f in status.bitfields] == [("Ready", 0, 1), ("Fault", 2, 1)]
    assert status.title == "Status"
    assert [(f.lsb, f.width) for f in _reg(device, 0x30, "holding").bitfields] == [(8, 4)]
    run_bit = _reg(device, 0x40, "holding")
    assert run_bit.access.writable and [(f.title, f.lsb) for f in run_bit.bitfields] == [("Run", 1)]


def test_selects_and_hexbytes_maps_become_enums(imported: tuple[subprocess.CompletedProcess[str], Device]) -> None:
    _, device = imported
    mode = _reg(device, 0x60, "holding")
    assert mode.enum is not None and [(m.value, m.title, m.writable) for m in mode.enum.members] == [
        (0, "Off", True),
        (1, "Heat", True),
        (2, "Cool", True),
    ]
    state = _reg(device, 0x80, "holding")
    assert state.enum is not None and [(m.value, m.title, m.writable) for m in state.enum.members] == [
        (0, "Idle", False),
        (1, "Running", False),
    ]
    text = _reg(device, 0x70, "holding")
    assert (text.type.value, text.words) == ("string", 5)


def test_skip_updates_give_poll_classes() -> None:
    assert skip_poll_class(0, 10, False) == "normal"
    assert skip_poll_class(5, 10, False) == "slow"
    assert skip_poll_class(29, 10, True) == "normal"  # a setting read seldom is still a normal register
    assert skip_poll_class(0, 5, False) == "fast"
    assert skip_poll_class(65535, 10, False) == "static"


def test_skip_updates_in_the_draft(imported: tuple[subprocess.CompletedProcess[str], Device]) -> None:
    _, device = imported
    assert _reg(device, 0x12, "input").poll.value == "slow"
    assert _reg(device, 0x20, "holding").poll.value == "static"
    assert _reg(device, 0x10, "input").poll.value == "normal"


def test_lambdas_filters_and_range_breaks_are_notes_and_reported(imported: tuple[subprocess.CompletedProcess[str], Device]) -> None:
    run, device = imported
    voltage = _reg(device, 0x16, "input")
    assert voltage.notes is not None and "return x * 2;" in voltage.notes
    power = _reg(device, 0x14, "input")
    assert power.notes is not None and "sliding_window_moving_average" in power.notes and "force_new_range" in power.notes
    assert power.scale == 1000
    for said in (
        "voltage: lambda kept as a note",
        "power: force_new_range kept as a note",
        "filters kept as a note: {sliding_window_moving_average",
    ):
        assert said in run.stdout
    assert "packages are not followed" in run.stdout


def test_tags_are_read_as_data_and_nothing_they_name_is_opened() -> None:
    config = read_config(CONFIG, "node.yaml")
    assert config.data["wifi"]["ssid"] == Tagged("!secret", "wifi_ssid")
    assert config.data["packages"]["extra"] == Tagged("!include", "/nonexistent/never-opened.yaml")
    lam = config.data["sensor"][3]["lambda"]
    assert isinstance(lam, Tagged) and lam.tag == "!lambda"


def test_substitutions_are_resolved(imported: tuple[subprocess.CompletedProcess[str], Device]) -> None:
    _, device = imported
    assert device.transport.slave_min <= 7 <= device.transport.slave_max
    names = {r.name for r in device.registers}
    assert {"speed", "energy"} <= names  # ${prefix}_speed: the substitution that names the device is not part of the register's name


BAD = [
    ("value_type: U_WORD\n", "value_type: U_WROD\n", "value_type 'U_WROD': expected one of U_WORD"),
    ("register_type: read\n    address: 0x0010", "register_type: reed\n    address: 0x0010", "register_type 'reed'"),
    ("    address: 0x0060\n", "    address: sixty\n", "address 'sixty'"),
    ("    multiply: 10\n", "    multiply: 0\n", "multiply 0: expected a non-zero number"),
]


@pytest.mark.parametrize(("old", "new", "message"), BAD, ids=[b[2].split(":")[0] for b in BAD])
def test_errors_name_file_line_and_column_without_a_traceback(tmp_path: Path, old: str, new: str, message: str) -> None:
    text = CONFIG.replace(old, new, 1)
    assert text != CONFIG
    run, out = _import(tmp_path, text)
    assert run.returncode == ExitCode.INVALID_MAP
    assert "Traceback" not in run.stderr and not out.exists()
    line = next(i for i, (a, b) in enumerate(zip(CONFIG.splitlines(), text.splitlines(), strict=False), 1) if a != b)
    assert f"node.yaml:{line}:" in run.stderr and message in run.stderr, run.stderr


def test_a_yaml_syntax_error_is_located(tmp_path: Path) -> None:
    run, _ = _import(tmp_path, CONFIG.replace("  - id: pump\n", "  - id: pump\n   bad: [\n", 1))
    assert run.returncode == ExitCode.INVALID_MAP and "Traceback" not in run.stderr
    assert "node.yaml:22:" in run.stderr or "node.yaml:23:" in run.stderr, run.stderr


def test_a_config_without_modbus_is_refused(tmp_path: Path) -> None:
    with pytest.raises(ConfigError) as err:
        config = tmp_path / "x.yaml"
        config.write_text("esphome:\n  name: x\nsensor: []\n", encoding="utf-8")
        read(config, None)
    assert "neither an ESPHome config" in str(err.value)


def test_an_entity_whose_reading_contradicts_another_at_its_address_is_left_out_and_said(tmp_path: Path) -> None:
    clash = "  - platform: modbus_controller\n    id: clash\n    name: Clash\n    register_type: read\n    address: 0x0010\n    value_type: U_DWORD\n"
    text = CONFIG.replace("sensor:\n", "sensor:\n" + clash, 1)
    config = tmp_path / "n.yaml"
    config.write_text(text, encoding="utf-8")
    _, imported = read(config, None)
    assert any("not imported" in line and "clash" in line for line in imported.report), imported.report


def test_a_byte_offset_into_the_read_moves_the_address(tmp_path: Path) -> None:
    """ESPHome's `offset` counts bytes from `address` (bits for coils); a register is two bytes, an odd offset no register."""
    text = CONFIG.replace("    address: 0x0016\n    value_type: FP32\n", "    address: 0x0010\n    offset: 12\n    value_type: FP32\n", 1)
    text = text.replace("    register_type: coil\n    address: 5\n", "    register_type: coil\n    address: 0\n    offset: 5\n", 1)
    config = tmp_path / "node.yaml"
    config.write_text(text, encoding="utf-8")
    _, imported = read(config, None)
    (device,) = imported.devices
    assert any(r.address == 0x16 and r.type == "f32" and r.space == "input" for r in device.registers)
    assert any(r.address == 5 and r.space == "coil" for r in device.registers)
    run, _ = _import(tmp_path, text.replace("offset: 12", "offset: 3"))
    assert run.returncode == ExitCode.INVALID_MAP and "offset 3: a byte offset" in run.stderr
