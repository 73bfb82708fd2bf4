"""f16 in C: the shared header's half <-> float conversions (bit arithmetic, no _Float16), compiled warning-free
as C99 and C++17 and run: every one of the 65,536 bit patterns decodes as Python's struct 'e' does, and the
encoder rounds as struct does on the edges, on every tie between two neighbouring halves and on random
floats and doubles; then the value helpers of a map of f16 registers agree with the Python client's codec
(range, rounding, 'not available' markers, an enum coded as a half, a scale)."""

from __future__ import annotations

import itertools
import math
import os
import random
import struct
import subprocess
from pathlib import Path
from typing import Any

import pytest

from regmap.frontend import load_map
from regmap.generate import render
from regmap.runtime_bridge import runtime_specs
from regmap_runtime.codec import RangeError, raw_to_words, value_to_raw
from regmap_runtime.spec import RegisterSpec

from conftest import require_tool
from support.half_map import EDGE_VALUES, half, half_bits, write_half_map

FLAGS = ("-Wall", "-Wextra", "-Wpedantic", "-Werror")
COMPILERS = {
    "gcc-c99-sanitizers": ("gcc", "-std=c99", "-O1", "-fsanitize=address,undefined", "-fno-sanitize-recover=all", *FLAGS),
    "g++-c++17": ("g++", "-x", "c++", "-std=c++17", "-O2", *FLAGS),
    "clang-c99": ("clang", "-std=c99", "-O2", *FLAGS),
}


@pytest.fixture(scope="module")
def headers(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("c-half")
    for rel, text in render([load_map(write_half_map(out))], ["c"])["c"].items():
        (out / rel).write_text(text, encoding="utf-8")
    return out


def _run(compiler: str, program: str, headers: Path, tmp_path: Path) -> list[str]:
    tool, *flags = COMPILERS[compiler]
    source, binary = tmp_path / "half.c", tmp_path / f"half-{compiler}"
    source.write_text(program, encoding="utf-8")
    built = subprocess.run(
        [require_tool(tool), *flags, "-I", str(headers), str(source), "-o", str(binary)], capture_output=True, text=True, check=False
    )
    assert built.returncode == 0 and not built.stderr.strip(), f"{compiler}:\n{built.stderr[-4000:]}"
    env = {**os.environ, "ASAN_OPTIONS": "detect_leaks=0"}
    run = subprocess.run([str(binary)], capture_output=True, text=True, check=False, timeout=120, env=env)
    assert run.returncode == 0, run.stderr[-3000:]
    return run.stdout.splitlines()


def _float_bits(value: float) -> int:
    return int(struct.unpack(">I", struct.pack(">f", value))[0])


def _floats_to_encode() -> list[float]:
    """Edge values, every half, every tie between neighbouring halves and one float either side of it, random floats."""
    values = [v for v in EDGE_VALUES if abs(v) < 3.4e38] + [65520.0, -65520.0, 1e6, math.inf, -math.inf]
    finite = sorted({half(b) for b in range(0x10000) if not math.isnan(half(b)) and not math.isinf(half(b))})
    values += finite
    for low, high in itertools.pairwise(finite):
        tie = (low + high) / 2  # exact in a float: a half has 11 bits, the tie 12
        below, above = (struct.unpack(">f", struct.pack(">I", _float_bits(tie) + d))[0] for d in ((-1, 1) if tie > 0 else (1, -1)))
        values += [tie, below, above] if tie != 0 else [tie]
    rng = random.Random(35)
    for _ in range(20000):  # exponents from below the smallest subnormal to beyond the largest half
        bits = rng.getrandbits(1) << 31 | rng.randrange(95, 145) << 23 | rng.getrandbits(23)
        values.append(struct.unpack(">f", struct.pack(">I", bits))[0])
    return values


def _doubles_to_encode() -> list[float]:
    """Doubles a float cannot hold next to the ties: rounded once to the half (struct), never twice."""
    rng = random.Random(16)
    finite = [half(b) for b in range(0x0001, 0x7BFF)]
    values = []
    for _ in range(4000):
        i = rng.randrange(len(finite) - 1)
        tie = (finite[i] + finite[i + 1]) / 2
        nudge = tie * rng.choice((2.0**-30, -(2.0**-30), 2.0**-45, -(2.0**-45)))
        values += [tie + nudge, -(tie + nudge)]
    return values + [rng.uniform(-70000.0, 70000.0) for _ in range(2000)]


def _expected_half(value: float) -> int:
    if math.isnan(value):
        return -1
    if abs(value) >= 65520.0:
        return 0xFC00 if value < 0 else 0x7C00
    return half_bits(value)


def _conversions_program(floats: list[float], doubles: list[float]) -> str:
    float_list = ",\n".join(f"    {v.hex()}" if math.isfinite(v) else ("    -HUGE_VALF" if v < 0 else "    HUGE_VALF") for v in floats)
    double_list = ",\n".join(f"    {v.hex()}" for v in doubles)
    return f"""\
#include <math.h>
#include <stdio.h>
#include "regmap_rtu.h"

static const float floats[] = {{
{float_list}
}};
static const double doubles[] = {{
{double_list}
}};

int main(void)
{{
    unsigned long i;
    for (i = 0; i < 0x10000ul; i++) {{
        printf("d %08lx\\n", (unsigned long)regmap_f32_to_bits(regmap_f16_from_bits((uint16_t)i)));
    }}
    for (i = 0; i < sizeof floats / sizeof floats[0]; i++) {{
        printf("e %04x\\n", (unsigned)regmap_f16_to_bits(floats[i]));
    }}
    for (i = 0; i < sizeof doubles / sizeof doubles[0]; i++) {{
        printf("D %04x\\n", (unsigned)regmap_f16_to_bits_from_double(doubles[i]));
    }}
    printf("n %04x %04x\\n", (unsigned)regmap_f16_to_bits((float)NAN), (unsigned)regmap_f16_to_bits_from_double((double)NAN));
    printf("w %04x %04x\\n", (unsigned)regmap_f16_to_wire(1.5f, REGMAP_LOW_FIRST), (unsigned)regmap_f32_to_bits(regmap_f16_from_wire(0x003Eu, REGMAP_LOW_FIRST)));
    return 0;
}}
"""


@pytest.mark.parametrize("compiler", COMPILERS)
def test_half_conversions_agree_with_struct_e_on_every_pattern(compiler: str, headers: Path, tmp_path: Path) -> None:
    floats, doubles = _floats_to_encode(), _doubles_to_encode()
    lines = _run(compiler, _conversions_program(floats, doubles), headers, tmp_path)
    decoded = [int(line[2:], 16) for line in lines if line.startswith("d ")]
    assert len(decoded) == 0x10000
    for bits, got in enumerate(decoded):
        expected = half(bits)
        if math.isnan(expected):  # a NaN: the float's NaN with the same sign and payload
            assert got == ((bits & 0x8000) << 16 | 0x7F800000 | (bits & 0x3FF) << 13), hex(bits)
        else:
            assert got == _float_bits(expected), f"{bits:#06x}: {got:#010x}, struct says {expected!r}"
    encoded = [int(line[2:], 16) for line in lines if line.startswith("e ")]
    assert len(encoded) == len(floats)
    wrong = [(v, hex(g), hex(_expected_half(v))) for v, g in zip(floats, encoded, strict=True) if g != _expected_half(v)]
    assert wrong == [], f"{len(wrong)} floats rounded unlike struct 'e', e.g. {wrong[:5]}"
    narrowed = [int(line[2:], 16) for line in lines if line.startswith("D ")]
    wrong = [(v, hex(g), hex(_expected_half(v))) for v, g in zip(doubles, narrowed, strict=True) if g != _expected_half(v)]
    assert wrong == [], f"{len(wrong)} doubles rounded unlike struct 'e' (twice?), e.g. {wrong[:5]}"
    nan = next(line for line in lines if line.startswith("n ")).split()[1:]
    assert all(int(b, 16) & 0x7C00 == 0x7C00 and int(b, 16) & 0x3FF for b in nan), nan  # a NaN, never infinity
    assert next(line for line in lines if line.startswith("w ")).split()[1:] == ["003e", f"{_float_bits(1.5):08x}"]


# -- the value helpers of f16 registers, against the Python client's codec ---------------------

VALUES = (21.5, 5.0, 30.0, 4.99, 30.01, 29.99, 30.0078125, 0.1, -1.0, -1.0001, -0.9999, 65504.0, 65519.0, 65520.0, 1e9, 0.0, 2.0, 3.0, 1.5)
SCALED = (0.0, 0.1, 12.34, 499.9, 500.0, 500.01, -0.01, 204.85, 204.95, 1e-9)


def _python(spec: RegisterSpec[Any], value: float) -> str:
    try:
        return f"{raw_to_words(spec, value_to_raw(spec, value))[0]:04x}"
    except RangeError:
        return "refused"


def _values_program(cases: list[tuple[str, str, float]]) -> str:
    lines = []
    for function, cast, value in cases:
        literal = f"({cast}){int(value)}" if cast.endswith("_fan") else f"({cast}){value.hex()}"  # an enum from an integer (C++)
        lines.append(
            f'    {{ uint16_t w[1] = {{0xDEADu}}; if ({function}({literal}, w)) printf("%04x\\n", (unsigned)w[0]); else printf("refused\\n"); }}'
        )
    return (
        '#include <stdio.h>\n#include "half_sensor.h"\n\nint main(void)\n{\n'
        + "\n".join(lines)
        + "\n    { uint16_t nan_word[1] = {0x7E01u}, marker[1] = {0xBC00u}, w[1] = {0x4D60u}; float t = 0.0f; double f = 0.0;\n"
        + '      printf("%d %d %d\\n", (int)half_sensor_temperature_is_available(nan_word), (int)half_sensor_alarm_limit_is_available(marker),'
        + " (int)half_sensor_temperature_decode(w, &t));\n"
        + "      int flowed = (int)half_sensor_flow_decode(w, &f);\n"
        + '      printf("%.9g %d %.9g\\n", (double)t, flowed, f); }\n'
        + "    return 0;\n}\n"
    )


@pytest.mark.parametrize("compiler", COMPILERS)
def test_f16_value_helpers_agree_with_the_python_client(compiler: str, headers: Path, tmp_path: Path) -> None:
    specs = {s.name: s for s in runtime_specs(load_map(headers / "half_sensor.yaml"))}
    cases = [(f"half_sensor_{name}_encode", "float", v) for name in ("setpoint", "alarm_limit") for v in VALUES]
    cases += [("half_sensor_fan_mode_encode", "half_sensor_fan", v) for v in (0.0, 1.0, 2.0, 3.0)]
    cases += [("half_sensor_flow_limit_encode", "double", v) for v in SCALED]
    lines = _run(compiler, _values_program(cases), headers, tmp_path)
    expected = [_python(specs[function.split("_", 2)[2].removesuffix("_encode")], value) for function, _, value in cases]
    assert list(zip(cases, lines[: len(cases)], strict=True)) == list(zip(cases, expected, strict=True))
    assert "refused" in expected and len(set(expected)) > 10  # the cases reach both outcomes
    assert lines[-2] == "0 0 1"  # NaN and -1.0 are 'not available'; 0x4D60 is 21.5
    assert lines[-1].split()[:2] == ["21.5", "1"] and float(lines[-1].split()[2]) == pytest.approx(2.15)
