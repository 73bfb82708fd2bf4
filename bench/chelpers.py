"""The C frame helpers of generated/c/regmap_rtu.h: Cortex-M0 text size at -Os and host ns per frame.

Size: bench/c/m0_frames.c wraps every helper out of line (all of them, and the subset a read-only
master needs), compiled with arm-none-eabi-gcc -mcpu=cortex-m0 -mthumb -Os and measured with
arm-none-eabi-size. Speed: bench/c/host_frames.c compiled with the host's gcc -O2.
"""

from __future__ import annotations

import shutil
import subprocess
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

from bench.common import GENERATED, ROOT, median, regmap_command

C_DIR = ROOT / "bench" / "c"
HEADER = GENERATED / "c" / "regmap_rtu.h"
M0_FLAGS = ["-mcpu=cortex-m0", "-mthumb", "-Os", "-std=c99", "-Wall", "-Wextra", "-Werror", "-ffunction-sections", "-fdata-sections"]
HOST_FLAGS = ["-O2", "-std=c99", "-Wall", "-Wextra", "-Werror"]
CASES = {
    "build_read": "build a read request (8 bytes)",
    "build_write_multiple_10": "build a write of 10 registers (29 bytes)",
    "parse_read_1": "check and parse a 1-register read response (7 bytes)",
    "parse_read_100": "check and parse a 100-register read response (205 bytes)",
}


@dataclass
class CResult:
    header: str  # where regmap_rtu.h came from, or why this part is blocked
    blocked: str | None = None
    m0_text: int | None = None  # every frame helper + CRC
    m0_text_read_only: int | None = None  # build read + parse read response + CRC
    m0_symbols: list[tuple[str, int]] = field(default_factory=list)
    host_ns: dict[str, float] = field(default_factory=dict)
    python_ns: dict[str, float] = field(default_factory=dict)
    compilers: dict[str, str] = field(default_factory=dict)


def _run(cmd: list[str], cwd: Path) -> str:
    result = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, timeout=120, check=False)
    if result.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed:\n{result.stdout}{result.stderr}")
    return result.stdout


def _text_size(size_output: str) -> int:
    # arm-none-eabi-size (Berkeley format): a header line, then "text data bss dec hex filename".
    return int(size_output.splitlines()[1].split()[0])


def m0_size(include: Path, work: Path, result: CResult, gcc: str) -> None:
    size = shutil.which("arm-none-eabi-size") or "arm-none-eabi-size"
    nm = shutil.which("arm-none-eabi-nm") or "arm-none-eabi-nm"
    full, read_only = work / "m0_frames.o", work / "m0_read_only.o"
    _run([gcc, *M0_FLAGS, f"-I{include}", "-c", str(C_DIR / "m0_frames.c"), "-o", str(full)], work)
    _run([gcc, *M0_FLAGS, "-DBENCH_READ_ONLY", f"-I{include}", "-c", str(C_DIR / "m0_frames.c"), "-o", str(read_only)], work)
    result.m0_text = _text_size(_run([size, str(full)], work))
    result.m0_text_read_only = _text_size(_run([size, str(read_only)], work))
    symbols = []
    for line in _run([nm, "-S", "--size-sort", str(full)], work).splitlines():
        parts = line.split()
        if len(parts) == 4 and parts[2] in "tT":
            symbols.append((parts[3], int(parts[1], 16)))
    result.m0_symbols = sorted(symbols, key=lambda s: (-s[1], s[0]))


def host_speed(include: Path, work: Path, result: CResult, cc: str, iterations: int) -> None:
    exe = work / "host_frames"
    _run([cc, *HOST_FLAGS, f"-I{include}", str(C_DIR / "host_frames.c"), "-o", str(exe)], work)
    for line in _run([str(exe), str(iterations)], work).splitlines():
        name, *samples = line.split()
        result.host_ns[name] = median([float(s) for s in samples])


def python_speed(result: CResult, repeats: int) -> None:
    """The same operations with regmap_runtime.rtu, for scale."""
    from bench.common import calibrate, time_call
    from regmap_runtime.rtu import build_read, build_read_response, build_write_multiple, parse_frame

    one = build_read_response(1, [0x1234])
    hundred = build_read_response(1, [(i * 2654435761) & 0xFFFF for i in range(100)])
    words = list(range(1, 11))
    cases = {
        "build_read": lambda: build_read(1, 0x0191, 1),
        "build_write_multiple_10": lambda: build_write_multiple(1, 0x0191, words),
        "parse_read_1": lambda: parse_frame(one, "response"),
        "parse_read_100": lambda: parse_frame(hundred, "response"),
    }
    for name, fn in cases.items():
        number = calibrate(fn, 0.01)
        result.python_ns[name] = median(time_call(fn, repeats, number)) * 1e9


def measure(iterations: int = 200000, repeats: int = 7) -> CResult:
    gcc_arm = shutil.which("arm-none-eabi-gcc")
    cc = shutil.which("gcc") or shutil.which("cc")
    with tempfile.TemporaryDirectory(prefix="regmap-bench-c-") as tmp:
        work = Path(tmp)
        if HEADER.exists():
            include, source = HEADER.parent, "generated/c/regmap_rtu.h (committed)"
        else:  # not committed yet: render it from the C back end, as `regmap generate` would
            out = work / "generated"
            subprocess.run(
                [*regmap_command(), "generate", "--target", "c", "--out", str(out)], cwd=ROOT, capture_output=True, check=False, timeout=120
            )
            include, source = out / "c", "rendered by `regmap generate --target c` (generated/c/regmap_rtu.h not committed yet)"
        result = CResult(header=source)
        if not (include / "regmap_rtu.h").exists():
            result.blocked = "no regmap_rtu.h: the C back end does not produce it yet"
            return result
        python_speed(result, repeats)
        if cc is not None:
            result.compilers["host"] = f"{Path(cc).name} {' '.join(HOST_FLAGS)}"
            host_speed(include, work, result, cc, iterations)
        if gcc_arm is None or shutil.which("arm-none-eabi-size") is None:
            result.blocked = "arm-none-eabi-gcc is not installed (apt-get install gcc-arm-none-eabi libnewlib-arm-none-eabi)"
        else:
            result.compilers["m0"] = f"arm-none-eabi-gcc {' '.join(M0_FLAGS)}"
            m0_size(include, work, result, gcc_arm)
    return result
