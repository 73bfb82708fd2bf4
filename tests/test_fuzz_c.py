"""Fuzz the generated C response parsers with libFuzzer + AddressSanitizer + UBSan, for a bounded time."""

from __future__ import annotations

import os
import re
import subprocess
from pathlib import Path

from regmap.frontend import load_map

from conftest import GENERATED, MAPS, ROOT, require_tool

FUZZ_SECONDS = int(os.environ.get("REGMAP_FUZZ_SECONDS", "20"))


def test_response_parsers_survive_fuzzing(tmp_path: Path) -> None:
    clang = require_tool("clang")
    binary = tmp_path / "fuzz_response"
    build = subprocess.run(
        [clang, "-g", "-O1", "-fsanitize=fuzzer,address,undefined", "-fno-sanitize-recover=all", "-I", str(GENERATED / "c"),
         str(ROOT / "tests" / "c" / "fuzz_response.c"), "-o", str(binary)],
        capture_output=True, text=True, check=False,
    )  # fmt: skip
    assert build.returncode == 0, build.stderr
    corpus = tmp_path / "corpus"
    corpus.mkdir()
    seeds = 0
    for path in MAPS:  # seeds: every response frame printed in the manuals, under every parser selector
        for example in load_map(path).examples:
            if example.direction == "response":
                for selector in range(4):
                    (corpus / f"{example.id}-{selector}").write_bytes(bytes([selector]) + example.wire_frame)
                    seeds += 1
    assert seeds > 0
    run = subprocess.run(
        [str(binary), str(corpus), f"-max_total_time={FUZZ_SECONDS}", "-max_len=300", "-print_final_stats=1"],
        capture_output=True, text=True, check=False, timeout=FUZZ_SECONDS + 120,
    )  # fmt: skip
    assert run.returncode == 0, run.stderr[-3000:]
    executions = re.search(r"stat::number_of_executed_units:\s*(\d+)", run.stderr)
    assert executions is not None and int(executions.group(1)) > 10_000, run.stderr[-2000:]
    print(f"fuzzed {FUZZ_SECONDS}s from {seeds} seeds: {executions.group(1)} executions")
