"""A timestamp register in C: the raw uint32_t seconds, decoded from the same words to the same seconds as the
Python client's datetime (both word orders, 0 and 2^32-1), and encoded back to the same words; gcc C99 and
g++ C++17 warning-free. The float meter fixture has one on each clock: `clock` (local, high word first by default;
it follows the meter's word-order switch, so its C helpers take the order the meter uses now) and `last_reset`
(UTC, low word first always, 0 is its "not available" marker)."""

from __future__ import annotations

import subprocess
from datetime import datetime
from pathlib import Path

import pytest

from regmap.frontend import load_map
from regmap.generate import render
from regmap.runtime_bridge import runtime_specs
from regmap_runtime.codec import decode_value, raw_to_words, value_to_raw, words_to_raw
from regmap_runtime.timestamps import datetime_to_seconds

from conftest import FIXTURE_MAPS, require_tool

METER = next(p for p in FIXTURE_MAPS if p.stem == "float_meter")
FLAGS = ("-Wall", "-Wextra", "-Wpedantic", "-Werror")
COMPILERS = {"gcc-c99": ("gcc", "-std=c99", *FLAGS), "g++-c++17": ("g++", "-x", "c++", "-std=c++17", *FLAGS)}
WORDS = ([0x0000, 0x0000], [0x0000, 0x0001], [0x6592, 0x0080], [0x0080, 0x6592], [0xC340, 0x65E1], [0x8000, 0x0000], [0xFFFF, 0xFFFF])


# (register, the C word-order argument or "" for a register with a fixed order, the Python client's order)
CASES = (("clock", "REGMAP_HIGH_FIRST", "high_first"), ("clock", "REGMAP_LOW_FIRST", "low_first"), ("last_reset", "", None))


def _python_seconds() -> dict[tuple[str, str, int, int], int | None]:
    """(register, C order, words) -> the seconds of the datetime the Python client reads (None: not available)."""
    specs = {s.name: s for s in runtime_specs(load_map(METER))}
    seen: dict[tuple[str, str, int, int], int | None] = {}
    for name, c_order, order in CASES:
        spec = specs[name].in_word_order(order)
        assert spec.zone is not None
        for words in WORDS:
            when = decode_value(spec, words_to_raw(spec, words))
            assert when is None or isinstance(when, datetime)
            seen[(name, c_order, words[0], words[1])] = None if when is None else datetime_to_seconds(when, spec.zone)
            if when is not None:
                assert raw_to_words(spec, value_to_raw(spec, when)) == words  # the words a write of that time sends
    return seen


@pytest.mark.parametrize("compiler", COMPILERS)
def test_c_decodes_the_words_to_the_seconds_python_reads(compiler: str, tmp_path: Path) -> None:
    for rel, text in render([load_map(METER)], ["c"])["c"].items():
        (tmp_path / rel).write_text(text, encoding="utf-8")
    expected = _python_seconds()
    lines = [
        "#include <stdio.h>",
        '#include "fixture_float_meter.h"',
        "int main(void)",
        "{",
        "    uint16_t words[2], back[2];",
        "    uint32_t s;",
    ]
    for name, c_order, w0, w1 in expected:
        arg = f", {c_order}" if c_order else ""
        shown = c_order or "-"
        lines += [
            f"    words[0] = 0x{w0:04X}u; words[1] = 0x{w1:04X}u;",
            f"    if (fixture_float_meter_{name}_decode(words{arg}, &s)) "
            f'{{ printf("{name} {shown} %04X %04X %lu\\n", words[0], words[1], (unsigned long)s); }}',
            f'    else {{ printf("{name} {shown} %04X %04X none\\n", words[0], words[1]); }}',
        ]
        if name == "clock":  # writable: the encoder gives back the words
            lines.append(
                f"    if (!fixture_float_meter_clock_encode(s{arg}, back) || back[0] != words[0] || back[1] != words[1]) "
                f'{{ printf("encode {shown} %lu\\n", (unsigned long)s); }}'
            )
    source = tmp_path / "timestamps.c"
    source.write_text("\n".join([*lines, "    return 0;", "}", ""]), encoding="utf-8")
    tool, *flags = COMPILERS[compiler]
    binary = tmp_path / "timestamps"
    built = subprocess.run(
        [require_tool(tool), *flags, "-I", str(tmp_path), str(source), "-o", str(binary)], capture_output=True, text=True, check=False
    )
    assert built.returncode == 0 and not built.stderr.strip(), built.stderr[-4000:]
    out = subprocess.run([str(binary)], capture_output=True, text=True, check=True, timeout=60).stdout.splitlines()
    got = {
        (name, "" if order == "-" else order, int(w0, 16), int(w1, 16)): None if s == "none" else int(s)
        for name, order, w0, w1, s in (line.split() for line in out if not line.startswith("encode"))
    }
    assert got == expected
    assert not [line for line in out if line.startswith("encode")], out
    high, low = "REGMAP_HIGH_FIRST", "REGMAP_LOW_FIRST"
    assert got[("clock", high, 0xFFFF, 0xFFFF)] == (1 << 32) - 1 and got[("clock", high, 0, 0)] == 0
    assert got[("clock", high, 0x6592, 0x0080)] == got[("clock", low, 0x0080, 0x6592)] == 1704067200  # the switch swaps words
    assert got[("last_reset", "", 0xC340, 0x65E1)] == 0x65E1C340 and got[("last_reset", "", 0, 0)] is None  # low word first; 0 is na
