"""ESPHome packages and Home Assistant modbus hubs (issue 21): accepted by the real tools, and equal to the model.

The tools run once per map (`esphome config`, `hass --script check_config`), on the committed default
selection and on the full one; the semantic tests read the generated YAML back and decode the manuals'
example responses the way ESPHome (value_type, multiply) and Home Assistant (data_type, swap, scale) do.
"""

from __future__ import annotations

import math
import subprocess
import sys
from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path
from typing import Any

import pytest
import yaml

from regmap.backends.esphome import render_device as esphome_files
from regmap.backends.homeassistant import render_device as hass_files
from regmap.frontend import load_map
from regmap.model import DataType, Device, Register, WordOrder
from regmap.runtime_bridge import documented_addresses, read_plan

from conftest import GENERATED, MAPS, ROOT

HOSTILE = ROOT / "tests" / "maps" / "hostile" / "hostile.yaml"
ALL = ("*",)

# The tools' spellings, written out here independently of the back ends.
ESP_TYPES = {"U_WORD": (1, False, False), "S_WORD": (1, True, False), "U_DWORD": (2, False, False), "S_DWORD": (2, True, False)}
ESP_TYPES |= {"U_DWORD_R": (2, False, True), "S_DWORD_R": (2, True, True)}  # (words, signed, low word first)
HASS_TYPES = {"uint16": (1, False), "int16": (1, True), "uint32": (2, False), "int32": (2, True)}


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


# -- the real tools ---------------------------------------------------------------------------------


def _esphome_config(esphome: Path, tmp_path: Path, package: str) -> None:
    (tmp_path / "device.yaml").write_text(package, encoding="utf-8")
    main = "esphome:\n  name: regmap-check\nesp32:\n  board: esp32dev\n  framework:\n    type: esp-idf\npackages:\n  device: !include device.yaml\n"
    (tmp_path / "main.yaml").write_text(main, encoding="utf-8")
    result = subprocess.run([str(esphome), "config", "main.yaml"], cwd=tmp_path, capture_output=True, text=True, timeout=300, check=False)
    out = result.stdout + result.stderr
    assert result.returncode == 0, out[-4000:]
    assert "Configuration is valid!" in out
    assert "WARNING" not in out.replace("WARNING 💡", ""), [line for line in out.splitlines() if "WARNING" in line]


def _hass_check(hass: Path, tmp_path: Path, package: str) -> None:
    (tmp_path / "device.yaml").write_text(package, encoding="utf-8")
    (tmp_path / "configuration.yaml").write_text("homeassistant:\n  packages:\n    device: !include device.yaml\n", encoding="utf-8")
    result = subprocess.run(
        [str(hass), "--script", "check_config", "-c", str(tmp_path)], capture_output=True, text=True, timeout=300, check=False
    )
    out = result.stdout + result.stderr
    assert result.returncode == 0, out[-4000:]
    assert "Incorrect config" not in out and "Failed config" not in out, out[-4000:]
    assert "components.modbus" not in out, out[-4000:]  # the integration's validators warn, e.g. "... is duplicate, not loaded!"


@pytest.mark.parametrize("selection", ["default", "all"])
@pytest.mark.parametrize("device", DEVICES, ids=[d.id for d in DEVICES])
def test_esphome_config_accepts_the_package(esphome: Path, tmp_path: Path, device: Device, selection: str) -> None:
    if selection == "default":
        package = (GENERATED / "esphome" / f"{device.id}.yaml").read_text(encoding="utf-8")
    else:
        package = _file("esphome", device, ALL)
    _esphome_config(esphome, tmp_path, package)


@pytest.mark.parametrize("selection", ["default", "all"])
@pytest.mark.parametrize("device", DEVICES, ids=[d.id for d in DEVICES])
def test_home_assistant_check_config_accepts_the_hub(hass: Path, tmp_path: Path, device: Device, selection: str) -> None:
    if selection == "default":
        package = (GENERATED / "homeassistant" / f"{device.id}.yaml").read_text(encoding="utf-8")
    else:
        package = _file("homeassistant", device, ALL)
    _hass_check(hass, tmp_path, package)


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
        assert code.value.startswith("id(hostile_dev_controller)->queue_command(esphome::modbus_controller::ModbusCommandItem::"), code
        assert "pwn" not in code.value.lower() and '"' not in code.value
    assert "$" not in package.split("\nsubstitutions:", 1)[1].replace("${hostile_dev_", "")
    titles = {
        e["name"] for platform in ("sensor", "number", "select", "text_sensor", "binary_sensor", "switch") for e in data.get(platform, [])
    }
    assert any("__import__" in t for t in titles)  # the hostile text survives, as text
    (tmp_path / "esp").mkdir()
    (tmp_path / "ha").mkdir()
    _esphome_config(esphome, tmp_path / "esp", package)
    _hass_check(hass, tmp_path / "ha", hub)


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


def _scale_of(entity: dict[str, Any], platform: str) -> float:
    if platform == "number":
        return 1 / float(entity.get("multiply", 1))
    multiply = [f["multiply"] for f in entity.get("filters", []) if "multiply" in f]
    return float(multiply[0]) if multiply else 1.0


@pytest.mark.parametrize("device", DEVICES, ids=[d.id for d in DEVICES])
def test_esphome_entities_equal_the_model(device: Device) -> None:
    seen = set()
    for platform, e in _esp_entities(device):
        reg = device.at_address(e["address"])
        assert reg is not None and reg.address == e["address"], e
        seen.add(reg.name)
        if "value_type" in e and "bitmask" not in e:
            words, signed, low_first = ESP_TYPES[e["value_type"]]
            assert (words, signed) == (reg.type.words, reg.type.signed), e
            assert low_first == (reg.words == 2 and reg.word_order is WordOrder.LOW_FIRST), e
        if platform in ("sensor", "number") and "bitmask" not in e:
            assert math.isclose(_scale_of(e, platform), float(reg.scale), rel_tol=1e-12), e
        if platform == "number":
            assert reg.access.writable
            assert math.isclose(e["min_value"], max(-16777215, float(reg.raw_min * reg.scale)))
            assert math.isclose(e["max_value"], min(16777215, float(reg.raw_max * reg.scale)))
        if "bitmask" in e:
            assert e["bitmask"] in {b.mask for b in reg.bitfields}, e
        if platform == "select":
            assert reg.enum is not None and sorted(e["optionsmap"].values()) == sorted(m.value for m in reg.enum.members)
        if platform in ("number", "select", "switch"):
            assert reg.access.writable, e
    readable = {r.name for r in device.registers if r.access.readable}
    assert seen == readable  # every readable register has an entity under the full selection


@pytest.mark.parametrize("device", DEVICES, ids=[d.id for d in DEVICES])
def test_home_assistant_entities_equal_the_model(device: Device) -> None:
    seen = set()
    for platform, e in _hass_entities(device):
        reg = device.at_address(e["address"])
        assert reg is not None and reg.address == e["address"], e
        assert e["slave"] in range(device.transport.slave_min, device.transport.slave_max + 1)
        if platform == "sensors":
            words, signed = HASS_TYPES[e["data_type"]]
            assert (words, signed) == (reg.type.words, reg.type.signed), e
            assert (e.get("swap") == "word") == (reg.words == 2 and reg.word_order is WordOrder.LOW_FIRST), e
            assert math.isclose(float(e.get("scale", 1)), float(reg.scale), rel_tol=1e-12), e
            for i in range(e.get("virtual_count", 0) + 1):  # a virtual sensor reads the next registers of its array
                nxt = device.at_address(reg.address + i * reg.words)
                assert nxt is not None and (nxt.type, nxt.scale, nxt.array and nxt.array.member) == (
                    reg.type,
                    reg.scale,
                    reg.array and reg.array.member,
                )
                seen.add(nxt.name)
        else:
            seen.add(reg.name)
        if platform == "switches":
            assert reg.access.writable and e["verify"]["address"] == reg.address
    assert seen == {r.name for r in device.registers if r.access.readable}


# -- decoding the manuals' example responses as the tools do -----------------------------------------


def _responses(device: Device) -> list[tuple[int, list[int], Any]]:
    """(start address, words, example) of every read response among the map's examples."""
    out = []
    for ex in device.examples:
        frame = ex.wire_frame
        if ex.direction != "response" or ex.request is None or frame[1] != 0x03 or not ex.values:
            continue
        request = device.example(ex.request).wire_frame
        start = int.from_bytes(request[2:4], "big")
        data = frame[3 : 3 + frame[2]]
        out.append((start, [int.from_bytes(data[i : i + 2], "big") for i in range(0, len(data), 2)], ex))
    return out


def _expected(reg: Register, raw: int | None, value: Any) -> float | None:
    if isinstance(value, int | float) and not isinstance(value, bool):
        return float(value)
    return float(raw * reg.scale) if raw is not None and reg.enum is None else None


@pytest.mark.parametrize("device", DEVICES, ids=[d.id for d in DEVICES])
def test_example_responses_decode_as_the_map_says(device: Device) -> None:
    esp = {e["address"]: (p, e) for p, e in _esp_entities(device) if "bitmask" not in e}
    ha = {e["address"]: e for p, e in _hass_entities(device) if p == "sensors"}
    checked = 0
    for start, words, ex in _responses(device):
        for v in ex.values:
            reg = v.register
            if v.words is not None or not start <= reg.address < start + len(words):
                continue
            mine = words[reg.address - start :]
            platform, e = esp[reg.address]
            if platform in ("sensor", "number"):
                n, signed, low_first = ESP_TYPES[e["value_type"]]
                esp_value = _words_value(mine, n, signed, low_first) * _scale_of(e, platform)
                expected = _expected(reg, v.raw, v.value)
                if expected is not None:
                    assert math.isclose(esp_value, expected, abs_tol=1e-9), (ex.id, reg.name, esp_value, expected)
                    checked += 1
            elif platform == "text_sensor":
                hexbytes = "".join(f"{w:04x}" for w in mine[: reg.words])
                labels = {m["from"]: m["to"] for m in e["filters"][0]["map"]}
                assert reg.enum is not None
                member = reg.enum.member(str(v.value)) or reg.enum.by_value(v.raw if v.raw is not None else -1)
                assert member is not None and labels[hexbytes].startswith(" ".join(member.title.split())[:10].replace("/", "\u2044"))
                checked += 1
            elif platform == "select":
                assert _words_value(mine, reg.words, reg.signed, reg.word_order is WordOrder.LOW_FIRST) in e["optionsmap"].values()
            if reg.address in ha:
                h = ha[reg.address]
                n, signed = HASS_TYPES[h["data_type"]]
                ha_value = _words_value(mine, n, signed, h.get("swap") == "word") * float(h.get("scale", 1))
                expected = _expected(reg, v.raw, v.value)
                if expected is not None:
                    assert math.isclose(ha_value, expected, abs_tol=1e-9), (ex.id, reg.name, ha_value, expected)
    assert checked > 0


# -- read ranges: what ESPHome requests is within the read plan --------------------------------------


def _esphome_ranges(entities: list[tuple[str, dict[str, Any]]]) -> list[tuple[int, int, set[int]]]:
    """ESPHome's `create_register_ranges_` (2026.6): items sorted force_new_range first, then by address;
    an item extends the range when it starts where the range ends (or re-reads its last register)."""
    sizes = {"U_WORD": 1, "S_WORD": 1, "U_DWORD": 2, "S_DWORD": 2, "U_DWORD_R": 2, "S_DWORD_R": 2}
    items = []
    for platform, e in entities:
        count = e["response_size"] // 2 if platform == "text_sensor" else sizes.get(e.get("value_type", "U_WORD"), 1)
        if platform in ("binary_sensor", "switch"):
            count = 1
        items.append((not e.get("force_new_range", False), e["address"], count, int(str(e.get("skip_updates", 0)).startswith("$"))))
    items.sort()
    ranges: list[list[Any]] = []
    current: list[Any] | None = None
    prev_count = 0
    for plain, address, count, slow in items:
        if current is not None and plain and address == current[0] + current[1] - prev_count and count == prev_count:
            current[2].add(slow)
        elif current is not None and plain and address == current[0] + current[1]:
            current[1] += count
            current[2].add(slow)
        else:
            current = [address, count, {slow}]
            ranges.append(current)
        prev_count = count
    return [(a, c, s) for a, c, s in ranges]


@pytest.mark.parametrize("patterns", [None, ALL], ids=["default", "all"])
@pytest.mark.parametrize("device", DEVICES, ids=[d.id for d in DEVICES])
def test_esphome_reads_follow_the_read_plan(device: Device, patterns: tuple[str, ...] | None) -> None:
    entities = _esp_entities(device, patterns)
    documented = documented_addresses(device)
    chosen = {device.at_address(e["address"]) for _, e in entities}
    plan = read_plan(device, [r for r in chosen if r is not None])
    for start, count, classes in _esphome_ranges(entities):
        assert count <= device.transport.max_read_registers
        assert len(classes) == 1, f"range at {start:#06x} mixes polling rates"
        assert device.transport.tolerates_gaps or all(("holding", a) in documented for a in range(start, start + count)), (
            f"{start:#06x}+{count}"
        )
        assert any(b.address <= start and start + count <= b.address + b.count for b in plan), f"{start:#06x}+{count} not in a plan request"
        first = device.at_address(start)
        assert first is not None and (count == first.words or not first.paired), "a block read must start at a pair's high word"


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
    assert [b["name"] for b in data["button"]] == [c.title for c in device.commands if c.name == "fault_reset"]


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
