"""Safe YAML reading that keeps the line and column of every value.

PyYAML's safe loader forgets positions and lets a duplicate key silently win; this reader composes
the node tree itself, so duplicate keys become errors, alias expansion is bounded (no alias bombs),
and only the plain YAML types can be produced (no object tags).
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import Any

import yaml

Path = tuple[str | int, ...]

MAX_NODES = 200_000
_AMBIGUOUS_INT = re.compile(
    r"^[-+]?(0[0-9_]+|[0-9][0-9_]*(:[0-5]?[0-9])+)$"
)  # far above any real map (the largest has a few thousand nodes)


@dataclass
class Positions:
    """Line/column (1-based) of every value in the document, keyed by its path."""

    by_path: dict[Path, tuple[int, int]] = field(default_factory=dict)

    def locate(self, path: Path) -> tuple[int, int]:
        """Position of `path`, or of its closest ancestor that has one."""
        probe = tuple(path)
        while probe not in self.by_path and probe:
            probe = probe[:-1]
        return self.by_path.get(probe, (1, 1))


class YamlProblem(Exception):
    def __init__(self, line: int, column: int, message: str) -> None:
        super().__init__(message)
        self.line = line
        self.column = column
        self.message = message


class _ScalarConstructor(yaml.SafeLoader):
    pass


def _mark(node: yaml.Node) -> tuple[int, int]:
    return node.start_mark.line + 1, node.start_mark.column + 1


def read_yaml(text: str) -> tuple[Any, Positions]:
    """Parse one YAML document into plain data plus the position of every value."""
    try:
        loader = _ScalarConstructor(text)
        try:
            root = loader.get_single_node()
        finally:
            loader.dispose()
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        line, col = (mark.line + 1, mark.column + 1) if mark else (1, 1)
        problem = exc.problem or exc.context or "invalid YAML"
        raise YamlProblem(line, col, f"YAML syntax error: {problem}") from None
    except yaml.YAMLError as exc:
        raise YamlProblem(1, 1, f"YAML syntax error: {exc}") from None
    if root is None:
        raise YamlProblem(1, 1, "the file is empty; a map is a YAML mapping starting with `format: regmap/1`")
    positions = Positions()
    builder = _Builder(positions)
    data = builder.build(root, ())
    return data, positions


class _Builder:
    def __init__(self, positions: Positions) -> None:
        self.positions = positions
        self.count = 0
        self.constructor = yaml.SafeLoader("")

    def build(self, node: yaml.Node, path: Path) -> Any:
        self.count += 1
        if self.count > MAX_NODES:
            line, col = _mark(node)
            raise YamlProblem(line, col, f"the document expands to more than {MAX_NODES} values (alias bomb?)")
        self.positions.by_path.setdefault(path, _mark(node))
        if isinstance(node, yaml.MappingNode):
            return self._mapping(node, path)
        if isinstance(node, yaml.SequenceNode):
            return [self.build(item, (*path, i)) for i, item in enumerate(node.value)]
        return self._scalar(node)

    def _mapping(self, node: yaml.MappingNode, path: Path) -> dict[str, Any]:
        if node.tag not in ("tag:yaml.org,2002:map",):
            line, col = _mark(node)
            raise YamlProblem(line, col, f"unsupported YAML tag {node.tag!r}")
        result: dict[str, Any] = {}
        for key_node, value_node in node.value:
            if key_node.tag == "tag:yaml.org,2002:merge":
                line, col = _mark(key_node)
                raise YamlProblem(line, col, "YAML merge keys (<<) are not supported in maps")
            key = self._scalar(key_node)
            if not isinstance(key, str):
                line, col = _mark(key_node)
                raise YamlProblem(line, col, f"mapping key {key!r} must be a string")
            if key in result:
                line, col = _mark(key_node)
                first_line, _ = self.positions.by_path.get((*path, key), (0, 0))
                raise YamlProblem(line, col, f"duplicate key {key!r} (first defined on line {first_line})")
            result[key] = self.build(value_node, (*path, key))
        return result

    def _scalar(self, node: yaml.Node) -> Any:
        if not isinstance(node, yaml.ScalarNode):
            line, col = _mark(node)
            raise YamlProblem(line, col, "a mapping key must be a plain scalar")
        if node.tag == "tag:yaml.org,2002:int" and _AMBIGUOUS_INT.match(str(node.value)):
            line, col = _mark(node)
            raise YamlProblem(
                line,
                col,
                f"ambiguous integer {node.value!r}: YAML reads a leading 0 as octal and a colon as base 60;"
                " write it in decimal without the leading zero, in hex (0x...), or quote it if it is text",
            )
        try:
            value = self.constructor.construct_object(node, deep=True)
        except yaml.constructor.ConstructorError as exc:
            line, col = _mark(node)
            raise YamlProblem(line, col, f"unsupported YAML value: {exc.problem}") from None
        if not isinstance(value, (str, int, float, bool)) and value is not None:
            line, col = _mark(node)
            raise YamlProblem(line, col, f"unsupported YAML value of type {type(value).__name__}; quote it")
        return value
