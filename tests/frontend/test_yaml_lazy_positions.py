"""The fast reader leaves the deeper scalar values' positions out until one is asked; then it knows them all."""

from __future__ import annotations

from pathlib import Path

import pytest

from regmap.frontend import yamlsource

ROOT = Path(__file__).resolve().parents[2]
MAPS = sorted((ROOT / "maps").glob("*.yaml"))


@pytest.mark.parametrize("map_path", MAPS, ids=lambda p: p.name)
def test_a_lazy_reading_locates_every_value_where_the_eager_one_does(map_path: Path) -> None:
    text = map_path.read_text(encoding="utf-8")
    data, positions = yamlsource.read_yaml(text)
    eager = yamlsource._read_fast(text)
    assert eager is not None
    assert data == eager[0]
    assert positions.complete is not None  # the three maps are read lazily: this test is about that reading
    for path, mark in eager[1].keys.items():
        assert positions.locate_key(path) == mark, path
    assert positions.complete is None
    assert list(positions.keys.items()) == list(eager[1].keys.items())
    _, positions = yamlsource.read_yaml(text)
    for path, mark in eager[1].by_path.items():
        assert positions.locate(path) == mark, path
    assert positions.complete is None
    assert list(positions.by_path.items()) == list(eager[1].by_path.items())


def test_a_deep_scalar_is_located_at_its_own_column_not_its_mapping() -> None:
    text = "format: regmap/1\ngroups:\n  - id: a\n    registers:\n      - name: x\n        address: 7\n"
    _, positions = yamlsource.read_yaml(text)
    assert positions.locate(("groups", 0, "registers", 0, "address")) == (6, 18)
    assert positions.locate(("groups", 0, "registers", 0, "name")) == (5, 15)
    assert positions.locate(("groups", 0, "registers", 0, "nothing")) == (5, 9)
    _, positions = yamlsource.read_yaml(text)
    assert positions.locate_key(("groups", 0, "registers", 0, "address")) == (6, 9)
