"""The C header's float and coil-bit helpers against libmodbus's own, linked into one program.

tests/c/libmodbus_compare.c includes the generated regmap_rtu.h and libmodbus's modbus.h: for every
float below, in each of the four orders, regmap_f32_from_wire must read the same bits as
modbus_get_float_abcd/_badc/_cdab/_dcba from the same two registers, and the registers
regmap_f32_to_wire writes must read back through libmodbus's getter as the same bits; regmap's bit
packing must equal modbus_get_byte_from_bits and modbus_set_bits_from_bytes for every count up to
2000. The float bit patterns come from Python's struct, not from regmap.
"""

from __future__ import annotations

import random
import re
import struct
import subprocess
from pathlib import Path

import pytest

from regmap.frontend import load_map
from regmap.generate import render

from conftest import FIXTURE_MAPS, MAPS, ROOT, require_tool
from support.libmodbus_ref import libmodbus_flags

SOURCE = ROOT / "tests" / "c" / "libmodbus_compare.c"


def _f32_bits(value: float) -> int:
    bits: int = struct.unpack(">I", struct.pack(">f", value))[0]
    return bits


SPECIAL_BITS = [
    0x00000000,  # 0.0
    0x80000000,  # -0.0
    0x00000001,  # the smallest subnormal
    0x80000001,
    0x007FFFFF,  # the largest subnormal
    0x00800000,  # FLT_MIN
    0x7F7FFFFF,  # FLT_MAX
    0xFF7FFFFF,
    0x7F800000,  # inf
    0xFF800000,  # -inf
    0x7FC00000,  # the quiet NaN
    0xFFC00000,
    0x7FC00001,  # a quiet NaN with a payload
    0x7FFFFFFF,
    0x7F800001,  # signalling NaNs
    0x7FBFFFFF,
    0xFF800001,
    0x12345678,  # four different bytes
    0x40490FDB,  # pi
]
SPECIAL_VALUES = [230.1, 230.5, 12.25, 3.4e38, -3.4e38, 1.0, -1.0, 0.1, 900.0, 1e-40, -1e-45, 65535.0, 1.5e-38]


def _float_bits() -> list[int]:
    rng = random.Random(19)
    patterns = {*SPECIAL_BITS, *(_f32_bits(v) for v in SPECIAL_VALUES)}
    patterns |= {rng.getrandbits(32) for _ in range(20000)}
    return sorted(patterns)


@pytest.fixture(scope="module")
def compare_program(tmp_path_factory: pytest.TempPathFactory) -> Path:
    cc = require_tool("cc")
    flags = libmodbus_flags()
    out = tmp_path_factory.mktemp("c-libmodbus")
    devices = [load_map(p) for p in (*MAPS, *FIXTURE_MAPS)]
    for rel, text in render(devices, ["c"])["c"].items():
        (out / rel).write_text(text, encoding="utf-8")
    binary = out / "libmodbus_compare"
    cflags = ["-std=c99", "-O2", "-Wall", "-Wextra", "-Wpedantic", "-Werror", "-Wconversion"]
    build = subprocess.run([cc, *cflags, f"-I{out}", str(SOURCE), "-o", str(binary), *flags], capture_output=True, text=True, check=False)
    assert build.returncode == 0, build.stderr
    return binary


def test_float_and_bit_helpers_equal_libmodbus(compare_program: Path) -> None:
    patterns = _float_bits()
    stdin = "".join(f"{bits:08x}\n" for bits in patterns)
    run = subprocess.run([str(compare_program)], input=stdin, capture_output=True, text=True, timeout=120, check=False)
    assert run.returncode == 0, run.stdout[-4000:] + run.stderr[-2000:]
    summary = re.search(r"^(\d+) passed, (\d+) failed$", run.stdout, flags=re.M)
    assert summary is not None, run.stdout
    # 3 checks per order per float, and 2 per bit count
    assert int(summary.group(1)) == 3 * 4 * len(patterns) + 2 * 2000 and summary.group(2) == "0", run.stdout
    assert f"{len(patterns)} floats x 4 orders" in run.stdout


def test_a_wrong_byte_swap_is_caught(compare_program: Path, tmp_path: Path) -> None:
    """The comparison can fail: a regmap_rtu.h whose byte swap does nothing disagrees with libmodbus's badc/dcba."""
    include = compare_program.parent
    header = (include / "regmap_rtu.h").read_text(encoding="utf-8")
    swap = "(uint16_t)(((unsigned)word << 8) | ((unsigned)word >> 8))"
    assert header.count(swap) == 1
    (tmp_path / "regmap_rtu.h").write_text(header.replace(swap, "word"), encoding="utf-8")
    binary = tmp_path / "broken"
    build = subprocess.run(
        [require_tool("cc"), "-std=c99", f"-I{tmp_path}", str(SOURCE), "-o", str(binary), *libmodbus_flags()],
        capture_output=True,
        text=True,
        check=False,
    )
    assert build.returncode == 0, build.stderr
    run = subprocess.run([str(binary)], input=f"{_f32_bits(230.1):08x}\n", capture_output=True, text=True, timeout=60, check=False)
    assert run.returncode == 1 and "FAIL decode badc" in run.stdout and "FAIL decode dcba" in run.stdout, run.stdout
