"""Device variants in C (issue #34): a map that declares variants gets a bit per variant, a `_VARIANTS` mask and
an `<name>_on_variant()` helper per register only some variants have, and a read plan per variant. A C program
(gcc C99 and g++ C++17, warning-free) walks each variant's plan and asks every helper; what it prints is held to
the Python client made with `variant=` (its read_all() plan, both flavours) and to the model."""

from __future__ import annotations

import subprocess
from collections.abc import Iterable
from pathlib import Path

import pytest

from regmap.backends import c as c_backend
from regmap.backends.c import CIdentifier, CSymbol
from regmap.frontend import load_map, load_map_text
from regmap.generate import render
from regmap.model import Device
from regmap_runtime.spaces import SPACES

from conftest import FIXTURE_MAPS, MAPS, SMALL_MAPS, require_tool
from support.fixture_clients import FLAVOURS, flavour

METER = next(p for p in FIXTURE_MAPS if p.stem == "float_meter")
VARIANT_MAPS = [p for p in (*MAPS, *SMALL_MAPS, *FIXTURE_MAPS) if load_map(p).info.variants]
FLAGS = ("-Wall", "-Wextra", "-Wpedantic", "-Werror", "-Wconversion", "-Wsign-conversion", "-Wshadow")
COMPILERS = {"gcc-c99": ("gcc", "-std=c99", *FLAGS), "g++-c++17": ("g++", "-x", "c++", "-std=c++17", *FLAGS)}


def _plans(device: Device) -> dict[tuple[str, str], list[str]]:
    """(variant, poll class or "all") -> the requests the Python client made for the variant sends for read_all() (with
    poll=, where the map has more than one poll class, as the C header has a plan per class), as the C program prints them."""
    classes = sorted({r.poll.value for r in device.registers})
    per_flavour = []
    for name in FLAVOURS:
        out = {}
        for v in device.info.variants:
            client = flavour(name, device.id).sync_class(object(), 1, variant=v.name)
            for poll in [None, *classes] if len(classes) > 1 else [None]:
                plan = client.plan_reads(client.readable(poll))
                if plan or poll is None:
                    shown = [f"plan {v.name} {poll or 'all'} {SPACES[b.space].read} {b.address} {b.count}" for b in plan]
                    out[(v.name, poll or "all")] = shown
        per_flavour.append(out)
    assert all(plans == per_flavour[0] for plans in per_flavour), "the runtime and the generated client plan alike"
    return per_flavour[0]


def _program(device: Device, plans: Iterable[tuple[str, str]]) -> str:
    """C that prints the plans of `plans` (`plan <variant> <class> <function> <address> <count>`) and each helper's
    answer for each variant (`has <register> <variant> <0|1> <0|1>`); every name spelled as the back end spells it."""
    prefix = CIdentifier(device.id)
    implementation = CIdentifier(prefix, "IMPLEMENTATION")
    lines = ["#include <stdio.h>", f"#define {implementation}", f'#include "{device.id}.h"', "int main(void)", "{", "    size_t i;"]
    spaces = any(r.space != "holding" for r in device.registers if r.access.readable)
    for variant, poll in plans:
        parts = (variant,) if poll == "all" else (poll, variant)
        table = CSymbol(device.id, "read_plan", *parts)
        length = CIdentifier(prefix, "READ_PLAN", *parts, "LEN")
        function = f"(unsigned){CSymbol(device.id, 'read_plan', *parts, 'function')}[i]" if spaces else "3u"
        shown = f"plan {variant} {poll} %u %u %u"
        lines += [
            f"    for (i = 0; i < {length}; i++) {{",
            f'        printf("{shown}\\n", {function}, (unsigned){table}[i].address, (unsigned){table}[i].count);',
            "    }",
        ]
    for reg in device.registers:
        if not reg.variants:
            continue
        owner = f"{reg.array.array}_{reg.array.member}" if reg.array else reg.name
        for v in device.info.variants:
            bit = CIdentifier(prefix, "VARIANT", v.name)
            helper = CSymbol(device.id, owner, "on_variant")
            mask = CIdentifier(prefix, owner, "VARIANTS")
            lines.append(f'    printf("has {reg.name} {v.name} %d %d\\n", {helper}({bit}) ? 1 : 0, ({mask} & {bit}) != 0u ? 1 : 0);')
    return "\n".join([*lines, "    return 0;", "}", ""])


def _run(compiler: str, device: Device, tmp_path: Path, plans: Iterable[tuple[str, str]] = ()) -> list[str]:
    for rel, text in render([device], ["c"])["c"].items():
        (tmp_path / rel).write_text(text, encoding="utf-8")
    source = tmp_path / "variants.c"
    source.write_text(_program(device, plans), encoding="utf-8")
    tool, *flags = COMPILERS[compiler]
    binary = tmp_path / "variants"
    built = subprocess.run([require_tool(tool), *flags, f"-I{tmp_path}", str(source), "-o", str(binary)], capture_output=True, text=True)
    assert built.returncode == 0 and not built.stderr.strip(), built.stderr
    ran = subprocess.run([str(binary)], capture_output=True, text=True, check=True)
    return ran.stdout.splitlines()


@pytest.mark.parametrize("compiler", COMPILERS)
@pytest.mark.parametrize("map_path", VARIANT_MAPS, ids=lambda p: p.stem)
def test_each_variants_plan_is_what_its_python_client_reads(compiler: str, map_path: Path, tmp_path: Path) -> None:
    device = load_map(map_path)
    expected = _plans(device)
    printed = _run(compiler, device, tmp_path, expected)
    for (variant, poll), lines in expected.items():
        assert [line for line in printed if line.startswith(f"plan {variant} {poll} ")] == lines, (variant, poll)
    if len({r.poll for r in device.registers}) > 1:  # the per-class plans are walked too
        assert any(poll != "all" for _, poll in expected)
    _check_helpers(device, printed)


def _check_helpers(device: Device, printed: list[str]) -> None:
    helpers = {line for line in printed if line.startswith("has ")}
    model = {
        f"has {r.name} {v.name} {int(r.on_variant(v.name))} {int(r.on_variant(v.name))}"
        for r in device.registers
        if r.variants
        for v in device.info.variants
    }
    assert helpers == model and any(line.endswith(" 0 0") for line in helpers)  # some variant lacks a register


def _meter_with_variants(count: int) -> Device:
    """The float meter with `count` variants: its two, then made-up ones."""
    text = METER.read_text(encoding="utf-8")
    declared = "    - {name: three_phase, title: Three-phase model}\n"
    more = "".join(f"    - {{name: extra_{i}, title: Extra variant {i}}}\n" for i in range(count - 2))
    last = f"extra_{count - 3}" if count > 2 else "three_phase"
    text = text.replace("variants: [three_phase]", f"variants: [three_phase, {last}]")  # voltage_l2 on the last bit too
    return load_map_text(text.replace(declared, declared + more), f"{count}_variants.yaml")


@pytest.mark.parametrize("compiler", COMPILERS)
def test_the_last_of_32_variant_bits_compiles_and_answers(compiler: str, tmp_path: Path) -> None:
    device = _meter_with_variants(32)
    printed = _run(compiler, device, tmp_path, [(v.name, "all") for v in device.info.variants])  # each variant's plan is there
    _check_helpers(device, printed)


def test_more_variants_than_bits_are_reported_at_the_device_id() -> None:
    """Each variant is a bit of a uint32_t: 32 variants fit, a 33rd is refused."""
    assert c_backend.check(_meter_with_variants(32)) == []
    problems = [(p.line, p.message) for p in c_backend.check(_meter_with_variants(33))]
    assert problems == [(12, "33 variants: the C header gives each one bit of a uint32_t (at most 32)")]
