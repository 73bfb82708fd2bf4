"""`regmap diff`: every change kind on a pair of maps, its classification and the exit status; PATH@GITREV;
bad input; `regmap generate --since`; the committed example changelog.

Each case edits tests/maps/diff/idm_rs_small_v1.yaml (loaded as YAML, changed, written to tmp_path) and
states the changes `regmap diff` must report, exactly: no more, no fewer.
"""

from __future__ import annotations

import copy
import functools
import json
import os
import shutil
import subprocess
import sys
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest
import yaml

from regmap.cli import main
from regmap.frontend import load_map
from regmap.tools import diff

from conftest import ROOT

V1 = ROOT / "tests" / "maps" / "diff" / "idm_rs_small_v1.yaml"
V2 = ROOT / "tests" / "maps" / "diff" / "idm_rs_small_v2.yaml"
FV1 = ROOT / "tests" / "maps" / "diff" / "fixture_v1.yaml"  # issue #19's features: spaces, floats, strings, gates ...
FV2 = ROOT / "tests" / "maps" / "diff" / "fixture_v2.yaml"
EXAMPLE = ROOT / "docs" / "changelog-example.md"
EXAMPLE_COMMAND = [
    "regmap",
    "diff",
    "tests/maps/diff/idm_rs_small_v1.yaml",
    "tests/maps/diff/idm_rs_small_v2.yaml",
    "--format",
    "markdown",
]

Map = dict[str, Any]
Edit = Callable[[Map], None]


# -- editing a map --------------------------------------------------------------------------


@functools.cache
def _load(path: Path) -> Map:
    data: Map = yaml.safe_load(path.read_text(encoding="utf-8"))
    return data


def base() -> Map:
    """A fresh copy of v1 as plain data, to edit."""
    return copy.deepcopy(_load(V1))


def fixture_base() -> Map:
    """A fresh copy of fixture_v1 (input registers, coils, floats, strings, gates ...), to edit."""
    return copy.deepcopy(_load(FV1))


def write(data: Map, path: Path) -> Path:
    dumper = getattr(yaml, "CSafeDumper", yaml.SafeDumper)
    path.write_text(yaml.dump(data, Dumper=dumper, allow_unicode=True, sort_keys=False), encoding="utf-8")
    return path


def register(data: Map, name: str) -> dict[str, Any]:
    for group in data["groups"]:
        for reg in group["registers"]:
            if reg.get("name") == name:
                result: dict[str, Any] = reg
                return result
    raise KeyError(name)


def array(data: Map) -> dict[str, Any]:
    result: dict[str, Any] = next(r for g in data["groups"] for r in g["registers"] if r.get("array") == "pr_path")
    return result


def member(data: Map, name: str) -> dict[str, Any]:
    result: dict[str, Any] = next(m for m in array(data)["members"] if m["name"] == name)
    return result


def group(data: Map, gid: str) -> dict[str, Any]:
    result: dict[str, Any] = next(g for g in data["groups"] if g["id"] == gid)
    return result


def enum_values(data: Map, name: str) -> list[dict[str, Any]]:
    result: list[dict[str, Any]] = data["enums"][name]["values"]
    return result


def enum_value(data: Map, enum: str, name: str) -> dict[str, Any]:
    return next(v for v in enum_values(data, enum) if v["name"] == name)


def bitfield(data: Map, reg: str, name: str) -> dict[str, Any]:
    result: dict[str, Any] = next(b for b in register(data, reg)["bitfields"] if b["name"] == name)
    return result


def command(data: Map, name: str) -> dict[str, Any]:
    result: dict[str, Any] = next(c for c in data["commands"] if c["name"] == name)
    return result


def example(data: Map, eid: str) -> dict[str, Any]:
    result: dict[str, Any] = next(e for e in data["examples"] if e["id"] == eid)
    return result


def remove(items: list[Any], pred: Callable[[Any], bool]) -> None:
    items[:] = [i for i in items if not pred(i)]


def rename_register(data: Map, old: str, new: str) -> None:
    register(data, old)["name"] = new
    for ex in data["examples"]:
        for value in ex.get("values", []):
            if value["register"] == old:
                value["register"] = new


ERRATUM = {
    "id": "E1",
    "title": "Default of the peak current",
    "readings": [{"source": "5.3.1", "says": "default 2.2 A"}, {"source": "附录4", "says": "default 2.0 A"}],
    "choice": "default 2.2 A",
    "reason": "5.3.1 is the parameter table.",
    "registers": ["peak_current"],
}
FAULT = {"code": "Er.1", "value": 1, "name": "overcurrent", "title": "Overcurrent", "kind": "fault", "source": "6.1"}


def set_(path: Callable[[Map], dict[str, Any]], key: str, value: Any) -> Edit:
    def edit(data: Map) -> None:
        path(data)[key] = value

    return edit


def delete(path: Callable[[Map], dict[str, Any]], key: str) -> Edit:
    def edit(data: Map) -> None:
        del path(data)[key]

    return edit


def chain(*edits: Edit) -> Edit:
    def edit(data: Map) -> None:
        for e in edits:
            e(data)

    return edit


def peak(data: Map) -> dict[str, Any]:
    return register(data, "peak_current")


def status(data: Map) -> dict[str, Any]:
    return register(data, "run_status")


def transport(data: Map) -> dict[str, Any]:
    result: dict[str, Any] = data["transport"]
    return result


def serial(data: Map) -> dict[str, Any]:
    result: dict[str, Any] = data["transport"]["serial"]
    return result


# -- the cases --------------------------------------------------------------------------------

Expected = tuple[str, str, bool]  # kind, subject, breaking


@dataclass(frozen=True)
class Case:
    id: str
    new: Edit  # applied to v1 to get NEW
    expect: tuple[Expected, ...]
    old: Edit | None = None  # applied to v1 to get OLD (default: v1 itself)
    start: Callable[[], Map] = base  # the map both sides start from


def _add_register(data: Map) -> None:
    group(data, "basic")["registers"].append(
        {"name": "lock_current", "param": "Pr0.01", "address": 3, "title": "Lock current", "unit": "%", "min": 0, "max": 100}
    )


def _move_with_param(data: Map) -> None:
    register(data, "motor_direction").update(param="Pr0.05", address=0x0B)


def _remove_special(data: Map) -> None:
    remove(array(data)["members"], lambda m: m["name"] == "special")


def _speed_default_of_element_3(data: Map) -> None:
    member(data, "speed")["default"] = [60, 60, 60, 90, *[60] * 12]


def _add_first_bitfield(data: Map) -> None:
    member(data, "special")["bitfields"] = [{"name": "flag", "bits": 0, "title": "Flag"}]


def _new_example(data: Map) -> None:
    data["examples"].append({**example(data, "read_current_req"), "id": "read_current_again"})


def _rename_enum(data: Map) -> None:
    data["enums"] = {("rotation" if k == "direction" else k): v for k, v in data["enums"].items()}
    register(data, "motor_direction")["enum"] = "rotation"


def _remove_enum(data: Map) -> None:
    del data["enums"]["direction"]
    del register(data, "motor_direction")["enum"]


R, C = True, False  # breaking, compatible

CASES = [
    # registers: added, removed, renamed, moved
    Case("register_added", _add_register, (("register_added", "lock_current", C),)),
    Case(
        "register_removed",
        lambda d: remove(group(d, "basic")["registers"], lambda r: r["name"] == "motor_direction"),
        (("register_removed", "motor_direction", R),),
    ),
    Case("renamed", lambda d: rename_register(d, "peak_current", "max_current"), (("register_renamed", "peak_current", R),)),
    Case(
        "renamed_matched_by_address", lambda d: rename_register(d, "run_status", "drive_status"), (("register_renamed", "run_status", R),)
    ),
    Case("moved", set_(status, "address", 0x1004), (("register_moved", "run_status", R),)),
    Case("moved_with_its_param", _move_with_param, (("register_moved", "motor_direction", R),)),
    # width / type / word order / pairing
    Case("width_changed", set_(status, "type", "u32"), (("register_type_changed", "run_status", R),)),
    Case("signedness_changed", set_(peak, "type", "s16"), (("register_type_changed", "peak_current", R),)),
    Case(
        "word_order_changed",
        set_(lambda d: member(d, "position"), "word_order", "low_first"),
        (("register_word_order_changed", "pr_path[0..15].position", R),),
    ),
    Case("paired_changed", set_(peak, "paired", False), (("register_paired_changed", "peak_current", R),)),
    # access
    Case("rw_to_r", set_(peak, "access", "r"), (("register_access_changed", "peak_current", R),)),
    Case("r_to_rw", set_(status, "access", "rw"), (("register_access_changed", "run_status", C),)),
    Case("w_to_rw", set_(lambda d: register(d, "control_word"), "access", "rw"), (("register_access_changed", "control_word", C),)),
    # unit and scale
    Case("unit_changed", set_(peak, "unit", "mA"), (("register_unit_changed", "peak_current", R),)),
    Case("unit_given", set_(status, "unit", "flags"), (("register_unit_changed", "run_status", C),)),
    Case("scale_changed", set_(peak, "scale", 0.01), (("register_scale_changed", "peak_current", R),)),
    # range and default
    Case("range_narrowed", set_(peak, "max", 60), (("register_range_changed", "peak_current", R),)),
    Case("range_widened", set_(peak, "max", 100), (("register_range_changed", "peak_current", C),)),
    Case(
        "range_narrowed_by_a_new_min",
        set_(lambda d: member(d, "dwell"), "min", 0),
        (("register_range_changed", "pr_path[0..15].dwell", R),),
    ),
    Case("range_spelled_out", set_(status, "min", 0), (("register_range_changed", "run_status", C),)),
    Case("default_changed", set_(peak, "default", 25), (("register_default_changed", "peak_current", C),)),
    Case("default_of_one_element", _speed_default_of_element_3, (("register_default_changed", "pr_path[3].speed", C),)),
    # enum reference, parameter id, documentation
    Case(
        "register_enum_dropped",
        delete(lambda d: register(d, "motor_direction"), "enum"),
        (("register_enum_changed", "motor_direction", R),),
    ),
    Case("param_changed", set_(status, "param", "St.01"), (("register_param_changed", "run_status", C),)),
    Case("register_doc", set_(peak, "title", "Motor peak current"), (("register_doc_changed", "peak_current", C),)),
    # enums
    Case(
        "enum_value_added",
        lambda d: enum_values(d, "di_function").append({"value": 0x2A, "name": "addr2", "title": "Path address 2"}),
        (("enum_value_added", "di_function.addr2", C),),
    ),
    Case(
        "enum_value_removed",
        lambda d: remove(enum_values(d, "di_function"), lambda v: v["name"] == "servo_on"),
        (("enum_value_removed", "di_function.servo_on", R),),
    ),
    Case(
        "enum_value_renumbered",
        set_(lambda d: enum_value(d, "di_function", "ctrg"), "value", 0x21),
        (("enum_value_renumbered", "di_function.ctrg", R),),
    ),
    Case(
        "enum_value_renamed",
        set_(lambda d: enum_value(d, "direction", "negative"), "name", "reverse"),
        (("enum_value_renamed", "direction.negative", R),),
    ),
    Case(
        "enum_value_doc",
        set_(lambda d: enum_value(d, "direction", "negative"), "title", "Reverse"),
        (("enum_doc_changed", "direction.negative", C),),
    ),
    Case(
        "enum_added",
        lambda d: d["enums"].update(spare={"title": "Spare", "values": [{"value": 0, "name": "off", "title": "Off"}]}),
        (("enum_added", "spare", C),),
    ),
    Case("enum_removed", _remove_enum, (("enum_removed", "direction", R), ("register_enum_changed", "motor_direction", R))),
    Case("enum_renamed", _rename_enum, (("enum_renamed", "direction", R),)),
    Case("enum_doc", set_(lambda d: d["enums"]["direction"], "title", "Direction of rotation"), (("enum_doc_changed", "direction", C),)),
    # bitfields
    Case(
        "bitfield_added",
        lambda d: status(d)["bitfields"].append({"name": "warning", "bits": 3, "title": "Warning"}),
        (("bitfield_added", "run_status.warning", C),),
    ),
    Case("first_bitfield", _add_first_bitfield, (("bitfield_added", "pr_path[0..15].special.flag", R),)),
    Case(
        "bitfield_removed",
        lambda d: remove(status(d)["bitfields"], lambda b: b["name"] == "homing_done"),
        (("bitfield_removed", "run_status.homing_done", R),),
    ),
    Case(
        "bitfield_moved",
        set_(lambda d: bitfield(d, "run_status", "homing_done"), "bits", 7),
        (("bitfield_moved", "run_status.homing_done", R),),
    ),
    Case(
        "bitfield_resized",
        set_(lambda d: bitfield(d, "di2_function", "function"), "bits", "0-5"),
        (("bitfield_resized", "di2_function.function", R),),
    ),
    Case(
        "bitfield_renamed",
        set_(lambda d: bitfield(d, "run_status", "fault"), "name", "alarm"),
        (("bitfield_renamed", "run_status.fault", R),),
    ),
    Case(
        "bitfield_enum",
        set_(lambda d: bitfield(d, "run_status", "running"), "enum", "direction"),
        (("bitfield_enum_changed", "run_status.running", R),),
    ),
    Case(
        "bitfield_doc",
        set_(lambda d: bitfield(d, "run_status", "fault"), "title", "Alarm"),
        (("bitfield_doc_changed", "run_status.fault", C),),
    ),
    # arrays
    Case("array_fewer", set_(array, "count", 8), (("array_count_changed", "pr_path", R),)),
    Case("array_more", set_(array, "count", 20), (("array_count_changed", "pr_path", C),)),
    Case("array_moved", set_(array, "base", 0x6300), (("array_layout_changed", "pr_path", R),)),
    Case("array_member_removed", _remove_special, (("array_member_removed", "pr_path.special", R),)),
    Case("array_member_added", lambda d: None, (("array_member_added", "pr_path.special", C),), old=_remove_special),
    Case("array_member_renamed", set_(lambda d: member(d, "speed"), "name", "velocity"), (("array_member_renamed", "pr_path.speed", R),)),
    Case("array_renamed", set_(array, "array", "path_table"), (("array_renamed", "pr_path", R),)),
    Case(
        "array_removed",
        lambda d: remove(d["groups"], lambda g: g["id"] == "pr"),
        (("array_removed", "pr_path", R), ("group_removed", "pr", C)),
    ),
    Case(
        "array_added",
        lambda d: None,
        (("array_added", "pr_path", C), ("group_added", "pr", C)),
        old=lambda d: remove(d["groups"], lambda g: g["id"] == "pr"),
    ),
    Case("array_doc", set_(array, "title", "Path table"), (("array_doc_changed", "pr_path", C),)),
    # commands
    Case(
        "command_added",
        lambda d: d["commands"].append(
            {"name": "factory_reset", "title": "Factory reset", "register": "control_word", "value": 0x2233, "source": "5.3.3"}
        ),
        (("command_added", "factory_reset", C),),
    ),
    Case(
        "command_removed",
        lambda d: remove(d["commands"], lambda c: c["name"] == "reset_current_alarm"),
        (("command_removed", "reset_current_alarm", R),),
    ),
    Case(
        "command_value",
        set_(lambda d: command(d, "reset_current_alarm"), "value", 0x2233),
        (("command_changed", "reset_current_alarm", R),),
    ),
    Case(
        "command_renamed",
        set_(lambda d: command(d, "save_all_parameters"), "name", "save"),
        (("command_renamed", "save_all_parameters", R),),
    ),
    Case(
        "command_effect",
        set_(lambda d: command(d, "reset_current_alarm"), "effect", {"kind": "restore_defaults"}),
        (("command_effect_changed", "reset_current_alarm", C),),
    ),
    Case(
        "command_doc",
        set_(lambda d: command(d, "reset_current_alarm"), "title", "Clear the alarm"),
        (("command_doc_changed", "reset_current_alarm", C),),
    ),
    # faults
    Case("fault_added", lambda d: d.update(faults=[FAULT]), (("fault_added", "overcurrent", C),)),
    Case("fault_removed", lambda d: None, (("fault_removed", "overcurrent", R),), old=lambda d: d.update(faults=[FAULT])),
    Case(
        "fault_value",
        lambda d: d.update(faults=[{**FAULT, "value": 2}]),
        (("fault_changed", "overcurrent", R),),
        old=lambda d: d.update(faults=[FAULT]),
    ),
    Case(
        "fault_doc",
        lambda d: d.update(faults=[{**FAULT, "title": "Over-current"}]),
        (("fault_doc_changed", "overcurrent", C),),
        old=lambda d: d.update(faults=[FAULT]),
    ),
    # examples
    Case("example_added", _new_example, (("example_added", "read_current_again", C),)),
    Case(
        "example_removed", lambda d: remove(d["examples"], lambda e: e["id"] == "write_di_rsp"), (("example_removed", "write_di_rsp", C),)
    ),
    Case(
        "example_changed", set_(lambda d: example(d, "save_req"), "meaning", "Save every parameter"), (("example_changed", "save_req", C),)
    ),
    # errata
    Case("erratum_added", lambda d: d.update(errata=[ERRATUM]), (("erratum_added", "E1", C),)),
    Case("erratum_removed", lambda d: None, (("erratum_removed", "E1", C),), old=lambda d: d.update(errata=[ERRATUM])),
    Case(
        "erratum_changed",
        lambda d: d.update(errata=[{**ERRATUM, "choice": "default 2.0 A"}]),
        (("erratum_changed", "E1", C),),
        old=lambda d: d.update(errata=[ERRATUM]),
    ),
    # groups
    Case("group_changed", set_(lambda d: group(d, "status"), "title", "Status words"), (("group_changed", "status", C),)),
    # device and transport
    Case("device_id", set_(lambda d: d["device"], "id", "idm_rs_mini"), (("device_id_changed", "id", R),)),
    Case("device_text", set_(lambda d: d["device"], "model", "iDM-RS (V2.1)"), (("device_changed", "model", C),)),
    Case("baud", set_(serial, "baud", 38400), (("transport_changed", "baud", R),)),
    Case("parity", set_(serial, "parity", "even"), (("transport_changed", "parity", R),)),
    Case("baud_rate_added", set_(serial, "baud_rates", [9600, 19200, 38400, 57600, 115200]), (("transport_changed", "baud_rates", C),)),
    Case("baud_rate_removed", set_(serial, "baud_rates", [19200, 38400, 115200]), (("transport_changed", "baud_rates", R),)),
    Case("slave_ids_widened", set_(lambda d: transport(d)["slave_ids"], "max", 247), (("transport_changed", "slave_ids", C),)),
    Case("slave_ids_narrowed", set_(lambda d: transport(d)["slave_ids"], "max", 15), (("transport_changed", "slave_ids", R),)),
    Case("broadcast_dropped", set_(transport, "broadcast_id", None), (("transport_changed", "broadcast_id", R),)),
    Case("function_code_added", set_(transport, "function_codes", [0x03, 0x04, 0x06, 0x10]), (("transport_changed", "function_codes", C),)),
    Case("function_code_removed", set_(transport, "function_codes", [0x03, 0x10]), (("transport_changed", "function_codes", R),)),
    Case("max_read_smaller", set_(transport, "max_read_registers", 40), (("transport_changed", "max_read_registers", R),)),
    Case("max_write_smaller", set_(transport, "max_write_registers", 40), (("transport_changed", "max_write_registers", R),)),
    Case("max_message_larger", set_(transport, "max_message_bytes", 120), (("transport_changed", "max_message_bytes", C),)),
    Case("device_word_order", set_(transport, "word_order", "low_first"), (("transport_changed", "word_order", R),)),
    Case(
        "undocumented_rejected",
        lambda d: None,
        (("transport_changed", "undocumented_addresses", R),),
        old=set_(transport, "undocumented_addresses", "tolerate"),
    ),
    Case("timing", set_(lambda d: transport(d)["timing"][0], "total_ms", 14.0), (("transport_changed", "timing", C),)),
    Case(
        "exception_added",
        lambda d: transport(d)["exceptions"].append({"code": 0x04, "name": "device_failure", "title": "Device failure"}),
        (("transport_changed", "exceptions", C),),
    ),
]


# -- issue #19: spaces, wide and float types, strings, byte order, offsets, gates, poll classes ------


def fx(case_id: str, new: Edit, expect: tuple[Expected, ...], old: Edit | None = None) -> Case:
    return Case(case_id, new, expect, old, start=fixture_base)


def _thd_as_time(zone: str) -> Edit:
    """thd_current (2 words) as a timestamp on the clock `zone` (issue #34)."""

    def edit(data: Map) -> None:
        reg = register(data, "thd_current")
        reg.pop("unit")
        reg.update(type="timestamp", zone=zone)

    return edit


def firmware_register(data: Map) -> dict[str, Any]:
    result: dict[str, Any] = data["device"]["firmware_register"]
    return result


def _relay_2_becomes_an_input(data: Map) -> None:
    register(data, "relay_2").update(space="discrete_input", access="r")


def _relay_2_renamed_into_another_space(data: Map) -> None:
    register(data, "relay_2").update(name="relay_b", space="discrete_input", access="r")


def _drop_firmware_register(data: Map) -> None:
    del data["device"]["firmware_register"]


def _firmware_as_major_minor(data: Map) -> None:
    firmware_register(data).update(format="major_minor")
    del firmware_register(data)["decimals"]


CASES += [
    fx("fx_space", lambda d: register(d, "energy").update(space="holding", access="r"), (("register_space_changed", "energy", R),)),
    fx(
        "fx_space_and_access",
        set_(lambda d: register(d, "energy"), "space", "holding"),  # holding registers default to rw
        (("register_space_changed", "energy", R), ("register_access_changed", "energy", C)),
    ),
    fx(
        "fx_coil_to_discrete_input",
        _relay_2_becomes_an_input,
        (("register_space_changed", "relay_2", R), ("register_access_changed", "relay_2", R)),
    ),
    fx(
        "fx_other_name_in_another_space_is_another_register",
        _relay_2_renamed_into_another_space,
        (("register_removed", "relay_2", R), ("register_added", "relay_b", C)),
    ),
    fx("fx_float_to_int", set_(lambda d: register(d, "voltage"), "type", "s32"), (("register_type_changed", "voltage", R),)),
    fx("fx_u64_to_f64", set_(lambda d: register(d, "energy"), "type", "f64"), (("register_type_changed", "energy", R),)),
    fx("fx_string_words", set_(lambda d: register(d, "model_name"), "words", 4), (("register_string_changed", "model_name", R),)),
    fx(
        "fx_string_encoding",
        set_(lambda d: register(d, "serial_number"), "encoding", "gbk"),
        (("register_string_changed", "serial_number", R),),
    ),
    fx(
        "fx_string_padding",
        set_(lambda d: register(d, "serial_number"), "padding", "space"),
        (("register_string_changed", "serial_number", R),),
    ),
    fx(
        "fx_register_byte_order",
        set_(lambda d: register(d, "voltage"), "byte_order", "low_first"),
        (("register_byte_order_changed", "voltage", R),),
    ),
    fx(
        "fx_register_byte_order_back_to_the_device",
        delete(lambda d: register(d, "swapped_word"), "byte_order"),
        (("register_byte_order_changed", "swapped_word", R),),
    ),
    # registers that follow the device's byte order change with it: one row, the transport's
    fx("fx_device_byte_order", set_(transport, "byte_order", "low_first"), (("transport_changed", "byte_order", R),)),
    fx(
        "fx_f32_word_order",
        delete(lambda d: register(d, "current"), "word_order"),
        (("register_word_order_changed", "current", R),),
    ),
    fx("fx_offset_changed", set_(lambda d: register(d, "temperature"), "offset", -50), (("register_offset_changed", "temperature", R),)),
    fx("fx_offset_added", set_(lambda d: register(d, "energy"), "offset", 100), (("register_offset_changed", "energy", R),)),
    # firmware gates: a version that loses the register is breaking, one that gains it is not
    fx(
        "fx_gate_added",
        set_(lambda d: register(d, "voltage"), "firmware", {"from": "2.00"}),
        (("register_firmware_changed", "voltage", R),),
    ),
    fx("fx_gate_removed", delete(lambda d: register(d, "running_hours"), "firmware"), (("register_firmware_changed", "running_hours", C),)),
    fx(
        "fx_gate_widened",
        set_(lambda d: register(d, "running_hours"), "firmware", {"from": "1.50"}),
        (("register_firmware_changed", "running_hours", C),),
    ),
    fx(
        "fx_gate_narrowed",
        set_(lambda d: register(d, "running_hours"), "firmware", {"from": "2.10"}),
        (("register_firmware_changed", "running_hours", R),),
    ),
    fx(
        "fx_gate_gains_an_end",
        set_(lambda d: register(d, "running_hours"), "firmware", {"from": "2.00", "until": "3.00"}),
        (("register_firmware_changed", "running_hours", R),),
    ),
    fx(
        "fx_gate_ends_later",
        set_(lambda d: register(d, "legacy_mode"), "firmware", {"until": "4.00"}),
        (("register_firmware_changed", "legacy_mode", C),),
    ),
    fx(
        "fx_gate_shifted",
        set_(lambda d: register(d, "legacy_mode"), "firmware", {"from": "1.00", "until": "4.00"}),
        (("register_firmware_changed", "legacy_mode", R),),
    ),
    fx(
        "fx_group_gate_narrowed",
        set_(lambda d: group(d, "quality"), "firmware", {"from": "2.10"}),
        (("register_firmware_changed", "thd_current", R), ("register_firmware_changed", "thd_voltage", R)),
    ),
    fx("fx_na_added", set_(lambda d: register(d, "voltage"), "na", ["nan"]), (("register_na_changed", "voltage", R),)),
    fx("fx_timestamp_zone", _thd_as_time("local"), (("register_zone_changed", "thd_current", R),), old=_thd_as_time("utc")),
    fx(
        "fx_u32_becomes_timestamp",
        _thd_as_time("utc"),
        (("register_type_changed", "thd_current", R),),
        old=lambda d: register(d, "thd_current").update(type="u32", unit=None),
    ),
    fx("fx_poll", set_(lambda d: register(d, "voltage"), "poll", "normal"), (("register_poll_changed", "voltage", C),)),
    fx(
        "fx_group_poll",
        delete(lambda d: group(d, "nameplate"), "poll"),
        tuple(("register_poll_changed", n, C) for n in ("firmware_version", "model_name", "serial_number")),
    ),
    # float ranges and defaults, as for integers
    fx(
        "fx_float_range_narrowed", set_(lambda d: register(d, "alarm_limit"), "max", 800.0), (("register_range_changed", "alarm_limit", R),)
    ),
    fx("fx_float_range_widened", set_(lambda d: register(d, "alarm_limit"), "min", -10.0), (("register_range_changed", "alarm_limit", C),)),
    fx("fx_float_default", set_(lambda d: register(d, "alarm_limit"), "default", 230.5), (("register_default_changed", "alarm_limit", C),)),
    # the device's firmware register
    fx(
        "fx_firmware_register_added",
        lambda d: None,
        (("firmware_register_changed", "firmware_register", C),),
        old=_drop_firmware_register,
    ),
    fx("fx_firmware_register_removed", _drop_firmware_register, (("firmware_register_changed", "firmware_register", R),)),
    fx("fx_firmware_register_format", _firmware_as_major_minor, (("firmware_register_changed", "firmware_register", R),)),
    # coil limits, as the register limits
    fx("fx_max_read_coils_smaller", set_(transport, "max_read_coils", 1000), (("transport_changed", "max_read_coils", R),)),
    fx(
        "fx_max_write_coils_larger",
        lambda d: None,
        (("transport_changed", "max_write_coils", C),),
        old=set_(transport, "max_write_coils", 800),
    ),
]


def run_case(case: Case, tmp_path: Path) -> tuple[diff.Report, Path, Path]:
    old_data, new_data = case.start(), case.start()
    if case.old is not None:
        case.old(old_data)
    case.new(new_data)
    old, new = write(old_data, tmp_path / "old.yaml"), write(new_data, tmp_path / "new.yaml")
    return diff.compare(diff.load_spec(str(old)), diff.load_spec(str(new))), old, new


@pytest.mark.parametrize("case", CASES, ids=[c.id for c in CASES])
def test_change_kind(case: Case, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    report, old, new = run_case(case, tmp_path)
    got = sorted((c.kind, c.subject, c.breaking) for c in report.changes)
    assert got == sorted(case.expect), "\n" + diff.render_text(report)
    breaking = any(b for _, _, b in case.expect)
    assert report.exit_status == (7 if breaking else 6)
    assert main(["diff", str(old), str(new)]) == report.exit_status
    out = capsys.readouterr().out
    for kind, subject, _ in case.expect:
        assert f"{kind:<28} {subject}:" in out


def test_every_kind_has_a_case() -> None:
    covered = {kind for case in CASES for kind, _, _ in case.expect}
    assert set(diff.KINDS) - covered == set()


def test_every_kind_is_documented_in_the_readme() -> None:
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    section = readme.split("## `regmap diff`", 1)[1].split("\n## ", 1)[0]
    missing = [k for k in diff.KINDS if f"`{k}`" not in section]
    assert not missing, f"README's regmap diff section does not list {missing}"


def test_a_rename_is_one_change(tmp_path: Path) -> None:
    case = next(c for c in CASES if c.id == "renamed")
    report, _, _ = run_case(case, tmp_path)
    (change,) = report.changes
    assert (change.before, change.after, change.note) == ("peak_current", "max_current", "matched by parameter id")


def test_a_move_is_one_change(tmp_path: Path) -> None:
    case = next(c for c in CASES if c.id == "moved_with_its_param")
    report, _, _ = run_case(case, tmp_path)
    (change,) = report.changes
    assert (change.before, change.after) == ("0x0007 (Pr0.03)", "0x000B (Pr0.05)")


def test_a_rename_and_a_move_together_are_honestly_two(tmp_path: Path) -> None:
    """With no name, parameter id or address in common nothing ties the two registers together."""
    data = base()
    rename_register(data, "run_status", "drive_status")
    register(data, "drive_status")["address"] = 0x1004
    report = diff.compare(diff.load_spec(str(V1)), diff.load_spec(str(write(data, tmp_path / "new.yaml"))))
    assert sorted((c.kind, c.subject) for c in report.changes) == [("register_added", "drive_status"), ("register_removed", "run_status")]


def test_array_changes_merge_over_elements(tmp_path: Path) -> None:
    case = next(c for c in CASES if c.id == "word_order_changed")
    report, _, _ = run_case(case, tmp_path)
    (change,) = report.changes
    assert change.count == 16


def test_identical_maps(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["diff", str(V1), str(V1)]) == 0
    assert "no differences" in capsys.readouterr().out


def test_map_version_alone_is_no_difference(tmp_path: Path) -> None:
    data = base()
    data["device"]["map_version"] = "0.1.1"
    report = diff.compare(diff.load_spec(str(V1)), diff.load_spec(str(write(data, tmp_path / "new.yaml"))))
    assert report.changes == () and report.exit_status == 0
    assert report.old.fingerprint != report.new.fingerprint


@pytest.mark.parametrize(
    ("case_id", "new_version", "bump", "suggested", "ok"),
    [
        ("moved", "0.2.0", "major", "1.0.0", False),
        ("moved", "1.0.0", "major", "1.0.0", True),
        ("register_added", "0.1.1", "minor", "0.2.0", False),
        ("register_added", "0.2.0", "minor", "0.2.0", True),
        ("register_added", "1.0.0", "minor", "0.2.0", True),
        ("default_changed", "0.1.0", "patch", "0.1.1", False),
        ("default_changed", "0.1.1", "patch", "0.1.1", True),
    ],
)
def test_version_bump(case_id: str, new_version: str, bump: str, suggested: str, ok: bool, tmp_path: Path) -> None:
    case = next(c for c in CASES if c.id == case_id)
    edit = chain(case.new, set_(lambda d: d["device"], "map_version", new_version))
    report, _, _ = run_case(Case(case.id, edit, case.expect), tmp_path)
    assert (report.bump.label, report.suggested_version, report.version_ok) == (bump, suggested, ok)


def test_json_shape(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["diff", str(V1), str(V2), "--format", "json"]) == 7
    doc = json.loads(capsys.readouterr().out)
    assert set(doc) == {"format", "old", "new", "summary", "changes"}
    assert doc["format"] == "regmap-diff/1"
    assert set(doc["old"]) == {"map", "device", "map_version", "fingerprint"}
    assert doc["summary"] == {
        "changes": 15,
        "breaking": 4,
        "compatible": 11,
        "bump": "major",
        "suggested_version": "1.0.0",
        "version_ok": False,
        "exit_status": 7,
    }
    keys = {"kind", "item", "subject", "breaking", "bump", "before", "after", "old", "new", "note", "count"}
    assert all(set(c) == keys for c in doc["changes"])
    flags = [c["breaking"] for c in doc["changes"]]
    assert flags == sorted(flags, reverse=True)  # breaking first
    renamed = next(c for c in doc["changes"] if c["kind"] == "register_renamed")
    assert (renamed["old"], renamed["new"], renamed["bump"]) == ("peak_current", "motor_peak_current", "major")


def test_markdown_is_a_changelog(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["diff", str(V1), str(V2), "--format", "markdown"]) == 7
    page = capsys.readouterr().out
    assert page.startswith("# Changelog: ")
    assert page.index("## Breaking changes") < page.index("## Compatible changes")
    assert "### Registers renamed" in page and "| `peak_current` | peak\\_current | motor\\_peak\\_current |" in page
    assert "does **not** satisfy it" in page


def test_markdown_escapes_map_text(tmp_path: Path) -> None:
    data = base()
    register(data, "peak_current")["title"] = "<script>x</script> | `code` *bold*"
    report = diff.compare(diff.load_spec(str(V1)), diff.load_spec(str(write(data, tmp_path / "new.yaml"))))
    page = diff.render_markdown(report)
    assert "<script>" not in page and "| `code`" not in page
    assert "&lt;script&gt;" in page


def test_fixture_v2_reports_every_new_kind_and_shows_the_gates(capsys: pytest.CaptureFixture[str]) -> None:
    """A later firmware's map: each of issue #19's kinds once, gates in text, Markdown and JSON."""
    assert main(["diff", str(FV1), str(FV2)]) == 7
    text = capsys.readouterr().out
    assert "12 changes: 7 breaking, 5 compatible" in text
    breaking, compatible = text.split("\ncompatible:\n")
    for line in (
        "register_space_changed       energy: input -> holding  (read 0x04 -> 0x03)",
        "register_string_changed      serial_number: encoding ascii -> encoding utf-8",
        "register_word_order_changed  voltage: high_first -> low_first",
        "register_byte_order_changed  swapped_word: low_first -> high_first",
        "register_offset_changed      temperature: -40 -> -50",
        "register_firmware_changed    thd_voltage: firmware >= 2.00 -> firmware >= 2.10  (firmware before 2.10 loses it)",
    ):
        assert line in breaking, line
    for line in (
        "register_firmware_changed    legacy_mode: firmware < 3.00 -> every firmware  (firmware 3.00 and later gains it)",
        "register_firmware_changed    running_hours: firmware >= 2.00 -> every firmware  (firmware before 2.00 gains it)",
        "register_poll_changed        legacy_mode: normal -> slow",
        "register_range_changed       alarm_limit: 0.0..1000.0 -> 0.0..1200.0  (widened)",
        'register_added               power_factor: 0x0006 input f32 R, "Power factor", firmware >= 2.10',
    ):
        assert line in compatible, line
    assert main(["diff", str(FV1), str(FV2), "--format", "markdown"]) == 7
    page = capsys.readouterr().out
    assert "### Register firmware gates changed" in page
    assert "| `thd_voltage` | firmware &gt;= 2.00 | firmware &gt;= 2.10 | firmware before 2.10 loses it |" in page
    assert '| `power_factor` | 0x0006 input f32 R, "Power factor", firmware &gt;= 2.10 |' in page
    assert main(["diff", str(FV1), str(FV2), "--format", "json"]) == 7
    changes = {(c["kind"], c["subject"]): c for c in json.loads(capsys.readouterr().out)["changes"]}
    gate = changes[("register_firmware_changed", "thd_voltage")]
    assert (gate["old"], gate["new"], gate["bump"]) == ({"from": "2.00", "until": None}, {"from": "2.10", "until": None}, "major")
    assert changes[("register_firmware_changed", "running_hours")]["new"] is None
    assert changes[("register_offset_changed", "temperature")]["old"] == -40
    assert changes[("register_string_changed", "serial_number")]["new"] == {"encoding": "utf-8"}


def test_the_fixture_maps_are_valid_and_use_the_new_features() -> None:
    for path in (FV1, FV2):
        device = load_map(path)  # the front end's checks (`validate` adds the back ends')
        assert {r.space for r in device.registers} == {"holding", "input", "coil", "discrete_input"}
        assert {r.type.value for r in device.registers} >= {"f32", "f64", "u64", "string", "bool"}
        assert device.info.firmware_register is not None and any(r.firmware for r in device.registers)


def test_changelog_example_is_current() -> None:
    fresh = subprocess.run([sys.executable, "-m", "regmap", *EXAMPLE_COMMAND[1:]], cwd=ROOT, capture_output=True, text=True, check=False)
    assert fresh.returncode == 7, fresh.stderr
    assert fresh.stdout == EXAMPLE.read_text(encoding="utf-8"), (
        f"docs/changelog-example.md is stale; regenerate it with: {' '.join(EXAMPLE_COMMAND)} > docs/changelog-example.md"
    )


# -- OLD/NEW arguments ------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("spec", "expected"),
    [
        ("maps/x.yaml", ("maps/x.yaml", None)),
        ("maps/x.yaml@HEAD~1", ("maps/x.yaml", "HEAD~1")),
        ("maps/x.yaml@HEAD@{1}", ("maps/x.yaml", "HEAD@{1}")),
        ("maps/x.yml@v1.0", ("maps/x.yml", "v1.0")),
        ("maps/x@origin/main", ("maps/x", "origin/main")),
    ],
)
def test_split_spec(spec: str, expected: tuple[str, str | None]) -> None:
    assert diff.split_spec(spec) == expected


def regmap(*args: str, cwd: Path = ROOT) -> subprocess.CompletedProcess[str]:
    env = {k: v for k, v in os.environ.items() if k != "REGMAP_DEBUG"}
    return subprocess.run([sys.executable, "-m", "regmap", *args], cwd=cwd, env=env, capture_output=True, text=True, check=False)


def git(repo: Path, *args: str) -> None:
    env = {
        **os.environ,
        "GIT_AUTHOR_NAME": "t",
        "GIT_AUTHOR_EMAIL": "t@example.com",
        "GIT_COMMITTER_NAME": "t",
        "GIT_COMMITTER_EMAIL": "t@example.com",
        "GIT_CONFIG_GLOBAL": os.devnull,
        "GIT_CONFIG_SYSTEM": os.devnull,
    }
    subprocess.run(["git", "-C", str(repo), *args], env=env, check=True, capture_output=True)


@pytest.fixture
def repo(tmp_path: Path) -> Path:
    """A git repository with maps/small.yaml at v1 (first commit), then at v2 (second commit)."""
    if shutil.which("git") is None:
        pytest.skip("git is not installed")
    root = tmp_path / "repo"
    (root / "maps").mkdir(parents=True)
    git(root, "init", "-q")
    shutil.copy(V1, root / "maps" / "small.yaml")
    git(root, "add", ".")
    git(root, "commit", "-q", "-m", "v1")
    shutil.copy(V2, root / "maps" / "small.yaml")
    git(root, "commit", "-q", "-am", "v2")
    return root


def test_git_revisions(repo: Path) -> None:
    # From the repository root, relative paths.
    result = regmap("diff", "maps/small.yaml@HEAD~1", "maps/small.yaml@HEAD", cwd=repo)
    assert result.returncode == 7, result.stderr
    assert "15 changes: 4 breaking, 11 compatible" in result.stdout
    assert "old: maps/small.yaml@HEAD~1" in result.stdout
    # From elsewhere (a subdirectory, and outside the repository), against the working tree.
    assert regmap("diff", "small.yaml@HEAD~1", "small.yaml", cwd=repo / "maps").returncode == 7
    assert regmap("diff", f"{repo}/maps/small.yaml@HEAD", f"{repo}/maps/small.yaml").returncode == 0
    # The fingerprint of a map read from git is the fingerprint of the same file on disk.
    assert diff.load_spec(f"{repo}/maps/small.yaml@HEAD~1").fingerprint == diff.load_spec(str(V1)).fingerprint


@pytest.mark.parametrize(
    ("args", "code", "message"),
    [
        (("maps/missing.yaml", "maps/small.yaml"), 1, "maps/missing.yaml:1:1: no such map file"),
        (("maps/small.yaml@nosuchrev", "maps/small.yaml"), 2, "regmap diff: error: unknown git revision 'nosuchrev'"),
        (("maps/other.yaml@HEAD", "maps/small.yaml"), 1, "maps/other.yaml does not exist at git revision HEAD"),
        (("maps/small.yaml@--output=x", "maps/small.yaml"), 2, "regmap diff: error: '--output=x' is not a git revision"),
        (("maps/small.yaml", "maps/broken.yaml"), 1, "maps/broken.yaml:"),
    ],
)
def test_bad_input_exits_as_everywhere_else(repo: Path, args: tuple[str, ...], code: int, message: str) -> None:
    (repo / "maps" / "broken.yaml").write_text("format: regmap/1\ndevice: {}\n", encoding="utf-8")
    result = regmap("diff", *args, cwd=repo)
    assert result.returncode == code, result  # the same code validate and frame give (README "Exit status")
    assert result.stdout == ""
    assert "Traceback" not in result.stderr
    assert message in result.stderr
    assert not (repo / "maps" / "x").exists()


def test_outside_git(tmp_path: Path) -> None:
    shutil.copy(V1, tmp_path / "small.yaml")
    result = regmap("diff", "small.yaml@HEAD", "small.yaml", cwd=tmp_path)
    assert result.returncode == 2
    assert result.stderr.strip() == "regmap diff: error: small.yaml is not inside a git repository (needed for @HEAD)"


def test_missing_git(repo: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    monkeypatch.setenv("PATH", str(repo / "no-bin-here"))
    monkeypatch.chdir(repo)
    assert main(["diff", "maps/small.yaml@HEAD", "maps/small.yaml"]) == 2
    assert "git is not installed" in capsys.readouterr().err


# -- regmap generate --since ------------------------------------------------------------------


def test_generate_since_writes_a_changelog_page(repo: Path) -> None:
    shutil.copy(V1, repo / "maps" / "new_device.yaml")  # not committed: no page for it
    (repo / "maps" / "new_device.yaml").write_text(
        V1.read_text(encoding="utf-8").replace("id: idm_rs_small", "id: new_device"), encoding="utf-8"
    )
    result = regmap("generate", "--out", "out", "--target", "markdown", "--since", "HEAD~1", cwd=repo)
    assert result.returncode == 0, result.stderr
    pages = sorted(p.name for p in (repo / "out" / "docs").glob("*-changelog.md"))
    assert pages == ["idm_rs_small-changelog.md"]
    page = (repo / "out" / "docs" / "idm_rs_small-changelog.md").read_text(encoding="utf-8")
    assert "<!-- Generated by regmap from maps/small.yaml - do not edit. -->" in page
    assert "regenerate with `regmap generate --since HEAD~1`" in page
    assert "| old | `maps/small.yaml@HEAD~1` |" in page and "### Registers renamed" in page

    # Without --since the docs carry no changelog: the output does not depend on git history.
    result = regmap("generate", "--out", "out", "--target", "markdown", cwd=repo)
    assert result.returncode == 0, result.stderr
    assert not list((repo / "out" / "docs").glob("*-changelog.md"))


def test_generate_since_bad_revision_writes_nothing(repo: Path) -> None:
    result = regmap("generate", "--out", "out", "--since", "nosuchrev", cwd=repo)
    assert result.returncode == 2
    assert "unknown git revision 'nosuchrev'" in result.stderr and "Traceback" not in result.stderr
    assert not (repo / "out").exists()


def test_generate_since_needs_the_docs_target(repo: Path) -> None:
    result = regmap("generate", "--out", "out", "--target", "python", "--since", "HEAD", cwd=repo)
    assert result.returncode == 2
    assert "--since writes changelog pages into the docs" in result.stderr
