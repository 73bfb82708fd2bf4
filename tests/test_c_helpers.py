"""Every helper the C headers emit, called on known values and on the edges, under ASan and UBSan.

The expected values come from the model (masks, widths, element addresses) and from Python's own
integer arithmetic, never from the header, so a header that agrees with itself but not with the
map (a setter that does not clear its field, an address formula off by one element) fails here.
"""

from __future__ import annotations

import subprocess
from pathlib import Path

import pytest

from regmap.backends.c.names import Context
from regmap.frontend import load_map
from regmap.model import Device
from regmap_runtime.rtu import with_crc

from conftest import GENERATED, MAPS, require_tool

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


def _bitfield_cases(device: Device, ctx: Context) -> list[str]:
    out: list[str] = []
    seen: set[str] = set()
    for reg in device.registers:
        owner = ctx.owner(reg)
        if not reg.bitfields or owner in seen:
            continue
        seen.add(owner)
        full = (1 << (16 * reg.words)) - 1
        for b in reg.bitfields:
            get, put = ctx.symbol_ref(owner, "get", b.name), ctx.symbol_ref(owner, "set", b.name)
            widest = b.max_value
            middle = widest // 2 + (1 if widest > 1 else 0)
            out += [
                f"    EXPECT({put}(0x{full:X}u, 0u) == 0x{full & ~b.mask:X}u);  /* clears only its field */",
                f"    EXPECT({put}(0u, {widest}u) == 0x{b.mask:X}u);",
                f"    EXPECT({put}(0x{full:X}u, {middle}u) == 0x{(full & ~b.mask) | (middle << b.lsb):X}u);",
                f"    EXPECT({put}(0x{b.mask:X}u, {middle}u) == 0x{middle << b.lsb:X}u);  /* replaces, never ORs */",
                f"    EXPECT({get}(0x{full:X}u) == {widest}u);",
                f"    EXPECT({get}(0x{full & ~b.mask:X}u) == 0u);",
                f"    EXPECT({get}(0x{middle << b.lsb:X}u) == {middle}u);",
            ]
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


def helper_program(device: Device, header: str) -> str:
    ctx = Context(device)
    body = _bitfield_cases(device, ctx) + _array_cases(device, ctx) + _word_cases() + _parser_cases()
    return PROLOGUE.format(header=header) + "\n".join(body) + "\n" + EPILOGUE


@pytest.mark.parametrize("map_path", MAPS, ids=lambda p: p.stem)
def test_every_generated_helper_behaves(map_path: Path, tmp_path: Path) -> None:
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
    built = subprocess.run(
        [cc, *flags, "-I", str(GENERATED / "c"), str(source), "-o", str(binary)], capture_output=True, text=True, check=False
    )
    assert built.returncode == 0, built.stderr[-3000:]
    run = subprocess.run([str(binary)], capture_output=True, text=True, check=False, timeout=60)
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-3000:]
    checks = int(run.stdout.strip().splitlines()[-1].split()[0])
    assert checks > 40, run.stdout


def test_a_setter_that_does_not_clear_its_field_is_caught(tmp_path: Path) -> None:
    """The mutant the mutation run found: set() that ORs the value in without clearing the field."""
    cc = require_tool("gcc")
    device = load_map(MAPS[[p.stem for p in MAPS].index("idm_rs")])
    header = (GENERATED / "c" / "idm_rs.h").read_text(encoding="utf-8")
    broken = header.replace("((uint32_t)raw & ~(uint32_t)IDM_RS_DI2_FUNCTION_FUNCTION_MASK) |", "((uint32_t)raw) |", 1)
    assert broken != header
    (tmp_path / "idm_rs.h").write_text(broken, encoding="utf-8")
    (tmp_path / "regmap_rtu.h").write_text((GENERATED / "c" / "regmap_rtu.h").read_text(encoding="utf-8"), encoding="utf-8")
    source = tmp_path / "helpers.c"
    source.write_text(helper_program(device, "idm_rs.h"), encoding="utf-8")
    built = subprocess.run(
        [cc, "-std=c99", "-I", str(tmp_path), str(source), "-o", str(tmp_path / "helpers")], capture_output=True, text=True, check=False
    )
    assert built.returncode == 0, built.stderr[-2000:]
    run = subprocess.run([str(tmp_path / "helpers")], capture_output=True, text=True, check=False, timeout=60)
    assert run.returncode == 1 and "idm_rs_di2_function_set_function(0xFFFFu, 0u)" in run.stdout
