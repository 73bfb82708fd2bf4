"""f16 in Structured Text: the device's F16_FROM_BITS / F16_TO_BITS helpers rebuild a half from its WORD (and
back) with exact LREAL arithmetic; matiec compiles them, and the C it makes, run, decodes every one of the 65,536
patterns as Python's struct 'e' does and rounds doubles to the nearest half (ties to even) as struct does; the
generated encoders and decoders of a map of f16 registers agree with the Python client."""

from __future__ import annotations

import itertools
import math
import random
from pathlib import Path
from typing import Any

import pytest

from regmap.backends.st.names import StIdentifier
from regmap.frontend import load_map
from regmap.runtime_bridge import runtime_specs
from regmap_runtime.codec import RangeError, raw_to_words, value_to_raw
from regmap_runtime.spec import RegisterSpec

from support.half_map import EDGE_VALUES, half, half_bits, write_half_map
from support.st_exec import Decode, Encode, StProgram
from support.st_matiec import DRIVER_PRELUDE, build_and_run, decoding_program, iec2c, matiec_and_gcc, program_text


@pytest.fixture(scope="session")
def matiec() -> Path:
    return matiec_and_gcc()


def _doubles() -> list[float]:
    """Edge values, every finite half, every tie between neighbours and a double either side of it, random doubles."""
    finite = sorted({half(b) for b in range(0x10000) if math.isfinite(half(b))})
    values = [*EDGE_VALUES, *finite, 65520.0, -65520.0, 1e6]
    for low, high in itertools.pairwise(finite):
        tie = (low + high) / 2
        values += [tie, math.nextafter(tie, -math.inf), math.nextafter(tie, math.inf)]
    rng = random.Random(16)
    values += [rng.uniform(-70000.0, 70000.0) for _ in range(3000)] + [rng.uniform(-1e-4, 1e-4) for _ in range(3000)]
    return [v for v in values if v != 0.0]  # -0.0: the helper writes +0 (no sign of zero in plain ST arithmetic)


def test_the_half_helpers_agree_with_struct_e(matiec: Path, tmp_path: Path) -> None:
    program = StProgram(load_map(write_half_map(tmp_path)))
    decode, encode = (StIdentifier("F", program.device.id, "F16", what, "BITS") for what in ("FROM", "TO"))
    doubles = _doubles()
    listed = ",\n".join(f"    {v.hex()}" for v in doubles)
    driver = "\n".join(
        [
            *DRIVER_PRELUDE,
            f"static const double doubles[] = {{\n{listed}\n}};",
            "int main(void) {",
            "    BOOL eno; LREAL v; WORD bits; unsigned long i;",
            "    for (i = 0; i < 0x10000ul; i++) {",
            f"        BOOL ok = {decode}(1, &eno, (WORD)i, &v);",
            '        printf("d %d %a\\n", (int)ok, ok ? (double)v : 0.0);',
            "    }",
            "    for (i = 0; i < sizeof doubles / sizeof doubles[0]; i++) {",
            f"        BOOL ok = {encode}(1, &eno, (LREAL)doubles[i], &bits);",
            '        printf("e %d %u\\n", (int)ok, (unsigned)bits);',
            "    }",
            "    return 0;",
            "}",
            "",
        ]
    )
    source = program_text(program.files, decoding_program(program.files, program.values_type), "P_DECODE_ALL")
    compiled = iec2c(matiec, source, tmp_path, program.device.id)
    assert compiled.returncode == 0 and not compiled.errors, compiled.output[-3000:]
    lines = build_and_run(matiec, compiled, driver, tmp_path / "half_st").splitlines()
    decoded = [line.split()[1:] for line in lines if line.startswith("d ")]
    assert len(decoded) == 0x10000
    for bits, (ok, text) in enumerate(decoded):
        expected = half(bits)
        if math.isfinite(expected):
            assert ok == "1" and float.fromhex(text) == expected, (hex(bits), text, expected)
        else:
            assert ok == "0", hex(bits)  # infinity or NaN: no value in plain ST
    encoded = [line.split()[1:] for line in lines if line.startswith("e ")]
    assert len(encoded) == len(doubles)
    wrong = []
    for value, (ok, word) in zip(doubles, encoded, strict=True):
        want = ("0", None) if abs(value) >= 65520.0 else ("1", half_bits(value))
        if (ok, int(word) if ok == "1" else None) != want:
            wrong.append((value, ok, word, want))
    assert wrong == [], f"{len(wrong)} values rounded unlike struct 'e', e.g. {wrong[:5]}"


VALUES = (21.5, 5.0, 30.0, 4.99, 30.01, 29.99, 30.0078125, 0.1, -1.0, -1.0001, -0.9999, 65504.0, 65519.0, 65520.0, 0.0, 2.0)
SCALED = (0.0, 0.1, 12.34, 499.9, 500.0, 500.01, -0.01, 204.85, 204.95)


def _python(spec: RegisterSpec[Any], value: float) -> tuple[int, ...] | None:
    try:
        return tuple(raw_to_words(spec, value_to_raw(spec, value)))
    except RangeError:
        return None


def test_f16_encoders_and_decoders_agree_with_the_python_client(matiec: Path, tmp_path: Path) -> None:
    device = load_map(write_half_map(tmp_path))
    program = StProgram(device)
    specs = {s.name: s for s in runtime_specs(device)}
    cases: list[Decode | Encode] = []
    expected: dict[str, tuple[int, ...] | None] = {}
    for name, values in (("setpoint", VALUES), ("alarm_limit", VALUES), ("flow_limit", SCALED)):
        function = program.functions[StIdentifier("F", device.id, "ENCODE", name)]
        for i, value in enumerate(values):
            cases.append(Encode(f"{name}_{i}", function, value, 1))
            expected[f"{name}_{i}"] = _python(specs[name], value)
    fan = program.functions[StIdentifier("F", device.id, "ENCODE", "fan_mode")]
    for member in range(3):
        cases.append(Encode(f"fan_{member}", fan, member, 1))
        expected[f"fan_{member}"] = (half_bits(float(member)),)
    (measurements,) = [b for b in program.blocks if b.space == "input"]
    for case_id, block_words in (("nan", (0x7E01, 0x4B00, 0x004D)), ("values", (0x4D60, 0x4B00, 0x604D))):
        cases.append(Decode(case_id, measurements, block_words, ("TEMPERATURE", "TEMPERATURE_AVAILABLE", "FLOW", "HUMIDITY")))
    results = program.run(matiec, tmp_path, cases)
    for case_id, words in expected.items():
        got = results[case_id]
        assert (got.words if got.ok else None) == words, (case_id, got)
    assert {k for k, w in expected.items() if w is None} and {k for k, w in expected.items() if w is not None}
    assert results["nan"].values["TEMPERATURE_AVAILABLE"] == "0" and float(results["nan"].values["HUMIDITY"]) == half(0x4D00)  # swapped
    read = results["values"].values
    assert (float(read["TEMPERATURE"]), read["TEMPERATURE_AVAILABLE"], float(read["HUMIDITY"])) == (21.5, "1", 21.5)
    assert math.isclose(float(read["FLOW"]), 1.4, rel_tol=1e-6)
