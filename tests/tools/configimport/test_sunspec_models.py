"""Every SunSpec model pysunspec2 ships becomes a map the front end accepts; the same register words decoded by
pysunspec2 (in its own venv) and by regmap's runtime codec (what the generated Python client runs) give the same
values, point for point, "not implemented" included."""

from __future__ import annotations

import json
import math
import random
import struct
import subprocess
from pathlib import Path
from typing import Any

import pytest

from regmap.frontend import load_map_text
from regmap.model import Device
from regmap.runtime_bridge import runtime_specs
from regmap.tools.configimport import sunspec
from regmap.tools.configimport.draft import map_text
from regmap_runtime.codec import words_to_raw

from conftest import ROOT, skip_or_fail
from support.tool_envs import ToolUnavailable, find

REPEATS = 2  # repetitions of a group whose count the device gives
SEED = 35


@pytest.fixture(scope="module")
def pysunspec_python() -> Path:
    try:
        return find("sunspec")
    except ToolUnavailable as exc:
        skip_or_fail(str(exc))
        raise


def _model_files(python: Path) -> list[Path]:
    out = subprocess.run(
        [str(python), "-c", "import sunspec2, os; print(os.path.dirname(sunspec2.__file__))"], capture_output=True, text=True, check=True
    )
    return sorted((Path(out.stdout.strip()) / "models" / "json").glob("model_*.json"), key=lambda p: int(p.stem.split("_")[1]))


def _words(pdef: dict[str, Any], rng: random.Random, counts: set[str]) -> list[int]:
    """Register words for one point: a random value of its type, the n/a value one time in eight."""
    kind, words, unimplemented = sunspec.TYPES[pdef["type"]]
    size = int(pdef.get("size") or words)
    if pdef["name"] in counts:
        return [REPEATS]
    if pdef["type"] == "string":
        text = bytes(rng.choice(b"ABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789 -") for _ in range(rng.randrange(0, 2 * size + 1)))
        raw = text.ljust(2 * size, b"\0")
        return [int.from_bytes(raw[i : i + 2], "big") for i in range(0, 2 * size, 2)]
    if rng.random() < 0.125 and isinstance(unimplemented, int):
        value = unimplemented & ((1 << (16 * size)) - 1)
    elif kind == "f32":
        value = struct.unpack(">I", struct.pack(">f", rng.uniform(-1e6, 1e6)))[0] if rng.random() > 0.125 else 0x7FC00000
    elif kind == "f64":
        value = struct.unpack(">Q", struct.pack(">d", rng.uniform(-1e9, 1e9)))[0]
    else:
        value = rng.getrandbits(16 * size)
    return [(value >> (16 * (size - 1 - i))) & 0xFFFF for i in range(size)]


def _count_points(group: dict[str, Any]) -> set[str]:
    names = {g["count"] for g in group.get("groups", []) if isinstance(g.get("count"), str)}
    for sub in group.get("groups", []):
        names |= _count_points(sub)
    return names


def _regmap_value(device: Device, address: int, words: list[int], pdef: dict[str, Any]) -> Any:
    spec = next(s for s in runtime_specs(device) if s.address == address)
    raw = words_to_raw(spec, words)
    kind, _, unimplemented = sunspec.TYPES[pdef["type"]]
    if pdef["type"] == "eui48":
        assert isinstance(raw, int)
        return None if raw in (0, 0xFFFFFFFFFFFFFFFF) else ":".join(f"{(raw >> (8 * i)) & 0xFF:02X}" for i in reversed(range(6)))
    if pdef["type"] == "ipv6addr":
        data = str(raw).encode("latin-1").ljust(16, b"\0")
        return None if not any(data) else ":".join(data[i : i + 4].hex().upper() for i in range(0, 16, 4))
    if kind == "string":
        return raw or None
    if isinstance(raw, float) and math.isnan(raw):
        return None
    if pdef["type"] != "pad" and raw == unimplemented:
        return None
    return raw


def test_every_shipped_model_becomes_a_map_that_decodes_as_pysunspec2_decodes(pysunspec_python: Path) -> None:
    rng = random.Random(SEED)
    blocks: list[dict[str, Any]] = []
    expected: list[dict[str, Any]] = []
    models = points = too_long = 0
    for path in _model_files(pysunspec_python):
        (model,) = sunspec.read_models([path])
        imported = sunspec.device([model], repeats=REPEATS)
        too_long += sum("longer than one read" in line for line in imported.report)
        device = load_map_text(
            map_text(imported.devices[0], f"sunspec_{model['id']}", "SunSpec", "model", path.name, imported.report), path.name
        )
        counts = _count_points(model["group"])
        laid = sunspec.points(model, REPEATS)
        words: list[int] = []
        decoded: dict[str, Any] = {}
        for point in laid:
            sent = _words(point.pdef, rng, counts)
            if point.pdef["name"] == "ID" and not point.group:
                sent = [model["id"]]
            elif point.pdef["name"] == "L" and not point.group:
                sent = [sunspec.model_length(model, REPEATS)]
            address = 40002 + point.offset
            if any(r.address == address for r in device.registers):
                decoded[point.name] = _regmap_value(device, address, sent, point.pdef)
            words += sent
        blocks.append({"file": str(path), "len": sunspec.model_length(model, REPEATS), "data": "".join(f"{w:04x}" for w in words)})
        expected.append(decoded)
        models += 1
        points += len(decoded)
    run = subprocess.run(
        [str(pysunspec_python), str(ROOT / "tests" / "support" / "sunspec_decode.py")],
        input=json.dumps(blocks),
        capture_output=True,
        text=True,
        check=True,
    )
    theirs = json.loads(run.stdout)
    differences, absent = [], []
    for block, mine, their in zip(blocks, expected, theirs, strict=True):
        assert their["error"] == "", (block["file"], their["error"])
        absent += [(Path(block["file"]).name, name) for name, _ in their["points"] if name not in mine]
        for name, value in their["points"]:
            if name in mine and mine[name] != value and not (isinstance(value, float) and math.isclose(value, mine[name], rel_tol=1e-6)):
                differences.append((Path(block["file"]).name, name, value, mine[name]))
    assert differences == []
    assert len(absent) == too_long == 9 and {file for file, _ in absent} == {"model_64411.json"}  # strings longer than one read
    assert models == len(_model_files(pysunspec_python)) and models >= 100
    print(f"{models} models, {points} points decoded alike")
