"""Every helper the C headers emit, called on known values and on the edges, under ASan and UBSan.

The expected values come from the model (masks, widths, element addresses, firmware gates), from
Python's own integer arithmetic and from pymodbus (its register conversions for every type and word
order, its PDUs for coil, discrete-input and input-register frames), never from the header, so a
header that agrees with itself but not with the map or the wire (a setter that does not clear its
field, an address formula off by one element, a float helper in the wrong order, a string copy
that keeps its padding) fails here. The seed maps and issue #19's fixture maps are generated into a
temporary directory, so the committed generated/ is not what is tested.
"""

from __future__ import annotations

import math
import struct
import subprocess
from pathlib import Path

import pytest
from pymodbus.client.mixin import ModbusClientMixin
from pymodbus.framer.rtu import FramerRTU
from pymodbus.pdu import ModbusPDU
from pymodbus.pdu.bit_message import (
    ReadCoilsRequest,
    ReadCoilsResponse,
    ReadDiscreteInputsRequest,
    ReadDiscreteInputsResponse,
    WriteMultipleCoilsRequest,
    WriteSingleCoilRequest,
)
from pymodbus.pdu.register_message import ReadInputRegistersRequest, ReadInputRegistersResponse

from regmap.backends.c.names import C_TYPES, CIdentifier, Context, c_raw
from regmap.backends.c.views import modern
from regmap.frontend import load_map
from regmap.generate import render
from regmap.model import Bitfield, ByteOrder, DataType, Device, Register, WordOrder
from regmap_runtime.rtu import with_crc

from conftest import FIXTURE_MAPS, MAPS, require_tool

DATATYPE = ModbusClientMixin.DATATYPE
PYMODBUS_TYPES = {
    DataType.U16: DATATYPE.UINT16,
    DataType.S16: DATATYPE.INT16,
    DataType.U32: DATATYPE.UINT32,
    DataType.S32: DATATYPE.INT32,
    DataType.U64: DATATYPE.UINT64,
    DataType.S64: DATATYPE.INT64,
    DataType.F32: DATATYPE.FLOAT32,
    DataType.F64: DATATYPE.FLOAT64,
    DataType.TIMESTAMP: DATATYPE.UINT32,  # seconds since 1970: the words of a u32
}
FLOAT_FORMATS = {DataType.F32: (">f", ">I", "regmap_f32"), DataType.F64: (">d", ">Q", "regmap_f64")}
FLOAT_VALUES = [0.0, -0.0, 230.1, 12.25, -1.5, 3.4e38, 1e-40, math.inf, -math.inf]

PROLOGUE = """\
#include <stdio.h>
#include <string.h>
#include "{header}"

static unsigned checks, failures;
#define EXPECT(cond) do {{ checks++; if (!(cond)) {{ failures++; printf("FAIL line %d: %s\\n", __LINE__, #cond); }} }} while (0)

int main(void)
{{
"""

EPILOGUE = """\
    printf("%u checks, %u failed\\n", checks, failures);
    return failures == 0u ? 0 : 1;
}
"""


def _field_value(ctx: Context, b: Bitfield, value: int) -> str:
    """A field value as the setter's parameter takes it: the enum's constant for a member, else the number (cast to the enum)."""
    member = b.enum.by_value(value) if b.enum is not None else None
    if member is not None and b.enum is not None:
        return CIdentifier(ctx.prefix, b.enum.name, member.name)
    return f"({ctx.symbol_ref(b.enum.name)}){value}u" if b.enum is not None else f"{value}u"


def _bitfield_cases(device: Device, ctx: Context) -> list[str]:
    """Each setter replaces only its field (never ORs) with a value it accepts, and refuses (false, the
    word unchanged) a value wider than the field or one its enum lacks; each getter reads its field."""
    out: list[str] = []
    seen: set[str] = set()
    for reg in device.registers:
        owner = ctx.owner(reg)
        if not reg.bitfields or owner in seen:
            continue
        seen.add(owner)
        full = (1 << (16 * reg.words)) - 1
        out.append(f"    {{ {C_TYPES[reg.type].bits} w;")
        for b in reg.bitfields:
            get, put = ctx.symbol_ref(owner, "get", b.name), ctx.symbol_ref(owner, "set", b.name)
            widest = b.max_value
            values = sorted({m.value for m in b.enum.members}) if b.enum else [0, widest // 2 + (1 if widest > 1 else 0), widest]
            for v in (values[0], values[len(values) // 2], values[-1]):
                out += [
                    f"        w = 0x{full:X}u; EXPECT({put}(&w, {_field_value(ctx, b, v)}) && w == 0x{(full & ~b.mask) | (v << b.lsb):X}u);"
                    "  /* clears only its field */",
                    f"        w = 0x{b.mask:X}u; EXPECT({put}(&w, {_field_value(ctx, b, v)}) && w == 0x{v << b.lsb:X}u);  /* replaces, never ORs */",
                    f"        EXPECT({get}(0x{(full & ~b.mask) | (v << b.lsb):X}u) == {v}u);",
                ]
            refused = [widest + 1] if b.width < 16 * reg.words else []
            if b.enum is not None:
                refused += [v for v in range(widest + 1) if b.enum.by_value(v) is None][:2]
            for v in refused:
                out.append(
                    f"        w = 0x1234u; EXPECT(!{put}(&w, {_field_value(ctx, b, v)}) && w == 0x1234u);  /* refused, the word unchanged */"
                )
            out += [f"        EXPECT({get}(0x{full:X}u) == {widest}u);", f"        EXPECT({get}(0x{full & ~b.mask:X}u) == 0u);"]
        out.append("    }")
    return out


def _array_cases(device: Device, ctx: Context) -> list[str]:
    if not device.arrays:
        return []
    out: list[str] = ["    {", "        uint16_t address = 0u;"]
    for array in device.arrays:
        for member in array.members:
            function = ctx.symbol_ref(f"{array.name}_{member.name}", "addr")
            for n in sorted(
                {array.first_index, array.first_index + 1, array.last_index} & set(range(array.first_index, array.last_index + 1))
            ):
                address = array.element_address(n, member)
                out.append(f"        EXPECT({function}({n}u, &address) && address == 0x{address:04X}u);")
            out.append(f"        address = 0x1234u; EXPECT(!{function}({array.last_index + 1}u, &address) && address == 0x1234u);")
            if array.first_index > 0:
                out.append(f"        EXPECT(!{function}({array.first_index - 1}u, &address));")
            out.append(f"        EXPECT(!{function}(0xFFFFFFFFu, &address));")
    out.append("    }")
    return out


def _word_cases() -> list[str]:
    out = ["    {", "        uint16_t w[2];"]
    for word, signed in ((0x0000, 0), (0x7FFF, 32767), (0x8000, -32768), (0xFFFF, -1)):
        out.append(f"        EXPECT(regmap_s16_from_word(0x{word:04X}u) == {signed});")
        out.append(f"        EXPECT(regmap_s16_to_word((int16_t){signed}) == 0x{word:04X}u);")
    for value in (0, 1, 0x7FFFFFFF, 0x80000000, 0xFFFFFFFF, 0x0001FFFF):
        high, low = value >> 16, value & 0xFFFF
        signed = value - (1 << 32) if value & 0x80000000 else value
        signed_c = f"({signed}LL)" if signed >= 0 else f"(-{-signed}LL)"
        out += [
            f"        w[0] = 0x{high:04X}u; w[1] = 0x{low:04X}u;",
            f"        EXPECT(regmap_u32_from_words(w, REGMAP_HIGH_FIRST) == 0x{value:08X}ul);",
            f"        EXPECT((long long)regmap_s32_from_words(w, REGMAP_HIGH_FIRST) == {signed_c});",
            f"        EXPECT(regmap_u32_from_words(w, REGMAP_LOW_FIRST) == 0x{(low << 16) | high:08X}ul);",
            f"        regmap_u32_to_words(0x{value:08X}ul, REGMAP_LOW_FIRST, w); EXPECT(w[0] == 0x{low:04X}u && w[1] == 0x{high:04X}u);",
            f"        regmap_s32_to_words((int32_t){signed_c}, REGMAP_HIGH_FIRST, w); EXPECT(w[0] == 0x{high:04X}u && w[1] == 0x{low:04X}u);",
        ]
    out += [
        "        EXPECT(regmap_pair_high_word(0x8000u, true) == 0xFFFFu);",
        "        EXPECT(regmap_pair_high_word(0x8000u, false) == 0x0000u);",
        "        EXPECT(regmap_pair_high_word(0x7FFFu, true) == 0x0000u);",
        "    }",
    ]
    return out


def _bytes(frame: bytes) -> str:
    return ", ".join(f"0x{b:02X}u" for b in frame)


def _parser_cases() -> list[str]:
    good = with_crc(bytes([1, 3, 2, 0x00, 0x16]))
    other_slave_exception = with_crc(bytes([2, 0x83, 0x02]))
    own_exception = with_crc(bytes([1, 0x83, 0x02]))
    short_count = with_crc(bytes([1, 3, 4, 0x00, 0x16]))  # the byte count disagrees with the data
    more_words = with_crc(bytes([1, 3, 4, 0x00, 0x16, 0x00, 0x17]))  # well formed, but two words for a read of one
    wrong_function = with_crc(bytes([1, 4, 2, 0x00, 0x16]))
    bad_crc = good[:-1] + bytes([good[-1] ^ 0xFF])
    echo = with_crc(bytes([1, 6, 0x01, 0x91, 0x00, 0x0F]))
    cases = [
        (good, "REGMAP_OK"),
        (other_slave_exception, "REGMAP_ERR_SLAVE"),
        (own_exception, "REGMAP_ERR_EXCEPTION"),
        (short_count, "REGMAP_ERR_LENGTH"),
        (more_words, "REGMAP_ERR_BYTE_COUNT"),
        (wrong_function, "REGMAP_ERR_FUNCTION"),
        (bad_crc, "REGMAP_ERR_CRC"),
    ]
    out = ["    {", "        uint16_t words[4] = {0u, 0u, 0u, 0u};", "        uint8_t exception = 0u;"]
    for index, (frame, status) in enumerate(cases):
        out.append(f"        static const uint8_t f{index}[] = {{{_bytes(frame)}}};")
        out.append(f"        EXPECT(regmap_rtu_parse_read_response(f{index}, sizeof f{index}, 1u, 1u, words, 4u, &exception) == {status});")
    out += [
        "        EXPECT(words[0] == 0x0016u);",
        f"        static const uint8_t e0[] = {{{_bytes(echo)}}};",
        "        EXPECT(regmap_rtu_parse_write_single_response(e0, sizeof e0, 1u, 0x0191u, 0x000Fu, &exception) == REGMAP_OK);",
        "        EXPECT(regmap_rtu_parse_write_single_response(e0, sizeof e0, 1u, 0x0191u, 0x0010u, &exception) == REGMAP_ERR_ECHO);",
        "        EXPECT(regmap_rtu_parse_write_single_response(e0, sizeof e0, 2u, 0x0191u, 0x000Fu, &exception) == REGMAP_ERR_SLAVE);",
        "        EXPECT(regmap_rtu_parse_read_response(f0, 3u, 1u, 1u, words, 4u, &exception) == REGMAP_ERR_LENGTH);",
        "        EXPECT(regmap_rtu_parse_read_response(f0, sizeof f0, 1u, 1u, words, 0u, &exception) == REGMAP_ERR_ARGUMENT);",
        "    }",
    ]
    return out


def _c_words(words: list[int]) -> str:
    return "{ " + ", ".join(f"0x{w:04X}u" for w in words) + " }"


def _swap(words: list[int]) -> list[int]:
    return [((w & 0xFF) << 8) | (w >> 8) for w in words]


def wire_words(reg: Register, raw: int | float) -> list[int]:
    """The words on the wire of `raw` in `reg`: pymodbus's conversion in the register's word order, then
    each word's bytes exchanged where the register's bytes are low first (pymodbus has no byte order)."""
    little = reg.wide and reg.word_order is WordOrder.LOW_FIRST
    words = ModbusClientMixin.convert_to_registers(raw, PYMODBUS_TYPES[reg.type], word_order="little" if little else "big")
    assert isinstance(words, list)
    return _swap(words) if reg.byte_order is ByteOrder.LOW_FIRST else words


def _int_values(reg: Register) -> list[int]:
    info = reg.type.info
    low, high = int(info.raw_min), int(info.raw_max)
    pattern = int.from_bytes(bytes(range(1, 2 * reg.words + 1)), "big") & high  # 0x0102..., every byte different
    return sorted({low, high, 0, 1, pattern, -1 if reg.signed else high - 1})


def _codec_cases(device: Device, ctx: Context) -> list[str]:
    """Each modern register's from_wire / to_wire on values whose words pymodbus computes."""
    out: list[str] = []
    seen: set[str] = set()
    for reg in device.registers:
        owner = ctx.owner(reg)
        if not modern(reg) or reg.type.is_bool or owner in seen:
            continue
        seen.add(owner)
        from_wire, to_wire = ctx.symbol_ref(owner, "from_wire"), ctx.symbol_ref(owner, "to_wire")
        if reg.type.is_string:
            out += _string_cases(reg, from_wire, to_wire)
        elif reg.type.is_float:
            value_format, bits_format, prefix = FLOAT_FORMATS[reg.type]
            for value in FLOAT_VALUES:
                bits = struct.unpack(bits_format, struct.pack(value_format, value))[0]
                words = wire_words(reg, struct.unpack(value_format, struct.pack(value_format, value))[0])
                literal = f"0x{bits:X}ull"
                out += [
                    "    {",
                    f"        static const uint16_t in[{len(words)}] = {_c_words(words)};",
                    f"        uint16_t w[{len(words)}];",
                    f"        {to_wire}({prefix}_from_bits({literal}), w);",
                    f"        EXPECT(memcmp(w, in, sizeof in) == 0);  /* {reg.name} = {value!r} */",
                    f"        EXPECT({prefix}_to_bits({from_wire}(in)) == {literal});",
                    "    }",
                ]
        else:
            for raw in _int_values(reg):
                words = wire_words(reg, raw)
                literal = c_raw(raw, reg.signed)
                if reg.words == 1:
                    out += [
                        f"    EXPECT({to_wire}({literal}) == 0x{words[0]:04X}u);  /* {reg.name} = {raw} */",
                        f"    EXPECT({from_wire}(0x{words[0]:04X}u) == {literal});",
                    ]
                    continue
                out += [
                    "    {",
                    f"        static const uint16_t in[{len(words)}] = {_c_words(words)};",
                    f"        uint16_t w[{len(words)}];",
                    f"        {to_wire}({literal}, w);",
                    f"        EXPECT(memcmp(w, in, sizeof in) == 0);  /* {reg.name} = {raw} */",
                    f"        EXPECT({from_wire}(in) == {literal});",
                    "    }",
                ]
    return out


def _text_words(reg: Register, data: bytes) -> list[int]:
    """The words of a string register holding `data`, padded as the map says (first byte high), in its byte order."""
    data += (b" " if reg.padding == "space" else b"\0") * (2 * reg.words - len(data))
    words = [data[i] << 8 | data[i + 1] for i in range(0, len(data), 2)]
    return _swap(words) if reg.byte_order is ByteOrder.LOW_FIRST else words


def _octal(data: bytes) -> str:
    """A C string literal of exactly these bytes."""
    return '"' + "".join(f"\\{b:03o}" for b in data) + '"'


def _string_cases(reg: Register, from_wire: str, to_wire: str) -> list[str]:
    size = 2 * reg.words
    texts = [b"", b"A", b"AB-12", (b"XY" * reg.words)[:size], "\u00e9x".encode(reg.encoding) if reg.encoding == "utf-8" else b"~z"]
    out = [f"    /* {reg.name}: {reg.words} words, {reg.padding} padded, bytes {reg.byte_order.value} */"]
    for data in texts:
        words = _text_words(reg, data)
        read_back = data.rstrip(b" ") if reg.padding == "space" else data
        literal, read_literal = _octal(data), _octal(read_back)
        out += [
            "    {",
            f"        static const uint16_t in[{reg.words}] = {_c_words(words)};",
            f"        uint16_t w[{reg.words}];",
            f"        char text[{size + 1}];",
            f"        EXPECT({to_wire}({literal}, w) && memcmp(w, in, sizeof in) == 0);",
            f"        EXPECT({from_wire}(in, text, sizeof text) == {len(read_back)}u && memcmp(text, {read_literal}, {len(read_back) + 1}u) == 0);",
            f"        EXPECT({from_wire}(in, text, 2u) == {len(read_back)}u && memcmp(text, {_octal(read_back[:1])}, {min(len(read_back), 1) + 1}u) == 0);",
            "    }",
        ]
    too_long = _octal(b"Z" * (size + 1))
    out += [
        "    {",
        f"        uint16_t w[{reg.words}];",
        "        memset(w, 0x5A, sizeof w);",
        f"        EXPECT(!{to_wire}({too_long}, w) && w[0] == 0x5A5Au);  /* one byte too many: refused, untouched */",
        "    }",
    ]
    return out


def _gate_cases(device: Device, ctx: Context) -> list[str]:
    """Each gated register's in_firmware() at the edges of its gate; the expected answers by tuple comparison here."""

    def version(text: str) -> tuple[int, int]:
        parts = [int(p) for p in text.split(".")] + [0]
        return parts[0], parts[1]

    out: list[str] = []
    seen: set[str] = set()
    for reg in device.registers:
        owner = ctx.owner(reg)
        gate = reg.firmware
        if gate is None or owner in seen:
            continue
        seen.add(owner)
        edges = {(0, 0), (255, 255)}
        for text in (gate.first, gate.until):
            if text is not None:
                major, minor = version(text)
                edges |= {(major, minor), (major, minor + 1), (major + 1, 0)} | ({(major, minor - 1)} if minor else {(major - 1, 99)})
        for major, minor in sorted(e for e in edges if e[0] >= 0):
            admitted = (gate.first is None or (major, minor) >= version(gate.first)) and (
                gate.until is None or (major, minor) < version(gate.until)
            )
            call = f"{ctx.symbol_ref(owner, 'in_firmware')}(REGMAP_VERSION({major}u, {minor}u))"
            out.append(f"    EXPECT({'' if admitted else '!'}{call});  /* {gate.text} */")
    return out


def _rtu(pdu: ModbusPDU, slave: int = 1) -> bytes:
    body = bytes([slave, pdu.function_code]) + pdu.encode()
    return body + FramerRTU.compute_CRC(body).to_bytes(2, "big")


def _builder_cases(device: Device, ctx: Context) -> list[str]:
    """The device's coil, discrete-input and input-register builders against pymodbus's PDUs."""
    spaces = {r.space for r in device.registers}
    codes = device.transport.function_codes
    t = device.transport
    out: list[str] = ["    {", "        uint8_t buf[REGMAP_RTU_MAX_FRAME];"]
    cases: list[tuple[str, str, bytes]] = []
    if "input" in spaces and 0x04 in codes:
        name = ctx.symbol_ref("build_read_input_registers")
        cases.append((name, "0x0008u, 1u", _rtu(ReadInputRegistersRequest(address=8, count=1))))
        cases.append((name, f"0x0000u, {t.max_read_registers}u", _rtu(ReadInputRegistersRequest(address=0, count=t.max_read_registers))))
        out.append(f"        EXPECT({name}(buf, sizeof buf, 1u, 0x0000u, {t.max_read_registers + 1}u) == 0u);")
    if "coil" in spaces:
        read, single, multiple = (ctx.symbol_ref(n) for n in ("build_read_coils", "build_write_single_coil", "build_write_multiple_coils"))
        cases.append((read, "0x0013u, 19u", _rtu(ReadCoilsRequest(address=0x13, count=19))))
        cases.append((read, f"0x0000u, {t.max_read_coils}u", _rtu(ReadCoilsRequest(address=0, count=t.max_read_coils))))
        out.append(f"        EXPECT({read}(buf, sizeof buf, 1u, 0x0000u, {t.max_read_coils + 1}u) == 0u);")
        cases.append((single, "0x00ACu, true", _rtu(WriteSingleCoilRequest(address=0xAC, bits=[True]))))
        cases.append((single, "0x00ACu, false", _rtu(WriteSingleCoilRequest(address=0xAC, bits=[False]))))
        pattern = [bool((i * 7) % 3) for i in range(t.max_write_coils)]
        out.append(f"        static const bool b[{len(pattern)}] = {{{', '.join('true' if bit else 'false' for bit in pattern)}}};")
        cases.append((multiple, f"0x0013u, b, {len(pattern)}u", _rtu(WriteMultipleCoilsRequest(address=0x13, bits=pattern))))
        cases.append((multiple, "0x0013u, b, 10u", _rtu(WriteMultipleCoilsRequest(address=0x13, bits=pattern[:10]))))
        out.append(f"        EXPECT({multiple}(buf, sizeof buf, 1u, 0x0000u, b, {t.max_write_coils + 1}u) == 0u);")
    if "discrete_input" in spaces:
        name = ctx.symbol_ref("build_read_discrete_inputs")
        cases.append((name, "0x00C4u, 22u", _rtu(ReadDiscreteInputsRequest(address=0xC4, count=22))))
    for index, (function, args, frame) in enumerate(cases):
        out += [
            f"        static const uint8_t want{index}[] = {{{_bytes(frame)}}};",
            f"        EXPECT({function}(buf, sizeof buf, 1u, {args}) == sizeof want{index} && memcmp(buf, want{index}, sizeof want{index}) == 0);",
        ]
    out.append("    }")
    return out if cases else []


def _bit_response_cases() -> list[str]:
    """Coil and discrete-input responses that pymodbus encodes, parsed back bit for bit; input registers too."""
    out = [
        "    {",
        "        static bool got[2000];",
        "        uint16_t regs[3];",
        "        uint8_t exc = 0u;",
        "        bool same;",
        "        unsigned i;",
    ]
    for index, count in enumerate((1, 7, 8, 9, 19, 22, 2000)):
        bits = [(i * 5 + count) % 7 < 3 for i in range(count)]
        expected = ", ".join("true" if bit else "false" for bit in bits)
        out.append(f"        static const bool want{index}[{count}] = {{{expected}}};")
        for kind, response, parser in (
            ("c", ReadCoilsResponse, "regmap_rtu_parse_read_coils_response"),
            ("d", ReadDiscreteInputsResponse, "regmap_rtu_parse_read_discrete_inputs_response"),
        ):
            frame = _rtu(response(bits=bits))
            out += [
                f"        static const uint8_t {kind}{index}[] = {{{_bytes(frame)}}};",
                f"        EXPECT({parser}({kind}{index}, sizeof {kind}{index}, 1u, {count}u, got, 2000u, &exc) == REGMAP_OK);",
                "        same = true;",
                f"        for (i = 0u; i < {count}u; ++i) {{",
                f"            same = same && got[i] == want{index}[i];",
                "        }",
                f"        EXPECT(same);  /* {count} bits from pymodbus's {response.__name__} */",
            ]
    frame = _rtu(ReadInputRegistersResponse(registers=[10, 0xFFFF, 0x1234]))
    out += [
        f"        static const uint8_t ir[] = {{{_bytes(frame)}}};",
        "        EXPECT(regmap_rtu_parse_read_input_response(ir, sizeof ir, 1u, 3u, regs, 3u, &exc) == REGMAP_OK);",
        "        EXPECT(regs[0] == 10u && regs[1] == 0xFFFFu && regs[2] == 0x1234u);",
        "        EXPECT(regmap_rtu_parse_read_response(ir, sizeof ir, 1u, 3u, regs, 3u, &exc) == REGMAP_ERR_FUNCTION);",
        "    }",
    ]
    return out


def helper_program(device: Device, header: str) -> str:
    ctx = Context(device)
    body = _bitfield_cases(device, ctx) + _array_cases(device, ctx) + _word_cases() + _parser_cases()
    body += _codec_cases(device, ctx) + _gate_cases(device, ctx) + _builder_cases(device, ctx) + _bit_response_cases()
    return PROLOGUE.format(header=header) + "\n".join(body) + "\n" + EPILOGUE


@pytest.fixture(scope="module")
def headers(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The C headers of the seed and fixture maps, as `regmap generate --target c` writes them now."""
    out = tmp_path_factory.mktemp("c-headers")
    for rel, text in render([load_map(p) for p in (*MAPS, *FIXTURE_MAPS)], ["c"])["c"].items():
        (out / rel).write_text(text, encoding="utf-8")
    return out


@pytest.mark.parametrize("map_path", [*MAPS, *FIXTURE_MAPS], ids=lambda p: p.stem)
def test_every_generated_helper_behaves(map_path: Path, tmp_path: Path, headers: Path) -> None:
    cc = require_tool("gcc")
    device = load_map(map_path)
    source = tmp_path / "helpers.c"
    source.write_text(helper_program(device, f"{device.id}.h"), encoding="utf-8")
    binary = tmp_path / "helpers"
    flags = [
        "-std=c99",
        "-Wall",
        "-Wextra",
        "-Wpedantic",
        "-Werror",
        "-Wno-unused-function",
        "-fsanitize=address,undefined",
        "-fno-sanitize-recover=all",
    ]
    built = subprocess.run([cc, *flags, "-I", str(headers), str(source), "-o", str(binary)], capture_output=True, text=True, check=False)
    assert built.returncode == 0, built.stderr[-3000:]
    run = subprocess.run([str(binary)], capture_output=True, text=True, check=False, timeout=60)
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-3000:]
    checks = int(run.stdout.strip().splitlines()[-1].split()[0])
    assert checks > 40, run.stdout


def test_a_setter_that_does_not_clear_its_field_is_caught(tmp_path: Path, headers: Path) -> None:
    """The mutant the mutation run found: set() that ORs the value in without clearing the field."""
    cc = require_tool("gcc")
    device = load_map(MAPS[[p.stem for p in MAPS].index("idm_rs")])
    header = (headers / "idm_rs.h").read_text(encoding="utf-8")
    broken = header.replace("((uint32_t)*raw & ~(uint32_t)IDM_RS_DI2_FUNCTION_FUNCTION_MASK) |", "((uint32_t)*raw) |", 1)
    assert broken != header
    (tmp_path / "idm_rs.h").write_text(broken, encoding="utf-8")
    (tmp_path / "regmap_rtu.h").write_text((headers / "regmap_rtu.h").read_text(encoding="utf-8"), encoding="utf-8")
    source = tmp_path / "helpers.c"
    source.write_text(helper_program(device, "idm_rs.h"), encoding="utf-8")
    built = subprocess.run(
        [cc, "-std=c99", "-I", str(tmp_path), str(source), "-o", str(tmp_path / "helpers")], capture_output=True, text=True, check=False
    )
    assert built.returncode == 0, built.stderr[-2000:]
    run = subprocess.run([str(tmp_path / "helpers")], capture_output=True, text=True, check=False, timeout=60)
    assert run.returncode == 1 and "idm_rs_di2_function_set_function(&w, IDM_RS_DI_FUNCTION_" in run.stdout
