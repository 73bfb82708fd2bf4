"""Home Assistant packages: a script per command (destructive ones need a deliberate `confirm`), template
binary sensors for flags and template sensors with enum labels over the register's sensor, classes from
the register's kind, and no write of a state the device only reports. Read back from the generated YAML;
the templates rendered with Jinja as HA would, the entity ids they read checked with HA's own slugify."""

from __future__ import annotations

import json
import subprocess
from dataclasses import replace
from pathlib import Path
from typing import Any

import jinja2
import pytest

from regmap.backends.homeassistant import render_device
from regmap.backends.homeassistant.hub import render_hub
from regmap.frontend import load_map
from regmap.homeauto.selection import Selection
from regmap.model import Access, Device, Register

from conftest import FIXTURE_MAPS, GENERATED, MAPS, ROOT
from support.homeauto_yaml import command_writes, expected_state_class, load, reserved_title

DEVICES = [load_map(p) for p in MAPS]
FIXTURES = [load_map(p, display_name=p.relative_to(ROOT).as_posix()) for p in FIXTURE_MAPS]
HOSTILE = load_map(ROOT / "tests" / "maps" / "hostile" / "hostile.yaml")
EVERY = DEVICES + FIXTURES
CASES = [(d, s) for d in EVERY for s in ("default", "all")]
IDS = [f"{d.id}-{s}" for d, s in CASES]


def _package(device: Device, selection: str) -> dict[str, Any]:
    if selection == "default" and device in DEVICES:
        text = (GENERATED / "homeassistant" / f"{device.id}.yaml").read_text(encoding="utf-8")
    else:
        (text,) = render_device(device, None if selection == "default" else ("*",)).values()
    data = load(text)
    assert isinstance(data, dict)
    return data


def _templates(data: dict[str, Any], kind: str) -> list[dict[str, Any]]:
    return [e for block in data.get("template", []) for e in block.get(kind, [])]


def _script_write(script: dict[str, Any]) -> tuple[int, tuple[int, ...]]:
    (step,) = [s for s in script["sequence"] if "service" in s]
    assert step["service"] == "modbus.write_register", step
    value = step["data"]["value"]
    return step["data"]["address"], tuple(value) if isinstance(value, list) else (value,)


def _render(template: str, states: dict[str, str]) -> str:
    """A template as HA renders it: `states()`, `has_value()` and the `bitwise_and` filter, on the given states."""
    env = jinja2.Environment(undefined=jinja2.StrictUndefined)
    env.filters["bitwise_and"] = lambda a, b: a & b
    env.globals["states"] = lambda entity: states.get(entity, "unavailable")
    env.globals["has_value"] = lambda entity: states.get(entity, "unavailable") not in ("unavailable", "unknown")
    return env.from_string(template).render()


def _sensor_register(device: Device, e: dict[str, Any]) -> Register:
    reg = device.at_address(e["address"], e.get("input_type", "holding"))
    assert reg is not None and reg.address == e["address"], e
    return reg


# -- commands are scripts ------------------------------------------------------------------------


@pytest.mark.parametrize("device", EVERY, ids=[d.id for d in EVERY])
def test_every_command_is_a_script_and_destructive_ones_need_confirm(device: Device) -> None:
    default = {_script_write(s) for s in _package(device, "default").get("script", {}).values()}
    full = {_script_write(s): (key, s) for key, s in _package(device, "all").get("script", {}).items()}
    for command in device.commands:
        for write in command_writes(device, command):
            key, script = full[write]
            assert key.startswith(f"{device.id}_{command.name}"), (key, command.name)
            assert script["mode"] == "single" and "retries" in script["description"]
            if command.destructive:
                assert write not in default or any(not c.destructive and write in command_writes(device, c) for c in device.commands)
                assert script["alias"].startswith("DESTRUCTIVE: "), script
                (condition,) = [s for s in script["sequence"] if "condition" in s]
                assert script["sequence"].index(condition) == 0 and script["fields"]["confirm"]["required"] is True
                for confirm, sent in ((command.name, "True"), ("", "False"), ("yes", "False")):
                    template = condition["value_template"].replace("confirm", repr(confirm))
                    assert _render(template, {}) == sent
            else:
                assert write in default and "fields" not in script, command.name


def test_the_idm_rs_default_has_the_homing_script() -> None:
    device = next(d for d in DEVICES if d.id == "idm_rs")
    scripts = _package(device, "default")["script"]
    homing = device.register("pr_trigger")
    home = device.enum("pr_trigger").member("home")
    assert home is not None and scripts["idm_rs_start_homing"]["sequence"][0]["data"]["address"] == homing.address
    assert scripts["idm_rs_start_homing"]["sequence"][0]["data"]["value"] == home.value
    assert not any(key.startswith("idm_rs_restore_factory_defaults") for key in scripts)


# -- no write of a reported state ----------------------------------------------------------------


@pytest.mark.parametrize(("device", "selection"), CASES, ids=IDS)
def test_switches_write_only_members_that_may_be_written(device: Device, selection: str) -> None:
    (hub,) = _package(device, selection)["modbus"]
    for e in hub.get("switches", []):
        if "command_on" not in e:
            continue
        reg = device.at_address(e["address"])
        assert reg is not None
        if reg.enum is not None:
            members = {m.value: m for m in reg.enum.members}
            for value in (e["command_on"], e["command_off"]):
                word = value if reg.byte_order.value == "high_first" else ((value & 0xFF) << 8) | (value >> 8)
                assert members[word].writable and members[word].readable, (reg.name, word)


# -- templates -------------------------------------------------------------------------------------


@pytest.mark.parametrize(("device", "selection"), CASES, ids=IDS)
def test_flags_and_labels_are_templates_over_the_register_sensor(device: Device, selection: str) -> None:
    data = _package(device, selection)
    (hub,) = data["modbus"]
    sensors = {e["unique_id"]: e for e in hub.get("sensors", [])}
    flags = {e["unique_id"]: e for e in _templates(data, "binary_sensor")}
    labels = {e["unique_id"]: e for e in _templates(data, "sensor")}
    source_of: dict[str, str] = {}
    for uid, e in sensors.items():
        reg = _sensor_register(device, e)
        source = "sensor." + _slug(e["name"])
        source_of[uid] = source
        for field in reg.bitfields:
            if field.width != 1 or reserved_title(field.title):
                assert f"{uid}_{field.name}" not in flags
                continue
            flag = flags[f"{uid}_{field.name}"]
            for value, on in ((field.mask, "True"), (0, "False"), (((1 << 16 * reg.words) - 1) ^ field.mask, "False")):
                assert _render(flag["state"], {source: str(value)}) == on, (reg.name, field.name, value)
            assert _render(flag["availability"], {}) == "False"
        if reg.enum is not None and "virtual_count" not in e:
            label = labels[f"{uid}_label"]
            for member in reg.enum.members:
                shown = _render(label["state"], {source: str(member.value)})
                if member.readable:
                    assert shown == " ".join(member.title.split()) or shown == member.name, (member, shown)
                else:
                    assert shown == str(member.value), member  # never reported: not given a label
            assert _render(label["state"], {source: "65537"}) == "65537"
    assert len(flags) + len(labels) == sum(1 for uid in flags | labels if any(uid.startswith(u + "_") for u in sensors))


def _slug(name: str) -> str:
    from regmap.backends.homeassistant.scripts import object_id

    return object_id(name)


def test_hostile_labels_stay_text(tmp_path: Path) -> None:
    data = _package(HOSTILE, "all")
    rendered = 0
    for label in _templates(data, "sensor"):
        (hub,) = data["modbus"]
        (source,) = [e for e in hub["sensors"] if label["unique_id"] == e["unique_id"] + "_label"]
        reg = _sensor_register(HOSTILE, source)
        assert reg.enum is not None
        for member in reg.enum.members:
            shown = _render(label["state"], {"sensor." + _slug(source["name"]): str(member.value)})
            assert shown == (" ".join(member.title.split()) or member.name), (member.title, shown)
            rendered += 1
    assert rendered > 0


def test_the_template_sources_are_the_ids_home_assistant_gives(hass: Path) -> None:
    """HA's own slugify (its venv's homeassistant.util) on every sensor name a template reads."""
    sources = {
        t["availability"].split("'")[1]
        for d in [*EVERY, HOSTILE]
        for k in ("sensor", "binary_sensor")
        for t in _templates(_package(d, "all"), k)
    }
    names = sorted(
        {
            e["name"]
            for d in [*EVERY, HOSTILE]
            for e in _package(d, "all")["modbus"][0].get("sensors", [])
            if "sensor." + _slug(e["name"]) in sources
        }
    )
    assert names
    python = hass.parent / "python"
    code = "import json, sys\nfrom homeassistant.util import slugify\nprint(json.dumps([slugify(n) for n in json.load(sys.stdin)]))"
    result = subprocess.run([str(python), "-c", code], input=json.dumps(names), capture_output=True, text=True, timeout=120, check=True)
    theirs = json.loads(result.stdout)
    mismatched = [(n, _slug(n), t) for n, t in zip(names, theirs, strict=True) if _slug(n) != t]
    assert not mismatched


# -- classes -------------------------------------------------------------------------------------


@pytest.mark.parametrize(("device", "selection"), CASES, ids=IDS)
def test_state_classes_follow_the_register_kind(device: Device, selection: str) -> None:
    (hub,) = _package(device, selection)["modbus"]
    for e in hub.get("sensors", []):
        reg = _sensor_register(device, e)
        assert not reserved_title(reg.title)
        assert e.get("state_class") == expected_state_class(device, reg), (reg.name, e.get("state_class"))
        if reg.unit in ("Wh", "kWh", "MWh"):
            assert e["device_class"] == "energy"
        if "unit_of_measurement" in e:
            assert reg.unit is not None and e["unit_of_measurement"] == " ".join(reg.unit.split())


# -- made-up members: a reported "on" state, labels that try to leave their literal ----------------


def _with_members(device: Device, name: str, titles_access: list[tuple[str, Access]]) -> tuple[Device, Register]:
    reg = device.register(name)
    assert reg.enum is not None and len(reg.enum.members) >= len(titles_access)
    members = tuple(replace(m, title=title, access=access) for m, (title, access) in zip(reg.enum.members, titles_access, strict=False))
    changed = replace(reg, enum=replace(reg.enum, members=members))
    return replace(device, registers=tuple(changed if r.name == name else r for r in device.registers)), changed


def _hub_of(device: Device, reg: Register) -> dict[str, Any]:
    (text,) = render_hub(device, Selection((reg,), (), "test")).values()
    data = load(text)
    assert isinstance(data, dict)
    return data


def test_a_switch_never_writes_a_state_the_device_only_reports() -> None:
    c630s = next(d for d in DEVICES if d.id == "c630s")
    reg = c630s.register("power_loss_save")
    assert _hub_of(c630s, reg)["modbus"][0]["switches"]  # the two members go both ways: a switch
    device, changed = _with_members(c630s, "power_loss_save", [("Off", Access.READ_WRITE), ("On (reported only)", Access.READ)])
    (hub,) = _hub_of(device, changed)["modbus"]
    assert "switches" not in hub and [e["address"] for e in hub["sensors"]] == [reg.address]


def test_labels_with_quotes_and_braces_stay_text() -> None:
    idm = next(d for d in DEVICES if d.id == "idm_rs")
    evil = ["It's {{ 7 * 7 }} }}", 'Quote " and \\ back', "{% raw %}é 😀 '~", "x' ~ (states('sensor.a')) ~ '"]
    device, reg = _with_members(idm, "current_alarm", [(t, Access.READ_WRITE) for t in evil])
    data = _hub_of(device, reg)
    (label,) = _templates(data, "sensor")
    (source,) = data["modbus"][0]["sensors"]
    assert reg.enum is not None
    for member in reg.enum.members[: len(evil)]:
        assert _render(label["state"], {"sensor." + _slug(source["name"]): str(member.value)}) == member.title


@pytest.mark.parametrize(
    ("name", "slug"),
    [('Don’t "stop" it\'s', "dont_stop_its"), ("‘Quoted’ name", "quoted_name"), ("a'b", "ab"), ('"', "unknown"), ("É’t'é", "ete")],
)
def test_quotes_are_dropped_from_object_ids(name: str, slug: str) -> None:
    """Straight and curly quotes are dropped, joining the words around them (`dont`, not `don_t`)."""
    assert _slug(name) == slug
