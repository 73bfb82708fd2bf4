"""The Structured Text back end: every generated file parses, and says what the model says, for the seed
maps, the hostile map and issue 19's fixture maps (input registers, coils, discrete inputs, floats,
64-bit values, text, byte swaps, offsets, firmware gates, poll classes).

blark (TwinCAT's grammar, lark-based) and tree-sitter-iec61131-3-st (the plain standard) live in a venv
of their own (tests/support/tool_envs.py, built by `make tools`), since their pins are not regmap's;
tests/st/parse_st.py runs inside it. Without it the parse tests skip, except under CI=true where they fail.
"""

from __future__ import annotations

import json
import re
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest
import yaml

from regmap.backends import st
from regmap.backends.st.codec import CODESYS, IEC, PLCOPEN
from regmap.backends.st.device import DeviceViews
from regmap.backends.st.functions import plan_blocks
from regmap.backends.st.names import Scope
from regmap.backends.st.view_types import SectionToSpell
from regmap.frontend import load_map, load_map_text
from regmap.generate import render
from regmap.model import ByteOrder, DataType, Device
from regmap.runtime_bridge import read_plan

from conftest import FIXTURE_MAPS, MAPS, ROOT, built_tool

PARSE = ROOT / "tests" / "st" / "parse_st.py"
HOSTILE = ROOT / "tests" / "maps" / "hostile" / "hostile.yaml"
SCALED_FROM = ROOT / "tests" / "maps" / "scaled_from" / "inverter.yaml"  # scale factors (scale_from)
CONST = re.compile(r"^\s+([A-Z0-9_]+) : ([A-Z]+(?:\(\d+\))?) := (.+?);(?: \(\*.*\*\))?$", re.M)
ALL_MAPS = [*MAPS, *FIXTURE_MAPS, SCALED_FROM]
SPACE_TAG = {"holding": "", "input": "INPUT_", "coil": "COIL_", "discrete_input": "DISCRETE_"}


@pytest.fixture(scope="session")
def st_python() -> Path:
    return built_tool("st")


@pytest.fixture(scope="module")
def out(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The ST of every map and of the hostile map, as `regmap generate --target st` writes it."""
    root = tmp_path_factory.mktemp("st")
    devices = [load_map(p, display_name=p.relative_to(ROOT).as_posix()) for p in [*MAPS, HOSTILE, *FIXTURE_MAPS, SCALED_FROM]]
    for rel, text in render(devices, ["st"])["st"].items():
        (root / rel).parent.mkdir(parents=True, exist_ok=True)
        (root / rel).write_text(text, encoding="utf-8")
    return root


def _parse(python: Path, tool: str, files: list[Path]) -> list[str]:
    result = subprocess.run([str(python), str(PARSE), tool, *map(str, files)], capture_output=True, text=True, timeout=240, check=False)
    assert result.returncode == 0, result.stderr
    problems: list[str] = json.loads(result.stdout)
    return problems


TYPED_ENUM_VALUE = re.compile(r"\bE_[A-Z0-9_]+#(?=[A-Z0-9_])")


@pytest.fixture(scope="module")
def parseable(out: Path, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The generated files as the two parsers read them: the plain-standard files with each typed enum
    value (`E_X#MEMBER`, IEC 61131-3's form, which neither grammar has) as its bare member; matiec
    (tests/backends/st/test_st_matiec.py) compiles them as generated."""
    root = tmp_path_factory.mktemp("st-parseable")
    for path in out.rglob("*.st"):
        text = path.read_text(encoding="utf-8")
        if path.parent.name == "iec":
            text = TYPED_ENUM_VALUE.sub("", text)
        (root / path.relative_to(out)).parent.mkdir(parents=True, exist_ok=True)
        (root / path.relative_to(out)).write_text(text, encoding="utf-8")
    return root


def test_every_file_parses_with_blark(st_python: Path, parseable: Path) -> None:
    # The pollers are one long function block each, which blark's Earley parser reads in minutes:
    # tests/backends/st/test_st_poller.py parses the pollers of the small fixture maps, the same text.
    files = sorted(p for p in parseable.rglob("*.st") if not p.name.endswith("_poll.st"))
    assert _parse(st_python, "blark", files) == []


def test_plain_standard_files_parse_with_tree_sitter(st_python: Path, parseable: Path) -> None:
    assert _parse(st_python, "tree-sitter", sorted(parseable.glob("*/iec/*.st"))) == []


def test_codesys_is_the_standard_text_plus_its_dialect(out: Path) -> None:
    """The CODESYS files are the plain-standard ones plus pragmas, enum values and base types, `.` for the
    standard's `#` in a qualified enum value and lengths on STRING, so tree-sitter's reading of the
    standard files (and matiec's compiling them) covers every other line of them too."""
    for codesys in sorted(p for p in out.glob("*/codesys/*.st") if not p.name.endswith("_poll.st")):  # the poller is CODESYS' alone
        iec = _without_float_helpers((codesys.parent.parent / "iec" / codesys.name).read_text(encoding="utf-8"))
        iec = iec.replace(", or a float is infinity or NaN (plain IEC 61131-3 has no value for them)", "")
        text = _without_float_helpers(codesys.read_text(encoding="utf-8")).replace("CODESYS / TwinCAT 3", "IEC 61131-3 (OpenPLC / matiec)")
        text = re.sub(r"^\{attribute '(qualified_only|strict)'\}\n", "", text, flags=re.M)
        text = re.sub(r"^\) (UINT|INT|DINT);$", ");", text, flags=re.M)
        text = re.sub(r"\b(E_[A-Z0-9_]+)\.([A-Z0-9_]+)", r"\1#\2", text)
        text = re.sub(r"^(    [A-Z0-9_]+) := -?\d+(,?) \(\*", r"\1\2 (*", text, flags=re.M)
        text = re.sub(r"\bSTRING\(\d+\)", "STRING", text)
        assert text == iec, codesys


@pytest.mark.parametrize(
    ("tool", "dialect", "old", "new"),
    [
        ("blark", "codesys", "END_TYPE", "END_TYP"),
        ("blark", "codesys", " := TRUE;", " := := TRUE;"),
        ("tree-sitter", "iec", "END_TYPE", "END_TYP"),
        ("tree-sitter", "iec", " := TRUE;", " := := TRUE;"),
    ],
)
def test_a_broken_line_fails_the_parse(
    st_python: Path, parseable: Path, tmp_path: Path, tool: str, dialect: str, old: str, new: str
) -> None:
    """The parse tests can fail: one broken generated line makes them report it."""
    for name in ("types", "functions"):
        source = parseable / "id243pro" / dialect / f"id243pro_{name}.st"
        broken = tmp_path / source.name
        text = source.read_text(encoding="utf-8")
        if old in text:
            broken.write_text(text.replace(old, new, 1), encoding="utf-8")
            problems = _parse(st_python, tool, [broken])
            assert problems and str(broken) in problems[0], problems
            return
    pytest.fail(f"{old!r} is in no generated file")


def _without_float_helpers(text: str) -> str:
    """The text less what differs by design: the float helpers' bodies (a UNION in CODESYS, exact
    arithmetic in plain IEC) and the UNION types; their names, signatures and callers stay."""
    text = re.sub(r"\n\(\* [^\n]*\*\)\nTYPE U_[A-Z0-9_]+ :\nUNION\n.*?END_TYPE\n", "", text, flags=re.S)
    text = re.sub(r"(FUNCTION F_[A-Z0-9_]+_F(?:32|64)_(?:FROM|TO)_BITS : BOOL\n).*?(END_FUNCTION)", r"\1\2", text, flags=re.S)
    return re.sub(r"\(\* The (?:IEEE 754|32 bits|64 bits)[^\n]*\*\)", "", text)


def _consts(path: Path) -> dict[str, str]:
    return {m[1]: m[3] for m in CONST.finditer(path.read_text(encoding="utf-8"))}


def _int(text: str) -> int:
    return int(text[3:], 16) if text.startswith("16#") else int(text)


def _number(text: str) -> int | float:
    return float(text) if "." in text or "e" in text else _int(text)


def _literal(text: str) -> int | float | str | bool:
    if text.startswith("'"):
        return re.sub(r"\$([0-9A-F]{2})", lambda m: chr(int(m[1], 16)), text[1:-1])
    if text in ("TRUE", "FALSE"):
        return text == "TRUE"
    return _number(text)


@pytest.mark.parametrize("map_path", ALL_MAPS, ids=lambda p: p.stem)
@pytest.mark.parametrize("dialect", ["codesys", "iec"])
def test_constants_equal_the_model(map_path: Path, dialect: str, out: Path) -> None:
    device = load_map(map_path)
    p = device.id.upper()
    consts = _consts(out / device.id / dialect / f"{device.id}_constants.st")
    for reg in device.registers:
        n = f"{p}_{reg.name.upper()}"
        assert _int(consts[f"{n}_ADDR"]) == reg.address, reg.name
        assert _int(consts[f"{n}_WORDS"]) == reg.words
        space = reg.space_info
        assert (f"{n}_FUNCTION" in consts) == (space.read != 0x03)
        if space.read != 0x03:
            assert _int(consts[f"{n}_FUNCTION"]) == space.read
        assert (f"{n}_HIGH_BYTE_FIRST" in consts) == (reg.byte_order is ByteOrder.LOW_FIRST and not reg.type.is_bool), reg.name
        assert (f"{n}_HIGH_WORD_FIRST" in consts) == reg.wide, reg.name
        if reg.type.numeric:
            assert (_number(consts[f"{n}_RAW_MIN"]), _number(consts[f"{n}_RAW_MAX"])) == (reg.raw_min, reg.raw_max)
            assert (_int(consts[f"{n}_SCALE_NUM"]), _int(consts[f"{n}_SCALE_DEN"])) == (reg.scale.numerator, reg.scale.denominator)
        else:
            assert f"{n}_RAW_MIN" not in consts and f"{n}_SCALE_NUM" not in consts
        if reg.type.is_string:
            assert _int(consts[f"{n}_BYTES"]) == 2 * reg.words
        if reg.offset:
            assert (_int(consts[f"{n}_OFFSET_NUM"]), _int(consts[f"{n}_OFFSET_DEN"])) == (reg.offset.numerator, reg.offset.denominator)
        if reg.poll.value != "normal":
            assert _int(consts[f"{n}_POLL"]) == _int(consts[f"{p}_POLL_{reg.poll.value.upper()}"])
        if reg.default is not None:
            assert _literal(consts[f"{n}_DEFAULT"]) == reg.default
        if reg.paired:
            assert _int(consts[f"{n}_FIRST_ADDR"]) == reg.first_address
        for b in reg.bitfields:
            owner = f"{reg.array.array}_{reg.array.member}" if reg.array else reg.name
            assert _int(consts[f"{p}_{owner.upper()}_{b.name.upper()}_MASK"]) == b.mask
    for cmd in device.commands:
        assert _int(consts[f"{p}_CMD_{cmd.name.upper()}_VALUE"]) == cmd.value
        assert _int(consts[f"{p}_CMD_{cmd.name.upper()}_ADDR"]) == cmd.register.address
    assert consts[f"{p}_MAP_FINGERPRINT"] == f"'{device.fingerprint}'"
    assert _int(consts[f"{p}_MAX_READ_REGISTERS"]) == device.transport.max_read_registers
    assert _int(consts[f"{p}_DEFAULT_BAUD"]) == device.transport.baud


# The firmware gates as raw values of each fixture's firmware register, worked out by hand: power_meter
# reports decimal with 2 decimals (1.20 -> 120, 2.00 -> 200), swapped_gated high byte major, low byte minor.
FIRMWARE_RAW = {
    "fixture_power_meter": {"DEMAND_PERIOD_FIRMWARE_FROM": 120, "THD_VOLTAGE_L1_FIRMWARE_FROM": 200},
    "fixture_swapped_drive": {
        "TORQUE_LIMIT_FIRMWARE_FROM": 0x0200,
        "LEGACY_MODE_FIRMWARE_UNTIL": 0x0200,
        "RUNTIME_HOURS_FIRMWARE_FROM": 0x0205,
        "FAULT_COUNT_FIRMWARE_FROM": 0x0205,
    },
}


@pytest.mark.parametrize("name", sorted(FIRMWARE_RAW))
def test_firmware_gates_are_raw_values_of_the_firmware_register(name: str, out: Path) -> None:
    consts = _consts(out / name / "iec" / f"{name}_constants.st")
    gate = re.compile(r"_FIRMWARE_(FROM|UNTIL)$")
    gates = {k.removeprefix(f"{name.upper()}_"): _int(v) for k, v in consts.items() if gate.search(k) and "_BLOCK_" not in k}
    assert gates == FIRMWARE_RAW[name]
    blocks = {k: _int(v) for k, v in consts.items() if gate.search(k) and "_BLOCK_" in k}
    assert set(blocks.values()) <= set(FIRMWARE_RAW[name].values()) and blocks


def _blocks(device: Device, consts: dict[str, str]) -> list[tuple[str, int, int]]:
    p = device.id.upper()
    out = []
    for k in consts:
        m = re.fullmatch(f"{p}_BLOCK_((?:INPUT_|COIL_|DISCRETE_)?)([0-9A-F]{{4}})_ADDR", k)
        if m:
            space = {v: s for s, v in SPACE_TAG.items()}[m[1]]
            out.append((space, _int(consts[k]), _int(consts[k.replace("_ADDR", "_COUNT")])))
    return out


@pytest.mark.parametrize("map_path", FIXTURE_MAPS, ids=lambda p: p.stem)
def test_fixture_blocks_cover_each_register_once_and_never_mix_spaces_classes_or_gates(map_path: Path, out: Path) -> None:
    device = load_map(map_path)
    p = device.id.upper()
    consts = _consts(out / device.id / "codesys" / f"{device.id}_constants.st")
    types = (out / device.id / "codesys" / f"{device.id}_types.st").read_text(encoding="utf-8")
    covered: list[str] = []
    blocks = _blocks(device, consts)
    planned = plan_blocks(device)
    assert blocks == [(b.space, b.address, b.count) for b, *_ in planned]
    for (space, address, count), (block, *_) in zip(blocks, planned, strict=True):
        regs = [device.register(spec.name) for spec in block.registers]
        assert all(r.space == space and address <= r.address and r.address + r.words <= address + count for r in regs)
        assert len({(r.poll, r.firmware, r.variants) for r in regs}) == 1, (space, address)
        tag = f"{SPACE_TAG[space]}{address:04X}"
        assert _int(consts[f"{p}_BLOCK_{tag}_FUNCTION"]) == regs[0].space_info.read if space != "holding" else True
        struct = types.split(f"TYPE ST_{p}_RAW_{tag} :\nSTRUCT\n", 1)[1].split("END_STRUCT", 1)[0]
        if regs[0].space_info.bits:  # the response's bytes: ceil(count / 8)
            assert re.search(rf"BITS : ARRAY\[0\.\.{(count + 7) // 8 - 1}\] OF BYTE;", struct), struct
            assert count <= device.transport.max_read_coils
        else:
            sizes = [int(m[1]) + 1 if m else 1 for m in (re.search(r"ARRAY\[0\.\.(\d+)\]", line) for line in struct.strip().splitlines())]
            assert sum(sizes) == count <= device.transport.max_read_registers
        covered += [r.name for r in regs]
    assert sorted(covered) == sorted(r.name for r in device.registers if r.access.readable)


@pytest.mark.parametrize("map_path", MAPS, ids=lambda p: p.stem)
def test_enums_and_read_plan_equal_the_model(map_path: Path, out: Path) -> None:
    device = load_map(map_path)
    p = device.id.upper()
    types = (out / device.id / "codesys" / f"{device.id}_types.st").read_text(encoding="utf-8")
    for e in device.enums:
        body = types.split(f"TYPE E_{p}_{e.name.upper()} :\n(\n", 1)[1].split("\n)", 1)[0]
        found = re.findall(r"^\s+([A-Z0-9_]+) := (-?\d+)", body, re.M)
        assert [(name.removesuffix("_KW"), int(v)) for name, v in found] == [(m.name.upper(), m.value) for m in e.members]
    consts = _consts(out / device.id / "codesys" / f"{device.id}_constants.st")
    blocks = [
        (_int(consts[k]), _int(consts[k.replace("_ADDR", "_COUNT")])) for k in consts if re.fullmatch(f"{p}_BLOCK_[0-9A-F]{{4}}_ADDR", k)
    ]
    plan = read_plan(device)
    assert blocks == [(b.address, b.count) for b in plan]
    for b in plan:
        struct = types.split(f"TYPE ST_{p}_RAW_{b.address:04X} :\nSTRUCT\n", 1)[1].split("END_STRUCT", 1)[0]
        words = sum(2 if "ARRAY[0..1]" in line else 1 for line in struct.strip().splitlines())
        assert words == b.count, f"block 0x{b.address:04X}: SIZEOF / 2 must be the request's quantity"
        members = re.findall(r"^\s+([A-Z0-9_]+) :", struct, re.M)
        assert [m for m in members if not re.fullmatch("RESERVED_[0-9A-F]{4}", m)] == [s.name.upper() for s in b.registers]


def _code_only(text: str) -> str:
    return re.sub(r"'(?:\$.|[^'$])*'", "''", re.sub(r"\(\*.*?\*\)", "", text))


def test_hostile_map_injects_nothing(out: Path) -> None:
    for path in sorted((out / "hostile_dev").rglob("*.st")):
        code = _code_only(path.read_text(encoding="utf-8"))
        assert "pwn" not in code.lower(), path
        assert "(*" not in code and "*)" not in code, f"{path}: a comment broke out"
        pragmas = set(re.findall(r"\{[^}]*\}", re.sub(r"\(\*.*?\*\)", "", path.read_text(encoding="utf-8"))))
        assert pragmas <= {"{attribute 'qualified_only'}", "{attribute 'strict'}"}, pragmas
    assert "RETURN_KW" in (out / "hostile_dev" / "iec" / "hostile_dev_types.st").read_text(encoding="utf-8")


def test_hostile_comments_hold_no_other_comment_marker(out: Path) -> None:
    """CODESYS nests (* *) and IEC 61131-3 edition 3 also reads /* */: inside a comment the map's text holds neither
    an opener nor a /* */ closer, also where it has no (* at all."""
    for path in sorted((out / "hostile_dev").rglob("*.st")):
        for comment in re.findall(r"\(\*(.*?)\*\)", path.read_text(encoding="utf-8")):
            assert not any(token in comment for token in ("(*", "/*", "*/")), (path, comment)


def test_function_statements_sit_under_their_declarations(out: Path) -> None:
    """In the functions files only a function's declaration lines and comments start at the margin; its statements
    and variables are indented."""
    margin = re.compile(r"(?:FUNCTION |VAR_INPUT$|VAR_IN_OUT$|VAR$|END_VAR$|END_FUNCTION$|\(\*|$)")
    for path in sorted(out.glob("*/*/*_functions.st")):
        flush = [line for line in path.read_text(encoding="utf-8").splitlines() if not line.startswith("    ") and not margin.match(line)]
        assert flush == [], (path, flush[:3])


def _small_map() -> dict[str, Any]:
    small = ROOT / "tests" / "maps" / "small"
    data: dict[str, Any] = yaml.safe_load((small / sorted(p.name for p in small.glob("*.yaml"))[0]).read_text(encoding="utf-8"))
    return data


def test_a_name_past_64_characters_is_refused() -> None:
    """matiec and several IDE views cut names past 64 characters: a map whose generated name is longer is refused."""
    data = _small_map()
    data["enums"]["e" + "x" * 63] = next(iter(data["enums"].values()))  # as long as a map name may be: E_<DEV>_<it> is longer
    problems = st.check(load_map_text(yaml.safe_dump(data, allow_unicode=True, sort_keys=False), "small.yaml"))
    assert any("longer than 64 characters" in p.message for p in problems), problems


@pytest.mark.parametrize(
    ("parts", "suffix"),
    [
        (("dev", "speed"), "RAW_MIN"),  # the usual name: spelled from the stem
        (("dev", "x" * 56), "ADDR"),  # the stem fits in 64 characters, the name does not
        (("dev", "bad__name"), "ADDR"),  # the stem has a problem of its own
        (("dev", "ends_"), "ADDR"),
        (("var",), "INPUT"),  # the whole name is a keyword: VAR_INPUT_KW
        (("dev", ""), "ADDR"),
        (("dev", "speed"), "raw_min"),  # a suffix not upper-case: spelled in full
        (("dev", "speed"), "_ADDR"),
    ],
)
def test_a_stem_spells_each_name_as_its_parts_do(parts: tuple[str, ...], suffix: str) -> None:
    """A register's constants are spelled from its stem (`<DEV>_<REG>`, checked once): each equals the name spelled
    from all its parts, problem and keyword escape included."""
    made = st.StIdentifier.stem(*parts)(suffix)
    whole = st.StIdentifier(*parts, suffix)
    assert (made, made.problem, type(made)) == (whole, whole.problem, st.StIdentifier)


@pytest.mark.parametrize("suffix", ["RAW_MIN", "raw_min", "_ADDR"])
@pytest.mark.parametrize("parts", [("dev", "speed"), ("dev", "x" * 56), ("dev", "bad__name"), ("var",), ("dev", "")])
@pytest.mark.parametrize("taken_by", [None, "register speed", "register other"])
def test_a_stem_declares_each_name_as_the_scope_adds_it(parts: tuple[str, ...], suffix: str, taken_by: str | None) -> None:
    """`Stem.declared_in` (a register's constants) gives the name `Scope.add` gives and reports what it reports: the
    name's own problem, and a name another item declared first (the same item declaring it again is no collision)."""
    device = load_map(MAPS[0])
    results = []
    for declare in ("stem", "scope"):
        problems: list[Any] = []
        scope = Scope(device, "a global name", problems)
        if taken_by is not None:
            scope.add(st.StIdentifier(*parts, suffix), taken_by)
        stem = st.StIdentifier.stem(*parts)
        made = stem.declared_in(scope, "register speed", None)(suffix) if declare == "stem" else scope.add(stem(suffix), "register speed")
        results.append((made, made.problem, type(made), problems, scope.seen))
    assert results[0] == results[1]


def test_a_name_two_map_items_generate_is_refused_naming_both() -> None:
    """A register named like a read block's constants (`block_0300` for the block at 0x0300) generates the block's
    `<DEV>_BLOCK_0300_ADDR` again: refused once, naming the block first and the register second."""
    data = _small_map()
    reg = data["groups"][0]["registers"][0]  # the first register starts the first read block
    reg["name"] = f"block_{reg['address']:04x}"
    problems = st.check(load_map_text(yaml.safe_dump(data, allow_unicode=True, sort_keys=False), "small.yaml"))
    assert len(problems) == 1, problems
    assert (
        f"_BLOCK_{reg['address']:04X}_ADDR (a global name) is used by both read block 0 at holding 0x{reg['address']:04X} and register {reg['name']}"
        in problems[0].message
    )


def test_validate_reports_st_name_problems_at_their_line(tmp_path: Path) -> None:
    """Names ST cannot take (two underscores, names differing only by case in one scope) are found by
    `regmap validate` and refused by `generate`, at file:line:col."""
    data = _small_map()
    enum = next(iter(data["enums"].values()))
    enum["values"][0]["name"] = "bad__name"
    text = yaml.safe_dump(data, allow_unicode=True, sort_keys=False)
    device = load_map_text(text, "small.yaml")
    problems = st.check(device)
    assert problems and all(p.file == "small.yaml" and p.line > 1 for p in problems), problems
    assert "two underscores" in problems[0].message
    path = tmp_path / "small.yaml"
    path.write_text(text, encoding="utf-8")
    result = subprocess.run([sys.executable, "-m", "regmap", "validate", str(path)], cwd=ROOT, capture_output=True, text=True, check=False)
    assert result.returncode == 1 and "two underscores" in result.stdout + result.stderr, result.stdout + result.stderr


@pytest.mark.parametrize("map_path", ALL_MAPS, ids=lambda p: p.stem)
def test_a_decoder_says_it_refuses_infinity_and_nan_where_it_does(map_path: Path) -> None:
    """A block decoder refuses infinity and NaN where its floats are rebuilt with exact arithmetic (plain IEC and the
    PLCopen XML, and a half in every dialect); CODESYS reads a single or a double through a UNION and keeps them.
    The dialects share one set of views (DeviceViews), so each must still print its own decoders."""
    device = load_map(map_path)
    views = DeviceViews(device, [])
    for dialect in (CODESYS, IEC, PLCOPEN):
        context = views.context(dialect)
        printed = {f.name: f for f in context["functions"]}
        for block in context["plan"]:
            refuses = any(r.type is DataType.F16 or (r.type.is_float and not dialect.unions) for r in block.registers)
            comment = printed[block.decode.name].comment
            assert ("infinity or NaN" in comment) == refuses, (dialect.name, block.decode.name, comment)


@pytest.mark.parametrize("map_path", ALL_MAPS, ids=lambda p: p.stem)
def test_each_dialect_gets_from_the_shared_views_what_it_makes_alone(map_path: Path) -> None:
    """One DeviceViews serves CODESYS, then plain IEC, then the PLCopen XML, each taking what an earlier one made
    where its notation changes nothing: every view of each equals the one that dialect makes on its own."""
    device = load_map(map_path)
    shared = DeviceViews(device, [])
    for dialect in (CODESYS, IEC, PLCOPEN):
        together = {k: v for k, v in shared.context(dialect).items() if k != "names"}
        alone = {k: v for k, v in DeviceViews(device, []).context(dialect).items() if k != "names"}
        assert together.keys() == alone.keys()
        for key in alone:
            assert together[key] == alone[key], (dialect.name, key)


@pytest.mark.parametrize("map_path", ALL_MAPS, ids=lambda p: p.stem)
def test_the_constants_text_is_each_sections_text_in_each_notation(map_path: Path) -> None:
    """The constants files print the register, array, bitfield and command sections from one text made for every
    notation (`SpelledText`): in each dialect it is what those sections, spelled in its notation, print one by one."""
    views = DeviceViews(load_map(map_path), [])
    for dialect in (CODESYS, IEC):
        context = views.context(dialect)
        one_by_one = "".join(
            s.spelled(dialect.notation).text if isinstance(s, SectionToSpell) else s.text for s in context["const_sections"]
        )
        assert context["const_text"] == one_by_one, dialect.name


def test_the_plcopen_variable_lists_cache_is_bounded() -> None:
    """The PLCopen XML's parameter lists are made once per list of members, in a cache no bigger than the text caches."""
    from regmap.backends.st.plcopen import _variables
    from regmap.render import TEXT_CACHE_SIZE

    assert _variables.cache_info().maxsize == TEXT_CACHE_SIZE
