"""The output cache of `regmap generate` (regmap/outputcache.py): a hit gives the same bytes as a render, and an entry
is used only for the same maps, the same regmap and an intact file."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

import regmap.cli.generate as cli_generate
from regmap import outputcache
from regmap.cli import main
from regmap.outputcache import OutputCache, entry_key, read_sources

from conftest import ROOT

SMALL = ROOT / "tests" / "maps" / "small" / "idm_rs_small.yaml"
TARGETS = ("--target", "c", "--target", "markdown")


@pytest.fixture
def cache_dir(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.delenv("REGMAP_NO_CACHE", raising=False)
    monkeypatch.setenv("REGMAP_CACHE_DIR", str(tmp_path / "cache"))
    return tmp_path / "cache"


def _generate(map_path: Path, out: Path) -> dict[str, bytes]:
    assert main(["generate", str(map_path), *TARGETS, "--out", str(out)]) == 0
    return {p.relative_to(out).as_posix(): p.read_bytes() for p in sorted(out.rglob("*")) if p.is_file()}


def _no_loading(monkeypatch: pytest.MonkeyPatch) -> None:
    def refuse(paths: object) -> object:
        raise AssertionError("the maps were read again")

    monkeypatch.setattr(cli_generate, "load_all", refuse)


def test_a_hit_writes_the_rendered_bytes_without_reading_the_maps(cache_dir: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    rendered = _generate(SMALL, tmp_path / "cold")
    assert len(list(cache_dir.glob("*.json"))) == 2  # one entry per target
    _no_loading(monkeypatch)
    assert _generate(SMALL, tmp_path / "warm") == rendered


def test_a_changed_map_is_rendered_again(cache_dir: Path, tmp_path: Path) -> None:
    map_path = tmp_path / "maps" / SMALL.name
    map_path.parent.mkdir()
    shutil.copy(SMALL, map_path)
    before = _generate(map_path, tmp_path / "one")
    text = map_path.read_text(encoding="utf-8")
    assert "title: Wrong function code," in text
    map_path.write_text(text.replace("title: Wrong function code,", "title: Unknown function code,"), encoding="utf-8")
    after = _generate(map_path, tmp_path / "two")
    assert after != before and any(b"Unknown function code" in content for content in after.values())
    monkeypatch = pytest.MonkeyPatch()
    with monkeypatch.context() as patch:
        patch.setenv("REGMAP_NO_CACHE", "1")
        assert _generate(map_path, tmp_path / "uncached") == after


def test_another_regmap_misses(cache_dir: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    _generate(SMALL, tmp_path / "one")
    sources = read_sources([SMALL])
    assert sources is not None
    cache = OutputCache(cache_dir)
    assert cache.get(entry_key("c", sources)) is not None
    monkeypatch.setattr(outputcache, "code_digest", lambda: "another regmap")  # a new version, or an edited template
    assert cache.get(entry_key("c", sources)) is None


def test_a_corrupt_or_foreign_entry_is_a_miss(cache_dir: Path, tmp_path: Path) -> None:
    rendered = _generate(SMALL, tmp_path / "one")
    entries = sorted(cache_dir.glob("*.json"))
    entry = json.loads(entries[0].read_text(encoding="utf-8"))
    first = sorted(entry["files"])[0]
    entry["files"][first] += "// edited\n"  # the files no longer match their digest
    entries[0].write_text(json.dumps(entry), encoding="utf-8")
    entries[1].write_bytes(entries[1].read_bytes()[:100])  # truncated
    cache = OutputCache(cache_dir)
    assert cache.get(entries[0].stem) is None and cache.get(entries[1].stem) is None
    assert _generate(SMALL, tmp_path / "two") == rendered  # both rendered again, and stored again whole
    assert all(cache.get(e.stem) is not None for e in entries)
    shutil.copy(entries[0], cache_dir / f"{'0' * 64}.json")  # an intact entry under a key that is not its own
    assert cache.get("0" * 64) is None


def test_no_cache_writes_nothing(cache_dir: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("REGMAP_NO_CACHE", "1")
    _generate(SMALL, tmp_path / "one")
    assert not cache_dir.exists()


def test_an_unwritable_cache_only_costs_speed(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv("REGMAP_NO_CACHE", raising=False)
    blocker = tmp_path / "file"
    blocker.write_text("not a directory", encoding="utf-8")
    monkeypatch.setenv("REGMAP_CACHE_DIR", str(blocker / "cache"))
    assert _generate(SMALL, tmp_path / "one")
