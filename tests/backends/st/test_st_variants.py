"""Device variants in Structured Text (issue #34), on the float meter fixture (voltage_l2: three-phase model only).

- The read-plan blocks never hold a register some variant lacks beside one it has: the blocks whose
  `BLOCK_<tag>_VARIANTS` mask (as the generated constants give it; none: every variant) holds a variant's
  `VARIANT_<NAME>` bit read exactly the registers the Python client made with `variant=` reads (read_all()),
  and only words a device of that variant answers (the runtime's own table of them).
- The poller, compiled by matiec and run against a played bus with `dwVariant` set to a variant's constant,
  requests exactly those blocks and never one the variant lacks; left 0 (not known) it reads every block.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import pytest

from regmap.backends import st as st_backend
from regmap.backends.st.functions import SPACE_TAG, plan_blocks
from regmap.frontend import load_map, load_map_text
from regmap.generate import render
from regmap.model import Device

from conftest import FIXTURE_MAPS, ROOT
from support.fixture_clients import flavour
from support.st_matiec import matiec_and_gcc
from support.st_poll import PollBench
from support.st_values import block_words, edge_words, register_spec

METER = next(p for p in FIXTURE_MAPS if p.stem == "float_meter")
CONST = re.compile(r"^\s*(\w+) : (\w+) := ([^;]+);", re.M)


def _device() -> Device:
    return load_map(METER, display_name=METER.relative_to(ROOT).as_posix())


def _number(text: str) -> int:
    return int(text[3:], 16) if text.startswith("16#") else int(text)


def _constants(device: Device) -> dict[str, int]:
    files = render([device], ["st"])["st"]
    text = files[f"{device.id}/iec/{device.id}_constants.st"]
    return {name: _number(value) for name, kind, value in CONST.findall(text) if kind in ("UINT", "USINT", "DWORD")}


def _blocks(device: Device, consts: dict[str, int]) -> list[tuple[str, int, int, int | None]]:
    """(tag, address, count, variants mask or None) of each block, from the generated constants."""
    p = device.id.upper()
    tags = [name.removeprefix(f"{p}_BLOCK_").removesuffix("_ADDR") for name in consts if name.endswith("_ADDR") and "_BLOCK_" in name]
    return [(t, consts[f"{p}_BLOCK_{t}_ADDR"], consts[f"{p}_BLOCK_{t}_COUNT"], consts.get(f"{p}_BLOCK_{t}_VARIANTS")) for t in tags]


def _tag(space: str, address: int) -> str:
    return "_".join(filter(None, (SPACE_TAG[space], f"{address:04X}")))


def _client(device: Device, variant: str | None) -> Any:
    """The Python client made for `variant` (None: made without one)."""
    return flavour("runtime", device.id).sync_class(object(), 1, variant=variant)


@pytest.mark.parametrize("variant", ["single_phase", "three_phase"])
def test_each_variants_blocks_read_what_its_python_client_reads(variant: str) -> None:
    device = _device()
    consts = _constants(device)
    bit = consts[f"{device.id.upper()}_VARIANT_{variant.upper()}"]
    client = _client(device, variant)
    answered = client.DEVICE.documented_in(None, variant)
    read: list[str] = []
    planned = {_tag(b.space, b.address): b for b, *_ in plan_blocks(device)}
    for tag, address, count, mask in _blocks(device, consts):
        if mask is not None and not mask & bit:
            continue
        block = planned[tag]
        assert (block.address, block.count) == (address, count)
        assert all((block.space, a) in answered for a in range(address, address + count)), (variant, tag)
        read += [spec.name for spec in block.registers]
    assert sorted(read) == sorted(r.name for r in client.readable())


@pytest.fixture(scope="session")
def matiec() -> Path:
    return matiec_and_gcc()


def _image(bench: PollBench) -> dict[str, dict[int, int]]:
    """Each block's registers at their minimum: words the device serves."""
    image: dict[str, dict[int, int]] = {"coil": {}, "discrete_input": {}, "holding": {}, "input": {}}
    for block in bench.plan:
        specs = {r.name: register_spec(bench.device, r) for r in block.registers}
        for k, word in enumerate(block_words(block, edge_words(specs, "min"))):
            image[block.space][block.address + k] = word
    return image


@pytest.mark.parametrize("runtime", ["codesys", "twincat"])
@pytest.mark.parametrize("variant", ["single_phase", "three_phase", pytest.param(None, id="not_known")])
def test_the_poller_skips_the_blocks_its_variant_lacks(variant: str | None, runtime: str, matiec: Path, tmp_path: Path) -> None:
    device = _device()
    bench = PollBench(device, runtime)
    bit = _constants(device)[f"{device.id.upper()}_VARIANT_{variant.upper()}"] if variant else 0
    inputs = [f"dwVariant := 16#{bit:08X}"] if variant else []  # the generated constant's value (a PROGRAM cannot see globals here)
    run = bench.run(matiec, tmp_path, _image(bench), {}, inputs=inputs, cycles=4000)
    assert run.passes >= 2
    requested = {(r.function, r.address, r.count) for r in run.requests}
    readable = {spec.name for spec in _client(device, variant).readable()}  # without a variant: every readable register
    for block in bench.plan:
        on_variant = all(r.name in readable for r in block.registers)
        assert ((block.function, block.address, block.count) in requested) == on_variant, (variant, block.address)
    read = {r.name for b in bench.plan if (b.function, b.address, b.count) in requested for r in b.registers}
    assert read == readable


def test_more_variants_than_a_dword_has_bits_are_reported_at_the_device_id() -> None:
    text = METER.read_text(encoding="utf-8")
    declared = "    - {name: three_phase, title: Three-phase model}\n"

    def meter(count: int) -> Device:
        more = "".join(f"    - {{name: extra_{i}, title: Extra variant {i}}}\n" for i in range(count - 2))
        return load_map_text(text.replace(declared, declared + more), f"{count}_variants.yaml")

    assert st_backend.check(meter(32)) == []
    problems = [(p.line, p.message) for p in st_backend.check(meter(33))]
    assert problems == [(12, "33 variants: Structured Text gives each one bit of a DWORD (at most 32)")]
