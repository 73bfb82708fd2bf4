"""The template cache (regmap/render.py `TemplateCache`): compiled templates kept on disk, used only by the same
regmap version and template text, and never a reason for a run to fail."""

from __future__ import annotations

import marshal
import os
import pickle
import sys
from collections.abc import Iterator
from pathlib import Path

import jinja2
import jinja2.bccache
import pytest

import regmap
from regmap import render
from regmap.cli import main

from conftest import ROOT

SMALL = ROOT / "tests" / "maps" / "small" / "idm_rs_small.yaml"
PACKAGE = "regmap_template_cache_probe"


@pytest.fixture
def cache_root(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Iterator[Path]:
    """A private cache directory, and `templates()` rebuilt from it (and again after the test, for the others)."""
    monkeypatch.setenv("REGMAP_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.delenv(render.NO_TEMPLATE_CACHE_VARIABLE, raising=False)
    render.templates.cache_clear()
    yield tmp_path / "cache"
    render.templates.cache_clear()


@pytest.fixture
def probe(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """An importable package with one template, `t.jinja`; returns the template's path."""
    package = tmp_path / "src" / PACKAGE
    (package / "templates").mkdir(parents=True)
    (package / "__init__.py").write_text("", encoding="utf-8")
    template = package / "templates" / "t.jinja"
    template.write_text("real {{ value }}\n", encoding="utf-8")
    monkeypatch.syspath_prepend(str(tmp_path / "src"))
    monkeypatch.delitem(sys.modules, PACKAGE, raising=False)  # another test's copy of the package
    return template


def _render(value: str = "x") -> str:
    render.templates.cache_clear()  # a new process, as far as the template cache is concerned
    return render.templates(PACKAGE).get_template("t.jinja").render(value=value)


def _entries(root: Path) -> list[Path]:
    return sorted(root.rglob("*.cache"))


def _forge(entry: Path, source: str) -> None:
    """Replace the compiled code of `entry` with that of `source`, keeping the checksum of the template it was made from."""
    with entry.open("rb") as f:
        f.read(len(jinja2.bccache.bc_magic))
        checksum = pickle.load(f)
    code = jinja2.Environment(**render._ENVIRONMENT_OPTIONS).compile(source, "t.jinja", "t.jinja")
    entry.write_bytes(jinja2.bccache.bc_magic + pickle.dumps(checksum, 2) + marshal.dumps(code))


def test_an_entry_is_used_by_the_same_regmap_only(cache_root: Path, probe: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    assert _render() == "real x\n"
    [entry] = _entries(cache_root)
    _forge(entry, "forged {{ value }}\n")
    assert _render() == "forged x\n"  # the entry is what the next run executes
    monkeypatch.setattr(regmap, "__version__", regmap.__version__ + ".post1")
    assert _render() == "real x\n"  # another regmap version compiles the template itself
    assert len(_entries(cache_root)) == 2


def test_an_edited_template_is_compiled_again(cache_root: Path, probe: Path) -> None:
    assert _render() == "real x\n"
    probe.write_text("edited {{ value }}\n", encoding="utf-8")
    assert _render() == "edited x\n"


@pytest.mark.parametrize("damage", ["truncated", "garbage", "empty"])
def test_a_damaged_entry_is_compiled_again(cache_root: Path, probe: Path, damage: str) -> None:
    assert _render() == "real x\n"
    [entry] = _entries(cache_root)
    data = entry.read_bytes()
    broken = {"truncated": data[: len(jinja2.bccache.bc_magic) + 3], "garbage": jinja2.bccache.bc_magic + b"\x80\x02junk", "empty": b""}
    entry.write_bytes(broken[damage])
    assert _render() == "real x\n"


def test_a_run_does_not_look_at_a_template_file_again(cache_root: Path, probe: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A template is loaded once per process: an include in a loop does not stat its file each time."""
    assert _render() == "real x\n"
    monkeypatch.setattr(os.path, "getmtime", lambda path: pytest.fail(f"{path} was looked at again"))
    assert render.templates(PACKAGE).get_template("t.jinja").render(value="y") == "real y\n"


def test_an_unwritable_cache_costs_nothing_but_time(tmp_path: Path, probe: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    blocker = tmp_path / "a-file"
    blocker.write_text("", encoding="utf-8")
    monkeypatch.setenv("REGMAP_CACHE_DIR", str(blocker / "cache"))  # below a file: no directory can be made
    monkeypatch.delenv(render.NO_TEMPLATE_CACHE_VARIABLE, raising=False)
    try:
        assert _render() == "real x\n"
    finally:
        render.templates.cache_clear()


def test_the_variable_turns_it_off(cache_root: Path, probe: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv(render.NO_TEMPLATE_CACHE_VARIABLE, "1")
    assert _render() == "real x\n"
    assert not cache_root.exists()


def test_the_options_are_part_of_the_key(cache_root: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    before = render.template_cache_dir()
    monkeypatch.setitem(render._ENVIRONMENT_OPTIONS, "trim_blocks", False)
    assert render.template_cache_dir() != before


def test_generated_files_are_the_same_bytes_from_the_cache(cache_root: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    def generate(out: Path) -> dict[str, bytes]:
        render.templates.cache_clear()
        assert main(["generate", str(SMALL), "--target", "st", "--target", "c", "--target", "markdown", "--out", str(out)]) == 0
        return {p.relative_to(out).as_posix(): p.read_bytes() for p in sorted(out.rglob("*")) if p.is_file()}

    filling = generate(tmp_path / "first")
    assert _entries(cache_root)
    from_cache = generate(tmp_path / "second")
    monkeypatch.setenv(render.NO_TEMPLATE_CACHE_VARIABLE, "1")
    assert filling == from_cache == generate(tmp_path / "uncached")
