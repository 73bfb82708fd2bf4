"""Home Assistant packages of a map with points scaled by another register (`scale_from`: value = raw x 10^sf):
raw modbus sensors for the point and its sf, a template sensor with the value, and for a writable point a
script that refuses what the Python runtime refuses. The templates are rendered with Jinja's sandbox and the
filters HA uses (its `int`/`float` take a default as Jinja's do) and compared with the runtime's
`scaled`/`unscaled`/`check_raw`/`raw_to_words`; `hass --script check_config` accepts the packages."""

from __future__ import annotations

import ast
import math
from pathlib import Path
from typing import Any

import pytest
from jinja2.sandbox import ImmutableSandboxedEnvironment

from regmap.backends.homeassistant import render_device, render_plant
from regmap.frontend import load_map, load_map_text
from regmap.frontend.plant import load_plant
from regmap.generate import render_plant as render_plant_targets
from regmap.homeauto.entities import device_class, state_class
from regmap.model import Device
from regmap.runtime_bridge import runtime_specs
from regmap_runtime.codec import RangeError, check_raw, raw_to_words
from regmap_runtime.scaling import scaled, unscaled

from support.hass_running import check_config
from support.homeauto_yaml import load
from support.plant_tcp_bus import write_plant

MAP = Path(__file__).resolve().parents[2] / "maps" / "scaled_from" / "inverter.yaml"
DEVICE = load_map(MAP)
POINTS = [reg for reg in DEVICE.registers if reg.scale_from is not None]
SFS = range(-4, 5)
RAWS = (0, 1, 7, 1234, 32767, -1, -1500, -32767, 65534, 123456, 4294967294)
VALUES: tuple[object, ...] = (
    0,
    15,
    20,
    25,
    250,
    2500,
    10000,
    10010,
    12.3,
    12.34,
    100.5,
    -10,
    0.1,
    1e6,
    "250",
    "abc",
    True,
    math.nan,
    math.inf,
)


def _package(device: Device, patterns: tuple[str, ...] | None = ("*",)) -> dict[str, Any]:
    (text,) = render_device(device, patterns).values()
    data = load(text)
    assert isinstance(data, dict)
    return data


def _render(template: str, states: dict[str, str], **variables: object) -> str:
    env = ImmutableSandboxedEnvironment()
    env.globals["states"] = lambda entity: states.get(entity, "unknown")
    env.globals["has_value"] = lambda entity: states.get(entity, "unknown") not in ("unknown", "unavailable")
    return env.from_string(template).render(**variables)


def _templates(data: dict[str, Any]) -> dict[str, dict[str, Any]]:
    return {e["unique_id"]: e for block in data.get("template", []) for e in block.get("sensor", [])}


def _sensors(data: dict[str, Any]) -> dict[str, dict[str, Any]]:
    (hub,) = data["modbus"]
    return {e["unique_id"]: e for e in hub["sensors"]}


def _slug(name: str) -> str:
    return "sensor." + "".join(c if c.isalnum() else "_" for c in name.lower()).strip("_").replace("__", "_")


def _sources(data: dict[str, Any], device: Device, name: str) -> tuple[str, str]:
    """The entity ids of the point's raw sensor and of its sf's sensor."""
    sensors = _sensors(data)
    reg = device.register(name)
    return _slug(sensors[f"{device.id}_{name}_raw"]["name"]), _slug(sensors[f"{device.id}_{reg.scale_from}"]["name"])


def test_each_point_is_a_raw_sensor_and_a_template_with_its_unit_and_classes() -> None:
    data = _package(DEVICE)
    sensors, templates = _sensors(data), _templates(data)
    for reg in POINTS:
        raw = sensors[f"sf_inverter_{reg.name}_raw"]
        assert raw["name"] == f"{reg.title} (raw)" and raw["precision"] == 0
        assert not {"unit_of_measurement", "device_class", "state_class", "scale", "offset"} & set(raw)
        assert raw.get("nan_value") == (reg.na[0] if reg.na else None)
        shown = templates[f"sf_inverter_{reg.name}"]
        assert shown["name"] == reg.title and shown.get("unit_of_measurement") == reg.unit
        assert shown.get("device_class") == device_class(reg) and shown.get("state_class") == state_class(DEVICE, reg)
        assert f"sf_inverter_{reg.scale_from}" in sensors
    assert templates["sf_inverter_wh"]["device_class"] == "energy" and templates["sf_inverter_wh"]["state_class"] == "total_increasing"


@pytest.mark.parametrize("name", [reg.name for reg in POINTS])
def test_the_template_shows_what_the_python_client_reads_and_nothing_for_not_available(name: str) -> None:
    data = _package(DEVICE)
    reg, shown = DEVICE.register(name), _templates(data)[f"sf_inverter_{name}"]
    sf_reg = DEVICE.register(reg.scale_from or "")
    raw_source, sf_source = _sources(data, DEVICE, name)
    for raw in (r for r in RAWS if reg.type.raw_min <= r <= reg.type.raw_max and r not in reg.na):
        for sf in SFS:
            states = {raw_source: str(raw), sf_source: str(sf)}
            assert _render(shown["availability"], states) == "True"
            value = scaled(raw, sf)
            assert value is not None and float(_render(shown["state"], states)) == value, (raw, sf)
    ok = {raw_source: "1234", sf_source: "-2"}
    assert _render(shown["state"], ok) == "12.34"  # correctly rounded, as the client: not 12.340000000000002
    for mark in reg.na:
        assert _render(shown["availability"], ok | {raw_source: str(int(mark))}) == "False"
    for mark in sf_reg.na:
        assert _render(shown["availability"], ok | {sf_source: str(int(mark))}) == "False"
    for gone in ("unknown", "unavailable"):
        assert _render(shown["availability"], ok | {raw_source: gone}) == "False"
        assert _render(shown["availability"], ok | {sf_source: gone}) == "False"


def test_a_point_selected_without_its_sf_still_reads_the_sf() -> None:
    data = _package(DEVICE, ("a",))
    assert set(_sensors(data)) == {"sf_inverter_a_raw", "sf_inverter_a_sf"}
    assert set(_templates(data)) == {"sf_inverter_a"}
    assert "script" not in data


# -- writes ------------------------------------------------------------------------------------------

WRITE_VARIANTS = {
    "u16": "",
    "s32 low word first": ", type: s32, word_order: low_first, min: -100000, max: 100000, na: [-99999]",
    "u32 bytes swapped": ", type: u32, byte_order: low_first, min: 0, max: 3000000",
}


def _variant(extra: str) -> Device:
    """The fixture with wmax_lim_pct of another type and order (`extra`: its keys; its sf moved past it)."""
    text = MAP.read_text(encoding="utf-8")
    if not extra:
        return load_map_text(text, "inverter.yaml")
    old = "type: u16, access: rw, unit: '%', min: 0, max: 1000"
    assert text.count(old) == 1 and text.count("wmax_lim_pct_sf, address: 0x0011") == 1
    text = text.replace(old, "access: rw, unit: '%'" + extra).replace(
        "wmax_lim_pct_sf, address: 0x0011", "wmax_lim_pct_sf, address: 0x0012"
    )
    return load_map_text(text, "inverter.yaml")


def _expected(device: Device, value: object, sf: int | None) -> int | None:
    spec = next(s for s in runtime_specs(device) if s.name == "wmax_lim_pct")
    try:
        raw = unscaled(spec, value, sf)
        check_raw(spec, raw)
    except RangeError:
        return None
    return raw


@pytest.mark.parametrize("variant", list(WRITE_VARIANTS))
def test_the_set_script_sends_exactly_what_the_runtime_would_and_refuses_the_rest(variant: str) -> None:
    device = _variant(WRITE_VARIANTS[variant])
    data = _package(device)
    script = data["script"]["sf_inverter_set_wmax_lim_pct"]
    update, variables, condition, write = script["sequence"]
    _, sf_source = _sources(data, device, "wmax_lim_pct")
    assert update == {"service": "homeassistant.update_entity", "target": {"entity_id": [sf_source]}}  # a fresh sf
    assert write["service"] == "modbus.write_register" and write["data"]["address"] == 0x0010
    (template,) = variables["variables"].values()
    spec = next(s for s in runtime_specs(device) if s.name == "wmax_lim_pct")
    sent = 0
    for sf in (*SFS, None):
        states = {sf_source: "-32768" if sf is None else str(sf)}
        for value in (*VALUES, 99999.0, -99999, 3000000, 3000010, -100010):
            shown = _render(template, states, value=value).strip()
            raw = int(shown) if shown else None
            assert raw == _expected(device, value, sf), (variant, value, sf, shown)
            passes = _render(condition["value_template"], {}, regmap_raw=raw if raw is not None else "") == "True"
            assert passes == (raw is not None)
            if raw is not None:
                words = ast.literal_eval(_render(write["data"]["value"], {}, regmap_raw=raw))
                assert (list(words) if isinstance(words, list) else [words]) == raw_to_words(spec, raw)
                sent += 1
    assert sent > 5
    for gone in ("unknown", "unavailable"):
        assert _render(template, {sf_source: gone}, value=250).strip() == ""


def test_the_header_says_how_scaled_points_are_shown_and_nothing_is_left_out() -> None:
    (text,) = render_device(DEVICE, ("*",)).values()
    assert "Registers scaled by another (value = raw x 10^sf)" in text
    assert "Not generated" not in text


# -- plants and HA's own check ---------------------------------------------------------------------


def test_a_plant_of_scaled_devices_gets_each_device_its_templates(tmp_path: Path) -> None:
    plant = load_plant(
        write_plant(tmp_path / "plant.yaml", "pv", [("line", "tcp: {host: 127.0.0.1, port: 1502}", [("inv1", MAP, 1), ("inv2", MAP, 2)])])
    )
    (text,) = render_plant(plant).values()
    data = load(text)
    templates = _templates(data)
    read_only = [reg.name for reg in POINTS if not reg.access.writable]
    assert sorted(templates) == sorted(f"pv_{dev}_{name}" for dev in ("inv1", "inv2") for name in read_only)
    assert templates["pv_inv2_a"]["name"] == "inv2 AC current" and "sensor.inv2_ac_current_raw" in templates["pv_inv2_a"]["state"]
    assert list(render_plant_targets(plant, ["homeassistant"])) == ["homeassistant"]


@pytest.mark.parametrize("patterns", [None, ("*",), "plant"], ids=["default", "all", "plant"])
def test_home_assistant_check_config_accepts_the_package(hass: Path, tmp_path: Path, patterns: tuple[str, ...] | str | None) -> None:
    if patterns == "plant":
        line = [("line", "tcp: {host: 127.0.0.1, port: 1502}", [("inv1", MAP, 1), ("inv2", MAP, 2)])]
        (text,) = render_plant(load_plant(write_plant(tmp_path / "plant.yaml", "pv", line))).values()
    else:
        assert not isinstance(patterns, str)
        (text,) = render_device(DEVICE, patterns).values()
    check_config(hass, tmp_path, text)


# -- the import reads the templates back -----------------------------------------------------------


def test_importing_the_package_gives_each_point_its_scale_factor_back(tmp_path: Path) -> None:
    from support.homeauto_roundtrip import reimport

    (text,) = render_device(DEVICE, ("*",)).values()
    (again,), report = reimport(text, tmp_path, "inverter")
    for reg in POINTS:
        back = again.at_address(reg.address, "holding")
        sf, sf_back = DEVICE.register(reg.scale_from or ""), again.at_address(DEVICE.register(reg.scale_from or "").address, "holding")
        assert back is not None and sf_back is not None
        assert (back.type, back.title, back.unit, back.na, back.scale_from) == (reg.type, reg.title, reg.unit, reg.na, sf_back.name)
        assert (sf_back.type, sf_back.na) == (sf.type, sf.na)
    assert sum("from its template sensor" in line for line in report) == len(POINTS)
    plain = text.replace("raw * 10 ** sf if sf >= 0", "raw * 10 ** sf if sf > 0")  # not the generated shape: not read
    (other,), _ = reimport(plain, tmp_path, "other")
    assert [r.name for r in other.registers if r.scale_from is not None] == []
