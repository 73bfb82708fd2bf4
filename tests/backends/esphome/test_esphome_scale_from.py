"""`scale_from` points in ESPHome (value = raw x 10^sf, sf another s16 register): `esphome config` accepts the package;
ESPHome's own ranges (a port of create_register_ranges_) read each point with its factor in one request; the lambdas,
taken from the configuration ESPHome validated, `id()` rewritten as ESPHome does and compiled with g++, give for the
same response words what the Python runtime reads (negative, positive and n/a factors, n/a points, u32 and s16
values), and a number's write lambda sends exactly what the runtime's encode sends and nothing where it refuses."""

from __future__ import annotations

import math
import random
import re
import shutil
import struct
import subprocess
from pathlib import Path
from typing import Any

import pytest

from regmap.backends.esphome import render_device
from regmap.frontend import load_map, load_map_text
from regmap.frontend.plant import load_plant
from regmap.generate import render, render_plant
from regmap.model import Device
from regmap.runtime_bridge import runtime_device
from regmap_runtime.base import ClientCore
from regmap_runtime.codec import RangeError, raw_to_words
from regmap_runtime.plan import ReadBlock
from regmap_runtime.scaling import scaled

from conftest import ROOT
from support.esphome_ranges import items_of, ranges
from support.homeauto_yaml import esphome_config, load
from support.plants import write_plant
from support.sunspec_models import chain_map, pysunspec_python

MAP = ROOT / "tests" / "maps" / "scaled_from" / "inverter.yaml"
POINTS = ("a", "w", "wh", "wmax_lim_pct")
FLOAT_OVERFLOW = 3.4028235677973366e38  # the largest float plus half its last step: rounds to infinity
NA = object()  # a register's "not available" marker in a case below
# ESPHome's lambda parser (esphome/core/__init__.py LAMBDA_PROG); process_lambda makes `id(x).` `x->`, `id(x)` the variable.
LAMBDA_PROG = re.compile(r"\bid\(\s*([a-zA-Z_][a-zA-Z0-9_]*)\s*\)(\.?)")


def _core(device: Device) -> ClientCore:
    cls: type[ClientCore] = type("Core", (ClientCore,), {"DEVICE": runtime_device(device)})
    return cls(None)


def _validated(esphome: Path, work: Path, device: Device, patterns: tuple[str, ...]) -> dict[str, Any]:
    (text,) = render_device(device, patterns).values()
    out = load(esphome_config(esphome, work, text))
    assert isinstance(out, dict)
    return out


def _entities(config: dict[str, Any]) -> dict[int, dict[str, Any]]:
    return {int(e["address"]): e for p in ("sensor", "number") for e in config.get(p, []) if e.get("platform") == "modbus_controller"}


def _code(value: Any) -> str:
    return str(getattr(value, "value", value))


def _cpp_ident(name: str) -> str:
    return re.sub(r"\W", "_", name)


def _compile_and_run(tmp_path: Path, functions: list[str], calls: list[str], entities: set[str]) -> list[str]:
    """Build the lambdas as ESPHome declares them, with g++ -Wall -Wextra -Werror and UBSan; one output line per call."""
    compiler = shutil.which("g++")
    if compiler is None:
        pytest.skip("g++ is not installed")
    head = [
        "#include <cmath>\n#include <cstdint>\n#include <cstdio>\n#include <cstring>\n#include <optional>\n#include <vector>\n",
        "struct Item { uint8_t offset; };\nstruct Entity { float state; };\n",
        '#define ESP_LOGW(tag, ...) (std::printf("refused %s: ", tag), std::printf(__VA_ARGS__), std::printf(" | "))\n',
        *(f"static Entity {_cpp_ident(e)}_obj{{NAN}};\nstatic Entity *{_cpp_ident(e)} = &{_cpp_ident(e)}_obj;\n" for e in sorted(entities)),
    ]
    source = tmp_path / "scaled.cpp"
    source.write_text("".join([*head, *functions, "int main() {\n", *calls, "return 0;\n}\n"]), encoding="utf-8")
    flags = ["-std=gnu++20", "-Wall", "-Wextra", "-Werror", "-fsanitize=undefined", "-fno-sanitize-recover=all"]
    built = subprocess.run([compiler, *flags, str(source), "-o", str(tmp_path / "scaled")], capture_output=True, text=True, check=False)
    assert built.returncode == 0, built.stderr[-3000:]
    ran = subprocess.run([str(tmp_path / "scaled")], capture_output=True, text=True, check=False, timeout=60)
    assert ran.returncode == 0 and not ran.stderr, ran.stderr[-3000:]
    return ran.stdout.splitlines()


def _rewrite_ids(code: str, entities: set[str]) -> str:
    def replace(m: re.Match[str]) -> str:
        entities.add(m.group(1))
        return _cpp_ident(m.group(1)) + ("->" if m.group(2) else "")

    return LAMBDA_PROG.sub(replace, code)


def _float_text(value: float) -> str:
    """What the harness prints for the float nearest `value` (%.9g: every float exactly); beyond float's range, infinity."""
    if math.isnan(value):
        return "nan"
    if abs(value) >= FLOAT_OVERFLOW:
        return f"{math.copysign(math.inf, value)}"
    return f"{struct.unpack('<f', struct.pack('<f', value))[0]:.9g}"


def _words(device: Device, block: ReadBlock, raws: dict[str, object]) -> list[int]:
    """The block's response words for the given raw values, packed by struct (an encoder apart from regmap's)."""
    words = [0] * block.count
    codes = {"u16": ">H", "s16": ">h", "u32": ">I", "s32": ">i"}
    for name, raw in raws.items():
        reg = device.register(name)
        if raw is NA:
            packed = struct.pack(codes[reg.type.value], reg.na[0])
        else:
            assert isinstance(raw, int)
            packed = struct.pack(codes[reg.type.value], raw)
        for k in range(reg.words):
            words[reg.address - block.address + k] = int.from_bytes(packed[2 * k : 2 * k + 2], "big")
    return words


READS: list[dict[str, object]] = [
    {"a": 1234, "a_sf": -2, "w": -1500, "w_sf": 1, "wh": 123456, "wh_sf": 0, "wmax_lim_pct": 1000, "wmax_lim_pct_sf": -1},
    {"a": 65534, "a_sf": -4, "w": -32767, "w_sf": -1, "wh": 4294967295, "wh_sf": -3, "wmax_lim_pct": 505, "wmax_lim_pct_sf": -1},
    {"a": NA, "a_sf": -2, "w": 5, "w_sf": NA, "wh": 16777217, "wh_sf": 2, "wmax_lim_pct": 3, "wmax_lim_pct_sf": 2},
    {"a": 7, "a_sf": 3, "w": -1, "w_sf": -5, "wh": 0, "wh_sf": NA, "wmax_lim_pct": 7, "wmax_lim_pct_sf": NA},
    {"a": 1, "a_sf": -45, "w": 32767, "w_sf": 40, "wh": 99, "wh_sf": -1, "wmax_lim_pct": 0, "wmax_lim_pct_sf": 0},
]


def test_esphome_reads_each_point_with_its_factor_as_the_runtime_does(esphome: Path, tmp_path: Path) -> None:
    device = load_map(MAP)
    config = _validated(esphome, tmp_path, device, ("*",))
    entities = _entities(config)
    core = _core(device)
    specs = list(core.DEVICE.registers)
    blocks = core.plan_reads(specs)
    esp_ranges = ranges(items_of(config))
    assert [(r.start, r.count) for r in esp_ranges] == [(b.address, b.count) for b in blocks]  # one request per plan block
    offsets = {item.address: item.offset for r in esp_ranges for item in r.items}
    names: set[str] = set()
    functions, calls, expected = [], [], []
    for index, name in enumerate(POINTS):
        reg = device.register(name)
        entity = entities[reg.address]
        code = _rewrite_ids(_code(entity["lambda"]), names)
        assert "->state" not in code  # same range: the factor comes from the same response
        functions.append(
            f"static std::optional<float> read_{index}(Item *item, float x, const std::vector<uint8_t> &data) {{\n(void) x;\n{code}\n}}\n"
        )
        (block,) = [b for b in blocks if any(s.name == name for s in b.registers)]
        for raws in READS:
            mine = {r: v for r, v in raws.items() if any(s.name == r for s in block.registers)}
            words = _words(device, block, mine)
            data = ", ".join(str(b) for w in words for b in w.to_bytes(2, "big"))
            calls.append(
                f'{{ Item item{{{offsets[reg.address]}}}; std::vector<uint8_t> data{{{data}}}; auto r = read_{index}(&item, 0.0f, data); std::printf("%.9g\\n", static_cast<double>(*r)); }}\n'
            )
            value = core.values_of(block, words)[name]
            expected.append((name, raws, "nan" if value is None else _float_text(float(value))))
    got = _compile_and_run(tmp_path, functions, calls, names)
    assert [e for _, _, e in expected] == got, [(n, r, e, g) for (n, r, e), g in zip(expected, got, strict=True) if e != g]
    assert sum(e == "nan" for _, _, e in expected) >= 4 and sum(e not in ("nan", "0") for _, _, e in expected) >= 12


def test_a_factor_the_selection_leaves_out_is_read_as_an_internal_sensor(esphome: Path, tmp_path: Path) -> None:
    device = load_map(MAP)
    config = _validated(esphome, tmp_path, device, ("a", "wmax_lim_pct"))
    entities = _entities(config)
    assert {e["id"]: e.get("internal", False) for e in entities.values()} == {
        "sf_inverter_a": False,
        "sf_inverter_a_sf": True,
        "sf_inverter_wmax_lim_pct": False,
        "sf_inverter_wmax_lim_pct_sf": True,
    }
    assert [e["id"] for e in config["number"]] == ["sf_inverter_wmax_lim_pct"]


def test_a_factor_read_in_another_range_is_taken_from_its_entity(esphome: Path, tmp_path: Path) -> None:
    """w_sf polled slowly is read in a request of its own: w's lambda takes its last state, NaN (unknown) until
    it is read and for its marker."""
    text = MAP.read_text(encoding="utf-8").replace(
        "default: 1, na: [0x8000], title: AC power scale factor", "default: 1, na: [0x8000], poll: slow, title: AC power scale factor"
    )
    device = load_map_text(text, "inverter.yaml")
    assert device.register("w_sf").poll.value == "slow"
    config = _validated(esphome, tmp_path, device, ("*",))
    esp_ranges = ranges(items_of(config))
    ranges_of = {item.address: index for index, r in enumerate(esp_ranges) for item in r.items}
    assert ranges_of[0x0002] != ranges_of[0x0003] and ranges_of[0x0000] == ranges_of[0x0001]
    entity = _entities(config)[0x0002]
    names: set[str] = set()
    code = _rewrite_ids(_code(entity["lambda"]), names)
    assert names == {"sf_inverter_w_sf"}
    functions = [f"static std::optional<float> read_w(Item *item, float x, const std::vector<uint8_t> &data) {{\n(void) x;\n{code}\n}}\n"]
    offset = next(item.offset for r in esp_ranges for item in r.items if item.address == 0x0002)
    data_of = {raw: ", ".join(str(b) for b in bytes(offset) + struct.pack(">h", raw)) for raw in (-1500, -32768)}  # w at its offset
    states = {"NAN": None, "1.0f": 1, "-2.0f": -2, "-32768.0f": None}
    calls, expected = [], []
    for raw, data in data_of.items():
        for state, sf in states.items():
            calls.append(
                f"{{ sf_inverter_w_sf->state = {state}; Item item{{{offset}}}; std::vector<uint8_t> data{{{data}}}; "
                f'auto r = read_w(&item, 0.0f, data); std::printf("%.9g\\n", static_cast<double>(*r)); }}\n'
            )
            point = None if raw == -32768 else raw
            value = scaled(point, sf)
            expected.append("nan" if value is None else _float_text(float(value)))
    assert _compile_and_run(tmp_path, functions, calls, names) == expected
    assert expected.count("nan") == 6


WRITES: list[tuple[str, int | None]] = [
    ("50.5", -1), ("50.55", -1), ("100", -1), ("100.1", -1), ("0.1", -1), ("-1", -1), ("0", -1), ("99.9", -1),
    ("1000", 0), ("1001", 0), ("12.5", 0), ("3000", 2), ("3001", 2), ("100000", 2), ("0.05", -2), ("10.01", -2),
    ("7", None), ("1e-3", -3), ("1", -32768), ("2", 5),
]  # fmt: skip


def test_a_write_sends_what_the_runtime_sends_and_nothing_it_refuses(esphome: Path, tmp_path: Path) -> None:
    device = load_map(MAP)
    config = _validated(esphome, tmp_path, device, ("*",))
    (number,) = config["number"]
    assert int(number["address"]) == device.register("wmax_lim_pct").address and number["value_type"] == "U_WORD"
    names: set[str] = set()
    code = _rewrite_ids(_code(number["write_lambda"]), names)
    assert names == {"sf_inverter_wmax_lim_pct_sf"}
    functions = [
        f"static std::optional<float> write_it(Item *item, float x, std::vector<uint16_t> &payload) {{\n(void) item; (void) payload;\n{code}\n}}\n"
    ]
    core = _core(device)
    spec = next(s for s in core.DEVICE.registers if s.name == "wmax_lim_pct")
    sf_reg = device.register("wmax_lim_pct_sf")
    calls, expected = [], []
    for value, sf in WRITES:
        state = "NAN" if sf is None else f"{float(sf)!r}f"
        # Home Assistant's value is a double, ESPHome's number a float; ESPHome sends float_to_payload(r, U_WORD): llroundf(r) & 0xFFFF
        calls.append(
            f"{{ sf_inverter_wmax_lim_pct_sf->state = {state}; Item item{{0}}; std::vector<uint16_t> payload; auto r = write_it(&item, static_cast<float>({value}), payload); "
            'if (r.has_value()) std::printf("sent %ld\\n", static_cast<long>(llroundf(*r) & 0xFFFF)); else std::printf("nothing sent\\n"); }\n'
        )
        factor = None if sf is None or sf_reg.is_na(sf) else sf
        try:
            raw = core.encode(spec, float(value), {"wmax_lim_pct_sf": factor})
            expected.append(f"sent {raw}")
        except RangeError:
            expected.append("nothing sent")
    got = _compile_and_run(tmp_path, functions, calls, names)
    assert [line.rsplit(" | ", 1)[-1] for line in got] == expected, list(zip(WRITES, got, expected, strict=True))
    for line, want in zip(got, expected, strict=True):
        assert ("refused regmap.wmax_lim_pct: " in line) == (want == "nothing sent"), line  # each refusal is logged
    assert 6 <= expected.count("nothing sent") <= len(WRITES) - 6


def test_the_esphome_target_generates_the_points_it_once_left_out() -> None:
    device = load_map(MAP)
    (text,) = render([device], ["esphome"])["esphome"].values()
    assert not [line for line in text.splitlines() if line.startswith("# Not generated")]
    assert "# Points scaled by a factor register" in text
    ids = {e["id"] for e in _entities(load(text)).values()}
    assert {"${sf_inverter_device_id}_" + name for name in ("a", "w", "wh")} <= ids


def test_a_plant_of_two_inverters_scales_each_by_its_own_factors(esphome: Path, tmp_path: Path) -> None:
    """Two inverters on one line: `regmap generate PLANT` no longer refuses the map for ESPHome, and each
    device's lambdas name its own factor entities."""
    path = write_plant(
        tmp_path,
        "pv",
        "serial: {port: /dev/ttyUSB0, baud: 9600, parity: none}",
        [("inv1", f"../{MAP.relative_to(ROOT)}", 1), ("inv2", f"../{MAP.relative_to(ROOT)}", 2)],
    )
    plant = load_plant(path)
    (text,) = render_plant(plant, ["esphome"])["esphome"].values()
    (tmp_path / "check").mkdir()
    config = load(esphome_config(esphome, tmp_path / "check", text))
    assert isinstance(config, dict)
    for device in ("inv1", "inv2"):
        (point,) = [e for e in config["sensor"] if e["id"] == f"{device}_w"]
        assert f"{device}_w_sf" not in _code(point["lambda"])  # read in the same range: from the response
        (factor,) = [e for e in config["sensor"] if e["id"] == f"{device}_w_sf"]
        assert "internal" not in factor or factor["internal"] is False  # the default selection shows it


def test_a_sunspec_inverters_points_read_as_the_runtime_reads_them(esphome: Path, tmp_path: Path) -> None:
    """The map `regmap import sunspec` makes of models 1, 103 (an inverter) and 160 (MPPT, two modules): ESPHome
    accepts its package, and each point's lambda gives for random words (factors -10..10, SunSpec's 0x8000 and each
    point's own marker one time in eight) the runtime's value. Where ESPHome reads a factor in another range (the
    125-register limit puts model 160's DCA_SF in the request before; DCV_SF, first of the next, is read alone as
    force_new_range), the factor's own sensor lambda runs on its response first, as ESPHome reads that range first,
    and the point's lambda takes that state."""
    device = load_map(chain_map(pysunspec_python(), [1, 103, 160], tmp_path / "chain.yaml", repeats=2))
    points = [reg for reg in device.registers if reg.scale_from is not None]
    assert len(points) >= 20
    work = tmp_path / "esphome"
    work.mkdir()
    config = _validated(esphome, work, device, ("*",))
    entities = _entities(config)
    core = _core(device)
    blocks = core.plan_reads(list(core.DEVICE.registers))
    specs = {spec.name: spec for spec in core.DEVICE.registers}
    items = {item.address: (r, item) for r in ranges(items_of(config)) for item in r.items}
    rng = random.Random(35)
    names: set[str] = set()
    functions, calls, expected, apart = [], [], [], 0

    def block_of(name: str) -> ReadBlock:
        (block,) = [b for b in blocks if name in {s.name for s in b.registers}]
        return block

    def response(memory: dict[int, int], address: int) -> tuple[int, str]:
        """(the item's offset, the bytes of the ESPHome range that reads `address`)."""
        esp_range, item = items[address]
        words = [memory.get(a, 0) for a in range(esp_range.start, esp_range.start + esp_range.count)]
        return item.offset, ", ".join(str(b) for w in words for b in w.to_bytes(2, "big"))

    for index, reg in enumerate(points):
        sf = device.register(reg.scale_from or "")
        code = _rewrite_ids(_code(entities[reg.address]["lambda"]), names)
        functions.append(
            f"static std::optional<float> read_{index}(Item *item, float x, const std::vector<uint8_t> &data) {{\n(void) x;\n{code}\n}}\n"
        )
        state = "->state" in code
        assert (items[sf.address][0] is not items[reg.address][0]) == state, reg.name  # ESPHome's ranges decide
        if state:  # the factor's range is read first: its sensor's lambda sets the state the point's lambda takes
            apart += 1
            factor = _rewrite_ids(_code(entities[sf.address]["lambda"]), names)
            functions.append(
                f"static std::optional<float> factor_{index}(Item *item, float x, const std::vector<uint8_t> &data) {{\n(void) x;\n{factor}\n}}\n"
            )
        block = block_of(reg.name)
        for _ in range(8):
            memory = {a: rng.randrange(0x10000) for b in blocks for a in range(b.address, b.address + b.count)}
            memory[sf.address] = 0x8000 if rng.random() < 0.125 else rng.randrange(-10, 11) & 0xFFFF
            if reg.na and rng.random() < 0.125:
                for k, word in enumerate(raw_to_words(specs[reg.name], reg.na[0])):
                    memory[reg.address + k] = word
            call = ""
            if state:
                offset, data = response(memory, sf.address)
                entity = _cpp_ident(str(entities[sf.address]["id"]))
                call += f"{{ Item item{{{offset}}}; std::vector<uint8_t> data{{{data}}}; {entity}->state = *factor_{index}(&item, 0.0f, data); }}\n"
            offset, data = response(memory, reg.address)
            call += f'{{ Item item{{{offset}}}; std::vector<uint8_t> data{{{data}}}; auto r = read_{index}(&item, 0.0f, data); std::printf("%.9g\\n", static_cast<double>(*r)); }}\n'
            calls.append(call)
            factors = {
                f.name: core.decode(specs[f.name], [memory[f.address]]) for f in {device.register(p.scale_from or "") for p in points}
            }
            value = core.values_of(block, [memory[a] for a in range(block.address, block.address + block.count)], factors)[reg.name]
            expected.append("nan" if value is None else _float_text(float(value)))
    got = _compile_and_run(tmp_path, functions, calls, names)
    assert got == expected, [(i, e, g) for i, (e, g) in enumerate(zip(expected, got, strict=True)) if e != g][:10]
    assert 0 < expected.count("nan") < len(expected) // 2
    assert 0 < apart < len(points) // 4  # most factors share their point's request


def test_a_point_whose_factor_shows_no_raw_value_is_listed_not_guessed() -> None:
    """A factor with a scale of its own: its sensor's state is no longer the s16 the point needs, so the point is left
    out and named in the header, never scaled by a wrong power."""
    text = MAP.read_text(encoding="utf-8").replace(
        "default: -2, na: [0x8000], title: AC current scale factor", "default: -2, na: [0x8000], scale: 0.1, title: AC current scale factor"
    )
    device = load_map_text(text, "inverter.yaml")
    (package,) = render_device(device, ("*",)).values()
    assert "# Not generated: a (scale_from a_sf: its entity shows no plain raw value)" in package
    ids = {e["id"] for e in _entities(load(package)).values()}
    assert "${sf_inverter_device_id}_a" not in ids and "${sf_inverter_device_id}_w" in ids
