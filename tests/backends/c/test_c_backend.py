"""The C back end: every generated header compiles warning-free everywhere and reproduces the manuals' frames.

Each map in maps/, tests/maps/small/ and tests/maps/fixtures/ (issue #19's made-up devices: input
registers, coils and discrete inputs, floats, 64-bit values, strings, swapped bytes, firmware gates)
is generated into a temporary directory, then:

- each header, alone (included twice, for the include guard) and all of them in one translation unit,
  compiles with gcc and clang as C99, g++ and clang++ as C++17, and arm-none-eabi-gcc for a Cortex-M0
  at -Os, under -Wall -Wextra -Wpedantic -Werror -Wconversion (plus a few stricter warnings);
- the frames test program that `support.c_frames.render_frames_test` emits for the map (it rebuilds
  every request frame of the map's examples with the header's helpers and parses every response frame
  to the recorded values) is compiled and run with each host compiler, and with clang's sanitizers;
- tests/c/rtu_selftest.c checks the shared regmap_rtu.h where the manuals' frames do not reach;
- examples/libmodbus/main.c compiles and links against libmodbus;
- the Cortex-M0 code size of the frame helpers stays within its budget.

A missing compiler skips its tests with a reason; under CI=true it fails them (`require_tool`).
"""

from __future__ import annotations

import functools
import os
import re
import subprocess
from collections.abc import Callable
from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path

import pytest
import yaml

from regmap.backends import c as c_backend
from regmap.backends.c.names import Context
from regmap.diagnostics import UsageError
from regmap.frontend import load_map, load_map_text
from regmap.generate import generate, render
from regmap.model import Device, PollClass
from regmap.runtime_bridge import read_plan

from conftest import FIXTURE_MAPS, MAPS, ROOT, SMALL_MAPS, require_tool
from support.c_frames import render_frames_test

C_TESTS = ROOT / "tests" / "c"
EXAMPLE = ROOT / "examples" / "libmodbus" / "main.c"
ALL_MAPS = [*MAPS, *SMALL_MAPS, *FIXTURE_MAPS]
M0_TEXT_BUDGET = 1024  # bytes of .text for the frame helpers and the CRC at -Os (744 with arm-none-eabi-gcc 12.2)

WARNINGS = ("-Wall", "-Wextra", "-Wpedantic", "-Werror", "-Wconversion")
STRICTER = ("-Wsign-conversion", "-Wshadow", "-Wcast-qual", "-Wundef")


@dataclass(frozen=True)
class Compiler:
    id: str
    tool: str
    flags: tuple[str, ...]
    host: bool  # its programs run here

    def command(self, *args: str) -> list[str]:
        return [require_tool(self.tool), *self.flags, *args]


COMPILERS = (
    Compiler("gcc-c99", "gcc", ("-std=c99", "-O2", *WARNINGS, *STRICTER, "-Wstrict-prototypes"), host=True),
    Compiler("clang-c99", "clang", ("-std=c99", "-O2", *WARNINGS, *STRICTER, "-Wstrict-prototypes"), host=True),
    Compiler("g++-c++17", "g++", ("-x", "c++", "-std=c++17", "-O2", *WARNINGS, *STRICTER), host=True),
    Compiler("clang++-c++17", "clang++", ("-x", "c++", "-std=c++17", "-O2", *WARNINGS, *STRICTER), host=True),
    Compiler(
        "arm-none-eabi-gcc-m0", "arm-none-eabi-gcc", ("-std=c99", "-mcpu=cortex-m0", "-mthumb", "-Os", *WARNINGS, *STRICTER), host=False
    ),
)
SANITIZED = Compiler(
    "clang-c99-sanitizers",
    "clang",
    ("-std=c99", "-g", "-fsanitize=undefined,address", "-fno-sanitize-recover=all", *WARNINGS, *STRICTER),
    host=True,
)
HOST = (*(c for c in COMPILERS if c.host), SANITIZED)


def _map_params(*, frames: bool = False) -> list[object]:
    params: list[object] = []
    for path in ALL_MAPS:
        params.append(pytest.param(path, id=path.stem))
    return params


@functools.cache
def _device(path: Path) -> Device:
    return load_map(path, display_name=path.relative_to(ROOT).as_posix())


@pytest.fixture(scope="module")
def out_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Every map's header and the shared header, as `regmap generate --target c` writes them."""
    out = tmp_path_factory.mktemp("c")
    devices = [_device(p) for p in ALL_MAPS]
    for rel, text in render(devices, ["c"])["c"].items():
        (out / rel).write_text(text, encoding="utf-8")
    return out


def _run(command: list[str]) -> subprocess.CompletedProcess[str]:
    # LeakSanitizer cannot run under ptrace (some sandboxes); the programs allocate nothing anyway.
    env = {**os.environ, "ASAN_OPTIONS": "detect_leaks=0"}
    return subprocess.run(command, env=env, capture_output=True, text=True, timeout=240, check=False)


def _compile(compiler: Compiler, source: Path, out_dir: Path, output: Path, *extra: str, link: bool = False) -> None:
    args = [f"-I{out_dir}", str(source), *extra, "-o", str(output)]
    result = _run(compiler.command(*([] if link else ["-c"]), *args))
    assert result.returncode == 0, f"{compiler.id} failed on {source.name}:\n{result.stdout}{result.stderr}"
    assert not result.stderr.strip(), f"{compiler.id} warned on {source.name}:\n{result.stderr}"


# -- compile matrix ------------------------------------------------------------------------------


@pytest.mark.parametrize("compiler", COMPILERS, ids=lambda c: c.id)
@pytest.mark.parametrize("map_path", _map_params())
def test_header_compiles(compiler: Compiler, map_path: Path, out_dir: Path, tmp_path: Path) -> None:
    header = f"{_device(map_path).id}.h"
    source = tmp_path / "unit.c"
    source.write_text(f'#include "{header}"\n#include "{header}" /* twice: the include guard */\n', encoding="utf-8")
    _compile(compiler, source, out_dir, tmp_path / "unit.o")


@pytest.mark.parametrize("compiler", COMPILERS, ids=lambda c: c.id)
def test_all_headers_in_one_unit(compiler: Compiler, out_dir: Path, tmp_path: Path) -> None:
    """Headers of several devices must not clash with each other (macro redefinitions, duplicate names)."""
    source = tmp_path / "all.c"
    source.write_text("".join(f'#include "{_device(p).id}.h"\n' for p in ALL_MAPS), encoding="utf-8")
    _compile(compiler, source, out_dir, tmp_path / "all.o")


@pytest.mark.parametrize("compiler", [c for c in COMPILERS if c.host], ids=lambda c: c.id)
def test_headers_link_from_two_units(compiler: Compiler, out_dir: Path, tmp_path: Path) -> None:
    """Every header included by two translation units, one of which defines <DEVICE>_IMPLEMENTATION (and
    includes the header once before defining it): each table is defined once, so the program links, and
    both units see the same tables; no unit warns (an unused table, a duplicate definition)."""
    devices = [_device(p) for p in ALL_MAPS]
    suffix = ".c" if "c++" not in compiler.flags else ".cpp"
    first, second = tmp_path / f"first{suffix}", tmp_path / f"second{suffix}"
    first.write_text(
        "".join(f'#include "{d.id}.h"\n#define {d.id.upper()}_IMPLEMENTATION\n#include "{d.id}.h"\n' for d in devices)
        + "const regmap_read_block *first_plan(void);\n"
        + f"const regmap_read_block *first_plan(void) {{ return {devices[0].id}_read_plan; }}\n",
        encoding="utf-8",
    )
    sums = " + ".join(f"(unsigned long){d.id}_read_plan[0].address" for d in devices if read_plan(d))
    second.write_text(
        "".join(f'#include "{d.id}.h"\n' for d in devices)
        + "const regmap_read_block *first_plan(void);\n"
        + f"int main(void) {{ unsigned long sum = {sums}; return first_plan() == {devices[0].id}_read_plan && sum == {sum(read_plan(d)[0].address for d in devices if read_plan(d))}ul ? 0 : 1; }}\n",
        encoding="utf-8",
    )
    objects = []
    for source in (first, second):
        objects.append(tmp_path / f"{source.stem}.o")
        _compile(compiler, source, out_dir, objects[-1])
    program = tmp_path / "two_units"
    linked = _run([require_tool(compiler.tool), *map(str, objects), "-o", str(program)])
    assert linked.returncode == 0, f"{compiler.id} could not link two units:\n{linked.stderr}"
    assert _run([str(program)]).returncode == 0, "the two units see different tables"


# -- the manuals' frames ---------------------------------------------------------------------------


def _frames_program(map_path: Path, out_dir: Path, tmp_path: Path) -> Path:
    device = _device(map_path)
    source = tmp_path / f"{device.id}_frames_test.c"
    source.write_text(render_frames_test(device), encoding="utf-8")
    return source


def _build_and_run(compiler: Compiler, source: Path, out_dir: Path, tmp_path: Path) -> subprocess.CompletedProcess[str]:
    program = tmp_path / f"{source.stem}-{compiler.id}"
    _compile(compiler, source, out_dir, program, link=True)
    return _run([str(program)])


@pytest.mark.parametrize("compiler", HOST, ids=lambda c: c.id)
@pytest.mark.parametrize("map_path", _map_params(frames=True))
def test_frames_of_the_manual(compiler: Compiler, map_path: Path, out_dir: Path, tmp_path: Path) -> None:
    source = _frames_program(map_path, out_dir, tmp_path)
    result = _build_and_run(compiler, source, out_dir, tmp_path)
    assert result.returncode == 0, f"{source.name} ({compiler.id}):\n{result.stdout}{result.stderr}"
    assert re.search(r": \d+ checks, 0 failures$", result.stdout.strip()), result.stdout


def test_frames_program_covers_every_example() -> None:
    for path in ALL_MAPS:
        device = _device(path)
        source = render_frames_test(device)
        for ex in device.examples:
            assert f"/* {ex.id} (" in source, f"{device.id}: example {ex.id} has no case in the frames test"


def test_frames_program_fails_on_a_wrong_header(out_dir: Path, tmp_path: Path) -> None:
    """The frames test must notice a wrong address macro and a wrong CRC: it checks bytes, not itself."""
    path = next((p for p in ALL_MAPS if _device(p).examples), None)
    if path is None:
        pytest.skip("no map with examples")
    device = _device(path)
    source = _frames_program(path, out_dir, tmp_path)
    header = (out_dir / f"{device.id}.h").read_text(encoding="utf-8")
    shared = (out_dir / "regmap_rtu.h").read_text(encoding="utf-8")
    defined = dict(re.findall(r"^#define (\w+_ADDR) +0x([0-9A-F]+)u$", header, flags=re.M))
    used = next(name for name in re.findall(r"\b[A-Z0-9_]+_ADDR\b", source.read_text(encoding="utf-8")) if name in defined)
    moved = re.sub(rf"^(#define {used} +)0x[0-9A-F]+u$", rf"\g<1>0x{int(defined[used], 16) + 1:04X}u", header, flags=re.M)
    for label, device_header, rtu_header in (
        (f"{used} one too high", moved, shared),
        ("CRC polynomial", header, shared.replace("0xA001u", "0xA003u")),
    ):
        broken = tmp_path / re.sub(r"\W", "_", label)
        broken.mkdir()
        (broken / f"{device.id}.h").write_text(device_header, encoding="utf-8")
        (broken / "regmap_rtu.h").write_text(rtu_header, encoding="utf-8")
        result = _build_and_run(COMPILERS[0], source, broken, broken)
        assert result.returncode != 0 and "FAIL" in result.stdout, f"the frames test passed a header with a wrong {label}"


# A header that agrees with itself but not with the wire: the frames test of each fixture must fail on it.
# (map, what is wrong, "device" or "shared" header, text, replacement)
WRONG_FIXTURE_HEADERS = [
    ("remote_io", "bits unpacked most significant first", "shared", ">> (unsigned)(i % 8u)) & 1u", ">> (7u - (unsigned)(i % 8u))) & 1u"),
    ("remote_io", "bits packed most significant first", "shared", "(1u << (unsigned)(i % 8u))", "(0x80u >> (unsigned)(i % 8u))"),
    ("remote_io", "coil on as 0x00FF", "shared", "#define REGMAP_COIL_ON 0xFF00u", "#define REGMAP_COIL_ON 0x00FFu"),
    (
        "power_meter",
        "current_l1 read high word first",
        "device",
        "CURRENT_L1_WORD_ORDER        REGMAP_LOW_FIRST",
        "CURRENT_L1_WORD_ORDER        REGMAP_HIGH_FIRST",
    ),
    (
        "power_meter",
        "64-bit words in the wrong order",
        "shared",
        "return ((uint64_t)w[0] << 48) | ((uint64_t)w[1] << 32)",
        "return ((uint64_t)w[1] << 48) | ((uint64_t)w[0] << 32)",
    ),
    (
        "power_meter",
        "the string copy keeps the padding",
        "shared",
        "regmap_string_byte(words, len, byte_order) != 0u",
        "regmap_string_byte(words, len, byte_order) != 0x100u",
    ),
    (
        "swapped_gated",
        "label bytes not swapped",
        "device",
        "LABEL_BYTE_ORDER           REGMAP_LOW_FIRST",
        "LABEL_BYTE_ORDER           REGMAP_HIGH_FIRST",
    ),
    ("swapped_gated", "the byte swap does nothing", "shared", "(uint16_t)(((unsigned)word << 8) | ((unsigned)word >> 8))", "word"),
]


@pytest.mark.parametrize(("stem", "label", "which", "old", "new"), WRONG_FIXTURE_HEADERS, ids=[w[1] for w in WRONG_FIXTURE_HEADERS])
def test_fixture_frames_fail_on_a_wrong_header(
    stem: str, label: str, which: str, old: str, new: str, out_dir: Path, tmp_path: Path
) -> None:
    path = next(p for p in FIXTURE_MAPS if p.stem == stem)
    device = _device(path)
    source = _frames_program(path, out_dir, tmp_path)
    files = {name: (out_dir / name).read_text(encoding="utf-8") for name in (f"{device.id}.h", "regmap_rtu.h")}
    name = f"{device.id}.h" if which == "device" else "regmap_rtu.h"
    assert files[name].count(old) == 1, f"{old!r} is not once in {name}"
    files[name] = files[name].replace(old, new)
    broken = tmp_path / "broken"
    broken.mkdir()
    for rel, text in files.items():
        (broken / rel).write_text(text, encoding="utf-8")
    result = _build_and_run(COMPILERS[0], source, broken, broken)
    assert result.returncode != 0 and "FAIL" in result.stdout, f"the frames test of {stem} passed a header where {label}:\n{result.stdout}"


# -- the shared header, the example, code size -----------------------------------------------------


@pytest.mark.parametrize("compiler", HOST, ids=lambda c: c.id)
def test_rtu_selftest(compiler: Compiler, out_dir: Path, tmp_path: Path) -> None:
    result = _build_and_run(compiler, C_TESTS / "rtu_selftest.c", out_dir, tmp_path)
    assert result.returncode == 0, result.stdout + result.stderr
    assert result.stdout.strip().endswith(" 0 failures"), result.stdout


@pytest.mark.parametrize("compiler", [c for c in COMPILERS if c.tool in ("gcc", "clang")], ids=lambda c: c.id)
def test_libmodbus_example_compiles(compiler: Compiler, out_dir: Path, tmp_path: Path) -> None:
    pkg_config = require_tool("pkg-config")
    flags = _run([pkg_config, "--cflags", "--libs", "libmodbus"])
    if flags.returncode != 0:
        message = "libmodbus-dev is not installed (.ci/run installs it)"
        if os.environ.get("CI") == "true":
            pytest.fail(message)
        pytest.skip(message)
    if not (out_dir / "idm_rs.h").exists():
        pytest.skip("maps/idm_rs.yaml is not there; the example reads an iDM-RS")
    cflags = [f for f in flags.stdout.split() if not f.startswith("-l")]
    libs = [f for f in flags.stdout.split() if f.startswith("-l")]
    _compile(compiler, EXAMPLE, out_dir, tmp_path / "read_idm_rs", *cflags, *libs, link=True)


# Bytes beyond M0_TEXT_BUDGET each option may add (measured with arm-none-eabi-gcc 12.2: 44 and 812).
M0_EXTRA_BUDGET = {"-DREGMAP_SIZE_WITH_WORDS": 128, "-DREGMAP_SIZE_WITH_SPACES": 1024}


@pytest.mark.parametrize(
    "extra",
    [(), ("-DREGMAP_SIZE_WITH_WORDS",), ("-DREGMAP_SIZE_WITH_SPACES",)],
    ids=["frame-helpers", "with-word-conversions", "with-coils-inputs-floats-strings"],
)
def test_cortex_m0_code_size(extra: tuple[str, ...], out_dir: Path, tmp_path: Path, record_property: Callable[[str, object], None]) -> None:
    compiler = COMPILERS[-1]
    size_tool = require_tool("arm-none-eabi-size")
    _compile(compiler, C_TESTS / "m0_size.c", out_dir, tmp_path / "m0.o", "-Wmissing-prototypes", *extra)
    result = _run([size_tool, str(tmp_path / "m0.o")])
    text = int(result.stdout.splitlines()[1].split()[0])
    record_property("cortex_m0_text_bytes", text)
    print(f"Cortex-M0 -Os .text of the RTU frame helpers{' with ' + ' '.join(extra) if extra else ''}: {text} bytes")
    assert 0 < text <= M0_TEXT_BUDGET + sum(M0_EXTRA_BUDGET[e] for e in extra)


# -- what the Python side computes ------------------------------------------------------------------


def _definition(header: str, name: str) -> str:
    """The initialiser of table `name` where the header defines it (behind <DEVICE>_IMPLEMENTATION)."""
    match = re.search(rf"^const \w+ {name}\[\w+\] = \{{\n(.*?)^\}};", header, flags=re.M | re.S)
    assert match is not None, f"no definition of {name}"
    return match.group(1)


@pytest.mark.parametrize("map_path", _map_params())
def test_read_plan_table_is_the_clients_plan(map_path: Path, out_dir: Path) -> None:
    device = _device(map_path)
    header = (out_dir / f"{device.id}.h").read_text(encoding="utf-8")
    table = _definition(header, f"{device.id}_read_plan") if read_plan(device) else ""
    rows = [(int(a, 16), int(n)) for a, n in re.findall(r"\{ (0x[0-9A-F]+)u, (\d+)u \}", table)]
    assert rows == [(b.address, b.count) for b in read_plan(device)]
    assert f"#define {device.id.upper()}_READ_PLAN_LEN {len(rows)}u" in header


FUNCTION_OF_SPACE = {"holding": "REGMAP_FC_READ_HOLDING", "input": "REGMAP_FC_READ_INPUT", "coil": "REGMAP_FC_READ_COILS",
                     "discrete_input": "REGMAP_FC_READ_DISCRETE_INPUTS"}  # fmt: skip


@pytest.mark.parametrize("map_path", [pytest.param(p, id=p.stem) for p in FIXTURE_MAPS])
def test_plans_per_space_and_poll_class_are_the_clients(map_path: Path, out_dir: Path) -> None:
    """Where a map reads more than holding registers, a function-code table runs beside the plan; where it
    has poll classes, each class has its plan, as read_all(poll=...) reads it."""
    device = _device(map_path)
    header = (out_dir / f"{device.id}.h").read_text(encoding="utf-8")

    def table(name: str) -> str:
        return _definition(header, name)

    plans = [("read_plan", read_plan(device))]
    classes = sorted({r.poll for r in device.registers}, key=list(PollClass).index)
    if len(classes) > 1:
        plans += [(f"read_plan_{poll.value}", read_plan(device, poll=poll)) for poll in classes if read_plan(device, poll=poll)]
    else:
        assert "read_plan_normal" not in header
    for name, blocks in plans:
        rows = [(int(a, 16), int(n)) for a, n in re.findall(r"\{ (0x[0-9A-F]+)u, (\d+)u \}", table(f"{device.id}_{name}"))]
        assert rows == [(b.address, b.count) for b in blocks], name
        if any(b.space != "holding" for b in read_plan(device)):
            functions = re.findall(r"REGMAP_FC_READ_\w+", table(f"{device.id}_{name}_function"))
            assert functions == [FUNCTION_OF_SPACE[b.space] for b in blocks], name
        else:
            assert f"{device.id}_{name}_function" not in header


def test_generated_headers_are_deterministic() -> None:
    devices = [_device(p) for p in ALL_MAPS]
    first, second = render(devices, ["c"]), render(devices, ["c"])
    assert first == second
    for text in first["c"].values():
        assert not re.search(r"\b20\d\d-\d\d-\d\d\b", text), "a date in generated output"
        assert text.endswith("\n")


def test_generate_writes_the_c_tree(tmp_path: Path) -> None:
    device = _device(SMALL_MAPS[0])
    generate([device], tmp_path / "generated", ["c"], complete=True)
    assert sorted(p.name for p in (tmp_path / "generated" / "c").iterdir()) == sorted([f"{device.id}.h", "regmap_rtu.h"])


def test_identifiers() -> None:
    CIdentifier, CSymbol = c_backend.CIdentifier, c_backend.CSymbol
    assert CIdentifier("idm_rs", "peak_current", "ADDR") == "IDM_RS_PEAK_CURRENT_ADDR"
    assert CSymbol("idm_rs", "build", "save") == "idm_rs_build_save"
    for keyword in ("register", "default", "class", "new", "and", "bool", "int"):
        assert CSymbol(keyword) == keyword + "_"
    for bad in ("_x", "a__b", "9a", "a-b", "a b", "", "peak\u00e9"):
        with pytest.raises(UsageError):
            CIdentifier(bad)
    for bad in ("_x", "x__y", "speed_t", "a-b"):
        with pytest.raises(UsageError):
            CSymbol(bad)
    with pytest.raises(UsageError):
        CIdentifier("null")  # NULL


def test_a_constant_name_is_checked_part_by_part() -> None:
    """Context.const checks each part of a name once per device; a name it cannot vouch for is checked whole."""
    ctx = Context(_device(SMALL_MAPS[0]))
    assert ctx.const("peak_current", "ADDR") == c_backend.CIdentifier(ctx.prefix, "peak_current", "ADDR")
    assert ctx.const("peak_current", "", "min") == f"{ctx.prefix}_PEAK_CURRENT_MIN"
    for bad in (("_x",), ("peak_current", "_words"), ("a-b",), ("a__b",), ("peak\u00e9",)):
        with pytest.raises(UsageError):
            ctx.const(*bad)


def test_a_registers_constants_are_named_as_const_names_them() -> None:
    """Context.owned (the owner spelled once per register) gives what const gives, also where the device id and the
    owner alone make a name of the C standard library (INT8_MAX) that the whole name (INT8_MAX_WORDS) is not."""
    text = SMALL_MAPS[0].read_text(encoding="utf-8")
    device = load_map_text(text, SMALL_MAPS[0].name)
    owners = [r.name for r in device.registers[:3]]
    for device_id in (device.id, "int8", "size"):
        renamed = load_map_text(text.replace(f"id: {device.id}\n", f"id: {device_id}\n", 1), f"{device_id}.yaml")
        assert renamed.id == device_id
        by_owned, by_const = Context(renamed), Context(renamed)
        for owner in [*owners, "max"]:
            for suffix in ("ADDR", "WORDS", "MAX"):
                assert by_owned.owned(by_owned.stem(owner), owner, suffix) == by_const.const(owner, suffix)
        if device_id == "int8":
            assert Context(renamed).const("max", "ADDR") == "INT8_MAX_ADDR"  # INT8_MAX alone is <stdint.h>'s


def test_a_function_name_takes_every_check_of_csymbol() -> None:
    """Context.symbol spells a plain name itself; a name CSymbol would change or refuse, it leaves to CSymbol."""
    ctx = Context(_device(SMALL_MAPS[0]))
    assert ctx.symbol("peak_current", "get") == c_backend.CSymbol(ctx.lower, "peak_current", "get")
    with pytest.raises(UsageError):
        ctx.symbol("speed", "t")  # POSIX reserves _t names
    ctx.lower = "static"  # a device id that makes a keyword of the whole name
    assert ctx.symbol("assert") == ctx.symbol_ref("assert") == "static_assert_"


def test_literals() -> None:
    assert c_backend.c_signed(-(1 << 31)) == "(-2147483647 - 1)"
    assert c_backend.c_signed(-5) == "(-5)"
    assert c_backend.c_unsigned(65535) == "65535u"
    assert c_backend.c_unsigned(65536) == "65536ul"
    assert c_backend.c_hex(0x191) == "0x0191u"
    assert c_backend.c_float(Fraction(1, 10)) == "0.1f"
    assert c_backend.c_float(Fraction(2)) == "2.0f"


def _small_map() -> dict[str, object]:
    data: dict[str, object] = yaml.safe_load((ROOT / "tests" / "maps" / "small" / "idm_rs_small.yaml").read_text(encoding="utf-8"))
    return data


HOSTILE = "EVIL */ #include <stdlib.h> /* ??/\n\\\n\" '"


def _strip_comments(code: str) -> str:
    """C code without its /* */ comments (string and character literals kept)."""
    return re.sub(r'/\*.*?\*/|("(?:\\.|[^"\\])*"|\'(?:\\.|[^\'\\])*\')', lambda m: m.group(1) or " ", code, flags=re.S)


def test_map_text_cannot_inject_code(tmp_path: Path) -> None:
    """Titles, Chinese titles, descriptions, units and range texts go into comments, escaped."""
    data = _small_map()
    device_info = data["device"]
    assert isinstance(device_info, dict)
    device_info["description"] = HOSTILE
    groups = data["groups"]
    assert isinstance(groups, list)
    reg = groups[0]["registers"][0]
    reg.update(title=HOSTILE, title_zh=HOSTILE, description=HOSTILE, unit=HOSTILE, range_text=HOSTILE)
    enums = data["enums"]
    assert isinstance(enums, dict)
    first_enum = next(iter(enums.values()))
    first_enum["title"] = HOSTILE
    first_enum["values"][0]["title"] = HOSTILE
    device = load_map_text(yaml.safe_dump(data, allow_unicode=True), "hostile.yaml")
    files = render([device], ["c"])["c"]
    header = files[f"{device.id}.h"]
    assert header.count("EVIL") >= 6
    assert "EVIL" not in _strip_comments(header)
    assert "#include <stdlib.h>" not in _strip_comments(header)
    for rel, text in files.items():
        (tmp_path / rel).write_text(text, encoding="utf-8")
    source = tmp_path / "unit.c"
    source.write_text(f'#include "{device.id}.h"\n', encoding="utf-8")
    _compile(COMPILERS[0], source, tmp_path, tmp_path / "unit.o", "-Wtrigraphs", "-Wcomment")


def test_a_name_clash_is_reported() -> None:
    """An enum member that generates the same macro as a register's address macro is refused, naming both."""
    data = _small_map()
    enums = data["enums"]
    assert isinstance(enums, dict)
    enums["peak_current"] = {"title": "Clash", "values": [{"value": 0, "name": "addr", "title": "Clash"}]}
    device = load_map_text(yaml.safe_dump(data, allow_unicode=True), "clash.yaml")
    with pytest.raises(UsageError, match=r"_PEAK_CURRENT_ADDR is used by both"):
        render([device], ["c"])


def test_a_firmware_version_c_cannot_compare_is_reported_at_its_line() -> None:
    """REGMAP_VERSION holds major.minor: a three-part gate (which only a firmware register that reports
    text can carry; the front end refuses it for a numeric one) is a diagnostic at the register's line,
    and generate refuses it."""
    path = next(p for p in FIXTURE_MAPS if p.stem == "swapped_gated")
    data = yaml.safe_load(path.read_text(encoding="utf-8"))
    data["device"]["firmware_register"] = {"register": "label", "format": "string"}
    group = next(g for g in data["groups"] if g["id"] == "diagnostics")
    group["firmware"] = {"from": "2.5.1"}
    device = load_map_text(yaml.safe_dump(data, allow_unicode=True, sort_keys=False), "three_parts.yaml")
    problems = c_backend.check(device)
    assert [p.message.split(":")[0] for p in problems] == ["runtime_hours", "fault_count"]
    assert all(p.file == "three_parts.yaml" and p.line > 1 and "2.5.1 is not major.minor" in p.message for p in problems)
    with pytest.raises(UsageError, match=r"^three_parts\.yaml:\d+:\d+: runtime_hours: firmware version 2\.5\.1"):
        render([device], ["c"])
    assert c_backend.check(_device(path)) == []
