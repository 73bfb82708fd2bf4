"""The map features of issue #19 as the front end builds them: spaces, wide/float/text/bit types,
byte order, offsets, firmware gates and poll classes, read from the fixture maps (tests/maps/fixtures,
test fixtures, not real devices) and from small maps written here.

The error texts of whole invalid maps are golden files (tests/frontend/test_invalid_maps.py); these tests pin the
model the valid maps give and the few rules that need a map of their own (inheritance, migration)."""

from __future__ import annotations

from fractions import Fraction

import pytest

from regmap.diagnostics import MapError
from regmap.frontend import load_map, load_map_text
from regmap.model import Access, ByteOrder, DataType, Device, FirmwareGate, PollClass, WordOrder
from regmap.runtime_bridge import read_plan, runtime_device

from conftest import ROOT

FIXTURES = ROOT / "tests" / "maps" / "fixtures"


@pytest.fixture(scope="module")
def meter() -> Device:
    return load_map(FIXTURES / "power_meter.yaml")


@pytest.fixture(scope="module")
def remote_io() -> Device:
    return load_map(FIXTURES / "remote_io.yaml")


@pytest.fixture(scope="module")
def swapped() -> Device:
    return load_map(FIXTURES / "swapped_gated.yaml")


def test_group_keys_are_inherited_and_registers_override_them(meter: Device) -> None:
    voltage, current = meter.register("voltage_l1"), meter.register("current_l1")
    assert (voltage.space, voltage.type, voltage.word_order, voltage.access) == ("input", DataType.F32, WordOrder.HIGH_FIRST, Access.READ)
    assert current.word_order is WordOrder.LOW_FIRST and current.word_order_fixed
    assert meter.register("model_name").poll is PollClass.STATIC  # from the group
    assert voltage.poll is PollClass.FAST and meter.register("power_factor").poll is PollClass.NORMAL
    assert meter.register("thd_voltage_l1").firmware == FirmwareGate(first="2.00")
    assert meter.register("demand_period").firmware == FirmwareGate(first="1.20")
    assert meter.register("ct_ratio").firmware is None


def test_types_words_offsets_and_text(meter: Device) -> None:
    temperature = meter.register("temperature")
    assert (temperature.scale, temperature.offset) == (Fraction(1, 10), Fraction(-40))
    assert [meter.register(n).words for n in ("active_energy", "energy_total", "model_name", "serial_number")] == [4, 4, 8, 6]
    assert meter.register("serial_number").padding == "space"
    label = meter.register("meter_label")
    assert (label.encoding, label.default, label.access) == ("utf-8", "", Access.READ_WRITE)
    period = meter.register("demand_period")
    assert (period.min, period.max, period.default) == (1.0, 3600.0, 900.0)


def test_the_firmware_register_and_its_format(meter: Device, swapped: Device) -> None:
    named = meter.info.firmware_register
    assert named is not None and (named.register.name, named.format, named.decimals) == ("firmware_version", "decimal", 2)
    spec = runtime_device(meter)
    assert spec.firmware_register == "firmware_version"
    assert spec.firmware_version(125) == (1, 25) and spec.firmware_version(200) == (2, 0)
    assert runtime_device(swapped).firmware_version(0x0203) == (2, 3)


@pytest.mark.parametrize(
    ("gate", "admitted", "refused"),
    [
        (FirmwareGate(first="2.0"), ["2.0", "2.1", "10.0"], ["1.9", "1.99"]),
        (FirmwareGate(until="2.0"), ["1.9", "0.1"], ["2.0", "2.0.1", "3"]),
        (FirmwareGate(first="2.9", until="2.10"), ["2.9", "2.9.5"], ["2.10", "2.8", "2.11"]),
    ],
)
def test_firmware_gates_compare_versions_as_numbers(gate: FirmwareGate, admitted: list[str], refused: list[str]) -> None:
    def version(text: str) -> tuple[int, ...]:
        return tuple(int(p) for p in text.split("."))

    assert all(gate.admits(version(v)) for v in admitted)
    assert not any(gate.admits(version(v)) for v in refused)


def test_bit_spaces_hold_bools_and_array_numbering_follows_the_map(remote_io: Device) -> None:
    relay = remote_io.register("relay_20_on")
    assert (relay.space, relay.type, relay.address, relay.words, relay.byte_order) == ("coil", DataType.BOOL, 0x13, 1, ByteOrder.HIGH_FIRST)
    assert remote_io.register("relay_38_on").address == 0x25
    assert remote_io.register("input_197_active").access is Access.READ  # discrete inputs are read-only by default
    assert remote_io.register("alarm_output").default == 0  # `false` is the raw bit 0


def test_byte_order_follows_the_device_unless_the_register_says(swapped: Device) -> None:
    assert swapped.transport.byte_order is ByteOrder.LOW_FIRST
    assert swapped.register("position").byte_order is ByteOrder.LOW_FIRST
    assert swapped.register("gain").byte_order is ByteOrder.HIGH_FIRST
    assert swapped.register("label").byte_order is ByteOrder.LOW_FIRST


def test_the_plan_never_mixes_spaces_and_filters_by_poll_class(remote_io: Device, meter: Device) -> None:
    blocks = read_plan(remote_io)
    assert {b.space for b in blocks} == {"holding", "input", "coil", "discrete_input"}
    assert all(len({r.space for r in b.registers}) == 1 for b in blocks)
    coils = next(b for b in blocks if b.space == "coil" and b.address == 0x13)
    assert coils.count == 19  # one 0x01 request for the 19 relays, as the spec's §6.1 example reads them
    static = read_plan(meter, poll=PollClass.STATIC)
    assert {r.name for b in static for r in b.registers} == {"model_name", "serial_number", "firmware_version"}
    assert [(b.address, b.count) for b in static] == [(0x0100, 14), (0x0110, 1)]  # the map documents no 0x010E-0x010F


MINIMAL = """\
format: regmap/1
device: {{id: m, vendor: v, model: m, manual: {{title: t, file: f}}, map_version: 0.1.0{device}}}
transport:
  serial: {{baud: 9600, parity: none, data_bits: 8, stop_bits: 1}}
  slave_ids: {{min: 1, max: 247}}
  function_codes: [{codes}]
  max_read_registers: 125
  max_write_registers: 123
  word_order: high_first
groups:
  - id: g
    title: G
    source: "1"
    registers:
{registers}
"""


def minimal(registers: str, codes: str = "0x03, 0x06, 0x10", device: str = "") -> str:
    return MINIMAL.format(registers=registers, codes=codes, device=device)


def messages(text: str) -> list[str]:
    with pytest.raises(MapError) as info:
        load_map_text(text, "m.yaml")
    return [f"{d.line}: {d.message}" for d in info.value.diagnostics]


def test_a_function_code_the_map_needs_but_the_device_does_not_list() -> None:
    text = minimal("      - {name: relay, address: 0, space: coil, title: Relay}")
    assert messages(text) == [
        "6: relay is in coils, which are read with function 0x01; function_codes does not list it",
        "6: relay is writable (access rw) in coils, which are written with 0x05 or 0x0F; function_codes lists neither",
    ]
    load_map_text(minimal("      - {name: relay, address: 0, space: coil, title: Relay}", codes="0x01, 0x0F"), "m.yaml")


def test_an_array_member_with_the_old_offset_key_is_told_to_rename_it() -> None:
    array = """\
      - array: a
        title: A
        count: 2
        stride: 1
        base: 0
        source: "1"
        members: [{name: x, offset: 0, title: X}]"""
    [message] = messages(minimal(array))
    assert message.startswith("21: array a: member x needs `word_offset`")
    assert "rename this member's `offset` to `word_offset`" in message


def test_an_array_members_problem_is_named_for_each_element_and_a_clean_member_expands_in_full() -> None:
    array = """\
      - array: a
        title: A
        count: 3
        stride: 2
        base: 4
        source: "1"
        members: [{name: x, word_offset: 0, title: X, enum: nope}, {name: y, word_offset: 1, title: Y, default: 7}]"""
    assert [m.split(": ", 1)[1] for m in messages(minimal(array))] == [f"a_{i}_x: unknown enum 'nope'" for i in range(3)]
    device = load_map_text(minimal(array.replace(", enum: nope", "")), "m.yaml")
    elements = [(r.name, r.address, r.array.index if r.array else None, r.default) for r in device.registers]
    assert elements == [(f"a_{i}_{m}", 4 + 2 * i + (m == "y"), i, 7 if m == "y" else None) for i in range(3) for m in "xy"]


def test_the_firmware_register_is_checked_against_its_format() -> None:
    reg = "      - {name: fw, address: 0, type: f32, title: Firmware}"
    device = ", firmware_register: {register: fw, format: major_minor}"
    assert messages(minimal(reg, device=device)) == ["2: firmware_register: format major_minor needs an integer register; fw is f32"]
    device = ", firmware_register: {register: nothere, format: decimal}"
    assert messages(minimal(reg, device=device)) == ["2: firmware_register: unknown register 'nothere'"]
