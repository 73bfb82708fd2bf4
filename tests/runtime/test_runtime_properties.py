"""Property-based tests of the runtime: codecs, framing, the planner and the decoder."""

from __future__ import annotations

import struct
from fractions import Fraction
from typing import Any

from hypothesis import given, settings
from hypothesis import strategies as st

from regmap.diagnostics import UsageError
from regmap.frontend import load_map
from regmap.tools.decode import decode_frame
from regmap_runtime.codec import check_raw, raw_to_value, raw_to_words, value_to_raw, words_to_raw
from regmap_runtime.plan import plan_reads, plan_writes
from regmap_runtime.rtu import (
    build_read,
    build_read_response,
    build_write_multiple,
    build_write_single,
    crc_ok,
    parse_frame,
    parse_hex,
    to_hex,
)
from regmap_runtime.spec import RegisterSpec

from conftest import MAPS

TYPES = ["u16", "s16", "u32", "s32"]
ORDERS = ["high_first", "low_first"]
SCALES = [Fraction(1), Fraction(1, 10), Fraction(1, 100), Fraction(1, 1000), Fraction(1, 20), Fraction(5), Fraction(1, 3)]
DEVICES = [load_map(p) for p in MAPS]


def spec(data_type: str, order: str = "high_first", scale: Fraction = Fraction(1), paired: bool = False, **kw: Any) -> RegisterSpec[Any]:
    return RegisterSpec(
        name="r",
        address=10,
        data_type=data_type,
        access="rw",
        word_order=order,
        paired=paired,
        scale_num=scale.numerator,
        scale_den=scale.denominator,
        **kw,
    )


@st.composite
def typed_raw(draw: st.DrawFn) -> tuple[RegisterSpec[Any], int]:
    data_type = draw(st.sampled_from(TYPES))
    s = spec(
        data_type, draw(st.sampled_from(ORDERS)), draw(st.sampled_from(SCALES)), paired=data_type in ("u16", "s16") and draw(st.booleans())
    )
    return s, draw(st.integers(int(s.type_min), int(s.type_max)))


@given(typed_raw())
def test_words_round_trip(case: tuple[RegisterSpec[Any], int]) -> None:
    s, raw = case
    words = raw_to_words(s, raw)
    assert all(0 <= w <= 0xFFFF for w in words)
    assert len(words) == s.words
    assert words_to_raw(s, words) == raw
    paired = raw_to_words(s, raw, with_pair=True)
    assert paired[-s.words :] == words
    assert len(paired) == s.span


@given(typed_raw())
def test_engineering_value_round_trip(case: tuple[RegisterSpec[Any], int]) -> None:
    s, raw = case
    assert value_to_raw(s, raw_to_value(s, raw)) == raw
    assert value_to_raw(s, str(raw_to_value(s, raw))) == raw


@given(st.sampled_from(TYPES), st.integers())
def test_values_outside_the_type_are_refused(data_type: str, raw: int) -> None:
    s = spec(data_type)
    if s.type_min <= raw <= s.type_max:
        assert value_to_raw(s, raw) == raw
    else:
        try:
            value_to_raw(s, raw)
        except ValueError:
            return
        raise AssertionError("accepted a value outside the type")


@given(st.integers(0, 255), st.integers(0, 0xFFFF), st.integers(1, 125))
def test_read_request_round_trip(slave: int, address: int, count: int) -> None:
    frame = build_read(slave, address, count)
    parsed = parse_frame(frame, "request")
    assert crc_ok(frame)
    assert (parsed.slave, parsed.function, parsed.address, parsed.count, parsed.problems) == (slave, 3, address, count, ())
    assert parse_hex(to_hex(frame)) == frame


@given(st.integers(0, 255), st.integers(0, 0xFFFF), st.lists(st.integers(0, 0xFFFF), min_size=1, max_size=123))
def test_write_frames_round_trip(slave: int, address: int, words: list[int]) -> None:
    multi = parse_frame(build_write_multiple(slave, address, words), "request")
    assert (multi.kind, multi.address, list(multi.words), multi.problems) == ("write_multiple_request", address, words, ())
    single = parse_frame(build_write_single(slave, address, words[0]))
    assert (single.kind, single.address, single.words) == ("write_single", address, (words[0],))
    response = parse_frame(build_read_response(slave, words[:125]), "response")
    assert (response.kind, list(response.words), response.problems) == ("read_response", words[:125], ())


@settings(max_examples=300)
@given(st.sampled_from(range(len(DEVICES))), st.binary(max_size=300), st.sampled_from([None, "request", "response"]))
def test_decoder_on_arbitrary_bytes_never_raises_anything_else(index: int, data: bytes, direction: str | None) -> None:
    try:
        decoded = decode_frame(DEVICES[index], data, direction=direction)
    except UsageError:
        assert len(data) < 4
        return
    assert decoded.frame.raw == data


@st.composite
def register_sets(draw: st.DrawFn) -> list[RegisterSpec[Any]]:
    specs: list[RegisterSpec[Any]] = []
    address = draw(st.integers(0, 50))
    for i in range(draw(st.integers(1, 25))):
        address += draw(st.integers(0, 3))  # gaps of up to 3 words
        data_type = draw(st.sampled_from(TYPES))
        paired = data_type in ("u16", "s16") and draw(st.booleans())
        if paired:
            address += 1
        specs.append(RegisterSpec(name=f"r{i}", address=address, data_type=data_type, access="rw", paired=paired))
        address += 2 if data_type in ("u32", "s32") else 1
    return specs


def _fewest_requests(specs: list[RegisterSpec[Any]], limit: int, documented: frozenset[tuple[str, int]] | None) -> int:
    """Dynamic programme over the sorted registers: the true minimum number of requests."""
    regs = sorted(specs, key=lambda r: r.first_address)
    best = [0] + [10**9] * len(regs)
    for end in range(1, len(regs) + 1):
        for start in range(end, 0, -1):
            chunk = regs[start - 1 : end]
            first = chunk[0].first_address if len(chunk) > 1 else chunk[0].address
            last = chunk[-1].address + chunk[-1].words
            if last - first > limit:
                break
            covered = {a for r in chunk for a in range(r.first_address, r.address + r.words)}
            if documented is not None and any((chunk[0].space, a) not in documented for a in range(first, last) if a not in covered):
                break
            best[end] = min(best[end], best[start - 1] + 1)
    return best[-1]


@settings(max_examples=300)
@given(register_sets(), st.integers(2, 20), st.booleans())
def test_read_plan_is_valid_and_optimal(specs: list[RegisterSpec[Any]], limit: int, tolerate: bool) -> None:
    documented = None if tolerate else frozenset((r.space, a) for r in specs for a in range(r.first_address, r.address + r.words))
    blocks = plan_reads(specs, limit, documented)
    seen = [r.name for b in blocks for r in b.registers]
    assert sorted(seen) == sorted(r.name for r in specs)  # every register exactly once
    for block in blocks:
        assert block.count <= max(limit, max(r.words for r in block.registers))
        for r in block.registers:
            assert block.address <= r.address and r.address + r.words <= block.address + block.count
        if documented is not None:
            assert all((block.space, a) in documented for a in range(block.address, block.address + block.count))
    assert len(blocks) == _fewest_requests(specs, limit, documented)


@given(register_sets(), st.integers(2, 20))
def test_write_plan_covers_every_value_once(specs: list[RegisterSpec[Any]], limit: int) -> None:
    values = [(s, 1) for s in specs]
    blocks = plan_writes(values, limit)
    assert sorted(r.name for b in blocks for r in b.registers) == sorted(s.name for s in specs)
    for block in blocks:
        assert len(block.words) <= max(limit, 3)
        if block.single:
            assert block.registers[0].words == 1


# -- issue #19: wide and float types in every byte and word order, strings, bit frames ------------

WIDE = {"u32": "I", "s32": "i", "u64": "Q", "s64": "q", "f32": "f", "f64": "d"}


def _struct_layout(fmt: str, raw: int | float, byte_order: str, word_order: str) -> list[int]:
    """struct's big-endian bytes laid out in the order: bytes swapped in each word, words reversed."""
    data = struct.pack(">" + fmt, raw)
    pairs = [data[i : i + 2] for i in range(0, len(data), 2)]
    if byte_order == "low_first":
        pairs = [p[::-1] for p in pairs]
    if word_order == "low_first":
        pairs = pairs[::-1]
    return [int.from_bytes(p, "big") for p in pairs]


@st.composite
def wide_raw(draw: st.DrawFn) -> tuple[RegisterSpec[Any], int | float, str]:
    data_type = draw(st.sampled_from(sorted(WIDE)))
    s: RegisterSpec[Any] = RegisterSpec(
        name="r",
        address=10,
        data_type=data_type,
        access="rw",
        byte_order=draw(st.sampled_from(ORDERS)),
        word_order=draw(st.sampled_from(ORDERS)),
    )
    if s.type_info.is_float:
        floats = st.floats(allow_nan=False, allow_infinity=False, width=32 if data_type == "f32" else 64)
        raw: int | float = draw(floats)
    else:
        raw = draw(st.integers(int(s.type_min), int(s.type_max)))
    return s, raw, WIDE[data_type]


@given(wide_raw())
def test_wide_values_are_laid_out_as_struct_says_in_every_order(case: tuple[RegisterSpec[Any], int | float, str]) -> None:
    s, raw, fmt = case
    words = raw_to_words(s, raw)
    assert words == _struct_layout(fmt, raw, s.byte_order, s.word_order)
    back = words_to_raw(s, words)
    assert back == raw and type(back) is type(raw)


@given(
    st.text(max_size=8), st.sampled_from(["ascii", "latin-1", "utf-8", "gbk"]), st.sampled_from(["nul", "space"]), st.sampled_from(ORDERS)
)
def test_text_round_trips_or_is_refused(text: str, encoding: str, padding: str, byte_order: str) -> None:
    s: RegisterSpec[str] = RegisterSpec(
        name="t", address=0, data_type="string", access="rw", string_words=4, encoding=encoding, padding=padding, byte_order=byte_order
    )
    try:
        data = text.encode(encoding)
    except UnicodeEncodeError:
        data = None
    fits = data is not None and len(data) <= 8 and b"\0" not in data
    if not fits:
        try:
            check_raw(s, text)
        except ValueError:
            return
        raise AssertionError(f"accepted {text!r} in {encoding}")
    assert data is not None
    padded = data.ljust(8, b" " if padding == "space" else b"\0")
    words = raw_to_words(s, text)
    pairs = [padded[i : i + 2] for i in range(0, 8, 2)]
    assert words == [int.from_bytes(p[::-1] if byte_order == "low_first" else p, "big") for p in pairs]
    expected = text.rstrip(" ") if padding == "space" else text
    assert words_to_raw(s, words) == expected


@given(st.integers(0, 255), st.integers(0, 0xFFFF), st.lists(st.integers(0, 1), min_size=1, max_size=1968))
def test_bit_frames_round_trip(slave: int, address: int, bits: list[int]) -> None:
    packed = sum(b << i for i, b in enumerate(bits)).to_bytes((len(bits) + 7) // 8, "little")
    request = build_write_multiple(slave, address, bits, space="coil")
    assert request[7 : 7 + len(packed)] == packed
    parsed = parse_frame(request, "request")
    assert (parsed.kind, parsed.count, list(parsed.bits), parsed.problems) == ("write_multiple_request", len(bits), bits, ())
    response = parse_frame(build_read_response(slave, bits, space="discrete_input"), "response")
    assert list(response.bits[: len(bits)]) == bits and not any(response.bits[len(bits) :])
    single = parse_frame(build_write_single(slave, address, bits[0], space="coil"))
    assert single.words == ((0xFF00 if bits[0] else 0x0000),) and single.bits == (bits[0],)
