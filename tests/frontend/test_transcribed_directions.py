"""What was transcribed from the three manuals about writes: which enum members are only reported,
which registers act when written (triggers), which commands are destructive; and, per map, that
every command writes a value the map lets one write."""

from __future__ import annotations

from pathlib import Path

import pytest

from regmap.frontend import load_map
from regmap.model import Access, Device
from regmap.runtime_bridge import runtime_specs
from regmap_runtime.codec import DestructiveWriteError, check_command, check_raw

from conftest import MAPS, ROOT, SMALL_MAPS


def load(name: str) -> Device:
    return load_map(ROOT / "maps" / f"{name}.yaml")


def triggers(device: Device) -> set[str]:
    return {r.name for r in device.registers if r.trigger}


def destructive(device: Device) -> set[str]:
    return {c.name for c in device.commands if c.destructive}


def directed(device: Device) -> dict[str, dict[str, Access]]:
    """The enums with a member that goes one way only: member name -> access."""
    return {
        e.name: {m.name: m.access for m in e.members} for e in device.enums if any(m.access is not Access.READ_WRITE for m in e.members)
    }


def test_idm_rs_pr_trigger_states_commands_triggers_and_destructive_commands() -> None:
    idm = load("idm_rs")
    members = directed(idm)["pr_trigger"]
    reported = {n for n, a in members.items() if a is Access.READ}
    commands = {n for n, a in members.items() if a is Access.WRITE}
    assert reported == {
        "done",
        "command_done_waiting",
        *(f"done_path_{p}" for p in range(1, 16)),
        *(f"running_path_{p}" for p in range(16)),
        *(f"following_error_path_{p}" for p in range(1, 16)),
    }
    assert commands == {*(f"start_path_{p}" for p in range(16)), "home", "set_zero", "emergency_stop"}
    assert set(directed(idm)) == {"pr_trigger"}  # 5.3.3's control word and status word are whole registers (W / R)
    # Pr9.07 of path 0 maps to Pr8.02: writing 0x10 there starts path 0 (4.8, 6.4).
    assert triggers(idm) == {f"pr_path_{n}_special" for n in range(16)}
    assert destructive(idm) == {"init_parameters", "restore_factory_defaults", "reset_history_alarms", "force_enable_on"}


def test_id243pro_pseudo_inputs_are_triggers_and_restart_is_destructive() -> None:
    dev = load("id243pro")
    assert triggers(dev) == {"virtual_in1", "virtual_in2"}  # 1.4: 1 triggers the action configured for the input
    assert destructive(dev) == {"reset_user_parameters", "restart"}
    assert directed(dev) == {}  # 1.2/1.3 describe only commands; what 0206/0323 read back is not stated
    assert {r.name for r in dev.registers if dev.is_trigger(r)} == {"virtual_in1", "virtual_in2", "user_command", "control_command"}


def test_c630s_auxiliary_functions_are_triggers_and_its_destructive_commands() -> None:
    dev = load("c630s")
    # 7.13: offline inertia identification, initial angle identification, JOG trial run; 7.18/7.16: the VDI levels.
    assert triggers(dev) == {"offline_inertia_identification", "initial_angle_identification", "jog_trial_run", "comm_vdi_level"}
    assert destructive(dev) == {"software_reset", "restore_factory_defaults", "clear_fault_records", "reset_abs_encoder_multiturn"}
    assert directed(dev) == {}  # no table prints a read/write direction per value
    assert not destructive(dev) & {"fault_reset", "emergency_stop"}


@pytest.mark.parametrize("path", MAPS + SMALL_MAPS, ids=lambda p: p.name)
def test_every_command_writes_a_writable_member(path: Path) -> None:
    device = load_map(path)
    specs = {s.name: s for s in runtime_specs(device)}
    for command in device.commands:
        arguments = [None] if command.argument is None else list(range(command.argument.min, command.argument.max + 1))
        for argument in arguments:
            raw = command.raw_value(argument)
            enum = command.register.enum
            if enum is not None and not command.register.bitfields:
                member = enum.by_value(raw)
                assert member is not None and member.writable, (command.name, raw)
            spec = specs[command.register.name]
            if command.destructive:  # sent only as its command, confirmed; a plain write of it is refused
                with pytest.raises(DestructiveWriteError):
                    check_raw(spec, raw)
                check_command(spec, raw, confirmed=True)
            else:
                check_raw(spec, raw)  # the runtime's one check agrees


@pytest.mark.parametrize("name", ["idm_rs", "id243pro", "c630s"])
def test_the_small_fixtures_agree_with_their_maps(name: str) -> None:
    full = load(name)
    small = load_map(ROOT / "tests" / "maps" / "small" / f"{name}_small.yaml")
    full_commands = {c.name: c for c in full.commands}
    for command in small.commands:
        assert command.destructive == full_commands[command.name].destructive, command.name
    full_registers = {r.name: r for r in full.registers}
    for reg in small.registers:
        if reg.name in full_registers:
            assert reg.trigger == full_registers[reg.name].trigger, reg.name
