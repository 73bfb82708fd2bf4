"""Every SunSpec model pysunspec2 ships becomes a map the front end accepts; the same register words decoded by
pysunspec2 (in its own venv) and by regmap give the same values, point for point, "not implemented" included: every
model through regmap's runtime codec and client core (what a generated client vendors byte for byte), and a chained
device of models 1, 103 and 160 through its generated Python client. A point scaled by a `sunssf` point
(`scale_from`) is compared computed: pysunspec2's `cvalue` against the client's value (raw x 10^sf), except where
the scale factor reads "not implemented": pysunspec2 then gives the raw number unscaled, regmap no value (None),
counted apart and printed."""

from __future__ import annotations

import importlib
import json
import math
import random
import struct
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

from regmap.diagnostics import ExitCode
from regmap.frontend import load_map, load_map_text
from regmap.generate import generate
from regmap.model import Device
from regmap.runtime_bridge import runtime_device, runtime_specs
from regmap.tools.configimport import sunspec
from regmap.tools.configimport.draft import map_text
from regmap_runtime.client import SyncClient
from regmap_runtime.codec import words_to_raw
from regmap_runtime.plan import ReadBlock

from conftest import ROOT
from support.sunspec_models import chain_map, model_files, pysunspec_python

REPEATS = 2  # repetitions of a group whose count the device gives
SEED = 35


@pytest.fixture(scope="module")
def python() -> Path:
    return pysunspec_python()


def _words(pdef: dict[str, Any], rng: random.Random, counts: set[str]) -> list[int]:
    """Register words for one point: a random value of its type, the n/a value one time in eight."""
    kind, words, unimplemented = sunspec.TYPES[pdef["type"]]
    size = int(pdef.get("size") or words)
    if pdef["name"] in counts:
        return [REPEATS]
    if pdef["type"] == "sunssf":  # SunSpec's range of a scale factor, or "not implemented"
        return [0x8000 if rng.random() < 0.125 else rng.randrange(-10, 11) & 0xFFFF]
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


Decode = Callable[[int, list[int]], Any]  # (address, words) -> the raw value regmap reads


def _regmap_value(decode: Decode, address: int, words: list[int], pdef: dict[str, Any]) -> Any:
    """What regmap reads, in pysunspec2's terms: None for the n/a value, an EUI-48 and an IPv6 address as text."""
    raw = decode(address, words)
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


def _block(
    path: Path, model: dict[str, Any], address: int, documented: set[int], decode: Decode, rng: random.Random
) -> tuple[dict[str, Any], dict[str, Any]]:
    """Random words for one model block at `address` (its ID), and what regmap reads from them, per point."""
    counts = _count_points(model["group"])
    words: list[int] = []
    decoded: dict[str, Any] = {}
    for point in sunspec.points(model, REPEATS):
        sent = _words(point.pdef, rng, counts)
        if point.pdef["name"] == "ID" and not point.group:
            sent = [model["id"]]
        elif point.pdef["name"] == "L" and not point.group:
            sent = [sunspec.model_length(model, REPEATS)]
        if address + point.offset in documented:
            decoded[point.name] = _regmap_value(decode, address + point.offset, sent, point.pdef)
        words += sent
    block = {"file": str(path), "len": sunspec.model_length(model, REPEATS), "data": "".join(f"{w:04x}" for w in words)}
    return block, decoded


def _computed(client_class: Any, specs: dict[int, Any], block: dict[str, Any], address: int, model: dict[str, Any]) -> dict[str, Any]:
    """The client's value of each `scale_from` point of the block (its core's `values_of`: the sf read in the same block)."""
    words = [int(block["data"][i : i + 4], 16) for i in range(0, len(block["data"]), 4)]
    chosen = tuple(specs[a] for a in range(address, address + len(words)) if a in specs)
    values = client_class.tcp("127.0.0.1", 1).values_of(ReadBlock(address, len(words), chosen), words)
    return {
        point.name: values[specs[address + point.offset].name]
        for point in sunspec.points(model, REPEATS)
        if address + point.offset in specs and specs[address + point.offset].scale_from is not None
    }


Counts = dict[str, int]


def _compare(
    python: Path, blocks: list[dict[str, Any]], expected: list[dict[str, Any]], computed: list[dict[str, Any]]
) -> tuple[list[Any], list[Any], Counts]:
    """(points decoded differently, points pysunspec2 has and regmap's map does not, counts): a scaled point is
    compared by its computed value."""
    run = subprocess.run(
        [str(python), str(ROOT / "tests" / "support" / "sunspec_decode.py")],
        input=json.dumps(blocks),
        capture_output=True,
        text=True,
        check=True,
    )
    differences, absent = [], []
    counts = {"points": 0, "scaled": 0, "scaled_values": 0, "sf_not_implemented": 0}
    for block, mine, scaled, their in zip(blocks, expected, computed, json.loads(run.stdout), strict=True):
        assert their["error"] == "", (block["file"], their["error"])
        absent += [(Path(block["file"]).name, name) for name, _, _ in their["points"] if name not in mine]
        for name, value, cvalue in their["points"]:
            if name not in mine:
                continue
            counts["points"] += 1
            ours, theirs = (scaled[name], cvalue) if name in scaled else (mine[name], value)
            if name in scaled:
                counts["scaled"] += 1
                counts["scaled_values"] += ours is not None
                if ours is None and theirs is not None and theirs == value and mine[name] is not None:
                    counts["sf_not_implemented"] += 1  # pysunspec2 shows the raw number unscaled; regmap: no value
                    continue
            if ours != theirs and not (isinstance(theirs, float) and ours is not None and math.isclose(theirs, ours, rel_tol=1e-9)):
                differences.append((Path(block["file"]).name, name, theirs, ours))
    return differences, absent, counts


def _runtime_decode(device: Device) -> Decode:
    specs = {s.address: s for s in runtime_specs(device)}
    return lambda address, words: words_to_raw(specs[address], words)


def test_every_shipped_model_becomes_a_map_that_decodes_as_pysunspec2_decodes(python: Path) -> None:
    rng = random.Random(SEED)
    blocks: list[dict[str, Any]] = []
    expected: list[dict[str, Any]] = []
    computed: list[dict[str, Any]] = []
    too_long = 0
    files = model_files(python)
    for path in files:
        (model,) = sunspec.read_models([path])
        imported = sunspec.device([model], repeats=REPEATS)
        too_long += sum("longer than one read" in line for line in imported.report)
        text = map_text(imported.devices[0], f"sunspec_{model['id']}", "SunSpec", "model", path.name, imported.report)
        device = load_map_text(text, path.name)
        block, decoded = _block(path, model, 40002, {r.address for r in device.registers}, _runtime_decode(device), rng)
        blocks.append(block)
        expected.append(decoded)
        client_class = type("Client", (SyncClient,), {"DEVICE": runtime_device(device)})
        computed.append(_computed(client_class, {s.address: s for s in runtime_specs(device)}, block, 40002, model))
    differences, absent, counts = _compare(python, blocks, expected, computed)
    assert differences == []
    assert len(absent) == too_long == 9 and {file for file, _ in absent} == {"model_64411.json"}  # strings longer than one read
    assert len(files) == 112
    assert counts["scaled"] == sum(map(len, computed)) > 0 and counts["scaled_values"] > 0 and counts["sf_not_implemented"] > 0
    print(
        f"{len(files)} models, {counts['points']} points decoded alike; {counts['scaled']} of them scaled by a sunssf point"
        f" ({counts['scaled_values']} computed values equal; {counts['sf_not_implemented']} whose scale factor read"
        " 'not implemented': pysunspec2 the raw number, regmap None)"
    )


def test_the_generated_client_of_a_chained_device_decodes_as_pysunspec2(python: Path, tmp_path: Path) -> None:
    device = load_map(chain_map(python, [1, 103, 160], tmp_path / "sunspec_chain.yaml", repeats=REPEATS))
    generate([device], tmp_path / "generated", ["python"], complete=True)
    sys.path.insert(0, str(tmp_path / "generated" / "python"))
    try:
        module = importlib.import_module(device.id)
        codec = importlib.import_module(module.SyncClient.__module__.rsplit(".", 1)[0] + ".codec")
    finally:
        sys.path.pop(0)
    specs = {spec.address: spec for spec in module.DEVICE.registers}
    rng = random.Random(SEED)
    files = {int(p.stem.split("_")[1]): p for p in model_files(python)}
    blocks, expected, computed = [], [], []
    client_class = type("Client", (module.SyncClient,), {"DEVICE": module.DEVICE})
    address = 40002
    for mid in (1, 103, 160):
        (model,) = sunspec.read_models([files[mid]])
        block, decoded = _block(files[mid], model, address, set(specs), lambda a, w: codec.words_to_raw(specs[a], w), rng)
        blocks.append(block)
        expected.append(decoded)
        computed.append(_computed(client_class, specs, block, address, model))
        address += 2 + sunspec.model_length(model, REPEATS)
    differences, absent, counts = _compare(python, blocks, expected, computed)
    assert differences == [] and absent == []
    assert counts["scaled"] > 0 and counts["scaled_values"] > 0
    # model 160's repeating block: each module's DCA, DCV, DCW and DCWH scaled by the factor in the fixed block,
    # compared as values (pysunspec2's cvalue), not raw
    repeated = {f"module_{n}_{point}" for n in range(1, REPEATS + 1) for point in ("dca", "dcv", "dcw", "dcwh")}
    assert repeated <= set(computed[2]), sorted(computed[2])
    assert {device.register(f"m160_{name}").scale_from for name in repeated} == {f"m160_{p}_sf" for p in ("dca", "dcv", "dcw", "dcwh")}
    assert sum(map(len, expected)) == len(device.registers) - 3  # every point but the SunS and end markers


def test_address_points_say_how_their_raw_value_reads(python: Path) -> None:
    """An EUI-48, an IPv4 and an IPv6 address have no display form in a map: each is read raw, and its note says how."""
    files = {int(p.stem.split("_")[1]): p for p in model_files(python)}
    notes: dict[str, str] = {}
    for mid in (11, 63001):
        (found,) = sunspec.device(sunspec.read_models([files[mid]])).devices
        notes |= {reg.key: " ".join(reg.notes) for reg in found.registers}
    assert "an EUI-48: the low six bytes of the u64" in notes["m11_mac"]
    assert "an IPv4 address: its four bytes high first" in notes["m63001_ipaddr"]
    assert "an IPv6 address: its 16 bytes as latin-1 text" in notes["m63001_ipv6addr"]


BAD_MODELS = [
    (
        '{"id": 1, "group": {"name": "common", "points": [{"name": "ID", "type": "int8"}]}}',
        "1:73",
        "point ID: type 'int8' is not a SunSpec type",
    ),
    ('{"id": 1,\n "group": {"name": "c", "points": [\n  {"name": "Mn", "type": "string"}]}}', "3:3", "point Mn: a string needs its size"),
    ('{"id": 1, "group": [', "1:", "YAML syntax error"),
    ('{"model": 1}', "1:1", "not a SunSpec model definition"),
]


@pytest.mark.parametrize(("text", "where", "message"), BAD_MODELS, ids=[b[2][:30] for b in BAD_MODELS])
def test_a_bad_model_definition_is_located(tmp_path: Path, text: str, where: str, message: str) -> None:
    model = tmp_path / "model_1.json"
    model.write_text(text, encoding="utf-8")
    run = subprocess.run(
        [str(Path(sys.executable).with_name("regmap")), "import", str(model), "--into", str(tmp_path / "x.yaml")],
        capture_output=True,
        text=True,
        check=False,
    )
    assert run.returncode == ExitCode.INVALID_MAP and "Traceback" not in run.stderr
    assert f"model_1.json:{where}" in run.stderr and message in run.stderr, run.stderr
    assert not (tmp_path / "x.yaml").exists()
