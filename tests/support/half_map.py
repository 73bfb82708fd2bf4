"""A test-local map of half floats (f16, Home Assistant's `float16`): a made-up room sensor, not a real
device. The back-end and tool tests of f16 generate from it; `write_half_map` puts it in a folder."""

from __future__ import annotations

import struct
from pathlib import Path

HALF_MAP = """\
# TEST MAP - not a real device: a made-up room sensor whose values are IEEE 754 half floats (f16).
format: regmap/1
device:
  id: half_sensor
  vendor: regmap test fixtures
  model: HS-1 (test)
  manual: {title: none (test map), file: none}
  map_version: 0.1.0
transport:
  serial: {baud: 9600, parity: none, data_bits: 8, stop_bits: 1}
  slave_ids: {min: 1, max: 247}
  function_codes: [0x03, 0x04, 0x06, 0x10]
  max_read_registers: 60
  max_write_registers: 60
  word_order: high_first
enums:
  fan:
    title: Fan mode
    values:
      - {value: 0, name: auto, title: Automatic}
      - {value: 1, name: low, title: Low}
      - {value: 2, name: high, title: High}
groups:
  - id: measurements
    title: Measurements
    space: input
    source: "test"
    registers:
      - {name: temperature, address: 0x0000, type: f16, unit: °C, na: [nan], title: Room temperature (NaN while no sensor)}
      - {name: flow, address: 0x0001, type: f16, scale: 0.1, unit: l/min, title: Air flow}
      - {name: humidity, address: 0x0002, type: f16, byte_order: low_first, unit: "%", title: Relative humidity (bytes swapped)}
  - id: settings
    title: Settings
    source: "test"
    registers:
      - {name: setpoint, address: 0x0100, type: f16, unit: °C, min: 5.0, max: 30.0, default: 21.5, title: Temperature setpoint}
      - {name: fan_mode, address: 0x0101, type: f16, enum: fan, default: 0.0, title: Fan mode (a code sent as an f16)}
      - {name: alarm_limit, address: 0x0102, type: f16, unit: °C, na: [-1.0], title: Alarm limit (-1.0 while none is set)}
      - {name: flow_limit, address: 0x0103, type: f16, scale: 0.1, unit: l/min, min: 0.0, max: 5000.0, title: Air flow limit}
"""


def write_half_map(folder: Path) -> Path:
    path = folder / "half_sensor.yaml"
    path.write_text(HALF_MAP, encoding="utf-8")
    return path


def half(bits: int) -> float:
    """What Python's struct 'e' reads from a 16-bit pattern: the reference every target is checked against."""
    value: float = struct.unpack(">e", bits.to_bytes(2, "big"))[0]
    return value


def half_bits(value: float) -> int:
    """The pattern struct 'e' writes for a value (rounded to nearest, ties to even)."""
    bits: int = struct.unpack(">H", struct.pack(">e", value))[0]
    return bits


# Values an encoder must get right: exact, rounded each way, ties to even, the smallest and largest of each
# range, subnormals, signed zeros, and what rounds past the largest finite half (65520 and up: infinity).
EDGE_VALUES = (
    0.0,
    -0.0,
    1.0,
    -1.5,
    0.1,
    21.5,
    1.0 + 2.0**-11,  # halfway above 1.0: ties to even, 1.0
    1.0 + 3 * 2.0**-11,  # halfway: ties to even, up
    1.0 + 2.0**-11 + 2.0**-20,  # just above halfway: up
    2049.0,
    2051.0,
    65504.0,
    65519.0,  # rounds down to 65504
    -65504.0,
    6.103515625e-05,  # the smallest normal
    6.097555160522461e-05,  # the largest subnormal
    5.960464477539063e-08,  # the smallest subnormal
    2.9802322387695312e-08,  # half the smallest subnormal: ties to even, 0
    4.470348358154297e-08,  # 0.75 of the smallest subnormal: up
    1.0e-9,  # underflows to 0
    -3.0e-08,  # just above half the smallest subnormal: -1 ulp
    6.1e-05,  # between the largest subnormal and the smallest normal
    3.4e38,
)


def finite_edge_values() -> list[float]:
    """The edge values a half holds after rounding (65520 and beyond are infinity: refused, not encoded)."""
    return [v for v in EDGE_VALUES if abs(v) < 65520.0]
