"""ESPHome packages are safe on a live bus: a select offers only what may be written, commands go out
once, destructive ones are a deliberate step away; every entity has a stable id, so a package can be
extended and included twice; classes follow the register's kind; units are the map's. Each read back
from the generated YAML and compared with the model."""

from __future__ import annotations

import re
import struct
import subprocess
from pathlib import Path
from typing import Any

import pytest

from regmap.backends.esphome import render_device
from regmap.frontend import load_map
from regmap.model import Device, Register
from regmap.runtime_bridge import runtime_specs
from regmap_runtime.codec import raw_to_words

from conftest import FIXTURE_MAPS, GENERATED, MAPS, ROOT
from support.homeauto_yaml import Tagged, command_writes, expected_state_class, load, reserved_title, resolve

DEVICES = [load_map(p) for p in MAPS]
FIXTURES = [load_map(p, display_name=p.relative_to(ROOT).as_posix()) for p in FIXTURE_MAPS]
EVERY = DEVICES + FIXTURES
SPACE = {None: "holding", "holding": "holding", "read": "input", "coil": "coil", "discrete_input": "discrete_input"}
PLATFORMS = ("sensor", "binary_sensor", "text_sensor", "number", "select", "switch", "button")
C_ID = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")


def _text(device: Device, selection: str) -> str:
    if selection == "default" and device in DEVICES:
        return (GENERATED / "esphome" / f"{device.id}.yaml").read_text(encoding="utf-8")  # what is committed
    (text,) = render_device(device, None if selection == "default" else ("*",)).values()
    return text


def _package(device: Device, selection: str) -> dict[str, Any]:
    data = load(_text(device, selection))
    assert isinstance(data, dict)
    return data


def _entities(data: dict[str, Any]) -> list[tuple[str, dict[str, Any]]]:
    return [(p, e) for p in PLATFORMS for e in data.get(p, [])]


def _register(device: Device, e: dict[str, Any]) -> Register:
    """The register an item reads: at its address, or `offset` bytes on where an aligned device's item reads a whole unit."""
    address = e["address"] + e.get("offset", 0) // 2
    reg = device.at_address(address, SPACE[e.get("register_type")])
    assert reg is not None and reg.address == address, e
    return reg


def _wire(device: Device, reg: Register, raw: int) -> int:
    """The value ESPHome compares a select's option with: the register's wire words as one number."""
    spec = next(s for s in runtime_specs(device) if s.name == reg.name)
    value = 0
    for word in raw_to_words(spec, raw):
        value = (value << 16) | word
    if reg.type.is_float:  # a setting coded as a float: ESPHome reads its IEEE bits as U_DWORD(_R), whatever the word order
        return int.from_bytes(struct.pack(">f", float(raw)), "big")
    return value if reg.byte_order.value == "low_first" else raw


def _button_write(e: dict[str, Any]) -> tuple[int, tuple[int, ...]]:
    (action,) = e["on_press"]
    code = action["lambda"]
    assert isinstance(code, Tagged) and code.tag == "!lambda"
    single = re.search(r"create_write_single_command\(id\([^)]*\), 0x([0-9A-F]+), 0x([0-9A-F]+)\)", code.value)
    if single:
        return int(single.group(1), 16), (int(single.group(2), 16),)
    multiple = re.search(r"create_write_multiple_command\(id\([^)]*\), 0x([0-9A-F]+), (\d+), \{([^}]*)\}\)", code.value)
    assert multiple, code.value
    return int(multiple.group(1), 16), tuple(int(w, 16) for w in multiple.group(3).split(", "))


SELECTIONS = ["default", "all"]
CASES = [(d, s) for d in EVERY for s in SELECTIONS]
IDS = [f"{d.id}-{s}" for d, s in CASES]


# -- a select offers only members a write may send ------------------------------------------------


@pytest.mark.parametrize(("device", "selection"), CASES, ids=IDS)
def test_select_options_are_the_writable_members_and_states_have_a_sensor(device: Device, selection: str) -> None:
    data = _package(device, selection)
    selects: dict[int, dict[str, Any]] = {}
    texts: dict[int, dict[str, Any]] = {}
    for platform, e in _entities(data):
        if platform == "select":
            selects[e["address"]] = e
        elif platform == "text_sensor" and "filters" in e:
            texts[e["address"]] = e
    for e in selects.values():
        reg = _register(device, e)
        assert reg.enum is not None and reg.access.writable
        writable = sorted(_wire(device, reg, m.value) for m in reg.enum.members if m.writable)
        assert writable and sorted(e["optionsmap"].values()) == writable, (reg.name, e["optionsmap"])
    chosen = {r.name for r in _chosen(device, data)}
    for reg in device.registers:
        if reg.enum is None or not reg.access.readable or reg.name not in chosen:
            continue
        members = reg.enum.members
        if not any(m.writable for m in members) or not reg.access.writable:
            assert reg.address not in selects, f"{reg.name} has no member a write may send, yet a select"
        if any(m.readable and not m.writable for m in members):
            labels = {row["to"] for row in texts[reg.address]["filters"][0]["map"]}
            assert len(labels) == len([m for m in members if m.readable]), reg.name  # every reported state has its label


def _chosen(device: Device, data: dict[str, Any]) -> list[Register]:
    return [_register(device, e) for p, e in _entities(data) if p != "button"]


def test_the_pr_trigger_select_sends_commands_and_its_states_are_shown() -> None:
    device = next(d for d in DEVICES if d.id == "idm_rs")
    data = _package(device, "default")
    (select,) = [e for e in data["select"] if e["address"] == device.register("pr_trigger").address]
    enum = device.enum("pr_trigger")
    assert sorted(select["optionsmap"].values()) == sorted(m.value for m in enum.members if m.writable)
    done_path_5 = enum.member("done_path_5")
    assert done_path_5 is not None and done_path_5.value not in select["optionsmap"].values()
    (state,) = [e for e in data["text_sensor"] if e["address"] == select["address"]]
    assert "0005" in {row["from"] for row in state["filters"][0]["map"]}
    assert "skip_updates" not in state  # the drive changes it by itself: polled as a status value, not as a setting


# -- commands go out once ---------------------------------------------------------------------------


@pytest.mark.parametrize(("device", "selection"), CASES, ids=IDS)
def test_the_controller_sends_every_write_once(device: Device, selection: str) -> None:
    data = _package(device, selection)
    subs = data["substitutions"]
    (controller,) = data["modbus_controller"]
    assert controller["max_cmd_retries"] == 0  # ESPHome's default 4 would send an unanswered command 5 times
    throttle = resolve(controller["command_throttle"], subs)
    documented = [r.total_ms for r in device.transport.timing if r.baud == device.transport.baud and r.total_ms is not None]
    floor = max([*documented, device.transport.response_delay_ms or 0])
    assert re.fullmatch(r"\d+ms", throttle) and floor <= int(throttle[:-2]) >= 50, throttle
    controller_id = resolve(controller["id"], subs)
    for platform, e in _entities(data):
        if platform == "button":
            assert f"id({controller_id})" in resolve(e["on_press"][0]["lambda"].value, subs)
        else:
            assert resolve(e["modbus_controller_id"], subs) == controller_id


# -- destructive commands ------------------------------------------------------------------------


@pytest.mark.parametrize("device", EVERY, ids=[d.id for d in EVERY])
def test_destructive_commands_are_a_deliberate_step_away(device: Device) -> None:
    default = {_button_write(e) for e in _package(device, "default").get("button", [])}
    full = {_button_write(e): e for e in _package(device, "all").get("button", [])}
    for command in device.commands:
        for write in command_writes(device, command):
            if command.destructive:
                shared = [c for c in device.commands if not c.destructive and write in command_writes(device, c)]
                assert shared or write not in default, f"{command.name} is in the default selection"
                button = full[write]
                assert button["disabled_by_default"] is True and button["entity_category"] == "config", button
            else:
                assert write in default and "disabled_by_default" not in full[write], command.name


# -- ids ----------------------------------------------------------------------------------------------


@pytest.mark.parametrize(("device", "selection"), CASES, ids=IDS)
def test_every_entity_has_a_stable_unique_id(device: Device, selection: str) -> None:
    data = _package(device, selection)
    subs = data["substitutions"]
    prefix = "${" + device.id + "_device_id}_"
    ids = [e["id"] for _, e in _entities(data)]
    assert all(i.startswith(prefix) and C_ID.match(resolve(i, subs)) for i in ids), ids
    assert len(set(ids)) == len(ids)
    commands = {w: c for c in device.commands for w in command_writes(device, c)}
    for platform, e in _entities(data):
        key = e["id"].removeprefix(prefix)
        owner = commands[_button_write(e)].name if platform == "button" else _register(device, e).name
        assert key == owner or key.startswith(owner + "_"), (key, owner)
        assert e["name"].startswith("${" + device.id + "_name_prefix}"), e["name"]


# -- classes, categories, reserved registers ---------------------------------------------------------


@pytest.mark.parametrize(("device", "selection"), CASES, ids=IDS)
def test_state_classes_follow_the_register_kind(device: Device, selection: str) -> None:
    for platform, e in _entities(_package(device, selection)):
        if platform == "button":
            continue
        reg = _register(device, e)
        assert not reserved_title(reg.title), reg.name
        if platform != "sensor":
            assert "state_class" not in e, e
            continue
        if "bitmask" in e or ("lambda" in e and reg.bitfields):
            assert "state_class" not in e, e  # a field of a bit word
            continue
        assert e.get("state_class") == expected_state_class(device, reg), (reg.name, e.get("state_class"))
        if reg.unit in ("Wh", "kWh", "MWh"):
            assert e["device_class"] == "energy", e
        if reg.access.writable:
            assert e.get("entity_category") == ("diagnostic" if not device.is_trigger(reg) else None), e  # sensors allow no config


def test_known_kinds() -> None:
    """The issue's cases, by name: version, status and fault words are codes, a power-on time and a kWh counter totals."""
    by_id = {d.id: d for d in EVERY}

    def sensor(device_id: str, name: str) -> dict[str, Any]:
        device = by_id[device_id]
        reg = device.register(name)
        (e,) = [e for p, e in _entities(_package(device, "all")) if p == "sensor" and e["address"] == reg.address and "bitmask" not in e]
        return e

    for device_id, name in [("idm_rs", "version_info_1"), ("idm_rs", "r4d_status_word"), ("id243pro", "fault_code")]:
        e = sensor(device_id, name)
        assert "state_class" not in e and e["entity_category"] == "diagnostic", (name, e)
    power_on = sensor("c630s", "total_power_on_time")
    assert power_on["state_class"] == "total_increasing" and power_on["device_class"] == "duration"
    meter = next(d for d in FIXTURES if d.id == "power_meter" or "power_meter" in d.source_path)
    energy = sensor(meter.id, "active_energy")
    assert energy["state_class"] == "total_increasing" and energy["device_class"] == "energy"
    assert sensor(meter.id, "voltage_l1")["state_class"] == "measurement"
    c630s = _package(by_id["c630s"], "all")
    assert by_id["c630s"].register("reserved_p0d_10").address not in {e["address"] for _, e in _entities(c630s) if "address" in e}
    idm = _package(by_id["idm_rs"], "default")
    run_status = by_id["idm_rs"].register("run_status")
    invalid = next(b for b in run_status.bitfields if b.name == "invalid")
    assert all(e.get("bitmask") != invalid.mask for e in idm["binary_sensor"] if e["address"] == run_status.address)


# -- units -----------------------------------------------------------------------------------------


@pytest.mark.parametrize(("device", "selection"), CASES, ids=IDS)
def test_units_are_the_maps(device: Device, selection: str) -> None:
    units = 0
    for _platform, e in _entities(_package(device, selection)):
        if "unit_of_measurement" in e:
            reg = _register(device, e)
            assert reg.unit is not None and e["unit_of_measurement"] == " ".join(reg.unit.split()), (reg.unit, e["unit_of_measurement"])
            units += 1
        assert "\u2044" not in e.get("unit_of_measurement", "")
    assert units > 0


# -- two drives on one bus: esphome config --------------------------------------------------------


def _valid_config(esphome: Path, tmp_path: Path, main: str) -> dict[str, Any]:
    (tmp_path / "main.yaml").write_text(main, encoding="utf-8")
    result = subprocess.run([str(esphome), "config", "main.yaml"], cwd=tmp_path, capture_output=True, text=True, timeout=300, check=False)
    out = result.stdout + result.stderr
    assert result.returncode == 0 and "Configuration is valid!" in out, out[-4000:]
    assert "WARNING" not in out.replace("WARNING 💡", ""), [line for line in out.splitlines() if "WARNING" in line]
    body = "\n".join(line for line in result.stdout.splitlines() if not re.match(r"^(INFO|WARNING|DEBUG) ", line))
    data = load(body)
    assert isinstance(data, dict)
    return data


@pytest.mark.parametrize("device", DEVICES, ids=[d.id for d in DEVICES])
def test_two_drives_on_one_bus(esphome: Path, tmp_path: Path, device: Device) -> None:
    """The committed package included twice, the second drive at address 2 with its own ids and names,
    as `esphome config` validates and prints it: two controllers on one modbus, every entity twice."""
    (tmp_path / "drive.yaml").write_text(_text(device, "default"), encoding="utf-8")
    p = device.id
    second = f"{{file: drive.yaml, vars: {{{p}_device_id: drive2, {p}_slave_id: 2, {p}_name_prefix: 'Drive 2 '}}}}"
    main = (
        "esphome:\n  name: regmap-two-drives\nesp32:\n  board: esp32dev\n  framework:\n    type: esp-idf\n"
        f"packages:\n  drive1: !include drive.yaml\n  drive2: !include {second}\n"
    )
    config = _valid_config(esphome, tmp_path, main)
    controllers = {c["id"]: c for c in config["modbus_controller"]}
    assert set(controllers) == {f"{p}_controller", "drive2_controller"}
    assert {c["address"] for c in controllers.values()} == {1, 2}
    assert len({c["modbus_id"] for c in controllers.values()}) == 1 and len(config["modbus"]) == 1 and len(config["uart"]) == 1
    assert all(c["max_cmd_retries"] == 0 for c in controllers.values())
    one = _package(device, "default")
    for platform in PLATFORMS:
        made = config.get(platform, [])
        expected = len(one.get(platform, []))
        first = [e for e in made if str(e["id"]).startswith(f"{p}_")]
        other = [e for e in made if str(e["id"]).startswith("drive2_")]
        assert len(first) == len(other) == expected and len(made) == 2 * expected, platform
        assert {e["id"].removeprefix(f"{p}_") for e in first} == {e["id"].removeprefix("drive2_") for e in other}
        assert all(e["name"].startswith("Drive 2 ") for e in other)
        for e in other:
            if "modbus_controller_id" in e:
                assert e["modbus_controller_id"] == "drive2_controller"
