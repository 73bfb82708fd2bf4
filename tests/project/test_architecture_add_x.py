"""docs/architecture.md's "To add X, touch these files" table is what the code needs: in a scratch copy of
the package, a throwaway back end, register type and subcommand are each added by touching the files their
row names, and work; the files touched are exactly the files the row names (its tests aside: this is one)."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

from conftest import ROOT
from support.trees import tree

ARCHITECTURE = ROOT / "docs" / "architecture.md"
COPIED = ("generator/regmap", "generator/regmap_runtime", "pyproject.toml", "README.md", "docs")
ROOT_FILES = ("pyproject.toml", "README.md", "docs/", "tests/")  # table paths outside the package
PLACEHOLDERS = {"<target>": "beep", "<name>": "tally"}


def table_row(what: str) -> list[str]:
    """The files (and folders, ending in /) a row of the table names, as paths from the repository root."""
    text = ARCHITECTURE.read_text(encoding="utf-8")
    section = text[text.index("## To add X, touch these files") :]
    row = next(line for line in section.splitlines() if line.startswith(f"| {what} |"))
    paths = []
    for token in re.findall(r"`([^`]+)`", row.split("|")[2]):
        if not re.fullmatch(r"[\w./<>-]+", token) or not ("/" in token or re.search(r"\.(py|toml|md|json|jinja)$", token)):
            continue  # a name (`SUBCOMMANDS`, `Target.options`), not a file
        for placeholder, name in PLACEHOLDERS.items():
            token = token.replace(placeholder, name)
        if token.startswith(ROOT_FILES):
            paths.append(token)
        elif token.startswith("regmap_runtime/"):
            paths.append("generator/" + token)
        else:
            paths.append("generator/regmap/" + token)
    return [p for p in paths if not p.startswith("tests/")]  # the row's tests: this test stands in for them


def touched_equals_row(before: dict[str, bytes], copy: Path, what: str) -> None:
    after = tree(copy)
    touched = {name for name in set(before) | set(after) if before.get(name) != after.get(name)}
    touched -= {name for name in touched if name.startswith("generator/regmap.egg-info/")}  # written by the install step
    listed = table_row(what)
    covered = {name for name in touched if any(name == p or (p.endswith("/") and name.startswith(p)) for p in listed)}
    untouched = [p for p in listed if not any(name == p or (p.endswith("/") and name.startswith(p)) for name in touched)]
    assert sorted(touched - covered) == [], f"touched, but not in the row {what!r}"
    assert untouched == [], f"in the row {what!r}, but not needed"


@pytest.fixture
def copy(tmp_path: Path) -> Path:
    root = tmp_path / "copy"
    for name in COPIED:
        source, target = ROOT / name, root / name
        if source.is_dir():
            shutil.copytree(source, target, ignore=shutil.ignore_patterns("__pycache__"))
        else:
            target.parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(source, target)
    install(root)
    return root


def install(copy: Path) -> None:
    """What `pip install -e .` makes of pyproject.toml's entry points (the registry `regmap.targets` reads)."""
    project = tomllib.loads((copy / "pyproject.toml").read_text(encoding="utf-8"))["project"]
    info = copy / "generator" / "regmap.egg-info"
    info.mkdir(exist_ok=True)
    (info / "PKG-INFO").write_text(f"Metadata-Version: 2.1\nName: regmap\nVersion: {project['version']}\n", encoding="utf-8")
    groups = [
        f"[{group}]\n" + "".join(f"{name} = {value}\n" for name, value in points.items())
        for group, points in project["entry-points"].items()
    ]
    (info / "entry_points.txt").write_text("\n".join(groups), encoding="utf-8")


def regmap(copy: Path, *args: str) -> subprocess.CompletedProcess[str]:
    env = {**os.environ, "PYTHONPATH": str(copy / "generator"), "PYTHONDONTWRITEBYTECODE": "1"}
    return subprocess.run([sys.executable, *args], cwd=copy, env=env, capture_output=True, text=True, check=False, timeout=60)


def edit(path: Path, old: str, new: str, count: int = 1) -> None:
    text = path.read_text(encoding="utf-8")
    assert text.count(old) == count, f"{path}: {old!r} is there {text.count(old)} times"
    path.write_text(text.replace(old, new), encoding="utf-8")


def write(path: Path, text: str) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text, encoding="utf-8")


# -- the three throwaway additions ------------------------------------------------------------


def add_back_end(copy: Path) -> None:
    folder = copy / "generator" / "regmap" / "backends" / "beep"
    write(
        folder / "__init__.py",
        '"""A throwaway back end: one line per register."""\n\n'
        "from __future__ import annotations\n\n"
        "from regmap.diagnostics import Diagnostic\n"
        "from regmap.model import Device\n"
        "from regmap.render import templates\n"
        "from regmap.target import Files, ReservedWords, Target\n\n\n"
        "def render_device(device: Device) -> Files:\n"
        '    rows = [(r.name, f"0x{r.address:04X}") for r in device.registers]\n'
        '    return {f"{device.id}.txt": templates(__name__).get_template("beep.txt.jinja").render(rows=rows)}\n\n\n'
        "def check(device: Device) -> list[Diagnostic]:\n"
        "    return []\n\n\n"
        'TARGET = Target("beep", "beep", render_device, lambda devices: {}, check=check, order=70, '
        'reserved_words=ReservedWords("a beep word", frozenset({"beep"})))\n',
    )
    write(folder / "templates" / "beep.txt.jinja", "{% for name, address in rows %}\n{{ address }} {{ name }}\n{% endfor %}\n")
    edit(
        copy / "pyproject.toml",
        'st = "regmap.backends.st:TARGET"\n',
        'st = "regmap.backends.st:TARGET"\nbeep = "regmap.backends.beep:TARGET"\n',
    )


def add_register_type(copy: Path) -> None:
    # A second name for the half float (f16 is a real type): the same codec, its own row everywhere.
    runtime = copy / "generator" / "regmap_runtime" / "types.py"
    edit(
        runtime,
        '        TypeInfo("f64",',
        '        TypeInfo("half", words=1, signed=True, kind=FLOAT, codec="e"),\n        TypeInfo("f64",',
    )
    edit(copy / "generator" / "regmap" / "kinds.py", '    F64 = "f64"\n', '    F64 = "f64"\n    HALF = "half"\n')
    schema = copy / "generator" / "regmap" / "schema" / "map.schema.json"
    text = schema.read_text(encoding="utf-8")
    schema.write_text(re.sub(r'^( *)"f64",\n', r'\1"f64",\n\1"half",\n', text, flags=re.M), encoding="utf-8")
    assert schema.read_text(encoding="utf-8").count('"half"') == text.count('"f64"')
    edit(copy / "docs" / "map-format.md", "| `f64` | 4 |", "| `half` | 1 | IEEE 754 half precision | `1.5` |\n| `f64` | 4 |")


def add_subcommand(copy: Path) -> None:
    package = copy / "generator" / "regmap"
    write(
        package / "tools" / "tally.py",
        '"""A throwaway field tool: how many registers a map has in each space (returns them, prints nothing)."""\n\n'
        "from __future__ import annotations\n\n"
        "from collections import Counter\n\n"
        "from regmap.model import Device\n\n\n"
        "def tally(device: Device) -> dict[str, int]:\n"
        "    return dict(sorted(Counter(r.space for r in device.registers).items()))\n",
    )
    write(
        package / "cli" / "tally.py",
        '"""`regmap tally`: the registers of a map, counted by space."""\n\n'
        "from __future__ import annotations\n\n"
        "import argparse\n\n"
        "from regmap.cli.common import add_map, examples, load_map\n"
        "from regmap.diagnostics import ExitCode\n\n\n"
        "def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> argparse.ArgumentParser:\n"
        '    p = sub.add_parser("tally", help="count registers", epilog=examples("regmap tally maps/idm_rs.yaml"),\n'
        "                       formatter_class=argparse.RawDescriptionHelpFormatter)\n"
        "    add_map(p)\n"
        "    return p\n\n\n"
        "def run(args: argparse.Namespace) -> int:\n"
        "    from regmap.tools.tally import tally\n\n"
        "    for space, count in tally(load_map(args.map)).items():\n"
        '        print(f"{space}: {count}")\n'
        "    return ExitCode.OK\n",
    )
    edit(package / "cli" / "__init__.py", '    "probe",\n)', '    "probe",\n    "tally",\n)')
    edit(
        copy / "README.md",
        "## Checking a drive against its map\n",
        "## Counting registers\n\n`regmap tally MAP` counts a map's registers by space.\n\n## Checking a drive against its map\n",
    )


# -- each works, and touched what its row names ---------------------------------------------


def test_a_back_end_is_its_folder_and_one_entry_point(copy: Path, tmp_path: Path) -> None:
    before = tree(copy)
    add_back_end(copy)
    install(copy)
    out = tmp_path / "out"
    result = regmap(copy, "-m", "regmap", "generate", "--target", "beep", "--out", str(out), str(ROOT / "maps" / "idm_rs.yaml"))
    assert result.returncode == 0, result.stderr
    assert "0x0191 peak_current" in (out / "beep" / "idm_rs.txt").read_text(encoding="utf-8").splitlines()
    touched_equals_row(before, copy, "a back end")


def test_a_register_type_loads_from_a_map_and_encodes(copy: Path) -> None:
    before = tree(copy)
    add_register_type(copy)
    program = (
        "from regmap.frontend import load_map_text\n"
        "from regmap.runtime_bridge import runtime_specs\n"
        "from regmap_runtime.codec import raw_to_words, value_to_raw, words_to_raw\n"
        "device = load_map_text(open('m.yaml').read(), 'm.yaml')\n"
        "spec = next(s for s in runtime_specs(device) if s.name == 'level')\n"
        "raw = value_to_raw(spec, 1.5)\n"
        "print(device.register('level').type.value, raw_to_words(spec, raw), words_to_raw(spec, [0x3E00]))\n"
    )
    (copy / "m.yaml").write_text(
        "format: regmap/1\n"
        "device: {id: m, vendor: v, model: m, manual: {title: t, file: f}, map_version: 0.1.0}\n"
        "transport:\n  serial: {baud: 9600, parity: none, data_bits: 8, stop_bits: 1}\n  slave_ids: {min: 1, max: 247}\n"
        "  function_codes: [0x03, 0x06, 0x10]\n  max_read_registers: 125\n  max_write_registers: 123\n  word_order: high_first\n"
        "groups:\n  - id: g\n    title: G\n    source: '1'\n    registers:\n"
        "      - {name: level, address: 0x0010, type: half, title: Level}\n",
        encoding="utf-8",
    )
    result = regmap(copy, "-c", program)
    (copy / "m.yaml").unlink()
    assert result.returncode == 0, result.stderr
    assert result.stdout.split() == ["half", "[15872]", "1.5"]  # IEEE 754 half: 1.5 is 0x3E00
    touched_equals_row(before, copy, "a data type")


def test_a_subcommand_is_its_module_and_its_name(copy: Path) -> None:
    before = tree(copy)
    add_subcommand(copy)
    result = regmap(copy, "-m", "regmap", "tally", str(ROOT / "maps" / "idm_rs.yaml"))
    assert result.returncode == 0, result.stderr
    assert result.stdout.startswith("holding: ")
    assert "examples:" in regmap(copy, "-m", "regmap", "tally", "--help").stdout
    touched_equals_row(before, copy, "a subcommand")
