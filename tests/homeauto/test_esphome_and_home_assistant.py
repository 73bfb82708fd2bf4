"""ESPHome packages and Home Assistant modbus hubs (issues 21 and 19): accepted by the real tools, and equal to the model.

The tools run once per map (`esphome config`, `hass --script check_config`), seed maps and issue 19's
fixture maps, on the default selection and on the full one; the semantic tests read the generated YAML
back and decode the example responses the way ESPHome (value_type through pymodbus'
convert_from_registers, the generated lambdas compiled and run with g++, multiply then offset) and Home
Assistant (data_type as HA's struct format, swap, scale then offset) do.
"""

from __future__ import annotations

import math
import re
import shutil
import struct
import subprocess
import sys
from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path
from typing import Any, Literal

import pytest
import yaml
from pymodbus.client.mixin import ModbusClientMixin

from regmap.backends.esphome import render_device as esphome_files
from regmap.backends.homeassistant import render_device as hass_files
from regmap.frontend import load_map
from regmap.homeauto.entities import planned, reserved
from regmap.model import ByteOrder, DataType, Device, Register, WordOrder
from regmap.runtime_bridge import documented_addresses, read_plan

from conftest import FIXTURE_MAPS, GENERATED, MAPS, ROOT
from support.hass_running import check_config
from support.homeauto_yaml import esphome_config

HOSTILE = ROOT / "tests" / "maps" / "hostile" / "hostile.yaml"
ALL = ("*",)

# The tools' spellings, written out here independently of the back ends.
ESP_TYPES = {"U_WORD": (1, False, False), "S_WORD": (1, True, False), "U_DWORD": (2, False, False), "S_DWORD": (2, True, False)}
ESP_TYPES |= {"U_DWORD_R": (2, False, True), "S_DWORD_R": (2, True, True)}  # (words, signed, low word first)
ESP_TYPES |= {"U_QWORD": (4, False, False), "S_QWORD": (4, True, False), "U_QWORD_R": (4, False, True), "S_QWORD_R": (4, True, True)}
ESP_FLOATS = {"FP32": (2, True, False), "FP32_R": (2, True, True)}
HASS_TYPES = {"uint16": (1, False), "int16": (1, True), "uint32": (2, False), "int32": (2, True)}
HASS_TYPES |= {"uint64": (4, False), "int64": (4, True), "float32": (2, True), "float64": (4, True)}
HASS_STRUCT = {"uint16": "H", "int16": "h", "uint32": "I", "int32": "i", "uint64": "Q", "int64": "q", "float32": "f", "float64": "d"}
ESP_SPACE = {"holding": "holding", "read": "input", "coil": "coil", "discrete_input": "discrete_input"}
HASS_SPACE = {"holding": "holding", "input": "input", "coil": "coil", "discrete_input": "discrete_input"}
DT = ModbusClientMixin.DATATYPE
PYMODBUS_TYPE = {"U_WORD": DT.UINT16, "S_WORD": DT.INT16, "U_DWORD": DT.UINT32, "S_DWORD": DT.INT32, "U_QWORD": DT.UINT64}
PYMODBUS_TYPE |= {"S_QWORD": DT.INT64, "FP32": DT.FLOAT32}


class _Loader(yaml.SafeLoader):
    pass


@dataclass(frozen=True)
class Tagged:
    tag: str
    value: str


_Loader.add_multi_constructor("!", lambda loader, suffix, node: Tagged("!" + suffix, loader.construct_scalar(node)))


def load(text: str) -> Any:
    return yaml.load(text, Loader=_Loader)  # a SafeLoader that keeps tags as data


def _only(files: dict[str, str]) -> str:
    (text,) = files.values()
    return text


def _signed(value: int, bits: int) -> int:
    return value - (1 << bits) if value >= 1 << (bits - 1) else value


def _words_value(words: list[int], n: int, signed: bool, low_first: bool) -> int:
    ws = words[:n][::-1] if low_first else words[:n]
    raw = 0
    for w in ws:
        raw = (raw << 16) | w
    return _signed(raw, 16 * n) if signed else raw


def _devices() -> list[Device]:
    return [load_map(p) for p in MAPS]


DEVICES = _devices()
FIXTURES = [load_map(p, display_name=p.relative_to(ROOT).as_posix()) for p in FIXTURE_MAPS]
EVERY = DEVICES + FIXTURES


# -- the real tools ---------------------------------------------------------------------------------


def _esphome_config(esphome: Path, tmp_path: Path, package: str) -> None:
    esphome_config(esphome, tmp_path, package)


def _package(target: str, device: Device, selection: str) -> str:
    if selection == "all":
        return _file(target, device, ALL)
    if device in FIXTURES:  # not committed under generated/
        return _file(target, device, None)
    return (GENERATED / target / f"{device.id}.yaml").read_text(encoding="utf-8")


@pytest.mark.parametrize("selection", ["default", "all"])
@pytest.mark.parametrize("device", EVERY, ids=[d.id for d in EVERY])
def test_esphome_config_accepts_the_package(esphome: Path, tmp_path: Path, device: Device, selection: str) -> None:
    _esphome_config(esphome, tmp_path, _package("esphome", device, selection))


@pytest.mark.parametrize("selection", ["default", "all"])
@pytest.mark.parametrize("device", EVERY, ids=[d.id for d in EVERY])
def test_home_assistant_check_config_accepts_the_hub(hass: Path, tmp_path: Path, device: Device, selection: str) -> None:
    check_config(hass, tmp_path, _package("homeassistant", device, selection))


# -- the hostile map ------------------------------------------------------------------------------


def _tags(text: str) -> list[str]:
    tags = [getattr(e, "tag", None) for e in yaml.parse(text)]
    return [t for t in tags if isinstance(t, str) and not t.startswith("tag:yaml.org")]


def _check_hostile_yaml(text: str) -> None:
    assert not any(isinstance(e, yaml.AliasEvent) or getattr(e, "anchor", None) for e in yaml.parse(text)), "an anchor or alias"
    for line in text.splitlines():
        assert "!secret" not in line.split("#")[0] and "!include" not in line.split("#", 1)[0], line


def test_hostile_map_validates_and_injects_nothing(esphome: Path, hass: Path, tmp_path: Path) -> None:
    device = load_map(HOSTILE)
    package, hub = _only(esphome_files(device, ALL)), _only(hass_files(device, ALL))
    for text in (package, hub):
        _check_hostile_yaml(text)
    assert _tags(hub) == []
    assert set(_tags(package)) <= {"!lambda"}
    data = load(package)
    lambdas = [a["lambda"] for b in data.get("button", []) for a in b["on_press"]]
    assert len(lambdas) == len(_tags(package)) > 0
    for code in lambdas:  # built from numbers and the controller id only
        assert code.value.startswith(
            "id(${hostile_dev_device_id}_controller)->queue_command(esphome::modbus_controller::ModbusCommandItem::"
        ), code
        assert "pwn" not in code.value.lower() and '"' not in code.value
    assert "$" not in package.split("\nsubstitutions:", 1)[1].replace("${hostile_dev_", "")
    titles = {
        e["name"] for platform in ("sensor", "number", "select", "text_sensor", "binary_sensor", "switch") for e in data.get(platform, [])
    }
    assert any("__import__" in t for t in titles)  # the hostile text survives, as text
    (tmp_path / "esp").mkdir()
    (tmp_path / "ha").mkdir()
    _esphome_config(esphome, tmp_path / "esp", package)
    check_config(hass, tmp_path / "ha", hub)


# -- semantics: every entity equals the model -------------------------------------------------------


_FILES: dict[tuple[str, str, tuple[str, ...] | None], str] = {}


def _file(target: str, device: Device, patterns: tuple[str, ...] | None) -> str:
    """A generated file, made once per run (the full C630S selection is large)."""
    key = (target, device.id, patterns)
    if key not in _FILES:
        _FILES[key] = _only((esphome_files if target == "esphome" else hass_files)(device, patterns))
    return _FILES[key]


def _esp_entities(device: Device, patterns: tuple[str, ...] | None = ALL) -> list[tuple[str, dict[str, Any]]]:
    data = load(_file("esphome", device, patterns))
    return [
        (platform, e)
        for platform in ("sensor", "number", "select", "text_sensor", "binary_sensor", "switch")
        for e in data.get(platform, [])
    ]


def _hass_entities(device: Device, patterns: tuple[str, ...] | None = ALL) -> list[tuple[str, dict[str, Any]]]:
    (hub,) = load(_file("homeassistant", device, patterns))["modbus"]
    return [(platform, e) for platform in ("sensors", "binary_sensors", "switches") for e in hub.get(platform, [])]


def _ha_custom(e: dict[str, Any]) -> tuple[int, str]:
    """A custom sensor that reads a whole aligned unit (`structure` '>2xh', '>h2x'): its register's address and data type."""
    match = re.fullmatch(r">(?:(\d+)x)?([hHiIqQfd])(?:\d+x)?", e["structure"])
    assert match is not None, e
    return e["address"] + int(match.group(1) or 0) // 2, {code: name for name, code in HASS_STRUCT.items()}[match.group(2)]


def _ha_address(e: dict[str, Any]) -> int:
    return _ha_custom(e)[0] if e.get("data_type") == "custom" else int(e["address"])


def _ha_unit_shared(device: Device) -> set[str]:
    """Registers HA cannot load: the device reads only whole aligned units, and an earlier register's sensor has the unit's address."""
    a = device.transport.read_alignment
    if a is None:
        return set()
    taken: set[tuple[str, int]] = set()
    shared = set()
    for reg in sorted(device.registers, key=lambda r: r.address):
        if not reg.access.readable or reg.space not in a.spaces:
            continue
        start = reg.first_address - reg.first_address % a.words
        if (reg.space, start) in taken and reg.first_address % a.words:
            shared.add(reg.name)
        taken.add((reg.space, start))
    return shared


def _scale_of(entity: dict[str, Any], platform: str) -> float:
    if platform == "number":
        return 1 / float(entity.get("multiply", 1))
    multiply = [f["multiply"] for f in entity.get("filters", []) if "multiply" in f]
    return float(multiply[0]) if multiply else 1.0


def _offset_of(entity: dict[str, Any]) -> float:
    offsets = [f["offset"] for f in entity.get("filters", []) if "offset" in f]
    if offsets:  # ESPHome applies filters in order: the offset after the multiply
        assert [next(iter(f)) for f in entity["filters"]][-1] == "offset", entity
    return float(offsets[0]) if offsets else 0.0


def _swapped(reg: Register) -> bool:
    return reg.byte_order is ByteOrder.LOW_FIRST and not reg.type.is_bool


def _esp_register(device: Device, e: dict[str, Any]) -> Register:
    """The register an item reads: ESPHome's `offset` counts bytes from `address` (an aligned read's padding first)."""
    space = ESP_SPACE[e.get("register_type", "holding")]
    address = e["address"] + (e.get("offset", 0) // 2 if space in ("holding", "input") else 0)
    reg = device.at_address(address, space)
    assert reg is not None and reg.address == address, e
    return reg


@pytest.mark.parametrize("device", EVERY, ids=[d.id for d in EVERY])
def test_esphome_entities_equal_the_model(device: Device) -> None:
    seen = set()
    for platform, e in _esp_entities(device):
        reg = _esp_register(device, e)
        seen.add(reg.name)
        lambda_ = "lambda" in e
        if platform in ("sensor", "number") and "bitmask" not in e:
            # a lambda reads what no value_type can say: a double, a byte-swapped value (ESPHome has neither), a
            # sensor's "not available" marker (read as NaN: unknown)
            expected = reg.type is DataType.F64 or _swapped(reg) or (platform == "number" and reg.offset != 0)
            assert lambda_ == (expected or (platform == "sensor" and bool(reg.na))), e
            if platform == "sensor" and reg.na:
                assert all(f"if (raw == 0x{bits:X}u) return NAN;" in e["lambda"].value for bits in reg.na_bits), e
            if platform == "sensor" and lambda_:
                assert TYPE_WORDS[e["value_type"]] == reg.words, e
            elif not lambda_:
                words, signed, low_first = {**ESP_TYPES, **ESP_FLOATS}[e["value_type"]]
                assert (words, signed) == (reg.type.words, reg.type.signed), e
                assert e["value_type"].startswith("FP") == reg.type.is_float, e
                assert low_first == (reg.wide and reg.word_order is WordOrder.LOW_FIRST), e
            assert math.isclose(_scale_of(e, platform), float(reg.scale), rel_tol=1e-12), e
            if platform == "sensor":
                assert math.isclose(_offset_of(e), float(reg.offset)), e
        if platform == "number":
            assert reg.access.writable
            assert math.isclose(e["min_value"], max(-16777215, float(reg.raw_min * reg.scale)) + float(reg.offset))
            assert math.isclose(e["max_value"], min(16777215, float(reg.raw_max * reg.scale)) + float(reg.offset))
        if "bitmask" in e:
            masks = {b.mask for b in reg.bitfields}
            if _swapped(reg):
                masks = {((m & 0xFF) << 8) | (m >> 8) for m in masks}
            assert e["bitmask"] in masks, e
        if platform == "select":
            values = sorted(m.value for m in reg.enum.members if m.writable) if reg.enum else []  # never a reported state
            if _swapped(reg):
                values = sorted(((v & 0xFF) << 8) | (v >> 8) for v in values)
            elif reg.type is DataType.F32:  # a setting coded as a float: ESPHome's select compares its bits
                values = sorted(struct.unpack(">I", struct.pack(">f", v))[0] for v in values)
                assert e["value_type"] in ("U_DWORD", "U_DWORD_R"), e
            assert sorted(e["optionsmap"].values()) == values, e
        if platform in ("number", "select", "switch"):
            assert reg.access.writable, e
        if reg.type.is_bool:
            assert platform in ("binary_sensor", "switch") and e["register_type"] in ("coil", "discrete_input"), e
            assert platform == "binary_sensor" or reg.space == "coil"
        if reg.type.is_string:
            assert platform == "text_sensor" and e["register_count"] == reg.words and e["response_size"] == 2 * reg.words, e
            assert lambda_, e
    readable = {r.name for r in device.registers if r.access.readable and not reserved(r.title)}
    assert seen == readable  # every readable register has an entity under the full selection (none the manual calls reserved)


def _ha_swap(reg: Register) -> str | None:
    """HA's swap names, from its docs: byte (bytes in each word), word (words), word_byte (both)."""
    word = reg.wide and reg.word_order is WordOrder.LOW_FIRST
    return {(True, True): "word_byte", (True, False): "byte", (False, True): "word"}.get((_swapped(reg), word))


@pytest.mark.parametrize("device", EVERY, ids=[d.id for d in EVERY])
def test_home_assistant_entities_equal_the_model(device: Device) -> None:
    seen = set()
    for platform, e in _hass_entities(device):
        space = (
            HASS_SPACE[e["input_type"]]
            if "input_type" in e
            else ("coil" if e.get("write_type", "holding").startswith("coil") else "holding")
        )
        reg = device.at_address(_ha_address(e), space)
        assert reg is not None and reg.address == _ha_address(e), e
        assert e["slave"] in range(device.transport.slave_min, device.transport.slave_max + 1)
        if platform == "sensors":
            assert not reg.type.is_bool
            assert e.get("swap") == _ha_swap(reg), e
            if reg.type.is_string:
                assert e["data_type"] == "string" and e["count"] == reg.words, e
                seen.add(reg.name)
                continue
            data_type = _ha_custom(e)[1] if e["data_type"] == "custom" else e["data_type"]
            words, signed = HASS_TYPES[data_type]
            assert (words, signed) == (reg.type.words, reg.type.signed), e
            assert data_type.startswith("float") == reg.type.is_float, e
            assert math.isclose(float(e.get("scale", 1)), float(reg.scale), rel_tol=1e-12), e
            assert math.isclose(float(e.get("offset", 0)), float(reg.offset)), e
        for i in range(e.get("virtual_count", 0) + 1):  # a virtual entity reads the next registers of its array
            nxt = device.at_address(reg.address + i * reg.words, reg.space)
            assert nxt is not None and (nxt.type, nxt.scale, nxt.array and nxt.array.member) == (
                reg.type,
                reg.scale,
                reg.array and reg.array.member,
            )
            seen.add(nxt.name)
        if platform == "binary_sensors" and reg.type.is_bool:
            assert e["input_type"] == reg.space, e
        if platform == "switches":
            assert reg.access.writable and e["verify"]["address"] == reg.address
            if reg.type.is_bool:
                assert e["write_type"] in ("coil", "coils") and e["verify"]["input_type"] == "coil", e
    assert seen == {r.name for r in device.registers if r.access.readable and not reserved(r.title)} - _ha_unit_shared(device)


@pytest.mark.parametrize("device", FIXTURES, ids=[d.id for d in FIXTURES])
def test_poll_classes_become_scan_intervals_and_skips(device: Device) -> None:
    """HA: static 0 (read once at start-up), fast 5, normal 10 (settings 300), slow 60 (settings 300);
    ESPHome: static skips 65535 updates, fast none, and the other classes keep those rates on its tick."""
    tick = 5 if any(r.poll.value == "fast" for r in device.registers if r.access.readable) else 10
    data = load(_file("esphome", device, ALL))
    subs = data["substitutions"]
    assert subs[f"{device.id}_update_interval"] == f"{tick}s"
    for _platform, e in _hass_entities(device):
        space = HASS_SPACE[e["input_type"]] if "input_type" in e else ("coil" if e.get("write_type", "").startswith("coil") else "holding")
        reg = device.at_address(_ha_address(e), space)
        assert reg is not None
        setting = reg.access.writable
        expected = {"static": 0, "fast": 5, "normal": 300 if setting else 10, "slow": 300 if setting else 60}[reg.poll.value]
        assert e["scan_interval"] == expected, (reg.name, e)
    for _platform, e in _esp_entities(device):
        reg = _esp_register(device, e)
        skip = e.get("skip_updates", 0)
        if isinstance(skip, str):
            skip = int(subs[skip.removeprefix("${").removesuffix("}")])
        seconds = tick * (skip + 1)
        if reg.poll.value == "static":
            assert skip == 65535, e
        else:
            block_regs = [
                device.register(s.name)
                for b, _, _ in planned(device, [r for r in device.registers if r.access.readable], 255)
                for s in b.registers
                if reg.name in [x.name for x in b.registers]
            ]
            setting = all(r.access.writable for r in block_regs)
            expected = {"fast": 5, "normal": 300 if setting else 10, "slow": 60}[reg.poll.value]
            assert seconds == expected, (reg.name, e, seconds)


# -- decoding the example responses as the tools do -----------------------------------------------

TYPE_WORDS = {"U_WORD": 1, "S_WORD": 1, "U_DWORD": 2, "S_DWORD": 2, "U_DWORD_R": 2, "S_DWORD_R": 2, "FP32": 2, "FP32_R": 2}
TYPE_WORDS |= {"U_QWORD": 4, "S_QWORD": 4, "U_QWORD_R": 4, "S_QWORD_R": 4}
READS = {0x01: "coil", 0x02: "discrete_input", 0x03: "holding", 0x04: "input"}


def _responses(device: Device) -> list[tuple[str, int, bytes, Any]]:
    """(space, start address, data bytes, example) of every read response among the map's examples."""
    out = []
    for ex in device.examples:
        frame = ex.wire_frame
        if ex.direction != "response" or ex.request is None or frame[1] not in READS or not ex.values:
            continue
        request = device.example(ex.request).wire_frame
        start = int.from_bytes(request[2:4], "big")
        out.append((READS[frame[1]], start, frame[3 : 3 + frame[2]], ex))
    return out


def _expected(reg: Register, raw: Any, value: Any) -> float | str | bool | None:
    if reg.type.is_timestamp:  # ESPHome's text sensor: the ISO 8601 time the map records (HA's raw sensor: the seconds)
        return value if isinstance(value, str) else None
    if isinstance(raw, (str, bool)) or reg.type.is_bool:
        chosen: float | str | bool | None = raw if raw is not None else value
        return chosen
    if isinstance(value, int | float) and not isinstance(value, bool):
        return float(value)
    if raw is None or reg.enum is not None:
        return None
    return float(raw) * float(reg.scale) + float(reg.offset)


UNAVAILABLE = "unavailable"  # what an example of the device's "not available" marker expects


def _ha_value(e: dict[str, Any], words: list[int]) -> float | str | None:
    """What HA's modbus sensor makes of the words: its swap (bytes in each word, then the word order),
    the bytes big-endian, struct with the data type's format, then scale and offset; None (unavailable)
    for its `nan_value` (also negated, as HA compares) and for a NaN float."""
    if e["data_type"] == "custom":  # a whole aligned unit: `words` are its register's own, the pad words around it are zero
        address, data_type = _ha_custom(e)
        before = address - e["address"]
        unit = [0] * before + list(words[: struct.calcsize(HASS_STRUCT[data_type]) // 2])
        unit += [0] * (e["count"] - len(unit))
        (raw,) = struct.unpack(e["structure"], b"".join(w.to_bytes(2, "big") for w in unit))
        return _ha_scaled(e, raw)
    n = e["count"] if e["data_type"] == "string" else struct.calcsize(HASS_STRUCT[e["data_type"]]) // 2
    regs = list(words[:n])
    if e.get("swap") in ("byte", "word_byte"):
        regs = [int.from_bytes(r.to_bytes(2, "little"), "big") for r in regs]
    if e.get("swap") in ("word", "word_byte"):
        regs.reverse()
    data = b"".join(r.to_bytes(2, "big") for r in regs)
    if e["data_type"] == "string":
        return data.decode()
    (raw,) = struct.unpack(">" + HASS_STRUCT[e["data_type"]], data)
    return _ha_scaled(e, raw)


def _ha_scaled(e: dict[str, Any], raw: float) -> float | None:
    nan_value = e.get("nan_value")
    if (nan_value is not None and raw in (nan_value, -nan_value)) or raw != raw:
        return None
    return float(e.get("scale", 1)) * float(raw) + float(e.get("offset", 0))


def _esp_value(e: dict[str, Any], platform: str, words: list[int]) -> float:
    """What ESPHome's value_type makes of the words, decoded by pymodbus (an independent decoder)."""
    name = e["value_type"]
    n = TYPE_WORDS[name]
    order: Literal["big", "little"] = "little" if name.endswith("_R") else "big"
    value = ModbusClientMixin.convert_from_registers(list(words[:n]), PYMODBUS_TYPE[name.removesuffix("_R")], word_order=order)
    assert isinstance(value, int | float)
    return float(value) * _scale_of(e, platform) + (_offset_of(e) if platform == "sensor" else 0.0)


@dataclass
class _LambdaCase:
    code: str
    kind: str  # float, text, or write (a number's write_lambda: x -> the value ESPHome then sends)
    data: bytes
    offset: int
    x: float = 0.0


def _run_lambdas(tmp_path: Path, cases: list[_LambdaCase]) -> list[str]:
    """Compile the generated lambdas as ESPHome declares them (item, x, data) -> optional, with g++
    -Wall -Wextra -Werror -fsanitize=undefined, run each on its bytes and return what each returned."""
    compiler = shutil.which("g++")
    if compiler is None:
        pytest.skip("g++ is not installed")
    parts = [
        "#include <cmath>\n#include <cstdint>\n#include <cstdio>\n#include <cstring>\n#include <optional>\n#include <string>\n#include <vector>\n",
        "struct Item { uint8_t offset; };\n",
    ]
    calls = []
    for i, case in enumerate(cases):
        ret = "std::string" if case.kind == "text" else "float"
        arg = "std::string x" if case.kind == "text" else "float x"
        third = "std::vector<uint16_t> &payload" if case.kind == "write" else "const std::vector<uint8_t> &data"
        unused = "(void) payload;" if case.kind == "write" else "(void) data;"
        parts.append(
            f"static std::optional<{ret}> lambda_{i}(Item *item, {arg}, {third}) {{\n(void) item; (void) x; {unused}\n{case.code}\n}}\n"
        )
        data = ", ".join(str(b) for b in case.data) or "0"
        x = 'std::string("")' if case.kind == "text" else f"{case.x!r}f"
        if case.kind == "write":
            # ESPHome's number then sends float_to_payload(value, U_WORD / S_WORD): llroundf(value) & 0xFFFF
            show = 'std::printf("%u\\n", static_cast<unsigned>(llroundf(*r) & 0xFFFF));'
            calls.append(f"{{ Item item{{0}}; std::vector<uint16_t> payload; auto r = lambda_{i}(&item, {x}, payload); {show} }}")
            continue
        show = 'std::printf("%s\\n", r->c_str());' if case.kind == "text" else 'std::printf("%.9g\\n", static_cast<double>(*r));'
        calls.append(
            f"{{ Item item{{{case.offset}}}; std::vector<uint8_t> data{{{data}}}; auto r = lambda_{i}(&item, {x}, data); {show} }}"
        )
    parts.append("int main() {\n" + "\n".join(calls) + "\nreturn 0;\n}\n")
    source = tmp_path / "lambdas.cpp"
    source.write_text("".join(parts), encoding="utf-8")
    binary = tmp_path / "lambdas"
    flags = ["-std=gnu++20", "-Wall", "-Wextra", "-Werror", "-fsanitize=undefined", "-fno-sanitize-recover=all"]
    built = subprocess.run([compiler, *flags, str(source), "-o", str(binary)], capture_output=True, text=True, check=False)
    assert built.returncode == 0, built.stderr
    ran = subprocess.run([str(binary)], capture_output=True, text=True, check=False, timeout=60)
    assert ran.returncode == 0 and not ran.stderr, ran.stderr
    return ran.stdout.splitlines()


@pytest.mark.parametrize("device", EVERY, ids=[d.id for d in EVERY])
def test_example_responses_decode_as_the_map_says(device: Device, tmp_path: Path) -> None:
    esp = {(r.space, r.address): (p, e) for p, e in _esp_entities(device) if "bitmask" not in e and (r := _esp_register(device, e))}
    ha: dict[tuple[str, int], dict[str, Any]] = {}
    for p, e in _hass_entities(device):
        if p == "sensors":
            ha[(HASS_SPACE[e["input_type"]], _ha_address(e))] = e
    checked = 0
    lambdas: list[tuple[_LambdaCase, Any, str]] = []
    for space, start, data, ex in _responses(device):
        words = [int.from_bytes(data[i : i + 2], "big") for i in range(0, len(data) - 1, 2)]
        for v in ex.values:
            reg = v.register
            if (
                v.words is not None
                or reg.space != space
                or not start <= reg.address < start + (8 * len(data) if reg.type.is_bool else len(words))
            ):
                continue
            expected = UNAVAILABLE if v.not_available else _expected(reg, v.raw, v.value)
            if reg.type.is_bool:  # a coil or discrete input: ESPHome's coil_from_vector(offset, data)
                bit = reg.address - start
                assert bool(data[bit // 8] & (1 << (bit % 8))) == bool(expected), (ex.id, reg.name)
                platform, e = esp[(space, reg.address)]
                assert platform in ("binary_sensor", "switch")
                checked += 1
                continue
            mine = words[reg.address - start :]
            offset = 2 * (reg.address - start)
            platform, e = esp[(space, reg.address)]
            if "lambda" in e and platform in ("sensor", "text_sensor"):
                kind = "text" if platform == "text_sensor" else "float"
                lambdas.append((_LambdaCase(e["lambda"].value, kind, data, offset), expected, f"{ex.id} {reg.name}"))
                if platform == "sensor" and expected is not None and expected != UNAVAILABLE:
                    lambdas[-1] = (lambdas[-1][0], (float(expected) - _offset_of(e)) / _scale_of(e, platform), lambdas[-1][2])
            elif platform in ("sensor", "number") and "lambda" not in e:
                if expected is not None and expected != UNAVAILABLE:
                    got = _esp_value(e, platform, mine)
                    assert math.isclose(got, float(expected), rel_tol=1e-6, abs_tol=1e-9), (ex.id, reg.name, got, expected)
                    checked += 1
            elif platform == "text_sensor":
                hexbytes = "".join(f"{w:04x}" for w in mine[: reg.words])
                labels = {m["from"]: m["to"] for m in e["filters"][0]["map"]}
                assert reg.enum is not None
                member = reg.enum.member(str(v.value)) or reg.enum.by_value(v.raw if isinstance(v.raw, int) else -1)
                assert member is not None and labels[hexbytes].startswith(" ".join(member.title.split())[:10].replace("/", "\u2044"))
                checked += 1
            elif platform == "select":
                value = int.from_bytes(b"".join(w.to_bytes(2, "big") for w in mine[: reg.words]), "big")
                if not _swapped(reg):
                    value = _words_value(mine, reg.words, reg.signed, reg.word_order is WordOrder.LOW_FIRST)
                assert value in e["optionsmap"].values()
            if (space, reg.address) in ha and expected == UNAVAILABLE:
                # HA: unavailable for its one nan_value and for a NaN float; a second marker is listed as not generated
                got_ha = _ha_value(ha[(space, reg.address)], mine)
                assert got_ha is None or (v.raw is not None and v.raw != reg.na[0]), (ex.id, reg.name, got_ha)
                checked += 1
            elif (space, reg.address) in ha and expected is not None:
                got_ha = _ha_value(ha[(space, reg.address)], mine)
                assert got_ha is not None, (ex.id, reg.name)
                if reg.type.is_timestamp:  # the raw sensor's seconds; its template sensor makes the time (test_ha_timestamps.py)
                    assert got_ha == v.raw, (ex.id, reg.name, got_ha, v.raw)
                elif isinstance(got_ha, str):
                    # HA decodes every byte: NUL padding stays in its state, space padding too
                    assert got_ha.split("\0", 1)[0].rstrip(" " if reg.padding == "space" else "") == expected, (ex.id, reg.name, got_ha)
                else:
                    assert math.isclose(got_ha, float(expected), rel_tol=1e-6, abs_tol=1e-9), (ex.id, reg.name, got_ha, expected)
                checked += 1
    if lambdas:
        outputs = _run_lambdas(tmp_path, [case for case, _, _ in lambdas])
        for (case, expected, what), out in zip(lambdas, outputs, strict=True):
            if case.kind == "text":
                assert out == expected, (what, out, expected)
            elif expected == UNAVAILABLE:  # the device's "not available" marker: NaN, which ESPHome shows as unknown
                assert out == "nan", (what, out)
            elif expected is not None:
                assert math.isclose(float(out), float(expected), rel_tol=1e-6), (what, out, expected)
            checked += 1
    assert checked > 0


def test_the_lambdas_decode_every_order_as_struct_does(tmp_path: Path) -> None:
    """Every type x word order x byte order a lambda reads, on values struct encodes (an independent
    encoder), including a double beyond float's range, NaN, negative numbers and space-padded text."""
    from dataclasses import replace

    from regmap.backends.esphome import lambdas as esp_lambdas

    base = next(d for d in FIXTURES if d.id == "fixture_power_meter").registers[0]
    cases: list[tuple[_LambdaCase, str]] = []
    samples = {DataType.U16: 0xBEEF, DataType.S16: -2, DataType.U32: 0xDEADBEEF, DataType.S32: -123456, DataType.F32: -1.5}
    samples |= {DataType.U64: 123456789012, DataType.S64: -98765, DataType.F64: 2.5e-3}
    codes = {DataType.U16: "H", DataType.S16: "h", DataType.U32: "I", DataType.S32: "i", DataType.F32: "f"}
    codes |= {DataType.U64: "Q", DataType.S64: "q", DataType.F64: "d"}
    for data_type, value in samples.items():
        for word_order in WordOrder:
            for byte_order in ByteOrder:
                reg = replace(base, type=data_type, word_order=word_order, byte_order=byte_order)
                packed = struct.pack(">" + codes[data_type], value)
                ws = [packed[i : i + 2] for i in range(0, len(packed), 2)]
                if word_order is WordOrder.LOW_FIRST and len(ws) > 1:
                    ws.reverse()
                if byte_order is ByteOrder.LOW_FIRST:
                    ws = [w[::-1] for w in ws]
                wire = b"\x11\x22" + b"".join(ws)  # at byte offset 2 of the response
                cases.append((_LambdaCase(esp_lambdas.raw_lambda(reg), "float", wire, 2), f"{float(value):.9g}"))
    big = replace(base, type=DataType.F64)
    cases.append((_LambdaCase(esp_lambdas.raw_lambda(big), "float", struct.pack(">d", 1e300), 0), "inf"))
    cases.append((_LambdaCase(esp_lambdas.raw_lambda(big), "float", struct.pack(">d", float("nan")), 0), "nan"))
    cases.append((_LambdaCase(esp_lambdas.raw_lambda(big), "float", b"\0" * 7, 0), "nan"))  # a response too short
    text = replace(base, type=DataType.STRING, string_words=3, padding="space", byte_order=ByteOrder.LOW_FIRST)
    cases.append((_LambdaCase(esp_lambdas.text_lambda(text), "text", b"BAC   ", 0), "AB C"))
    latin = replace(base, type=DataType.STRING, string_words=2, encoding="latin-1")
    cases.append((_LambdaCase(esp_lambdas.text_lambda(latin), "text", "é!".encode("latin-1") + b"\0x", 0), "é!"))
    outputs = _run_lambdas(tmp_path, [c for c, _ in cases])
    for (case, expected), out in zip(cases, outputs, strict=True):
        if case.kind == "float" and expected not in ("inf", "nan"):
            assert math.isclose(float(out), float(expected), rel_tol=1e-6), (case.code, out, expected)
        else:
            assert out == expected, (case.code, out, expected)


def test_number_lambdas_read_and_write_the_wire_words(tmp_path: Path) -> None:
    """The fixtures' byte-swapped numbers (and a number with an offset) read a value from its wire word
    and write back the word struct encodes for it, bytes swapped, as ESPHome sends a U_WORD/S_WORD."""
    from dataclasses import replace

    cases: list[tuple[_LambdaCase, str]] = []
    numbers = [(d, e) for d in FIXTURES for p, e in _esp_entities(d) if p == "number" and "write_lambda" in e]
    assert {_esp_register(d, e).name for d, e in numbers} >= {"speed", "torque_limit"}
    for device, e in numbers:
        reg = _esp_register(device, e)
        for value in (float(reg.raw_min * reg.scale + reg.offset), float(reg.raw_max * reg.scale + reg.offset), float(e["step"])):
            raw = round((value - float(reg.offset)) / float(reg.scale))
            word = struct.pack(">h" if reg.signed else ">H", raw)
            wire = word[::-1] if _swapped(reg) else word
            x = float(raw) * _scale_of(e, "number")  # what ESPHome passes a number's read lambda: raw / multiply
            cases.append((_LambdaCase(e["lambda"].value, "float", wire, 0, x), f"{value:.9g}"))
            cases.append((_LambdaCase(e["write_lambda"].value, "write", b"", 0, value), str(int.from_bytes(wire, "big"))))
    from regmap.backends.esphome import lambdas as esp_lambdas

    power = next(d for d in FIXTURES if d.id == "fixture_power_meter")
    offset = replace(power.register("temperature"), access=power.register("ct_ratio").access)
    cases.append((_LambdaCase(esp_lambdas.offset_read_lambda(offset), "float", b"", 0, 55.0), "15"))  # 550 x 0.1 - 40
    cases.append((_LambdaCase(esp_lambdas.offset_write_lambda(offset), "write", b"", 0, 15.0), "550"))
    outputs = _run_lambdas(tmp_path, [c for c, _ in cases])
    for (case, expected), out in zip(cases, outputs, strict=True):
        assert math.isclose(float(out), float(expected), rel_tol=1e-6, abs_tol=1e-6), (case.code, case.x, out, expected)


# -- read ranges: what ESPHome requests is within the read plan --------------------------------------


def _esphome_ranges(entities: list[tuple[str, dict[str, Any]]]) -> list[tuple[str, int, int, set[str]]]:
    """ESPHome's `create_register_ranges_` (2026.6): items sorted by register type, force_new_range first,
    then by address; an item extends the range when it starts where the range ends (or re-reads its last
    register). (register type, start, count, the skip_updates of its items)."""
    items = []
    for platform, e in entities:
        if platform == "text_sensor":
            count = e["response_size"] // 2
        elif platform in ("binary_sensor", "switch") or e.get("register_type") in ("coil", "discrete_input"):
            count = 1
        else:
            count = TYPE_WORDS[e.get("value_type", "U_WORD")]
        items.append(
            (e.get("register_type", "holding"), not e.get("force_new_range", False), e["address"], count, str(e.get("skip_updates", 0)))
        )
    items.sort()
    ranges: list[list[Any]] = []
    current: list[Any] | None = None
    prev_count = 0
    for kind, plain, address, count, skip in items:
        if current is not None and kind == current[0] and plain and address == current[1] + current[2] - prev_count and count == prev_count:
            current[3].add(skip)
        elif current is not None and kind == current[0] and plain and address == current[1] + current[2]:
            current[2] += count
            current[3].add(skip)
        else:
            current = [kind, address, count, {skip}]
            ranges.append(current)
        prev_count = count
    return [(k, a, c, s) for k, a, c, s in ranges]


@pytest.mark.parametrize("patterns", [None, ALL], ids=["default", "all"])
@pytest.mark.parametrize("device", EVERY, ids=[d.id for d in EVERY])
def test_esphome_reads_follow_the_read_plan(device: Device, patterns: tuple[str, ...] | None) -> None:
    entities = _esp_entities(device, patterns)
    documented = documented_addresses(device)
    chosen = {_esp_register(device, e) for _, e in entities}
    plan = read_plan(device, list(chosen))
    for kind, start, count, skips in _esphome_ranges(entities):
        space = ESP_SPACE[kind]
        bits = space in ("coil", "discrete_input")
        assert count <= (255 if bits else device.transport.max_read_registers)
        assert len(skips) == 1, f"range at {start:#06x} mixes polling rates"
        assert device.transport.tolerates_gaps or all((space, a) in documented for a in range(start, start + count)), (
            f"{start:#06x}+{count}"
        )
        assert any(b.space == space and b.address <= start and start + count <= b.address + b.count for b in plan), (
            f"{space} {start:#06x}+{count} not in a plan request"
        )
        first = device.at_address(start, space)
        assert first is not None and (count == first.words or not first.paired), "a block read must start at a pair's high word"
        regs = [r for r in chosen if r.space == space and start <= r.address < start + count]
        assert len({(r.poll, r.firmware) for r in regs}) == 1, f"range at {start:#06x} mixes poll classes or firmware gates"


# -- the CLI ------------------------------------------------------------------------------------


def _generate(*args: str, cwd: Path = ROOT) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "regmap", "generate", *args], cwd=cwd, capture_output=True, text=True, check=False)


def test_select_patterns_and_file(tmp_path: Path) -> None:
    selection = tmp_path / "pick.txt"
    selection.write_text("# monitoring\np0b\n!P0B-0*  # but not the first ten\nfault_reset\n", encoding="utf-8")
    out = tmp_path / "out"
    result = _generate(
        "maps/c630s.yaml", "--target", "esphome", "--target", "homeassistant", "--select", f"@{selection}", "--out", str(out)
    )
    assert result.returncode == 0, result.stderr
    data = load((out / "esphome" / "c630s.yaml").read_text(encoding="utf-8"))
    device = load_map(ROOT / "maps" / "c630s.yaml")
    names = {device.at_address(e["address"]).param for p in ("sensor", "select", "number") for e in data.get(p, [])}  # type: ignore[union-attr]
    assert names == {r.param for r in device.registers if r.group == "p0b" and not r.param.startswith("P0B-0")} | {"P0D-01"}  # type: ignore[union-attr]
    assert [b["name"].removeprefix("${c630s_name_prefix}") for b in data["button"]] == [
        c.title for c in device.commands if c.name == "fault_reset"
    ]


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--target", "esphome", "--select", "no_such_register"], "match no register"),
        (["--target", "c", "--select", "p0b"], "none of which is chosen"),
        (["--target", "esphome", "--select", "@/nonexistent/pick.txt"], "cannot read the selection file"),
    ],
)
def test_select_refuses_what_would_do_nothing(tmp_path: Path, args: list[str], message: str) -> None:
    result = _generate("maps/c630s.yaml", *args, "--out", str(tmp_path / "out"))
    assert result.returncode == 2 and message in result.stderr, result.stderr
    assert not (tmp_path / "out").exists()


def test_number_ranges_and_steps_are_the_maps() -> None:
    device = load_map(ROOT / "maps" / "c630s.yaml")
    for platform, e in _esp_entities(device):
        if platform == "number":
            reg = device.at_address(e["address"])
            assert reg is not None and Fraction(e["step"]).limit_denominator(10**6) == reg.scale
            assert reg.type in (DataType.U16, DataType.S16) or e["value_type"].endswith(
                "DWORD" + ("_R" if reg.word_order is WordOrder.LOW_FIRST else "")
            )
