"""The compiled schema check (frontend/fastschema.py) decides exactly as jsonschema: on every map, fixture,
plant and invalid map the project holds, on random edits of them, and on JSON's equality corners. A map it
calls valid skips jsonschema, so one wrong "valid" would let a bad map through without a message."""

from __future__ import annotations

import copy
import math
from pathlib import Path
from typing import Any

import jsonschema
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from regmap.frontend.fastschema import compile_schema
from regmap.frontend.schema import _fast_check, _validator
from regmap.frontend.yamlsource import YamlProblem, read_yaml

from conftest import FIXTURE_MAPS, MAPS, ROOT

PLANTS = sorted((ROOT / "examples" / "plants").glob("*.yaml")) + sorted((ROOT / "tests" / "maps").rglob("*plant*.yaml"))
EVERY_MAP = sorted({*MAPS, *FIXTURE_MAPS, *(ROOT / "tests" / "maps").rglob("*.yaml")} - set(PLANTS))


def _data(path: Path) -> Any | None:
    try:
        data, _ = read_yaml(path.read_text(encoding="utf-8"))
    except (YamlProblem, UnicodeDecodeError, ValueError):
        return None  # not YAML the front end reads: the schema never sees it
    return data


def _agree(data: Any, schema_file: str = "map.schema.json") -> None:
    fast = _fast_check(schema_file)
    assert fast is not None, f"{schema_file} uses a keyword fastschema does not compile"
    assert fast(data) == _validator(schema_file).is_valid(data)


def test_every_map_the_project_holds_is_decided_as_jsonschema_decides() -> None:
    decided = {True: 0, False: 0}
    for path in EVERY_MAP:
        data = _data(path)
        if data is None:
            continue
        _agree(data)
        decided[_validator().is_valid(data)] += 1
    for path in PLANTS:
        data = _data(path)
        if data is not None:
            _agree(data, "plant.schema.json")
    assert decided[True] >= len(MAPS) + len(FIXTURE_MAPS) and decided[False] >= 25, decided  # both verdicts were exercised


_JSON = st.recursive(
    st.none() | st.booleans() | st.integers(-70000, 70000) | st.floats(allow_nan=True) | st.text(max_size=12),
    lambda inner: st.lists(inner, max_size=3) | st.dictionaries(st.text(max_size=8), inner, max_size=3),
    max_leaves=6,
)
_BASES = [d for d in (_data(p) for p in [*MAPS, *FIXTURE_MAPS]) if d is not None]


def _paths(value: Any, here: tuple[Any, ...] = ()) -> list[tuple[Any, ...]]:
    out = [here]
    if isinstance(value, dict):
        for key, item in value.items():
            out += _paths(item, (*here, key))
    elif isinstance(value, list):
        for i, item in enumerate(value):
            out += _paths(item, (*here, i))
    return out


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(base=st.sampled_from(range(len(_BASES))), where=st.integers(0, 10**9), value=_JSON, replace=st.booleans())
def test_a_random_edit_of_a_map_is_decided_as_jsonschema_decides(base: int, where: int, value: Any, replace: bool) -> None:
    data = copy.deepcopy(_BASES[base])
    paths = [p for p in _paths(data) if p]
    path = paths[where % len(paths)]
    parent = data
    for part in path[:-1]:
        parent = parent[part]
    if replace or not isinstance(parent, dict):
        parent[path[-1]] = value  # a value of another type or shape
    else:
        parent[f"{path[-1]}_extra"] = value  # a key the schema may not know
    _agree(data)


@pytest.mark.parametrize(
    ("schema", "instance"),
    [
        ({"enum": [1, 2]}, True),  # true is not 1
        ({"enum": [True]}, 1),
        ({"enum": [1]}, 1.0),  # 1.0 is 1
        ({"const": [1, {"a": False}]}, [1.0, {"a": False}]),
        ({"const": [1, {"a": False}]}, [1, {"a": 0}]),
        ({"type": "integer"}, 2.0),
        ({"type": "integer"}, 2.5),
        ({"type": "integer"}, True),
        ({"type": "number"}, False),
        ({"type": ["string", "null"]}, None),
        ({"uniqueItems": True}, [1, True]),
        ({"uniqueItems": True}, [1, 1.0]),
        ({"uniqueItems": True}, [{"a": 1}, {"a": 1}]),
        ({"uniqueItems": True}, [math.nan, math.nan]),
        ({"minimum": 0}, "text"),  # bounds apply to numbers only
        ({"exclusiveMinimum": 0}, 0),
        ({"maximum": 5}, True),
        ({"pattern": "^a"}, 5),
        ({"maxLength": 2}, "\u9644\u5f55"),  # code points, not bytes
        ({"maxLength": 1}, "\u9644\u5f55"),
        ({"oneOf": [{"type": "integer"}, {"type": "number"}]}, 3),  # both match: not exactly one
        ({"oneOf": [{"type": "integer"}, {"type": "string"}]}, 3),
        ({"not": {"required": ["a"]}}, {"a": 1}),
        ({"if": {"required": ["array"]}, "then": {"required": ["members"]}, "else": {"required": ["name"]}}, {"array": 1}),
        ({"if": {"required": ["array"]}, "then": {"required": ["members"]}, "else": {"required": ["name"]}}, {"name": 1}),
        ({"properties": {"a": {"type": "string"}}, "additionalProperties": False}, {"a": "x", "b": 1}),
        ({"properties": {"a": {"type": "string"}}}, {"a": 1}),
        ({"additionalProperties": {"type": "integer"}}, {"a": 1, "b": "x"}),
        ({"propertyNames": {"pattern": "^[a-z]+$"}}, {"Ab": 1}),
        ({"minProperties": 1}, {}),
        ({"items": {"type": "integer"}, "minItems": 2, "maxItems": 3}, [1]),
        ({"items": {"type": "integer"}, "minItems": 2, "maxItems": 3}, [1, 2, 3, 4]),
        ({"$defs": {"n": {"type": "integer"}}, "items": {"$ref": "#/$defs/n"}}, [1, "x"]),
        ({"enum": ["a", 1]}, "b"),  # a text is looked up among the texts alone
        ({"enum": ["a", 1]}, "a"),
        ({"enum": ["1", 2]}, 1),
        ({"enum": ["a", 1]}, 1.0),
        ({"type": ["integer", "string"]}, True),  # a list of types: its exact classes first, then each test
        ({"type": ["integer", "null"]}, 2.0),
        ({"type": ["number", "string"]}, False),
        ({"type": "integer", "minimum": 0, "maximum": 5}, 6),  # the fused nodes (`_typed`): a bound, a type, both
        ({"type": "integer", "minimum": 0, "maximum": 5}, 5.0),
        ({"type": "integer", "minimum": 0, "maximum": 5}, 6.0),
        ({"type": "integer", "minimum": 0}, True),
        ({"type": "string", "minLength": 2, "maxLength": 3, "pattern": "^a"}, "ab"),
        ({"type": "string", "minLength": 2, "maxLength": 3, "pattern": "^a"}, "ba"),
        ({"type": "string", "maxLength": 3}, "abcd"),
        ({"type": "array", "items": {"type": "integer"}, "maxItems": 2, "uniqueItems": True}, [1, 1.0]),
        ({"type": "array", "minItems": 1}, []),
        ({"type": "object", "required": ["a"], "minProperties": 2}, {"a": 1}),
        ({"type": "object", "required": ["a"]}, {"b": 1}),
        ({"type": "object", "properties": {"a": {"type": "string"}}, "required": ["a"]}, {"a": 1}),
    ],
)
def test_json_corners_are_decided_as_jsonschema_decides(schema: dict[str, Any], instance: Any) -> None:
    fast = compile_schema(schema)
    assert fast is not None
    assert fast(instance) == jsonschema.Draft202012Validator(schema).is_valid(instance)


def test_a_keyword_it_does_not_know_leaves_the_whole_check_to_jsonschema() -> None:
    assert compile_schema({"properties": {"a": {"format": "date"}}}) is None
    assert compile_schema({"patternProperties": {"^x": {}}, "additionalProperties": False}) is None
    assert compile_schema({"$ref": "other.json#/a"}) is None
