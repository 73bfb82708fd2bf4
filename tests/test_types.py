"""The one table of data types and the one table of register spaces, and everything that derives from them."""

from __future__ import annotations

import re
import struct
from typing import Any

import pytest

from regmap.frontend import load_map
from regmap.model import DataType
from regmap.runtime_bridge import documented_addresses, runtime_specs
from regmap_runtime import plan
from regmap_runtime.codec import raw_to_words, words_to_raw
from regmap_runtime.plan import plan_reads, plan_writes
from regmap_runtime.rtu import READS, WRITES_MULTIPLE, WRITES_SINGLE, build_read, build_write_multiple, build_write_single, parse_frame
from regmap_runtime.spaces import DEFAULT_SPACE, HOLDING, SPACES
from regmap_runtime.spec import RegisterSpec
from regmap_runtime.types import TYPES, TypeInfo

from conftest import ROOT

KINDS = {"int", "float", "string", "bool"}
ALL_TYPES = sorted(TYPES.values(), key=lambda t: t.name)


def _spec(info: TypeInfo, **kwargs: Any) -> RegisterSpec[Any]:
    return RegisterSpec(name="r", address=0x0100, data_type=info.name, access="rw", **kwargs)


# -- types -------------------------------------------------------------------------------


@pytest.mark.parametrize("info", ALL_TYPES, ids=lambda t: t.name)
def test_a_type_is_as_wide_and_signed_as_its_struct_format(info: TypeInfo) -> None:
    fmt = ">" + info.codec
    assert info.kind in KINDS
    assert struct.calcsize(fmt) == 2 * info.words
    assert info.bits == 8 * struct.calcsize(fmt)
    assert info.wide == (info.words > 1)
    assert info.signed == info.codec.islower()  # struct: lower case signed, upper case unsigned
    struct.pack(fmt, info.raw_min)
    struct.pack(fmt, info.raw_max)
    for outside in (info.raw_min - 1, info.raw_max + 1):
        with pytest.raises(struct.error):
            struct.pack(fmt, outside)


@pytest.mark.parametrize("info", ALL_TYPES, ids=lambda t: t.name)
def test_a_type_round_trips_its_edge_values_through_words(info: TypeInfo) -> None:
    for raw in (info.raw_min, -1 if info.signed else 1, 0, info.raw_max):
        words = info.to_words(raw)
        assert len(words) == info.words and all(0 <= w <= 0xFFFF for w in words)
        assert info.from_words(words) == raw
    assert info.to_words(info.raw_max if not info.signed else -1) == (0xFFFF,) * info.words


def test_data_type_is_the_table() -> None:
    assert {t.value for t in DataType} == set(TYPES)
    for dtype in DataType:
        info = TYPES[dtype.value]
        assert dtype.info is info
        assert (dtype.words, dtype.bits, dtype.signed, dtype.wide) == (info.words, info.bits, info.signed, info.wide)
        assert (dtype.raw_min, dtype.raw_max) == (info.raw_min, info.raw_max)


@pytest.mark.parametrize("info", ALL_TYPES, ids=lambda t: t.name)
def test_register_spec_agrees_with_the_table(info: TypeInfo) -> None:
    spec = _spec(info)
    assert spec.type_info is info
    assert (spec.words, spec.bits, spec.signed, spec.wide) == (info.words, info.bits, info.signed, info.wide)
    assert (spec.type_min, spec.type_max) == (info.raw_min, info.raw_max)
    assert (spec.raw_min, spec.raw_max) == (info.raw_min, info.raw_max)


@pytest.mark.parametrize("info", ALL_TYPES, ids=lambda t: t.name)
def test_the_codec_follows_the_table_and_the_word_order(info: TypeInfo) -> None:
    high, low = _spec(info), _spec(info, word_order="low_first")
    raw = info.raw_min + 0x1234
    assert raw_to_words(high, raw) == list(info.to_words(raw))
    assert raw_to_words(low, raw) == list(info.to_words(raw))[::-1]
    assert words_to_raw(high, raw_to_words(high, raw)) == words_to_raw(low, raw_to_words(low, raw)) == raw


def test_a_word_beyond_16_bits_is_refused() -> None:
    with pytest.raises(ValueError, match=r"0\.\.0xFFFF"):
        words_to_raw(_spec(TYPES["u16"]), [0x10000])


def test_only_a_wide_register_follows_the_device_word_order() -> None:
    assert _spec(TYPES["u16"]).in_word_order("low_first").word_order == "high_first"
    assert _spec(TYPES["u32"]).in_word_order("low_first").word_order == "low_first"
    assert _spec(TYPES["u32"], follows_device_order=False).in_word_order("low_first").word_order == "high_first"
    spec = _spec(TYPES["s32"])
    assert spec.in_word_order(None) is spec and spec.in_word_order("high_first") is spec


# -- spaces ------------------------------------------------------------------------------


def test_holding_registers_have_the_modbus_function_codes() -> None:
    # Modbus Application Protocol v1.1b3: 6.3 Read Holding Registers, 6.6 Write Single Register, 6.12 Write Multiple Registers.
    assert (HOLDING.read, HOLDING.write_single, HOLDING.write_multiple) == (0x03, 0x06, 0x10)
    assert HOLDING.codes == {"read": 0x03, "write_single": 0x06, "write_multiple": 0x10}
    assert SPACES == {"holding": HOLDING} and DEFAULT_SPACE == "holding"


def test_every_function_code_names_one_space_and_one_operation() -> None:
    codes = [code for space in SPACES.values() for code in space.codes.values()]
    assert len(codes) == len(set(codes))
    assert all(code < 0x80 for code in codes)  # 0x80 is the exception flag
    assert {code: s for s in SPACES.values() for code in s.codes.values()} == {**READS, **WRITES_SINGLE, **WRITES_MULTIPLE}


def test_frames_carry_the_space_function_codes() -> None:
    assert build_read(1, 0x0190, 2)[1] == HOLDING.read
    assert build_write_single(1, 0x0190, 7)[1] == HOLDING.write_single
    assert build_write_multiple(1, 0x0190, [1, 2])[1] == HOLDING.write_multiple
    assert parse_frame(build_read(1, 0x0190, 2)).space == HOLDING.name


def test_the_c_header_spells_the_table() -> None:
    header = (ROOT / "generated" / "c" / "regmap_rtu.h").read_text(encoding="utf-8")
    defined = {name: int(value, 16) for name, value in re.findall(r"#define REGMAP_FC_(\w+) (0x[0-9A-F]+)u", header)}
    assert defined == {"READ_HOLDING": 0x03, "WRITE_SINGLE": 0x06, "WRITE_MULTIPLE": 0x10, "EXCEPTION_FLAG": 0x80}


def test_generated_clients_leave_the_default_space_unsaid() -> None:
    modules = sorted((ROOT / "generated" / "python").glob("*/__init__.py"))
    assert modules and not any("space=" in m.read_text(encoding="utf-8") for m in modules if not m.parent.name.startswith("regmap_runtime"))


def test_registers_owners_and_documented_addresses_are_keyed_on_the_space() -> None:
    device = load_map(ROOT / "maps" / "idm_rs.yaml")
    reg = next(r for r in device.registers if r.access.readable)
    assert reg.space == DEFAULT_SPACE
    assert device.covering(reg.address) is device.covering(reg.address, HOLDING.name) is reg
    assert device.covering(reg.address, "elsewhere") is None and device.at_address(reg.address, "elsewhere") is None
    assert (HOLDING.name, reg.address) in documented_addresses(device)
    assert all(s.space == DEFAULT_SPACE for s in runtime_specs(device))


def test_a_plan_never_mixes_spaces(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(plan._SPACE_ORDER, "other", len(plan._SPACE_ORDER))
    placed = {"holding": (1, 3), "other": (1, 2, 3)}
    specs: list[RegisterSpec[Any]] = [
        RegisterSpec(name=f"{space}{a}", address=a, data_type="u16", access="rw", space=space) for space, at in placed.items() for a in at
    ]
    assert [(b.space, b.address, b.count) for b in plan_reads(specs, 125)] == [("holding", 1, 3), ("other", 1, 3)]
    # Address 2 is documented in the other space only: a holding read may not span it.
    documented = frozenset((s.space, s.address) for s in specs)
    assert [(b.space, b.address, b.count) for b in plan_reads(specs, 125, documented)] == [
        ("holding", 1, 1),
        ("holding", 3, 1),
        ("other", 1, 3),
    ]
    writes = plan_writes([(s, 1) for s in specs if s.address < 3], 123)
    assert [(b.space, b.address, len(b.words)) for b in writes] == [("holding", 1, 1), ("other", 1, 2)]
