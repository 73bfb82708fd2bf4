"""A JSON Schema compiled into Python closures that only answer "valid or not", for the fast path.

jsonschema walks the schema for every value (a descend, an evolve and a keyword lookup per property), which
for a 20,000-register table costs seconds. This compiles the keywords regmap's schemas use, once per process,
into one closure per schema node. It decides exactly as jsonschema does (its equality, where true is not 1
and 1 is 1.0, and its draft 2020-12 types); where it says "not valid", jsonschema runs and words the messages. A schema
using a keyword it does not know is not compiled (`compile_schema` gives None) and jsonschema does all the work.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable
from numbers import Number
from typing import Any

Check = Callable[[Any], bool]

# Keywords that never decide validity.
_ANNOTATIONS = frozenset({"$schema", "$id", "$defs", "$comment", "title", "description", "default", "examples"})


class _Unsupported(Exception):
    """The schema uses a keyword (or a form of one) this compiler does not decide."""


def _is_number(value: Any) -> bool:
    kind = type(value)
    if kind is int or kind is float:
        return True
    if kind is str:
        return False  # what the Number check below answers, without asking the ABC
    return isinstance(value, Number) and not isinstance(value, bool)


def _is_integer(value: Any) -> bool:
    # draft 2020-12: a float with no fraction is an integer (jsonschema's is_integer)
    if isinstance(value, bool):
        return False
    return isinstance(value, int) or (isinstance(value, float) and value.is_integer())


def equal(one: Any, two: Any) -> bool:
    """JSON equality as jsonschema decides it: a boolean equals only a boolean, lists and mappings item by item."""
    if one is two:
        return True
    if isinstance(one, str) or isinstance(two, str):
        return bool(one == two)
    if isinstance(one, list) and isinstance(two, list):
        return len(one) == len(two) and all(equal(a, b) for a, b in zip(one, two, strict=True))
    if isinstance(one, dict) and isinstance(two, dict):
        return one.keys() == two.keys() and all(equal(one[k], two[k]) for k in one)
    if isinstance(one, bool) or isinstance(two, bool):
        return type(one) is type(two) and one == two
    return bool(one == two)


def unique(items: list[Any]) -> bool:
    """No two items equal (`equal`); the lists regmap marks unique are short."""
    return not any(equal(a, b) for i, a in enumerate(items) for b in items[i + 1 :])


_TYPES: dict[str, Check] = {
    "object": lambda v: isinstance(v, dict),
    "array": lambda v: isinstance(v, list),
    "string": lambda v: isinstance(v, str),
    "integer": _is_integer,
    "number": _is_number,
    "boolean": lambda v: isinstance(v, bool),
    "null": lambda v: v is None,
}


_EXACT_TYPES: dict[str, tuple[type, ...]] = {
    "object": (dict,),
    "array": (list,),
    "string": (str,),
    "integer": (int,),
    "number": (int, float),
    "boolean": (bool,),
    "null": (type(None),),
}


def compile_schema(schema: dict[str, Any]) -> Check | None:
    """A function telling whether an instance is valid against `schema`, or None where the schema uses a
    keyword this module does not decide (the caller then validates with jsonschema alone)."""
    try:
        return _Compiler(schema).node(schema)
    except _Unsupported:
        return None


class _Compiler:
    def __init__(self, root: dict[str, Any]) -> None:
        self.root = root
        self.refs: dict[str, Check] = {}

    def ref(self, target: str) -> Check:
        """A local `#/$defs/x` reference, compiled once (and able to refer to itself)."""
        if not target.startswith("#/$defs/") or "/" in target[len("#/$defs/") :]:
            raise _Unsupported(target)
        if target not in self.refs:
            slot: list[Check] = []
            self.refs[target] = lambda v: slot[0](v)
            slot.append(self.node(self.root["$defs"][target[len("#/$defs/") :]]))
            self.refs[target] = slot[0]
        return self.refs[target]

    def node(self, schema: Any) -> Check:
        if schema is True:
            return lambda v: True
        if schema is False:
            return lambda v: False
        if not isinstance(schema, dict):
            raise _Unsupported(repr(schema))
        fused = self._typed(schema)
        if fused is not None:
            return fused
        checks: list[Check] = []
        for key, value in schema.items():
            if key in _ANNOTATIONS or key in ("then", "else", "properties"):
                continue  # then/else belong to if; properties to the object check below
            make = getattr(self, "_" + key.replace("$", "dollar_"), None)
            if make is None:
                raise _Unsupported(key)
            checks.append(make(value, schema))
        if "properties" in schema and "additionalProperties" not in schema:
            checks.append(self._properties_only(schema["properties"]))
        return _all(checks)

    def _typed(self, schema: dict[str, Any]) -> Check | None:
        """The commonest nodes (a string with lengths or a pattern, a bounded integer, a list of items, a mapping of
        properties) as one closure that tests the type once: the same answers as the keyword closures `_all` joins,
        for a call or three less per value. None for any other node."""
        kind = schema.get("type")
        keys = {key for key in schema if key not in _ANNOTATIONS} - {"type"}
        if kind == "string" and keys <= {"minLength", "maxLength", "pattern"}:
            return _string(schema.get("minLength", 0), schema.get("maxLength"), schema.get("pattern"))
        if kind == "integer" and keys <= {"minimum", "maximum"} and keys:
            return _integer(schema.get("minimum", -math.inf), schema.get("maximum", math.inf))
        if kind == "array" and keys <= {"items", "minItems", "maxItems", "uniqueItems"} and not isinstance(schema.get("items"), list):
            test = self.node(schema.get("items", True))
            return _array(test, schema.get("minItems", 0), schema.get("maxItems", math.inf), bool(schema.get("uniqueItems")))
        if kind == "object" and keys <= {"properties", "additionalProperties", "required", "minProperties"}:
            values = self._additionalProperties(schema["additionalProperties"], schema) if "additionalProperties" in keys else None
            if values is None:
                values = self._properties_only(schema.get("properties", {}))
            return _object(values, tuple(schema.get("required", ())), schema.get("minProperties", 0))
        return None

    # -- any type ------------------------------------------------------------------------------------------

    def _dollar_ref(self, target: str, _: dict[str, Any]) -> Check:
        return self.ref(target)

    def _type(self, wanted: str | list[str], _: dict[str, Any]) -> Check:
        names = [wanted] if isinstance(wanted, str) else wanted
        tests = [_TYPES[t] for t in names]
        if len(tests) == 1:
            return tests[0]
        # A value of one of these exact classes passes one of the tests; any other value asks each test.
        passing = frozenset(kind for t in names for kind in _EXACT_TYPES[t])
        some = _any(tests)
        return lambda v: type(v) in passing or some(v)

    def _enum(self, members: list[Any], _: dict[str, Any]) -> Check:
        texts = frozenset(m for m in members if isinstance(m, str))  # a text equals (`equal`) only the same text
        others = [m for m in members if not isinstance(m, str)]

        def check(v: Any) -> bool:
            if isinstance(v, str):
                return v in texts
            for member in others:  # noqa: SIM110 (a loop: any() of a generator costs a frame per value)
                if equal(v, member):
                    return True
            return False

        return check

    def _const(self, member: Any, _: dict[str, Any]) -> Check:
        return lambda v: equal(v, member)

    def _anyOf(self, branches: list[Any], _: dict[str, Any]) -> Check:
        return _any([self.node(b) for b in branches])

    def _oneOf(self, branches: list[Any], _: dict[str, Any]) -> Check:
        tests = [self.node(b) for b in branches]

        def check(v: Any) -> bool:
            passed = 0
            for test in tests:
                if test(v):
                    passed += 1
            return passed == 1

        return check

    def _not(self, branch: Any, _: dict[str, Any]) -> Check:
        test = self.node(branch)
        return lambda v: not test(v)

    def _if(self, condition: Any, schema: dict[str, Any]) -> Check:
        test = self.node(condition)
        then = self.node(schema.get("then", True))
        otherwise = self.node(schema.get("else", True))
        return lambda v: then(v) if test(v) else otherwise(v)

    # -- numbers ---------------------------------------------------------------------------------------------

    def _minimum(self, bound: float, _: dict[str, Any]) -> Check:
        return lambda v: not _is_number(v) or v >= bound

    def _maximum(self, bound: float, _: dict[str, Any]) -> Check:
        return lambda v: not _is_number(v) or v <= bound

    def _exclusiveMinimum(self, bound: float, _: dict[str, Any]) -> Check:
        return lambda v: not _is_number(v) or v > bound

    # -- strings --------------------------------------------------------------------------------------------

    def _pattern(self, pattern: str, _: dict[str, Any]) -> Check:
        search = re.compile(pattern).search
        return lambda v: not isinstance(v, str) or search(v) is not None

    def _minLength(self, size: int, _: dict[str, Any]) -> Check:
        return lambda v: not isinstance(v, str) or len(v) >= size

    def _maxLength(self, size: int, _: dict[str, Any]) -> Check:
        return lambda v: not isinstance(v, str) or len(v) <= size

    # -- arrays ---------------------------------------------------------------------------------------------

    def _items(self, item: Any, _: dict[str, Any]) -> Check:
        if isinstance(item, list):
            raise _Unsupported("items as a list")
        test = self.node(item)

        def check(v: Any) -> bool:
            if isinstance(v, list):
                for x in v:  # a loop: all() of a generator costs a frame per value
                    if not test(x):
                        return False
            return True

        return check

    def _minItems(self, size: int, _: dict[str, Any]) -> Check:
        return lambda v: not isinstance(v, list) or len(v) >= size

    def _maxItems(self, size: int, _: dict[str, Any]) -> Check:
        return lambda v: not isinstance(v, list) or len(v) <= size

    def _uniqueItems(self, unique_items: bool, _: dict[str, Any]) -> Check:
        return (lambda v: not isinstance(v, list) or unique(v)) if unique_items else (lambda v: True)

    # -- objects --------------------------------------------------------------------------------------------

    def _required(self, names: list[str], _: dict[str, Any]) -> Check:
        def check(v: Any) -> bool:
            if isinstance(v, dict):
                for name in names:
                    if name not in v:
                        return False
            return True

        return check

    def _minProperties(self, size: int, _: dict[str, Any]) -> Check:
        return lambda v: not isinstance(v, dict) or len(v) >= size

    def _propertyNames(self, names: Any, _: dict[str, Any]) -> Check:
        test = self.node(names)
        return lambda v: not isinstance(v, dict) or all(test(k) for k in v)

    def _properties_only(self, properties: dict[str, Any]) -> Check:
        tests = {name: self.node(s) for name, s in properties.items()}

        def check(v: Any) -> bool:
            if not isinstance(v, dict):
                return True
            for key, value in v.items():
                test = tests.get(key)
                if test is not None and not test(value):
                    return False
            return True

        return check

    def _additionalProperties(self, extra: Any, schema: dict[str, Any]) -> Check:
        if "patternProperties" in schema:
            raise _Unsupported("patternProperties")
        tests = {name: self.node(s) for name, s in schema.get("properties", {}).items()}
        other = self.node(extra)

        def check(v: Any) -> bool:
            if not isinstance(v, dict):
                return True
            for key, value in v.items():  # noqa: SIM110 (a loop: all() of a generator costs a frame per value)
                if not tests.get(key, other)(value):
                    return False
            return True

        return check


def _string(shortest: int, longest: int | None, pattern: str | None) -> Check:
    most = math.inf if longest is None else longest
    if pattern is None:
        return lambda v: isinstance(v, str) and shortest <= len(v) <= most
    search = re.compile(pattern).search
    return lambda v: isinstance(v, str) and shortest <= len(v) <= most and search(v) is not None


def _integer(low: float, high: float) -> Check:
    def check(v: Any) -> bool:
        if type(v) is int:
            return low <= v <= high
        return _is_integer(v) and low <= v <= high

    return check


def _array(test: Check, shortest: int, longest: float, unique_items: bool) -> Check:
    def check(v: Any) -> bool:
        if not isinstance(v, list) or not shortest <= len(v) <= longest:
            return False
        for x in v:  # a loop: all() of a generator costs a frame per value
            if not test(x):
                return False
        return not unique_items or unique(v)

    return check


def _object(values: Check, required: tuple[str, ...], fewest: int) -> Check:
    def check(v: Any) -> bool:
        if not isinstance(v, dict) or len(v) < fewest:
            return False
        for name in required:
            if name not in v:
                return False
        return values(v)

    return check


def _all(checks: list[Check]) -> Check:
    if not checks:
        return lambda v: True
    if len(checks) == 1:
        return checks[0]

    def every(v: Any) -> bool:
        for check in checks:  # noqa: SIM110 (a loop: all() of a generator costs a frame per value)
            if not check(v):
                return False
        return True

    return every


def _any(checks: list[Check]) -> Check:
    def some(v: Any) -> bool:
        for check in checks:  # noqa: SIM110 (a loop: any() of a generator costs a frame per value)
            if check(v):
                return True
        return False

    return some
