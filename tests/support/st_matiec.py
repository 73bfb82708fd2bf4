"""The generated Structured Text through matiec (`iec2c`, the compiler of OpenPLC and Beremiz).

A map's `iec/` output is three files: the types, the functions and a `VAR_GLOBAL CONSTANT` list. matiec
reads one source and emits C only for a CONFIGURATION, so `program_text` joins the types and the
functions and puts the constants in a resource of a configuration (as OpenPLC holds a project's global
variables), optionally beside a test PROGRAM that the resource runs as a task.
"""

from __future__ import annotations

import re
import shutil
import subprocess
from dataclasses import dataclass
from pathlib import Path

from regmap.generate import render
from regmap.model import Device

from conftest import built_tool, skip_or_fail

# iec2c's three forms: FILE:LINE, FILE:LINE-COL..LINE-COL and FILE:LINE-COL..FILE:LINE-COL (stage1_2/iec_bison.yy).
ERROR = re.compile(r"^(?P<file>[^:\n]+):(?P<line>\d+)(?:-\d+\.\.(?:[^:\n]+:)?\d+-\d+)?: error: (?P<what>.*)$", re.M)


def matiec_and_gcc() -> Path:
    """matiec's iec2c, and gcc to build the C it emits (each test using them skips without, or fails under CI=true)."""
    path: Path = built_tool("matiec")
    if shutil.which("gcc") is None:
        skip_or_fail("gcc is not installed: the C that matiec emits cannot be built")
    return path


def st_files(device: Device, dialect: str = "iec") -> dict[str, str]:
    """`types`, `functions`, `constants`: the text `regmap generate --target st` writes for the device."""
    files = render([device], ["st"])["st"]
    return {kind: files[f"{device.id}/{dialect}/{device.id}_{kind}.st"] for kind in ("types", "functions", "constants")}


def program_text(files: dict[str, str], program: str, program_name: str) -> str:
    """One matiec source: the types, the functions, `program` (the POUs of a test), then a configuration
    whose resource holds the constants and runs `program_name` (matiec wants a program in a resource)."""
    constants = files["constants"]
    start = constants.index("VAR_GLOBAL CONSTANT")
    return (
        files["types"]
        + "\n"
        + files["functions"]
        + "\n"
        + program
        + "\nCONFIGURATION C_TEST\nRESOURCE R_TEST ON PLC\n"
        + constants[start:]
        + "    TASK T_TEST(INTERVAL := T#10ms, PRIORITY := 0);\n"
        + f"    PROGRAM P_TEST WITH T_TEST : {program_name};\n"
        + "END_RESOURCE\nEND_CONFIGURATION\n"
    )


DECODER = re.compile(r"^FUNCTION (F_\w+_DECODE_\w+) : BOOL$", re.M)
RAW_INPUT = re.compile(r"^    stRaw : (\w+);$", re.M)
ORDER_INPUT = "    bHighWordFirst : BOOL;"


def decoding_program(files: dict[str, str], values_type: str) -> str:
    """A PROGRAM that decodes every read block (zeroed words) into one values struct: the resource's
    task, and a check that each decoder's call compiles."""
    functions = files["functions"]
    raws: list[str] = []
    calls: list[str] = []
    for match in DECODER.finditer(functions):
        head = functions[match.end() : functions.index("END_VAR", match.end())]
        raw = RAW_INPUT.search(head)
        assert raw is not None, match[1]
        local = f"st{len(raws)}"
        raws.append(f"    {local} : {raw[1]};")
        order = ", bHighWordFirst := TRUE" if ORDER_INPUT in head else ""
        calls.append(f"bOk := {match[1]}(stRaw := {local}{order}, stValues := stValues) AND bOk;")
    return "\n".join(
        ["PROGRAM P_DECODE_ALL", "VAR", "    bOk : BOOL;", f"    stValues : {values_type};", *raws, "END_VAR", *calls, "END_PROGRAM", ""]
    )


@dataclass(frozen=True)
class Compiled:
    returncode: int
    output: str
    errors: tuple[str, ...]  # "line: what", in the joined source
    c_dir: Path


def iec2c(matiec: Path, source: str, work: Path, name: str = "program", flags: tuple[str, ...] = ()) -> Compiled:
    """Run `iec2c [flags] -I lib -T work/<name>_c` on the source (written to work/<name>.st)."""
    path = work / f"{name}.st"
    path.write_text(source, encoding="utf-8")
    c_dir = work / f"{name}_c"
    c_dir.mkdir(exist_ok=True)
    result = subprocess.run(
        [str(matiec / "iec2c"), *flags, "-I", str(matiec / "lib"), "-T", str(c_dir), str(path)],
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
    )
    output = result.stdout + result.stderr
    errors = tuple(f"{m['line']}: {m['what']}" for m in ERROR.finditer(output))
    return Compiled(result.returncode, output, errors, c_dir)


# The start of a C driver: the C library of matiec, the compiled POUs, and the two globals that library expects.
DRIVER_PRELUDE = (
    "#include <math.h>",
    "#include <stdio.h>",
    "#include <string.h>",
    '#include "iec_std_lib.h"',
    '#include "POUS.h"',
    '#include "POUS.c"',
    "TIME __CURRENT_TIME;",
    "BOOL __DEBUG;",
)


def build_and_run(matiec: Path, compiled: Compiled, driver: str, binary: Path) -> str:
    """Build a C driver (which includes matiec's POUS.c) against the compiled ST with gcc, run it, its stdout."""
    source = compiled.c_dir / f"{binary.name}_driver.c"
    source.write_text(driver, encoding="utf-8")
    command = [
        "gcc",
        "-std=gnu11",
        "-O1",
        "-w",
        "-I",
        str(matiec / "lib" / "C"),
        "-I",
        str(compiled.c_dir),
        str(source),
        "-o",
        str(binary),
        "-lm",
    ]
    gcc = subprocess.run(command, capture_output=True, text=True, timeout=600, check=False)
    assert gcc.returncode == 0, gcc.stderr[-3000:]
    ran = subprocess.run([str(binary)], capture_output=True, text=True, timeout=300, check=False)
    assert ran.returncode == 0, ran.stderr[-3000:]
    return ran.stdout
