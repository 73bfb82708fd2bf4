"""What a map says about writes: enum members that are only reported, trigger registers, destructive commands."""

from __future__ import annotations

from pathlib import Path

import pytest

from regmap.diagnostics import MapError
from regmap.frontend import load_map, load_map_text
from regmap.model import Access, Device

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def idm() -> Device:
    return load_map(ROOT / "maps" / "idm_rs.yaml")


def test_the_pr_trigger_states_are_read_only_and_its_commands_write_only(idm: Device) -> None:
    members = {m.name: m for m in idm.enum("pr_trigger").members}
    assert not members["done_path_5"].writable and members["done_path_5"].readable
    assert not members["running_path_3"].writable and not members["command_done_waiting"].writable
    assert members["start_path_0"].access is Access.WRITE and not members["start_path_0"].readable
    assert all(members[f"start_path_{n}"].writable for n in range(16))
    assert {m.name for m in members.values() if m.writable} == {
        *(f"start_path_{n}" for n in range(16)),
        "home",
        "set_zero",
        "emergency_stop",
    }


def test_a_member_without_access_goes_both_ways(idm: Device) -> None:
    member = idm.enum(idm.register("control_word").enum.name).members[0]  # type: ignore[union-attr]
    assert member.access is Access.READ_WRITE and member.writable and member.readable


def test_registers_that_commands_write_are_triggers(idm: Device) -> None:
    assert idm.is_trigger(idm.register("pr_trigger")) and idm.is_trigger(idm.register("control_word"))
    assert not idm.is_trigger(idm.register("homing_high_speed"))


def test_destructive_commands_are_marked_and_restore_defaults_implies_it(idm: Device) -> None:
    destructive = {c.name for c in idm.commands if c.destructive}
    assert {"restore_factory_defaults", "init_parameters", "force_enable_on"} <= destructive
    assert not destructive & {"save_all_parameters", "emergency_stop", "start_homing", "jog_left"}


MAP = """\
format: regmap/1
device: {{id: d, vendor: v, model: m, manual: {{title: t, file: f}}, map_version: 0.1.0}}
transport:
  serial: {{baud: 9600, parity: none, data_bits: 8, stop_bits: 1}}
  slave_ids: {{min: 1, max: 247}}
  function_codes: [0x03, 0x06]
  max_read_registers: 125
  max_write_registers: 123
  word_order: high_first
enums:
  trig:
    title: Trigger
    values:
      - {{value: 0, name: idle, title: Idle, access: r}}
      - {{value: 1, name: busy, title: Busy, access: r}}
      - {{value: 16, name: go, title: Go, access: w}}
groups:
  - id: g
    title: G
    source: "1"
    registers:
      - {{name: trig, address: 0x10, type: u16, access: rw, title: Trigger, enum: trig{trigger}}}
commands:
  - {{name: kick, title: Kick, register: trig, value: {value}, source: "1"{argument}}}
"""


def test_a_command_that_writes_a_reported_state_is_refused() -> None:
    with pytest.raises(MapError) as info:
        load_map_text(MAP.format(value="busy", argument="", trigger=""), "m.yaml")
    assert any("busy" in d.message and "only reports" in d.message for d in info.value.diagnostics)


def test_a_command_whose_argument_reaches_a_reported_state_is_refused() -> None:
    with pytest.raises(MapError) as info:
        load_map_text(MAP.format(value=0, argument=", argument: {name: n, min: 0, max: 1}", trigger=""), "m.yaml")
    assert any("idle" in d.message for d in info.value.diagnostics)


def test_a_write_only_command_value_loads_and_a_map_can_mark_a_trigger() -> None:
    device = load_map_text(MAP.format(value="go", argument="", trigger=", trigger: true"), "m.yaml")
    assert device.register("trig").trigger and device.is_trigger(device.register("trig"))
