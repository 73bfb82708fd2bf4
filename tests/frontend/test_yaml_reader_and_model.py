"""Unit tests of the front end: the positional YAML reader and the model `load_map` builds.

The error texts of whole invalid maps are golden files (tests/frontend/test_invalid_maps.py); these tests pin the
pieces underneath: positions, the safety bounds of the reader, encodings, and the elaborated model.
"""

from __future__ import annotations

import json
from fractions import Fraction
from pathlib import Path

import pytest

from regmap.cli import main
from regmap.core.contract import export_json
from regmap.diagnostics import Diagnostic, MapError
from regmap.frontend import load_map, load_map_text
from regmap.frontend.crossrefs import check_references
from regmap.frontend.elaborate import elaborate
from regmap.frontend.load import MAX_MAP_BYTES, load_map_bytes, read_source
from regmap.frontend.stages import MapSource
from regmap.frontend.yamlsource import MAX_DEPTH, MAX_INT_CHARS, MAX_NODES, YamlProblem, read_yaml
from regmap.model import Access, DataType, Device, WordOrder

from conftest import ROOT

SMALL = ROOT / "tests" / "maps" / "small" / "idm_rs_small.yaml"
INVALID = ROOT / "tests" / "maps" / "invalid"


@pytest.fixture(scope="module")
def small() -> Device:
    return load_map(SMALL)


def small_text() -> str:
    return SMALL.read_text(encoding="utf-8")


def problems_of(text: str) -> list[Diagnostic]:
    with pytest.raises(MapError) as info:
        load_map_text(text, "m.yaml")
    return info.value.diagnostics


def yaml_problem(text: str) -> YamlProblem:
    with pytest.raises(YamlProblem) as info:
        read_yaml(text)
    return info.value


# -- positions -------------------------------------------------------------------------------------


def test_positions_of_values_and_keys() -> None:
    data, pos = read_yaml("a:\n  b: 1\n  c: [x, {d: 2}]\n")
    assert data == {"a": {"b": 1, "c": ["x", {"d": 2}]}}
    assert pos.locate(("a", "b")) == (2, 6)  # a scalar: the value itself
    assert pos.locate(("a", "c")) == (3, 6)  # a flow list on the key's line: the `[`
    assert pos.locate(("a", "c", 0)) == (3, 7)
    assert pos.locate(("a", "c", 1, "d")) == (3, 14)
    assert pos.keys[("a", "c", 1, "d")] == (3, 11)
    assert pos.locate_key(("a", "c", 1, "d")) == (3, 11)


def test_a_block_collection_is_located_at_its_key() -> None:
    # The mapping under `a` starts at `b` on line 2; a problem with `a` as a whole belongs on line 1.
    _, pos = read_yaml("# comment\na:\n  b: 1\n")
    assert pos.locate(("a",)) == (2, 1)
    assert pos.locate(()) == (2, 1)


def test_locate_falls_back_to_the_closest_ancestor() -> None:
    _, pos = read_yaml("a:\n  - {b: 1}\n")
    assert pos.locate(("a", 0, "missing", 3)) == (2, 5)
    assert pos.locate_key(("a", 0, "missing")) == (2, 5)


def test_diagnostics_print_as_file_line_col_message() -> None:
    assert str(Diagnostic("maps/x.yaml", 3, 7, "wrong")) == "maps/x.yaml:3:7: wrong"


# -- duplicate keys ---------------------------------------------------------------------------------


def test_duplicate_key_is_an_error_naming_the_first() -> None:
    problem = yaml_problem("a: 1\nb:\n  c: 1\n  c: 2\n")
    assert (problem.line, problem.column) == (4, 3)
    assert problem.message == "duplicate key 'c' (first defined on line 3)"


def test_duplicate_top_level_block_key_names_the_key_line() -> None:
    # The first `device` value starts on line 2; the key that repeats is on line 1.
    problem = yaml_problem("device:\n  id: x\ndevice:\n  id: y\n")
    assert (problem.line, problem.message) == (3, "duplicate key 'device' (first defined on line 1)")


def test_same_key_in_different_mappings_is_fine() -> None:
    data, _ = read_yaml("a: {x: 1}\nb: {x: 2}\n")
    assert data == {"a": {"x": 1}, "b": {"x": 2}}


# -- bounds: aliases, depth, size ---------------------------------------------------------------------


def test_plain_aliases_are_expanded() -> None:
    data, _ = read_yaml("a: &x {b: 1}\nc: *x\n")
    assert data == {"a": {"b": 1}, "c": {"b": 1}}


def test_alias_bomb_is_bounded() -> None:
    lines = ['l0: &a0 ["lol", "lol", "lol", "lol", "lol", "lol", "lol", "lol", "lol"]']
    lines += [f"l{i}: &a{i} [" + ", ".join([f"*a{i - 1}"] * 9) + "]" for i in range(1, 9)]
    problem = yaml_problem("\n".join(lines) + "\n")
    assert f"more than {MAX_NODES} values" in problem.message


def test_a_big_document_without_aliases_is_not_an_alias_bomb() -> None:
    """The bound counts values aliases add; a table of 20,000 registers has more values than that of its own."""
    rows = MAX_NODES // 4 + 1
    text = "r:\n" + "".join(f"  - {{a: {i}, b: x, c: y}}\n" for i in range(rows))
    data, positions = read_yaml(text)
    assert len(data["r"]) == rows and positions.locate(("r", rows - 1, "c")) == (rows + 1, 20 + len(str(rows - 1)))
    assert _checked_reading(text)[0] == data  # the checked reader, which reads any document the fast one does not, too


# Documents the fast reader (libyaml's events) must read exactly as the checked reader (a node tree) does, down to the
# order positions are recorded in: aliases of scalars and collections, nested anchors, block and flow styles, tags.
AGREEING_DOCUMENTS = [
    "a: &x [1, {b: c}]\nd: *x\ne: !!str 5\n",
    "a: &s hello\nb: *s\nc: [*s, *s]\n",
    "a: &m\n  x: 1\n  y: &n [1, 2]\nb: *m\nc:\n  - *n\n  - *m\nd: {e: *n}\n",
    "a:\n  &q {x: 1}\nb:\n  *q\nc: [*q]\n",
    "k: !!map {a: 1}\nl: !!seq [1]\nm: !!int '7'\nn: !!float 1\no: ! x\n",
    "- 1\n- [2, 3]\n- {a: b}\n- ~\n- true\n- 0x10\n- 1.5\n- ''\n- 'yes'\n- no\n",
    "x: |\n  block\n  text\ny: >\n  folded\n",
    "a:\n- x: 1\n  y: 2\n- &z\n  p: q\nb: *z\n",
    # integers in every spelling: the decimal and hexadecimal ones are read without a node, the others with one
    "- 0\n- -0\n- +5\n- -17\n- 0x1F\n- -0x1f\n- +0xFF\n- 0X1F\n- 0b11\n- 1_000\n- 0x1_0\n- !!int '0x2A'\n- !!int '-3'\n",
]


def _checked_reading(text: str) -> tuple[object, list[object], list[object]]:
    from regmap.frontend import yamlsource

    positions = yamlsource.Positions()
    data = yamlsource._Builder(positions).build(yamlsource._compose_checked(text), ())
    return data, list(positions.by_path.items()), list(positions.keys.items())


@pytest.mark.parametrize(
    "text", [*AGREEING_DOCUMENTS, SMALL.read_text(encoding="utf-8"), (ROOT / "maps" / "idm_rs.yaml").read_text("utf-8")]
)
def test_the_fast_reader_reads_as_the_checked_reader(text: str) -> None:
    from regmap.frontend import yamlsource

    fast = yamlsource._read_fast(text)
    assert fast is not None
    assert (fast[0], list(fast[1].by_path.items()), list(fast[1].keys.items())) == _checked_reading(text)


@pytest.mark.parametrize(
    "text",
    [
        "a: &a [1]\nb: &a [2]\n",
        "a: &r [*r]\n",
        "<<: {a: 1}\n",
        "a: 1\na: 2\n",
        "? [a]\n: 1\n",
        "*u : 1\n",
        "a: 012\n",
        "a: !!int '0X1F'\n",
        "a: .nan\n",
        "a: 2001-01-01\n",
        "a: 1\n---\nb: 2\n",
        "",
        "a: !!python/name:os.system x\n",
        "a: [" * (MAX_DEPTH + 1),
    ],
)
def test_the_fast_reader_leaves_every_problem_to_the_checked_reader(text: str) -> None:
    from regmap.frontend import yamlsource

    assert yamlsource._read_fast(text) is None
    with pytest.raises(YamlProblem):
        read_yaml(text)


def test_recursive_alias_is_refused() -> None:
    problem = yaml_problem("a: &n [*n]\n")
    assert "recursive" in problem.message


@pytest.mark.parametrize("depth", [MAX_DEPTH + 1, 5000])
def test_nesting_is_bounded(depth: int) -> None:
    # Past the builder's bound, and far past Python's recursion limit (PyYAML composes recursively).
    problem = yaml_problem("a: " + "[" * depth + "]" * depth + "\n")
    assert f"more than {MAX_DEPTH} levels" in problem.message


def test_nesting_within_the_bound_is_fine() -> None:
    data, _ = read_yaml("a: " + "[" * (MAX_DEPTH - 1) + "]" * (MAX_DEPTH - 1) + "\n")
    assert isinstance(data["a"], list)


def test_oversized_map_is_refused_before_parsing() -> None:
    with pytest.raises(MapError) as info:
        load_map_bytes(b" " * (MAX_MAP_BYTES + 1), "big.yaml")
    assert "larger than" in info.value.diagnostics[0].message and "is refused" in info.value.diagnostics[0].message


def test_unreadable_map_is_a_diagnostic(tmp_path: Path) -> None:
    with pytest.raises(MapError) as info:
        load_map(tmp_path / "absent.yaml")
    assert info.value.diagnostics[0].message.startswith("cannot read the map")


# -- encodings ------------------------------------------------------------------------------------------


def test_utf8_text_is_kept_verbatim(small: Device) -> None:
    assert small.info.vendor_zh == "雷赛"
    assert small.register("peak_current").title_zh == "峰值电流"
    assert small.enum("di_function").title_zh == "输入端子功能"


def test_utf8_bom_is_accepted_and_positions_do_not_move() -> None:
    bom = b"\xef\xbb\xbf"
    device = load_map_bytes(bom + SMALL.read_bytes(), "small.yaml")
    assert device.register("peak_current").address == 0x0191
    case = (INVALID / "min_greater_than_max.yaml").read_bytes()
    with pytest.raises(MapError) as plain:
        load_map_bytes(case, "x.yaml")
    with pytest.raises(MapError) as with_bom:
        load_map_bytes(bom + case, "x.yaml")
    assert with_bom.value.diagnostics == plain.value.diagnostics


def test_non_utf8_bytes_are_located() -> None:
    with pytest.raises(MapError) as info:
        load_map_bytes(b"format: regmap/1\ntitle: " + "峰值".encode("gbk") + b"\n", "x.yaml")
    assert info.value.diagnostics == [Diagnostic("x.yaml", 2, 8, "the map is not valid UTF-8 (byte 0xB7); save it as UTF-8")]


def test_control_characters_are_located() -> None:
    problem = yaml_problem("a: 1\nb: x\x00y\n")
    assert (problem.line, problem.column) == (2, 5)
    assert "U+0000" in problem.message


# -- numbers ----------------------------------------------------------------------------------------------


def test_integer_length_is_bounded() -> None:
    data, _ = read_yaml("a: " + "9" * MAX_INT_CHARS + "\n")
    assert data["a"] == int("9" * MAX_INT_CHARS)
    # Past the bound: refused while reading (Python itself refuses int() of over 4300 digits).
    for digits in (MAX_INT_CHARS + 1, 5000):
        assert "too large" in yaml_problem("a: " + "9" * digits + "\n").message


@pytest.mark.parametrize("text", ["1.0e+400", "-1.0e+400", ".inf", "-.Inf", ".nan"])
def test_non_finite_numbers_are_refused(text: str) -> None:
    assert "not finite" in yaml_problem(f"a: {text}\n").message


def test_huge_integers_reach_the_checks_without_crashing() -> None:
    text = small_text().replace("{value: 1, name: negative,", f"{{value: {10**30}, name: negative,")
    messages = [d.message for d in problems_of(text)]
    assert messages == [f"motor_direction: enum direction member negative = {10**30} does not fit u16"]


def test_ambiguous_integers_are_refused_with_their_reading() -> None:
    assert yaml_problem("param: 0302\n").message == "ambiguous integer '0302': YAML 1.1 reads it as 194 (octal); quote it if it is text"
    assert "90 (base 60)" in yaml_problem("t: 1:30\n").message
    data, _ = read_yaml("a: '0302'\nb: 0x0302\nc: 302\nd: !!str 0302\n")
    assert data == {"a": "0302", "b": 0x0302, "c": 302, "d": "0302"}


# -- tags ---------------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "value",
    [
        '!!python/object/apply:os.system ["true"]',
        "!!python/object:collections.OrderedDict {}",
        '!!python/name:os.system ""',
        "!!python/tuple [1, 2]",
        "!!binary aGVsbG8=",
        "!!set {a, b}",
        "!local text",
    ],
)
def test_unsafe_or_unknown_tags_are_refused(value: str) -> None:
    assert "unsupported YAML tag" in yaml_problem(f"a: {value}\n").message


def test_plain_tags_are_read() -> None:
    data, _ = read_yaml("a: !!str 12\nb: !!int '12'\nc: !!float '1.5'\nd: !!bool 'true'\ne: !!null ''\n")
    assert data == {"a": "12", "b": 12, "c": 1.5, "d": True, "e": None}


@pytest.mark.parametrize("value", ["!!int abc", "!!float x", "!!bool maybe"])
def test_a_plain_tag_on_unreadable_text_is_a_problem(value: str) -> None:
    assert "is not a valid YAML" in yaml_problem(f"a: {value}\n").message


def test_dates_and_non_text_keys_say_quote_it() -> None:
    assert "quote it" in yaml_problem("a: 2021-03-05\n").message
    assert yaml_problem("on: 1\n").message == "mapping key 'on' is read as the boolean true; quote it to make it text"


def test_merge_keys_are_refused() -> None:
    assert "merge keys" in yaml_problem("a: &x {b: 1}\nc: {<<: *x}\n").message


# -- the model from the small map -----------------------------------------------------------------------------


def test_arrays_are_expanded_with_params_from_the_rule(small: Device) -> None:
    (array,) = small.arrays
    assert (array.name, array.count, array.base, array.stride) == ("pr_path", 16, 0x6200, 8)
    elements = [r for r in small.registers if r.array is not None]
    assert len(elements) == 16 * len(array.members)
    mode_0, position_0, mode_1 = small.register("pr_path_0_mode"), small.register("pr_path_0_position"), small.register("pr_path_1_mode")
    assert (mode_0.address, mode_0.param) == (0x6200, "Pr9.00")
    assert (position_0.address, position_0.param, position_0.type, position_0.words) == (0x6201, "Pr9.01", DataType.S32, 2)
    assert (mode_1.address, mode_1.param) == (0x6208, "Pr9.08")
    assert small.register("pr_path_12_position").param == "Pr9.97"
    # 0x6264 is Pr9.100, which the rule's two-digit regex cannot name: no param rather than a wrong one.
    assert small.register("pr_path_12_acceleration").param is None
    speed = small.register("pr_path_7_speed")
    assert (speed.type, speed.min, speed.max, speed.default, speed.unit) == (DataType.S16, -6000, 6000, 60, "rpm")
    assert speed.source == ("附录4",) and speed.group == "pr"


def test_enums_are_resolved(small: Device) -> None:
    direction = small.register("motor_direction").enum
    assert direction is not None and direction is small.enum("direction")
    assert [(m.value, m.name) for m in direction.members] == [(0, "positive"), (1, "negative")]
    function = small.register("di2_function").bitfields[0]
    assert function.enum is not None and function.enum.name == "di_function"
    assert (function.lsb, function.msb, function.mask) == (0, 6, 0x7F)
    save = next(c for c in small.commands if c.name == "save_all_parameters")
    assert (save.register.name, save.value) == ("control_word", 0x2211)  # given as the member name


def test_group_defaults_and_paired_registers(small: Device) -> None:
    peak = small.register("peak_current")
    assert (peak.paired, peak.access, peak.type) == (True, Access.READ_WRITE, DataType.U16)
    assert (peak.address, peak.first_address, peak.last_address, peak.span) == (0x0191, 0x0190, 0x0191, 2)
    assert peak.scale == Fraction(1, 10)  # exact, not the binary float 0.1
    assert peak.param == "Pr5.00"
    status = small.register("run_status")
    assert (status.paired, status.first_address, status.access) == (False, 0x1003, Access.READ)
    assert small.covering(0x0190) is peak and small.at_address(0x0190) is None
    assert small.transport.word_order is WordOrder.HIGH_FIRST


def test_errata_are_attached_to_their_registers() -> None:
    erratum = (
        "errata:\n  - id: E1\n    title: Peak current default\n"
        '    readings: [{source: "5.3.1", says: "22"}, {source: "附录4", says: "20"}]\n'
        "    choice: '22'\n    reason: The chapter is newer.\n    registers: [Pr5.00, run_status]\n"
    )
    device = load_map_text(small_text().replace("errata: []\n", erratum), "small.yaml")
    assert device.register("peak_current").errata == ("E1",)  # named by its manual id
    assert device.register("run_status").errata == ("E1",)  # named by its name
    assert device.register("motor_direction").errata == ()
    assert device.errata[0].registers == ("peak_current", "run_status")


def test_loading_is_deterministic(small: Device) -> None:
    again = load_map(SMALL)
    assert again == small and again.fingerprint == small.fingerprint
    assert [r.address for r in small.registers] == sorted(r.address for r in small.registers)


def test_every_problem_is_reported_in_one_run() -> None:
    text = small_text().replace("max: 80, default: 22", "max: 8, default: 22").replace("D4 1B", "D4 1C")
    messages = [d.message for d in problems_of(text)]
    assert messages == [
        "peak_current: default 22 is outside min..max (0..8)",
        "example read_current_req: CRC D4 1C does not match the frame (expected D4 1B); fix the transcription or declare an erratum",
    ]


# -- the stages and their hand-over ------------------------------------------------------------------


PEAK_CURRENT_TOO_LOW = ("max: 80, default: 22", "max: 8, default: 22")  # an elaboration problem
EXAMPLE_CRC_WRONG = ("D4 1B", "D4 1C")  # a cross-reference problem


def source_of(text: str) -> MapSource:
    return read_source(text, "m.yaml", "0" * 16)


def test_the_stages_in_turn_build_what_load_map_text_builds() -> None:
    elaborated = elaborate(source_of(small_text()))
    assert elaborated.problems == ()
    assert check_references(elaborated) == load_map_text(small_text(), "m.yaml", fingerprint="0" * 16)


def test_elaboration_locates_every_register_it_builds() -> None:
    source = source_of(small_text())
    elaborated = elaborate(source)
    assert len(elaborated.registers) == len(elaborated.register_paths) > 0
    for register, path in zip(elaborated.registers, elaborated.register_paths, strict=True):
        assert register.pos == source.positions.locate(path)
    declared = [r.name for g in elaborated.groups for r in g.registers]
    assert declared == [r.name for r in elaborated.registers]  # in declaration order, not yet sorted by address


def test_elaboration_hands_its_problems_over_instead_of_raising() -> None:
    text = small_text().replace(*PEAK_CURRENT_TOO_LOW)
    elaborated = elaborate(source_of(text))
    line = next(n for n, row in enumerate(text.splitlines(), 1) if "name: peak_current" in row)
    assert [(d.line, d.message) for d in elaborated.problems] == [(line, "peak_current: default 22 is outside min..max (0..8)")]


def test_the_cross_reference_stage_refuses_a_map_whose_elaboration_found_problems() -> None:
    elaborated = elaborate(source_of(small_text().replace(*PEAK_CURRENT_TOO_LOW)))
    with pytest.raises(MapError) as info:
        check_references(elaborated)
    assert info.value.diagnostics == list(elaborated.problems)


def test_the_cross_reference_stage_adds_its_problems_to_the_elaborations() -> None:
    elaborated = elaborate(source_of(small_text().replace(*PEAK_CURRENT_TOO_LOW).replace(*EXAMPLE_CRC_WRONG)))
    with pytest.raises(MapError) as info:
        check_references(elaborated)
    found = info.value.diagnostics
    assert set(elaborated.problems) < set(found)
    assert [d.message for d in found if d not in elaborated.problems] == [
        "example read_current_req: CRC D4 1C does not match the frame (expected D4 1B); fix the transcription or declare an erratum"
    ]


def test_the_schema_stage_refuses_before_elaboration() -> None:
    with pytest.raises(MapError) as info:
        source_of(small_text().replace("  max_read_registers:", "  max_read_register:"))
    assert any("unknown key 'max_read_register'" in d.message for d in info.value.diagnostics)


# -- JSON export contract ------------------------------------------------------------------------------------


def test_export_contract_keys(small: Device) -> None:
    exported = export_json(small)
    assert {"device", "registers", "enums", "commands", "examples", "errata"} <= set(exported)
    required = {
        "name",
        "param",
        "address",
        "words",
        "type",
        "access",
        "unit",
        "scale",
        "min",
        "max",
        "default",
        "enum",
        "bitfields",
        "source",
    }
    for register in exported["registers"]:
        assert required <= set(register), register["name"]
        assert isinstance(register["address"], int)
    by_name = {r["name"]: r for r in exported["registers"]}
    assert len(by_name) == len(small.registers) == 119  # arrays expanded, one object per element
    assert by_name["pr_path_3_speed"]["param"] == "Pr9.27"
    assert by_name["peak_current"]["scale"] == 0.1
    assert by_name["motor_direction"]["enum"] == "direction"
    assert by_name["di2_function"]["bitfields"][0]["enum"] == "di_function"
    assert by_name["run_status"]["param"] is None
    json.dumps(exported)  # plain JSON all the way down


def test_export_command_prints_the_same_json(small: Device, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(ROOT)
    assert main(["export", str(SMALL.relative_to(ROOT))]) == 0
    printed = json.loads(capsys.readouterr().out)
    expected = json.loads(json.dumps(export_json(small)))
    printed["device"].pop("fingerprint", None)
    expected["device"].pop("fingerprint", None)
    assert printed["registers"] == expected["registers"] and printed["enums"] == expected["enums"]


@pytest.mark.parametrize("reader", ["fast", "checked"])
def test_reading_a_map_leaves_nothing_for_the_cyclic_collector(reader: str, monkeypatch: pytest.MonkeyPatch) -> None:
    """A generate run collects cycles rarely (cli/generate.py): the YAML constructor, whose parser state points back at
    it, must not keep every node it built alive until then."""
    import gc

    from regmap.frontend import yamlsource

    if reader == "checked":
        monkeypatch.setattr(yamlsource, "_FAST_PARSER", None)
    text = (ROOT / "maps" / "id243pro.yaml").read_text(encoding="utf-8")
    gc.collect()
    gc.disable()
    try:
        read_yaml(text)
        assert gc.collect() == 0
    finally:
        gc.enable()
