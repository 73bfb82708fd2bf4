"""The PLCopen XML project of each map (`st/<device>/plcopen/<device>.xml`): valid against the TC6 XML
v2.01 schema (../shared/tools/plcopen/tc6_xml_v201.xsd, validated with lxml in a tool venv of its own,
tests/st/validate_plcopen.py), and holding the same types, constants and functions as the CODESYS
files: names, variables, types, values and bodies (the float helpers' bodies are the plain-standard
ones, since TC6 XML has no UNION).

Without the schema (a clone outside the shared layout) or the venv the schema tests skip; CI=true fails.
"""

from __future__ import annotations

import json
import re
import subprocess
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from regmap.frontend import load_map
from regmap.generate import render
from regmap.render import xml_text

from conftest import FIXTURE_MAPS, MAPS, ROOT, SHARED, built_tool, skip_or_fail

VALIDATE = ROOT / "tests" / "st" / "validate_plcopen.py"
HOSTILE = ROOT / "tests" / "maps" / "hostile" / "hostile.yaml"
SCALED_FROM = ROOT / "tests" / "maps" / "scaled_from" / "inverter.yaml"  # scale factors (scale_from)
NS = {"p": "http://www.plcopen.org/xml/tc6_0201", "x": "http://www.w3.org/1999/xhtml"}
FLOAT_HELPER = re.compile(r"^F_[A-Z0-9_]+_F(?:32|64)_(?:FROM|TO)_BITS$")
FUNCTION = re.compile(r"^FUNCTION (\w+) : (\S+)\n(.*?)^END_FUNCTION$", re.M | re.S)
VARS = re.compile(r"^(VAR_INPUT|VAR_IN_OUT|VAR)\n(.*?)^END_VAR\n", re.M | re.S)
DECLARATION = re.compile(r"^    (\w+) : ([^;]+);", re.M)
CONST = re.compile(r"^    ([A-Z0-9_]+) : (\S+) := (.+?);(?: \(\*.*\*\))?$", re.M)
LISTS = {"VAR_INPUT": "inputVars", "VAR_IN_OUT": "inOutVars", "VAR": "localVars"}


@pytest.fixture(scope="module")
def out(tmp_path_factory: pytest.TempPathFactory) -> Path:
    root = tmp_path_factory.mktemp("st-plcopen")
    devices = [load_map(p, display_name=p.relative_to(ROOT).as_posix()) for p in [*MAPS, HOSTILE, *FIXTURE_MAPS, SCALED_FROM]]
    for rel, text in render(devices, ["st"])["st"].items():
        (root / rel).parent.mkdir(parents=True, exist_ok=True)
        (root / rel).write_text(text, encoding="utf-8")
    return root


@pytest.fixture(scope="session")
def schema() -> Path:
    path = SHARED / "tools" / "plcopen" / "tc6_xml_v201.xsd"
    if not path.is_file():
        skip_or_fail(f"{path} is absent: the TC6 schema is beside the repository only in the shared layout")
    return path


def _validate(schema: Path, files: list[Path]) -> list[str]:
    python = built_tool("plcopen")
    result = subprocess.run(
        [str(python), str(VALIDATE), str(schema), *map(str, files)], capture_output=True, text=True, timeout=300, check=False
    )
    assert result.returncode == 0, result.stderr
    problems: list[str] = json.loads(result.stdout)
    return problems


def test_every_project_validates_against_the_tc6_schema(schema: Path, out: Path) -> None:
    files = sorted(out.glob("*/plcopen/*.xml"))
    assert len(files) == len(MAPS) + len(FIXTURE_MAPS) + 2
    assert _validate(schema, files) == []


@pytest.mark.parametrize(
    ("old", "new"),
    [(' pouType="function"', ""), ("<returnType><BOOL/></returnType>", "<returnType><BOOLEAN/></returnType>"), ("</types>", "</type>")],
)
def test_a_broken_project_fails_the_schema(schema: Path, out: Path, tmp_path: Path, old: str, new: str) -> None:
    text = (out / "id243pro" / "plcopen" / "id243pro.xml").read_text(encoding="utf-8")
    assert old in text
    broken = tmp_path / "broken.xml"
    broken.write_text(text.replace(old, new, 1), encoding="utf-8")
    problems = _validate(schema, [broken])
    assert problems and str(broken) in problems[0], problems


def _type_text(element: ET.Element) -> str:
    """The ST spelling of a TC6 dataType element."""
    (child,) = list(element)
    tag = child.tag.split("}")[1]
    if tag == "derived":
        return child.attrib["name"]
    if tag == "string":
        return f"STRING({child.attrib['length']})" if "length" in child.attrib else "STRING"
    if tag == "array":
        dimension = child.find("p:dimension", NS)
        base = child.find("p:baseType", NS)
        assert dimension is not None and base is not None
        return f"ARRAY[{dimension.attrib['lower']}..{dimension.attrib['upper']}] OF {_type_text(base)}"
    return tag


def _st_functions(path: Path) -> dict[str, tuple[str, dict[str, list[tuple[str, str]]], str]]:
    """name -> (return type, {list: [(variable, type)]}, body) of every FUNCTION in an ST file."""
    out = {}
    for name, returns, text in FUNCTION.findall(path.read_text(encoding="utf-8")):
        lists = {LISTS[kind]: DECLARATION.findall(block) for kind, block in VARS.findall(text)}
        body = VARS.sub("", text)
        out[name] = (returns, lists, "\n".join(line.removeprefix("    ") for line in body.rstrip("\n").split("\n")))
    return out


@pytest.mark.parametrize("map_path", [*MAPS, *FIXTURE_MAPS, SCALED_FROM], ids=lambda p: p.stem)
def test_the_project_holds_what_the_codesys_files_hold(map_path: Path, out: Path) -> None:
    device_id = load_map(map_path).id
    root = ET.parse(out / device_id / "plcopen" / f"{device_id}.xml").getroot()
    codesys, iec = out / device_id / "codesys", out / device_id / "iec"
    types = (codesys / f"{device_id}_types.st").read_text(encoding="utf-8")
    expected_types = [t for t in re.findall(r"^TYPE (\w+) :$", types, re.M) if not t.startswith("U_")]
    assert [d.attrib["name"] for d in root.iterfind(".//p:dataType", NS)] == expected_types
    for data_type in root.iterfind(".//p:dataType", NS):
        name = data_type.attrib["name"]
        declared = types.split(f"TYPE {name} :\n", 1)[1].split("END_TYPE", 1)[0]
        struct = data_type.find("p:baseType/p:struct", NS)
        if struct is not None:
            members = [(v.attrib["name"], _type_text(v.find("p:type", NS))) for v in struct.iterfind("p:variable", NS)]  # type: ignore[arg-type]
            assert members == [(m, t) for m, t in DECLARATION.findall(declared)], name
            continue
        enum = data_type.find("p:baseType/p:enum", NS)
        assert enum is not None, name
        values = [(v.attrib["name"], v.attrib["value"]) for v in enum.iterfind("p:values/p:value", NS)]
        assert values == re.findall(r"^    (\w+) := (-?\d+)", declared, re.M), name
        base = enum.find("p:baseType", NS)
        assert base is not None and f") {_type_text(base)};" in declared, name
    functions = _st_functions(codesys / f"{device_id}_functions.st")
    plain = _st_functions(iec / f"{device_id}_functions.st")
    pous = root.findall(".//p:pou", NS)
    assert [p.attrib["name"] for p in pous] == list(functions)
    for pou in pous:
        name = pou.attrib["name"]
        returns, lists, body = plain[name] if FLOAT_HELPER.match(name) else functions[name]
        interface = pou.find("p:interface", NS)
        assert interface is not None
        return_type = interface.find("p:returnType", NS)
        assert return_type is not None and _type_text(return_type) == returns, name
        got = {
            v.tag.split("}")[1]: [(x.attrib["name"], _type_text(x.find("p:type", NS))) for x in v.iterfind("p:variable", NS)]  # type: ignore[arg-type]
            for v in interface
            if v.tag.split("}")[1] in LISTS.values()
        }
        assert got == lists, name
        text = pou.find("p:body/p:ST/x:p", NS)
        assert text is not None and text.text == body, name
    constants = dict((n, (t, v)) for n, t, v in CONST.findall((codesys / f"{device_id}_constants.st").read_text(encoding="utf-8")))
    found = {}
    for variable in root.iterfind(".//p:configuration/p:globalVars/p:variable", NS):
        value = variable.find("p:initialValue/p:simpleValue", NS)
        assert value is not None
        found[variable.attrib["name"]] = (_type_text(variable.find("p:type", NS)), value.attrib["value"])  # type: ignore[arg-type]
    assert found == constants


def test_xml_text_escapes_markup_once_and_control_characters_as_replacement() -> None:
    """Markup characters become entities, `&` first so that no entity is escaped again; a control character XML 1.0
    cannot carry becomes U+FFFD, while tabs and line breaks stay."""
    assert xml_text('a < b & "c" > d') == "a &lt; b &amp; &quot;c&quot; &gt; d"
    assert xml_text("x\x01y\t<\n\x1f") == "x\ufffdy\t&lt;\n\ufffd"
    assert xml_text("plain text") == "plain text"
    assert xml_text(None) == ""


def test_hostile_text_stays_text(out: Path) -> None:
    """Map text reaches the XML only as character data: no element inside any documentation, no comment broken."""
    path = out / "hostile_dev" / "plcopen" / "hostile_dev.xml"
    root = ET.parse(path).getroot()
    for doc in root.iter(f"{{{NS['x']}}}p"):
        assert list(doc) == [], ET.tostring(doc)[:200]
    comments = re.findall(r"<!--(.*?)-->", path.read_text(encoding="utf-8"), re.S)
    assert comments and all("--" not in c for c in comments)
