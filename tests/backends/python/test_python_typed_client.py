"""The generated clients' types say what the drive can return and what it accepts, and mypy --strict holds
users to them: an enum read is the enum or an Unlisted number, read_all() is a typed snapshot, an enum write
takes a writable member or its name, never a state the drive only reports."""

from __future__ import annotations

import re
from pathlib import Path

from conftest import mypy_strict
from support.clients import client_module

CORRECT = """
from typing import assert_type

import id243pro
import idm_rs
from idm_rs import IdmRs, IdmRsValues, PrTrigger, Unlisted


def use(drive: IdmRs) -> float:
    snapshot = drive.read_all()
    assert_type(snapshot, IdmRsValues)
    assert_type(drive.read_all(poll="static"), IdmRsValues)
    assert_type(drive.read_many(idm_rs.PEAK_CURRENT), IdmRsValues)
    trigger = drive.read_pr_trigger()
    assert_type(trigger, PrTrigger | Unlisted)
    if isinstance(trigger, PrTrigger):
        print(trigger.name)
    else:
        print(f"a value the manual does not list: {int(trigger)}")
    drive.write_pr_trigger(PrTrigger.START_PATH_3)
    drive.write_pr_trigger("start_path_3")
    drive.restore_factory_defaults(confirm="restore_factory_defaults")
    current: float = snapshot["peak_current"]
    return current


def use_mode(drive: id243pro.Id243pro) -> None:
    assert_type(drive.read_pulse_mode(), id243pro.PulseMode | id243pro.Unlisted)
    drive.write_pulse_mode(id243pro.PulseMode.DOUBLE_PULSE)
    drive.write_pulse_mode("pulse_direction")


async def use_async(drive: idm_rs.AsyncIdmRs) -> None:
    assert_type(await drive.read_all(), IdmRsValues)
    assert_type(await drive.read_pr_trigger(), PrTrigger | Unlisted)
    await drive.write_pr_trigger("start_path_3")
"""

# Each line marked `# refused` must be an error of mypy --strict, and no other line.
MISUSE = """
import id243pro
from idm_rs import IdmRs, PrTrigger


def misuse(drive: IdmRs, mode_drive: id243pro.Id243pro) -> None:
    snapshot = drive.read_all()
    print(snapshot["no_such_register"])  # refused: a key the map does not have
    name: str = snapshot["peak_current"]  # refused: a float is no str
    drive.write_pr_trigger("done_path_5")  # refused: a state the drive only reports, by name
    drive.write_pr_trigger(PrTrigger.DONE_PATH_5)  # refused: the same state as a member
    drive.write_pr_trigger("start_path_99")  # refused: no such member
    drive.write_pr_trigger(0x13)  # refused: a bare number
    mode_drive.write_pulse_mode("pulse")  # refused: any str
    state: PrTrigger = drive.read_pr_trigger()  # refused: an unlisted value is not a member
    drive.restore_factory_defaults()  # refused: a destructive command without its confirm keyword
    drive.restore_factory_defaults(confirm="restore")  # refused: confirm must repeat the command's name
    print(name, state)
"""


def _errors_by_line(result_text: str, program: Path) -> set[int]:
    return {int(m.group(1)) for m in re.finditer(rf"{re.escape(program.name)}:(\d+): error:", result_text)}


def test_a_correct_use_of_the_typed_client_passes_mypy_strict(tmp_path: Path) -> None:
    program = tmp_path / "correct_use.py"
    program.write_text(CORRECT, encoding="utf-8")
    result = mypy_strict(str(program))
    assert result.returncode == 0, result.stdout + result.stderr


def test_each_misuse_of_the_typed_client_fails_mypy_strict(tmp_path: Path) -> None:
    program = tmp_path / "misuse.py"
    program.write_text(MISUSE, encoding="utf-8")
    result = mypy_strict(str(program))
    refused = {number for number, line in enumerate(MISUSE.splitlines(), 1) if "# refused" in line}
    assert result.returncode == 1, result.stdout
    assert _errors_by_line(result.stdout, program) == refused, result.stdout


def test_the_snapshot_has_every_readable_register_and_nothing_else() -> None:
    for device_id, snapshot_name in (("idm_rs", "IdmRsValues"), ("id243pro", "Id243proValues"), ("c630s", "C630sValues")):
        module = client_module(device_id)
        snapshot = getattr(module, snapshot_name)
        readable = {r.name for r in module.DEVICE.registers if r.readable}
        assert set(snapshot.__optional_keys__) == readable
        assert not snapshot.__required_keys__  # read_all(poll=...) and firmware gates leave registers out


def test_a_value_the_enum_does_not_list_reads_as_unlisted() -> None:
    id243pro = client_module("id243pro")
    drive = id243pro.Id243pro.tcp("127.0.0.1", 1)  # never connected: decoding only
    value = drive.decode(id243pro.PULSE_MODE, [7])
    assert isinstance(value, id243pro.Unlisted) and value == 7
    assert drive.decode(id243pro.PULSE_MODE, [2]) is id243pro.PulseMode.DOUBLE_PULSE
