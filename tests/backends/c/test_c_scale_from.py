"""A `scale_from` register in C: `<reg>_decode_sf(words, sf, &value)` gives the value the Python runtime reads
(raw x 10^sf; false where the point or its scale factor reads "not available"), and `_encode_sf(value, sf, words)`
sends the raw value the runtime's write sends, refusing (false) what the runtime refuses: a value that is no whole
multiple of 10^sf, out of range, or with the factor not available. gcc C99 and g++ C++17 warning-free."""

from __future__ import annotations

import subprocess
from pathlib import Path

import pytest

from regmap.frontend import load_map
from regmap.generate import render
from regmap.runtime_bridge import runtime_specs
from regmap_runtime.codec import RangeError, check_raw, raw_to_words, words_to_raw
from regmap_runtime.scaling import scaled, unscaled

from conftest import ROOT, require_tool

MAP = ROOT / "tests" / "maps" / "scaled_from" / "inverter.yaml"
FLAGS = ("-Wall", "-Wextra", "-Wpedantic", "-Werror")
COMPILERS = {"gcc-c99": ("gcc", "-std=c99", *FLAGS), "g++-c++17": ("g++", "-x", "c++", "-std=c++17", *FLAGS)}
READS = (
    ("a", [1234], -2),
    ("a", [0xFFFF], 0),
    ("a", [7], -32768),
    ("w", [0xFA24], 1),
    ("w", [3], -1),
    ("wh", [1, 0xE240], 0),
    ("wh", [0, 5], 3),
)
WRITES = (
    ("wmax_lim_pct", 50.5, -1),
    ("wmax_lim_pct", 50.55, -1),
    ("wmax_lim_pct", 100.1, -1),
    ("wmax_lim_pct", 1000, 0),
    ("wmax_lim_pct", 3, -32768),
)


def _python() -> tuple[dict[tuple[str, int], float | None], dict[tuple[float, int], int | None]]:
    """What the runtime reads from READS and sends for WRITES (None: no value / refused)."""
    specs = {s.name: s for s in runtime_specs(load_map(MAP))}
    reads: dict[tuple[str, int], float | None] = {}
    for i, (name, words, sf) in enumerate(READS):
        raw = words_to_raw(specs[name], words)
        assert isinstance(raw, int)
        value = scaled(None if specs[name].is_na(raw) else raw, None if sf == -32768 else sf)
        reads[(name, i)] = None if value is None else float(value)
    writes: dict[tuple[float, int], int | None] = {}
    for _, value, sf in WRITES:
        spec = specs["wmax_lim_pct"]
        try:
            raw = unscaled(spec, value, None if sf == -32768 else sf)
            check_raw(spec, raw)
            writes[(value, sf)] = raw_to_words(spec, raw)[0]
        except RangeError:
            writes[(value, sf)] = None
    return reads, writes


@pytest.mark.parametrize("compiler", COMPILERS)
def test_c_scales_as_the_runtime_does(compiler: str, tmp_path: Path) -> None:
    for rel, text in render([load_map(MAP)], ["c"])["c"].items():
        (tmp_path / rel).write_text(text, encoding="utf-8")
    reads, writes = _python()
    lines = ["#include <stdio.h>", '#include "sf_inverter.h"', "int main(void)", "{", "    uint16_t words[2];", "    double v;"]
    for i, (name, words, sf) in enumerate(READS):
        lines += [
            *(f"    words[{k}] = 0x{w:04X}u;" for k, w in enumerate(words)),
            f'    if (sf_inverter_{name}_decode_sf(words, {sf}, &v)) {{ printf("read {name} {i} %.17g\\n", v); }}',
            f'    else {{ printf("read {name} {i} none\\n"); }}',
        ]
    for _, value, sf in WRITES:
        lines += [
            f"    if (sf_inverter_wmax_lim_pct_encode_sf({value!r}, {sf}, words)) "
            f'{{ printf("write {value!r} {sf} %u\\n", (unsigned)words[0]); }}',
            f'    else {{ printf("write {value!r} {sf} none\\n"); }}',
        ]
    source = tmp_path / "scaled.c"
    source.write_text("\n".join([*lines, "    return 0;", "}", ""]), encoding="utf-8")
    tool, *flags = COMPILERS[compiler]
    binary = tmp_path / "scaled"
    built = subprocess.run(
        [require_tool(tool), *flags, "-I", str(tmp_path), str(source), "-o", str(binary)], capture_output=True, text=True, check=False
    )
    assert built.returncode == 0 and not built.stderr.strip(), built.stderr[-4000:]
    out = [line.split() for line in subprocess.run([str(binary)], capture_output=True, text=True, check=True).stdout.splitlines()]
    got_reads = {(name, int(i)): None if v == "none" else float(v) for kind, name, i, v in out if kind == "read"}
    got_writes = {(float(value), int(sf)): None if w == "none" else int(w) for kind, value, sf, w in out if kind == "write"}
    assert got_reads == reads
    assert got_writes == {(float(v), sf): w for (v, sf), w in writes.items()}
    assert reads[("a", 0)] == 12.34 and reads[("a", 1)] is None and reads[("a", 2)] is None  # the point's and the factor's na
    assert writes[(50.5, -1)] == 505 and writes[(50.55, -1)] is None and writes[(100.1, -1)] is None
