"""The JSON Schema pass: a map's structure, with messages that name the key and its line."""

from __future__ import annotations

import json
import re
from collections.abc import Iterable
from pathlib import Path
from typing import TYPE_CHECKING, Any

from regmap.diagnostics import Diagnostic
from regmap.frontend.fastschema import Check, compile_schema
from regmap.frontend.yamlsource import Positions

if TYPE_CHECKING:  # jsonschema is imported only when a map fails the compiled check (its import costs ~30 ms)
    import jsonschema


SCHEMA_DIR = Path(__file__).parent.parent / "schema"  # regmap/schema: package data, beside the code


def _schema(file: str = "map.schema.json") -> dict[str, Any]:
    text = (SCHEMA_DIR / file).read_text(encoding="utf-8")
    schema: dict[str, Any] = json.loads(text)
    return schema


_VALIDATORS: dict[str, jsonschema.protocols.Validator] = {}
_FAST_CHECKS: dict[str, Check | None] = {}


def _validator(file: str = "map.schema.json") -> jsonschema.protocols.Validator:
    """One validator per schema file and process (building one costs more than validating a map)."""
    import jsonschema

    if file not in _VALIDATORS:
        _VALIDATORS[file] = jsonschema.Draft202012Validator(_schema(file))
    return _VALIDATORS[file]


def _fast_check(file: str = "map.schema.json") -> Check | None:
    """The schema compiled to closures (fastschema), once per process: a valid map skips jsonschema's walk."""
    if file not in _FAST_CHECKS:
        _FAST_CHECKS[file] = compile_schema(_schema(file))
    return _FAST_CHECKS[file]


def _kind(value: Any) -> str:
    return {list: "list", str: "string", int: "number", float: "number", bool: "boolean"}.get(type(value), type(value).__name__)


def _dotted(path: Iterable[str | int]) -> str:
    out = ""
    for part in path:
        out += f"[{part}]" if isinstance(part, int) else (f".{part}" if out else str(part))
    return out or "(top level)"


def _schema_problems(raw: dict[str, Any], positions: Positions, name: str, schema_file: str = "map.schema.json") -> list[Diagnostic]:
    fast = _fast_check(schema_file)
    if fast is not None and fast(raw):
        return []
    problems = []
    for umbrella in _validator(schema_file).iter_errors(raw):
        error, message = _pick(umbrella)
        path = tuple(error.absolute_path)
        instance: Any = error.instance
        if error.validator == "additionalProperties":
            # One line per unknown key, at the key itself.
            known = sorted(error.schema.get("properties", {})) if isinstance(error.schema, dict) else []
            for key in sorted(set(instance) - set(known)):
                line, col = positions.locate_key((*path, key))
                import difflib  # only for a map with an unknown key

                close = difflib.get_close_matches(key, known, n=1)
                hint = f" (did you mean {close[0]!r}?)" if close else ""
                problems.append(Diagnostic(name, line, col, f"{_dotted(path)}: unknown key {key!r}{hint}"))
            continue
        if "propertyNames" in error.schema_path:
            line, col = positions.locate_key((*path, instance))
        else:
            line, col = positions.locate(path)
        message = message if len(message) <= 200 else message[:197] + "..."
        problems.append(Diagnostic(name, line, col, f"{_dotted(path)}: {message}"))
    return problems


def _pick(error: jsonschema.ValidationError) -> tuple[jsonschema.ValidationError, str]:
    """The error to report for a oneOf/anyOf failure, and its message.

    The branch that takes the value's type explains best (a string that misses a pattern, not "is not an
    integer"); when no branch takes it, the message names every type that would do.
    """
    from jsonschema.exceptions import best_match

    while error.context:
        typed = [e for e in error.context if not (e.validator == "type" and not e.relative_path)]
        if not typed:
            types = [t for e in error.context for t in _as_list(e.validator_value)]
            return error, _type_message(error.instance, types)
        error = best_match(typed)
    return error, _schema_message(error)


# What the schema's patterns mean, for messages a person can act on.
_PATTERNS = {
    "^[a-z][a-z0-9_]*$": "a snake_case identifier (lowercase letters, digits and _, starting with a letter)",
    r"^(0|[1-9][0-9]*)\.(0|[1-9][0-9]*)\.(0|[1-9][0-9]*)$": "a semantic version such as 1.0.0",
    "^[0-9A-Fa-f]{2}( ?[0-9A-Fa-f]{2})*$": "hex bytes such as '01 03 00 01'",
    "^[0-9]{1,2}-[0-9]{1,2}$": "a bit number or an inclusive bit range low-high such as '8-10'",
    "^E[0-9]+$": "an erratum id such as E1",
}
# YAML 1.1 reads 1e-3 (no dot, unsigned exponent) as text, where JSON and YAML 1.2 read a number.
_FLOAT_AS_TEXT = re.compile(r"^[-+]?([0-9]+\.?[0-9]*|\.[0-9]+)[eE][-+]?[0-9]+$")


_TYPE_NAMES = {
    "object": "a mapping",
    "array": "a list",
    "string": "a string",
    "integer": "an integer",
    "number": "a number",
    "boolean": "true or false",
    "null": "null",
}


def _schema_message(error: jsonschema.ValidationError) -> str:
    """jsonschema's message, reworded where it would show Python spellings (None, True) or a bare regex."""
    value: Any = error.validator_value
    if error.validator == "required":
        return error.message.replace("is a required property", "is required")
    if error.validator == "pattern" and value in _PATTERNS:
        return f"{error.instance!r} is not {_PATTERNS[value]}"
    if error.validator == "type":
        return _type_message(error.instance, _as_list(value))
    if error.validator == "enum":
        return f"{_show(error.instance)} is not one of {', '.join(_show(v) for v in value)}"
    if error.validator == "const":
        return f"expected {_show(value)}, got {_show(error.instance)}"
    if error.validator == "exclusiveMinimum":
        return f"{_show(error.instance)} must be greater than {value}"
    return error.message


def _type_message(instance: Any, types: list[Any]) -> str:
    wanted = " or ".join(dict.fromkeys(_TYPE_NAMES.get(t, str(t)) for t in types))
    message = f"expected {wanted}, got {_describe(instance)}"
    if isinstance(instance, str) and _FLOAT_AS_TEXT.match(instance) and {"number", "integer"} & set(types):
        message += f"; YAML reads {instance} as text: write a number with a dot and a signed exponent, such as 1.0e-3"
    return message


def _as_list(value: Any) -> list[Any]:
    return value if isinstance(value, list) else [value]


def _show(value: Any) -> str:
    """A value as YAML spells it (null, true), strings quoted and cut short."""
    if isinstance(value, str):
        return repr(value if len(value) <= 60 else value[:57] + "...")
    if isinstance(value, dict | list):
        return _describe(value)
    return json.dumps(value)


def _describe(value: Any) -> str:
    if isinstance(value, dict):
        return "a mapping"
    if isinstance(value, list):
        return "a list"
    if isinstance(value, str):
        return f"the string {_show(value)}"
    if isinstance(value, bool) or value is None:
        return _show(value)
    return f"the {'integer' if isinstance(value, int) else 'number'} {value}"
