"""regmap.entrypoints reads a group's entry points as importlib.metadata.entry_points(group=...) does (the same
points, in the same order, the first distribution of a name winning), and leaves the layouts it does not read
(a zip on sys.path, a malformed line) to importlib.metadata."""

from __future__ import annotations

import importlib.metadata
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

from regmap import entrypoints

GROUP = "regmap.targets"


def _standard(group: str) -> list[tuple[str, str, str]]:
    return [(point.name, point.value, point.group) for point in importlib.metadata.entry_points(group=group)]


def _ours(group: str) -> list[tuple[str, str, str]]:
    found = entrypoints.read(group)
    assert found is not None
    return [(point.name, point.value, point.group) for point in found]


def _info(root: Path, folder: str, text: str | None) -> None:
    (root / folder).mkdir(parents=True)
    (root / folder / "METADATA").write_text(f"Metadata-Version: 2.1\nName: {folder.split('-')[0]}\nVersion: 1\n", encoding="utf-8")
    if text is not None:
        (root / folder / "entry_points.txt").write_text(text, encoding="utf-8")


@pytest.mark.parametrize("group", [GROUP, "console_scripts", "pytest11"])
def test_the_installed_groups_read_as_importlib_metadata_reads_them(group: str) -> None:
    assert _ours(group) == _standard(group)


def test_the_first_distribution_of_a_name_wins(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    first, second = tmp_path / "first", tmp_path / "second"
    _info(first, "Regmap_Extra-1.0.dist-info", "# a comment\nstray = line.before:sections\n[regmap.targets]\nbeep = extra.beep:TARGET\n")
    _info(first, "quiet-2.0.egg-info", None)  # no entry_points.txt: no points
    _info(first, "other.pkg-3.dist-info", "[console_scripts]\nx = y:z\n\n[regmap.targets]\n  buzz =  extra.buzz : TARGET  \n")
    _info(second, "regmap.extra-9.9.dist-info", "[regmap.targets]\nshadowed = never:LOADED\n")  # the same name, later on the path
    _info(second, "late-1.egg-info", "[regmap.targets]\nlate = late:TARGET\n")
    monkeypatch.setattr(sys, "path", [str(first), str(tmp_path / "missing"), str(second), *sys.path])
    ours = _ours(GROUP)
    assert ours == _standard(GROUP)
    assert {"beep", "buzz", "late"} <= {name for name, _, _ in ours} and "shadowed" not in {name for name, _, _ in ours}


def test_a_point_loads_what_it_names(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    _info(tmp_path, "probe-1.dist-info", "[regmap.probe]\nspaces = os.path :  join  \nmodule = os.path\n")
    monkeypatch.setattr(sys, "path", [str(tmp_path), *sys.path])
    found = entrypoints.read("regmap.probe")
    assert found is not None
    assert [point.load() for point in found] == [point.load() for point in importlib.metadata.entry_points(group="regmap.probe")]


def test_a_zip_on_the_path_is_left_to_importlib_metadata(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    archive = tmp_path / "plugins.zip"
    with zipfile.ZipFile(archive, "w") as zipped:
        zipped.writestr("zipped-1.dist-info/METADATA", "Metadata-Version: 2.1\nName: zipped\nVersion: 1\n")
        zipped.writestr("zipped-1.dist-info/entry_points.txt", "[regmap.targets]\nzipped = zipped:TARGET\n")
    monkeypatch.setattr(sys, "path", [str(archive), *sys.path])
    assert entrypoints.read(GROUP) is None
    assert ("zipped", "zipped:TARGET", GROUP) in _standard(GROUP)


def test_a_line_without_equals_is_left_to_importlib_metadata(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    _info(tmp_path, "broken-1.dist-info", "[console_scripts]\nno equals sign\n")
    monkeypatch.setattr(sys, "path", [str(tmp_path), *sys.path])
    assert entrypoints.read(GROUP) is None
    with pytest.raises(TypeError):  # what importlib.metadata makes of it, and so what `regmap generate` reports
        _standard(GROUP)


def test_the_targets_are_found_without_importing_importlib_metadata() -> None:
    """What the reader is for: importlib.metadata (and the email package it brings) stays unimported."""
    code = "import sys, regmap.generate as g; print(g.target_names(), 'importlib.metadata' in sys.modules)"
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, timeout=60)
    assert run.stdout.split() == ["['python',", "'c',", "'markdown',", "'st',", "'esphome',", "'homeassistant']", "False"]
