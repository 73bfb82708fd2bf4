"""Fuzz the generated C response parsers with libFuzzer + AddressSanitizer + UBSan, for a bounded time.

tests/c/fuzz_response.c picks a parser by the first input byte: the holding-register read and write
parsers, and (issue 19) the input-register, coil and discrete-input parsers, the coil write echoes,
the string copy both ways, bit unpacking and packing and the firmware version text. The header is
the one `regmap generate --target c` writes now (into a temporary directory), seeded with every
response frame of the seed and fixture maps under every selector.
"""

from __future__ import annotations

import os
import re
import subprocess
from pathlib import Path

from regmap.frontend import load_map
from regmap.generate import render

from conftest import FIXTURE_MAPS, MAPS, ROOT, require_tool

FUZZ_SECONDS = int(os.environ.get("REGMAP_FUZZ_SECONDS", "20"))
SOURCE = ROOT / "tests" / "c" / "fuzz_response.c"


def _selectors() -> int:
    match = re.search(r"^#define PARSERS (\d+)u$", SOURCE.read_text(encoding="utf-8"), flags=re.M)
    assert match is not None, "fuzz_response.c defines PARSERS"
    return int(match.group(1))


def test_response_parsers_survive_fuzzing(tmp_path: Path) -> None:
    clang = require_tool("clang")
    devices = [load_map(p) for p in (*MAPS, *FIXTURE_MAPS)]
    include = tmp_path / "c"
    include.mkdir()
    for rel, text in render(devices, ["c"])["c"].items():
        (include / rel).write_text(text, encoding="utf-8")
    binary = tmp_path / "fuzz_response"
    build = subprocess.run(
        [clang, "-g", "-O1", "-fsanitize=fuzzer,address,undefined", "-fno-sanitize-recover=all", "-I", str(include),
         str(SOURCE), "-o", str(binary)],
        capture_output=True, text=True, check=False,
    )  # fmt: skip
    assert build.returncode == 0, build.stderr
    corpus = tmp_path / "corpus"
    corpus.mkdir()
    seeds = 0
    functions: set[int] = set()
    for device in devices:  # seeds: every response frame of the maps' examples, under every parser selector
        for example in device.examples:
            if example.direction == "response":
                functions.add(example.wire_frame[1] & 0x7F)
                for selector in range(_selectors()):
                    (corpus / f"{device.id}-{example.id}-{selector}").write_bytes(bytes([selector]) + example.wire_frame)
                    seeds += 1
    (corpus / "text").write_bytes(bytes([9]) + b"V2.10 build 7\0PM-3000  ")
    assert {0x01, 0x02, 0x03, 0x04, 0x06, 0x0F, 0x10} <= functions, f"the seeds cover only function codes {sorted(functions)}"
    run = subprocess.run(
        [str(binary), str(corpus), f"-max_total_time={FUZZ_SECONDS}", "-max_len=300", "-print_final_stats=1"],
        capture_output=True, text=True, check=False, timeout=FUZZ_SECONDS + 120,
    )  # fmt: skip
    assert run.returncode == 0, run.stderr[-3000:]
    executions = re.search(r"stat::number_of_executed_units:\s*(\d+)", run.stderr)
    assert executions is not None and int(executions.group(1)) > 10_000, run.stderr[-2000:]
    print(f"fuzzed {FUZZ_SECONDS}s from {seeds} seeds: {executions.group(1)} executions")
