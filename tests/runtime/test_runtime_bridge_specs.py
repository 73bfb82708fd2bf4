"""The runtime specs the bridge builds once per device are the ones RegisterSpec's own constructor makes from the
model, field for field; the wire specs (what read plans and the back ends take) differ from them only in the enum
classes, which the runtime's value checks use and the generator does not build."""

from __future__ import annotations

import dataclasses
import gc
from pathlib import Path
from typing import Any

import pytest

from regmap.frontend import load_map
from regmap.model import Device
from regmap.runtime_bridge import command_extras, documented_addresses, read_plan, runtime_enum, runtime_specs, spec_extras, wire_specs
from regmap_runtime.codec import RangeError, check_raw
from regmap_runtime.spec import BitfieldSpec, RegisterSpec

from conftest import FIXTURE_MAPS, MAPS, ROOT

SEEDED = ("type_info", "words", "first_address")  # RegisterSpec's cached properties, filled in when the spec is made
EVERY = [*MAPS, *FIXTURE_MAPS, *sorted((ROOT / "tests" / "maps" / "scaled_from").glob("*.yaml"))]


def _constructed(device: Device) -> list[RegisterSpec[Any]]:
    """What runtime_specs built before: RegisterSpec(...) per register, each enum class made once."""
    enums = {e.name: runtime_enum(e) for e in device.enums}
    return [
        RegisterSpec(
            name=r.name,
            address=r.address,
            data_type=r.type.value,
            access=r.access.value,
            word_order=r.word_order.value,
            follows_device_order=not r.word_order_fixed,
            paired=r.paired,
            scale_num=r.scale.numerator,
            scale_den=r.scale.denominator,
            min=r.min,
            max=r.max,
            unit=r.unit,
            param=r.param,
            enum=enums[r.enum.name] if r.enum is not None else None,
            bitfields=tuple(BitfieldSpec(b.name, b.lsb, b.width, enums[b.enum.name] if b.enum else None) for b in r.bitfields),
            space=r.space,
            **spec_extras(r),
            **command_extras(device, r),
        )
        for r in device.registers
    ]


def _enum_facts(spec: RegisterSpec[Any]) -> tuple[Any, ...]:
    """An enum class as the checks see it (two builds of one enum are two classes): its name and members."""
    classes = [spec.enum, *(b.enum for b in spec.bitfields)]
    return tuple(None if c is None else (c.__name__, [(m.name, m.value) for m in c]) for c in classes)


def _without_enums(spec: RegisterSpec[Any]) -> dict[str, Any]:
    fields = {f.name: getattr(spec, f.name) for f in dataclasses.fields(RegisterSpec)}
    fields["enum"] = None
    fields["bitfields"] = tuple(dataclasses.replace(b, enum=None) for b in spec.bitfields)
    return fields


@pytest.mark.parametrize("path", EVERY, ids=[p.stem for p in EVERY])
def test_the_specs_are_what_the_constructor_makes(path: Path) -> None:
    device = load_map(path)
    built, wire, expected = runtime_specs(device), wire_specs(device), _constructed(device)
    assert len(built) == len(wire) == len(expected) == len(device.registers)
    for spec, plain, want in zip(built, wire, expected, strict=True):
        assert type(spec) is type(plain) is RegisterSpec
        # every field, in the constructor's order, then the facts the class caches, as its properties work them out
        assert list(vars(plain)) == list(vars(spec)) == [*vars(want), *SEEDED]
        assert [vars(plain)[name] for name in SEEDED] == [vars(spec)[name] for name in SEEDED] == [getattr(want, name) for name in SEEDED]
        assert _without_enums(spec) == _without_enums(want) == _without_enums(plain)
        assert _enum_facts(spec) == _enum_facts(want)
        assert plain.enum is None and all(b.enum is None for b in plain.bitfields)
        assert spec == plain if spec.enum is None and all(b.enum is None for b in spec.bitfields) else spec != plain
    assert runtime_specs(device) is built and wire_specs(device) is wire  # once per device


def test_the_runtime_specs_still_check_enum_values() -> None:
    """The runtime's check refuses a value no member has: the runtime specs carry the enum classes it checks with."""
    device = load_map(MAPS[0])
    for spec in runtime_specs(device):
        if spec.enum is not None and not spec.bitfields and spec.type_info.kind == "int":
            missing = max(m.value for m in spec.enum) + 1
            if spec.raw_min <= missing <= spec.raw_max:
                with pytest.raises(RangeError, match="is not one of"):
                    check_raw(spec, missing)
                return
    raise AssertionError("the map has no integer enum register to check")


def test_the_plan_holds_wire_specs_and_both_go_with_the_device() -> None:
    from regmap import runtime_bridge

    device = load_map(MAPS[0])
    key = id(device)
    wire = {s.name: s for s in wire_specs(device)}
    assert all(wire[s.name] is s for block in read_plan(device) for s in block.registers)
    runtime_specs(device)
    documented = documented_addresses(device)
    assert documented_addresses(device) is documented  # worked out once
    words = {(r.space, a) for r in device.registers if r.access.readable for a in range(r.first_address, r.last_address + 1)}
    assert documented == words
    memos = (runtime_bridge._SPECS, runtime_bridge._RUNTIME, runtime_bridge._PLANS, runtime_bridge._EXTRAS, runtime_bridge._DOCUMENTED)
    assert all(key in memo for memo in memos)
    del device, wire
    gc.collect()
    assert all(key not in memo for memo in memos)


def test_the_documented_words_of_some_variants_are_never_the_kept_ones() -> None:
    """The words of every variant are kept per device; a question about some variants is answered afresh."""
    device = next(d for d in map(load_map, EVERY) if d.info.variants)
    every = documented_addresses(device)
    fewer = 0
    for variant in device.info.variants:
        some = documented_addresses(device, (variant.name,))
        assert some == {
            (r.space, a)
            for r in device.registers
            if r.access.readable and r.on_variant(variant.name)
            for a in range(r.first_address, r.last_address + 1)
        }
        assert some <= every
        fewer += some != every
    assert fewer  # some variant lacks a register, so the kept answer would be wrong for it
    assert documented_addresses(device) is every
