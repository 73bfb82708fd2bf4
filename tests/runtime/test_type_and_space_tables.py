"""The one table of data types and the one table of register spaces, and everything that derives from them."""

from __future__ import annotations

import math
import re
import struct
from collections.abc import Callable
from typing import Any

import pytest

from regmap.frontend import load_map
from regmap.model import DataType
from regmap.runtime_bridge import documented_addresses, runtime_specs
from regmap_runtime.codec import raw_to_words, words_to_raw
from regmap_runtime.plan import plan_reads, plan_writes
from regmap_runtime.rtu import (
    READS,
    WRITES_MULTIPLE,
    WRITES_SINGLE,
    FrameError,
    build_read,
    build_read_response,
    build_write_multiple,
    build_write_single,
    parse_frame,
    parse_hex,
    to_hex,
    with_crc,
)
from regmap_runtime.spaces import COIL, DEFAULT_SPACE, DISCRETE_INPUT, HOLDING, INPUT, SPACES
from regmap_runtime.spec import RegisterSpec
from regmap_runtime.types import TYPES, TypeInfo

from conftest import ROOT

KINDS = {"int", "float", "string", "bool"}
ALL_TYPES = sorted(TYPES.values(), key=lambda t: t.name)


def _spec(info: TypeInfo, **kwargs: Any) -> RegisterSpec[Any]:
    return RegisterSpec(name="r", address=0x0100, data_type=info.name, access="rw", **kwargs)


# -- types -------------------------------------------------------------------------------


FIXED = [t for t in ALL_TYPES if t.kind in ("int", "float")]


@pytest.mark.parametrize("info", FIXED, ids=lambda t: t.name)
def test_a_type_is_as_wide_and_signed_as_its_struct_format(info: TypeInfo) -> None:
    fmt = ">" + info.codec
    assert info.kind in KINDS
    assert struct.calcsize(fmt) == 2 * info.words
    assert info.bits == 8 * struct.calcsize(fmt)
    assert info.wide == (info.words > 1)
    assert info.signed == info.codec.islower()  # struct: lower case signed, upper case unsigned
    struct.pack(fmt, info.raw_min)
    struct.pack(fmt, info.raw_max)
    if info.kind == "int":
        for outside in (info.raw_min - 1, info.raw_max + 1):
            with pytest.raises(struct.error):
                struct.pack(fmt, outside)
        return
    # A float's bounds are its largest finite values: the next one up is infinity in that width.
    assert info.raw_min == -info.raw_max
    above = struct.unpack(
        fmt, (struct.unpack({1: ">H", 2: ">I", 4: ">Q"}[info.words], struct.pack(fmt, info.raw_max))[0] + 1).to_bytes(2 * info.words, "big")
    )[0]
    assert above == math.inf


def test_string_and_bool_are_no_fixed_words() -> None:
    text, bit = TYPES["string"], TYPES["bool"]
    assert (text.kind, text.words, text.wide, text.numeric, text.has_byte_order) == ("string", 0, False, False, True)
    assert (bit.kind, bit.words, bit.bits, bit.wide, bit.numeric, bit.has_byte_order) == ("bool", 1, 1, False, False, False)
    assert (bit.raw_min, bit.raw_max) == (0, 1)
    assert bit.to_words(1) == (1,) and bit.from_words([0]) == 0


@pytest.mark.parametrize("info", FIXED, ids=lambda t: t.name)
def test_a_type_round_trips_its_edge_values_through_words(info: TypeInfo) -> None:
    for raw in (info.raw_min, -1 if info.signed else 1, 0, info.raw_max):
        words = info.to_words(raw)
        assert len(words) == info.words and all(0 <= w <= 0xFFFF for w in words)
        assert info.from_words(words) == raw
        assert list(words) == list(struct.unpack(f">{info.words}H", struct.pack(">" + info.codec, raw)))
    if info.kind == "int":
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


@pytest.mark.parametrize("info", FIXED, ids=lambda t: t.name)
def test_the_codec_follows_the_table_and_the_word_order(info: TypeInfo) -> None:
    high, low = _spec(info), _spec(info, word_order="low_first")
    raw = info.from_words(info.to_words(info.raw_min + 0x1234))  # an f16 holds -60832, not -60844
    assert raw_to_words(high, raw) == list(info.to_words(raw))
    assert raw_to_words(low, raw) == list(info.to_words(raw))[::-1]
    assert words_to_raw(high, raw_to_words(high, raw)) == words_to_raw(low, raw_to_words(low, raw)) == raw


@pytest.mark.parametrize("words", [[0x10000], [-1], [0x1234, -1], [0x10000, 0]])
def test_a_word_beyond_16_bits_is_refused(words: list[int]) -> None:
    with pytest.raises(ValueError, match=r"0\.\.0xFFFF"):
        words_to_raw(_spec(TYPES["u16" if len(words) == 1 else "u32"]), words)


def test_only_a_wide_register_follows_the_device_word_order() -> None:
    assert _spec(TYPES["u16"]).in_word_order("low_first").word_order == "high_first"
    assert _spec(TYPES["u32"]).in_word_order("low_first").word_order == "low_first"
    assert _spec(TYPES["u32"], follows_device_order=False).in_word_order("low_first").word_order == "high_first"
    spec = _spec(TYPES["s32"])
    assert spec.in_word_order(None) is spec and spec.in_word_order("high_first") is spec


# -- spaces ------------------------------------------------------------------------------


def test_the_spaces_have_the_modbus_function_codes() -> None:
    # Modbus Application Protocol v1.1b3 §6.1-§6.12.
    assert (HOLDING.read, HOLDING.write_single, HOLDING.write_multiple) == (0x03, 0x06, 0x10)
    assert HOLDING.codes == {"read": 0x03, "write_single": 0x06, "write_multiple": 0x10}
    assert INPUT.codes == {"read": 0x04} and DISCRETE_INPUT.codes == {"read": 0x02}
    assert COIL.codes == {"read": 0x01, "write_single": 0x05, "write_multiple": 0x0F}
    assert [s.bits for s in (HOLDING, INPUT, COIL, DISCRETE_INPUT)] == [False, False, True, True]
    assert [s.writable for s in (HOLDING, INPUT, COIL, DISCRETE_INPUT)] == [True, False, True, False]
    assert SPACES == {"holding": HOLDING, "input": INPUT, "coil": COIL, "discrete_input": DISCRETE_INPUT} and DEFAULT_SPACE == "holding"


def test_every_function_code_names_one_space_and_one_operation() -> None:
    codes = [code for space in SPACES.values() for code in space.codes.values()]
    assert len(codes) == len(set(codes))
    assert all(code < 0x80 for code in codes)  # 0x80 is the exception flag
    assert {code: s for s in SPACES.values() for code in s.codes.values()} == {**READS, **WRITES_SINGLE, **WRITES_MULTIPLE}


def test_frames_carry_the_space_function_codes() -> None:
    for space in SPACES.values():
        assert build_read(1, 0x0190, 2, space=space.name)[1] == space.read
        assert parse_frame(build_read(1, 0x0190, 2, space=space.name)).space == space.name
        words = [1, 0] if space.bits else [1, 2]
        if space.writable:
            assert build_write_single(1, 0x0190, 1, space=space.name)[1] == space.write_single
            assert build_write_multiple(1, 0x0190, words, space=space.name)[1] == space.write_multiple
        else:
            with pytest.raises(FrameError, match="cannot be written"):
                build_write_single(1, 0x0190, 1, space=space.name)
            with pytest.raises(FrameError, match="cannot be written"):
                build_write_multiple(1, 0x0190, words, space=space.name)


def test_bit_frames_are_the_specs_examples() -> None:
    """Modbus Application Protocol v1.1b3 §6.1, §6.2, §6.5, §6.11 (PDUs; RTU slave 1 and CRC added)."""
    coils = [1, 0, 1, 1, 0, 0, 1, 1, 1, 1, 0, 1, 0, 1, 1, 0, 1, 0, 1]  # CD 6B 05, coils 20..38
    assert to_hex(build_read(1, 0x13, 19, space="coil")) == "01 01 00 13 00 13 8C 02"
    assert to_hex(build_read_response(1, coils, space="coil")) == "01 01 03 CD 6B 05 42 82"
    response = parse_frame(parse_hex("01 01 03 CD 6B 05 42 82"), "response")
    assert (response.kind, response.bits[:19], response.bits[19:], response.problems) == ("read_response", tuple(coils), (0,) * 5, ())
    assert parse_frame(parse_hex("01 01 03 CD 6B 05 42 82")).kind == "read_response"  # 13 6B 05 asks for too many bits to be a request
    assert (
        parse_frame(parse_hex("01 02 03 AC DB 35 22 88"), "response").bits[:22]
        == tuple((byte >> i) & 1 for byte in (0xAC, 0xDB, 0x35) for i in range(8))[:22]
    )
    assert to_hex(build_write_single(1, 0xAC, 1, space="coil")) == "01 05 00 AC FF 00 4C 1B"
    on = parse_frame(parse_hex("01 05 00 AC FF 00 4C 1B"))
    assert (on.kind, on.address, on.words, on.bits) == ("write_single", 0xAC, (0xFF00,), (1,))
    assert parse_frame(build_write_single(1, 0xAC, 0, space="coil")).bits == (0,)
    odd = parse_frame(with_crc(bytes.fromhex("01 05 00 AC 00 01")))
    assert odd.bits == () and "FF 00 (on) or 00 00 (off), not 00 01" in odd.problems[0]
    with pytest.raises(FrameError, match="a bit is 0 or 1"):
        build_write_single(1, 0xAC, 0xFF00, space="coil")
    ten = [1, 0, 1, 1, 0, 0, 1, 1, 1, 0]
    assert to_hex(build_write_multiple(1, 0x13, ten, space="coil")) == "01 0F 00 13 00 0A 02 CD 01 72 CB"
    request = parse_frame(parse_hex("01 0F 00 13 00 0A 02 CD 01 72 CB"))
    assert (request.kind, request.count, request.bits, request.problems) == ("write_multiple_request", 10, tuple(ten), ())
    assert parse_frame(with_crc(bytes.fromhex("01 0F 00 13 00 0A 01 CD"))).problems == ("coil count says 10 but 1 data bytes follow",)


def test_frame_counts_follow_the_space_limits() -> None:
    build_read(1, 0, 2000, space="coil")
    build_read(1, 0, 125, space="input")
    build_write_multiple(1, 0, [1] * 1968, space="coil")
    calls: list[Callable[[], bytes]] = [
        lambda: build_read(1, 0, 2001, space="discrete_input"),
        lambda: build_read(1, 0, 126, space="input"),
        lambda: build_write_multiple(1, 0, [0] * 1969, space="coil"),
        lambda: build_write_multiple(1, 0, [0] * 124),
    ]
    for call in calls:
        with pytest.raises(FrameError, match="outside"):
            call()


def test_the_c_header_spells_the_table() -> None:
    header = (ROOT / "generated" / "c" / "regmap_rtu.h").read_text(encoding="utf-8")
    defined = {name: int(value, 16) for name, value in re.findall(r"#define REGMAP_FC_(\w+) (0x[0-9A-F]+)u", header)}
    assert {"READ_HOLDING": 0x03, "WRITE_SINGLE": 0x06, "WRITE_MULTIPLE": 0x10, "EXCEPTION_FLAG": 0x80}.items() <= defined.items()
    codes = {code for space in SPACES.values() for code in space.codes.values()}
    assert set(defined.values()) - {0x80} <= codes  # every function code the header names is one of the table's


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


def test_a_plan_never_mixes_spaces() -> None:
    placed = {"holding": (1, 3), "input": (1, 2, 3)}
    specs: list[RegisterSpec[Any]] = [
        RegisterSpec(name=f"{space}{a}", address=a, data_type="u16", access="rw", space=space) for space, at in placed.items() for a in at
    ]
    assert [(b.space, b.address, b.count) for b in plan_reads(specs, 125)] == [("holding", 1, 3), ("input", 1, 3)]
    # Address 2 is documented in the input space only: a holding read may not span it.
    documented = frozenset((s.space, s.address) for s in specs)
    assert [(b.space, b.address, b.count) for b in plan_reads(specs, 125, documented)] == [
        ("holding", 1, 1),
        ("holding", 3, 1),
        ("input", 1, 3),
    ]
    writes = plan_writes([(s, 1) for s in specs if s.address < 3], 123)
    assert [(b.space, b.address, len(b.words)) for b in writes] == [("holding", 1, 1), ("input", 1, 2)]


def test_bit_spaces_are_planned_within_the_bit_limit() -> None:
    coils: list[RegisterSpec[Any]] = [RegisterSpec(name=f"c{a}", address=a, data_type="bool", access="rw", space="coil") for a in range(20)]
    regs: list[RegisterSpec[Any]] = [RegisterSpec(name=f"h{a}", address=a, data_type="u16", access="rw") for a in range(20)]
    plan = plan_reads([*coils, *regs], 7, max_bits=8)
    assert [(b.space, b.address, b.count) for b in plan] == [
        ("holding", 0, 7),
        ("holding", 7, 7),
        ("holding", 14, 6),
        ("coil", 0, 8),
        ("coil", 8, 8),
        ("coil", 16, 4),
    ]
    writes = plan_writes([(c, i % 2) for i, c in enumerate(coils)], 123, max_bits=6)
    assert [(b.address, b.words) for b in writes] == [(0, (0, 1, 0, 1, 0, 1)), (6, (0, 1) * 3), (12, (0, 1) * 3), (18, (0, 1))]
