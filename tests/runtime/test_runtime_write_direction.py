"""A state the device only reports (an enum member with access r) is never encoded for a write: not by
name, not by number, not as a raw value, not inside a bitfield word; reading still decodes it. The
runtime specs carry the direction from the model, so the generated clients refuse it too, before
anything is sent."""

from __future__ import annotations

import asyncio
import importlib
from collections.abc import Callable
from typing import Any

import pytest

from regmap.frontend import load_map, load_map_text
from regmap.model import Device
from regmap.runtime_bridge import runtime_specs
from regmap_runtime.codec import DestructiveWriteError, RangeError, ReportedStateError, check_raw, decode_value, value_to_raw
from regmap_runtime.spec import RegisterSpec

from conftest import MAPS, ROOT, SMALL_MAPS, SimulatorFactory, generated_runtime

IDM = ROOT / "maps" / "idm_rs.yaml"


@pytest.fixture(scope="module")
def idm() -> Device:
    return load_map(IDM)


def spec_of(device: Device, name: str) -> RegisterSpec[Any]:
    return next(s for s in runtime_specs(device) if s.name == name)


def test_the_pr_trigger_spec_carries_its_reported_states_as_runs(idm: Device) -> None:
    assert spec_of(idm, "pr_trigger").reported == ((0x0000, 0x000F), (0x0100, 0x010F), (0x0200, 0x020F))
    assert spec_of(idm, "peak_current").reported == ()


@pytest.mark.parametrize("path", MAPS + SMALL_MAPS, ids=lambda p: p.name)
def test_every_spec_refuses_exactly_the_members_the_map_says_are_only_reported(path: Any) -> None:
    device = load_map(path)
    specs = {s.name: s for s in runtime_specs(device)}
    for reg in device.registers:
        if reg.enum is None or reg.bitfields or not reg.access.writable:
            continue
        spec = specs[reg.name]
        destructive = {c.value for c in device.destructive_commands(reg)}
        for member in reg.enum.members:
            if not reg.raw_min <= member.value <= reg.raw_max:
                continue
            if member.value in destructive:
                with pytest.raises(DestructiveWriteError):  # only its command, confirmed, sends it
                    check_raw(spec, member.value)
            elif member.writable:
                check_raw(spec, member.value)
            else:
                with pytest.raises(ReportedStateError):
                    check_raw(spec, member.value)


@pytest.mark.parametrize(
    ("raw", "name"),
    [
        (0x0000, "done"),
        (0x0005, "done_path_5"),
        (0x000F, "done_path_15"),
        (0x0100, "running_path_0"),
        (0x0105, "running_path_5"),
        (0x020F, "following_error_path_15"),
    ],
)
def test_a_reported_state_is_refused_by_number_with_its_name(idm: Device, raw: int, name: str) -> None:
    with pytest.raises(ReportedStateError) as info:
        check_raw(spec_of(idm, "pr_trigger"), raw)
    message = str(info.value)
    assert message.startswith("pr_trigger (Pr8.02): ") and f"{name} ({raw})" in message and "only reports" in message
    assert "start_path_0=16" in message and "done_path_1=" not in message  # the values that may be written instead
    assert isinstance(info.value, RangeError)  # every caller that catches a bad value catches this one


def test_a_reported_state_is_refused_by_name_and_a_command_is_encoded(idm: Device) -> None:
    spec = spec_of(idm, "pr_trigger")
    for text in ("done_path_5", "RUNNING_PATH_3", "command_done_waiting", "5", "0x0105"):
        with pytest.raises(ReportedStateError):
            value_to_raw(spec, text)
    assert value_to_raw(spec, "start_path_5") == 0x0015
    assert value_to_raw(spec, "emergency_stop") == 0x0040
    check_raw(spec, 0x0010)


def test_an_unknown_name_lists_only_the_values_that_may_be_written(idm: Device) -> None:
    with pytest.raises(RangeError) as info:
        value_to_raw(spec_of(idm, "pr_trigger"), "go")
    message = str(info.value)
    assert "home=32" in message and "emergency_stop=64" in message
    assert "done" not in message and "running_path" not in message


def test_reading_decodes_every_member(idm: Device) -> None:
    spec = spec_of(idm, "pr_trigger")
    assert decode_value(spec, 0x0105).name == "RUNNING_PATH_5"
    assert decode_value(spec, 0x0000).name == "DONE"
    assert decode_value(spec, 0x0010).name == "START_PATH_0"


BITFIELD_MAP = """\
format: regmap/1
device: {id: d, vendor: v, model: m, manual: {title: t, file: f}, map_version: 0.1.0}
transport:
  serial: {baud: 9600, parity: none, data_bits: 8, stop_bits: 1}
  slave_ids: {min: 1, max: 247}
  function_codes: [0x03, 0x06, 0x10]
  max_read_registers: 125
  max_write_registers: 123
  word_order: high_first
enums:
  stage:
    title: Stage
    values:
      - {value: 0, name: idle, title: Idle}
      - {value: 1, name: busy, title: Busy, access: r}
      - {value: 2, name: go, title: Go, access: w}
groups:
  - id: g
    title: G
    source: "1"
    registers:
      - {name: ctl, address: 0x10, type: u16, access: rw, title: Control,
         bitfields: [{name: stage, bits: "0-1", title: Stage, enum: stage}, {name: flag, bits: 4, title: Flag}]}
"""


def test_a_reported_state_in_a_bitfield_is_refused_inside_the_word() -> None:
    spec = spec_of(load_map_text(BITFIELD_MAP, "m.yaml"), "ctl")
    assert spec.reported_fields == (("stage", ((1, 1),)),)
    check_raw(spec, 0x0012)  # go, flag set
    with pytest.raises(ReportedStateError) as info:
        check_raw(spec, 0x0011)  # busy, flag set
    assert "ctl.stage: busy (1) is a state the device only reports" in str(info.value)


# -- the generated client: refused before anything is sent ---------------------------------


def idm_client() -> Any:
    return importlib.import_module("idm_rs")


def test_the_generated_client_refuses_a_reported_state_before_sending(simulator: SimulatorFactory) -> None:
    idm = idm_client()
    refused = generated_runtime("codec").ReportedStateError
    sim = simulator(IDM)
    assert sim.port is not None
    with idm.IdmRs.tcp("127.0.0.1", sim.port, slave=1, timeout=2) as drive:
        assert drive.read_pr_trigger() == idm.PrTrigger.DONE  # a reported state reads as its member
        before = drive.requests_sent
        attempts: list[Callable[[], object]] = [
            lambda: drive.write_pr_trigger("done_path_5"),
            lambda: drive.write_pr_trigger(0x0103),
            lambda: drive.write_pr_trigger(idm.PrTrigger.COMMAND_DONE_WAITING),
            lambda: drive.write(idm.PR_TRIGGER, 0x0105, raw=True),
            lambda: drive.write_many({idm.PEAK_CURRENT: 1.5, idm.PR_TRIGGER: "running_path_1"}),
            lambda: drive.plan_writes({idm.PR_TRIGGER: 0x0201}, raw=True),
        ]
        for attempt in attempts:
            with pytest.raises(refused, match=r"pr_trigger \(Pr8\.02\): \w+ \(\d+\) is a state the device only reports"):
                attempt()
        assert drive.requests_sent == before
        assert drive.read_raw(0x0191, 1) == [22]  # the write-many sent nothing, not even its valid half
        drive.write_pr_trigger("start_path_2")
        assert drive.read_raw(0x6002, 1) == [0x12]


def test_the_async_client_refuses_it_too(simulator: SimulatorFactory) -> None:
    idm = idm_client()
    refused = generated_runtime("codec").ReportedStateError
    sim = simulator(IDM)
    assert sim.port is not None

    async def main() -> None:
        async with idm.AsyncIdmRs.tcp("127.0.0.1", sim.port, timeout=2) as drive:
            before = drive.requests_sent
            with pytest.raises(refused):
                await drive.write_pr_trigger("done_path_5")
            with pytest.raises(refused):
                await drive.write_many({idm.PR_TRIGGER: 0x0100})
            assert drive.requests_sent == before
            assert await drive.read_pr_trigger() == idm.PrTrigger.DONE

    asyncio.run(main())
