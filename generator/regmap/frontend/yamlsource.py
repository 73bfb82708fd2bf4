"""Safe YAML reading that keeps the line and column of every value.

PyYAML's safe loader forgets positions and lets a duplicate key silently win; this reader composes
the node tree itself, so duplicate keys become errors, alias expansion and nesting are bounded (no
alias bombs, no recursion errors), and only the plain YAML types can be produced: strings, integers,
finite floats, booleans, null, lists and mappings with string keys (no object tags, dates or binary).
"""

from __future__ import annotations

import copy
import math
import re
from collections.abc import Callable
from dataclasses import field
from typing import Any

import yaml

from regmap.records import dataclass

Path = tuple[str | int, ...]

MAX_NODES = 200_000  # values aliases may add: far above any real map's (the file's own nodes are bounded by its size)
MAX_DEPTH = 64  # real maps nest about 8 levels; the bound keeps recursion far from Python's limit
MAX_INT_CHARS = 100  # no register value needs more; Python refuses int() of over 4300 digits anyway
_AMBIGUOUS_INT = re.compile(r"^[-+]?(0[0-9_]+|[0-9][0-9_]*(:[0-5]?[0-9])+)$")
_YAML_TAG = "tag:yaml.org,2002:"
_PLAIN_TAGS = {_YAML_TAG + "map", _YAML_TAG + "seq"}
# PyYAML's wording names parser states; these say what usually causes them.
_SYNTAX_HINTS = [
    ("mapping values are not allowed here", "; a key indented deeper than its siblings, or an unquoted ': ' inside a value?"),
    ("expected <block end>", "; check the indentation"),
    ("found character '\\t'", "; indent with spaces, not tabs"),
]
_SCALAR_TAGS = {_YAML_TAG + t for t in ("str", "int", "float", "bool", "null")}


@dataclass
class Positions:
    """Line/column (1-based) of every value in the document, keyed by its path, and of every mapping key."""

    by_path: dict[Path, tuple[int, int]] = field(default_factory=dict)
    keys: dict[Path, tuple[int, int]] = field(default_factory=dict)
    # Where `by_path` lacks the deeper scalar values and `keys` the deeper keys (the fast reader leaves them out: most
    # are never asked), what reads the document again with every position; called, once, when a path they lack is asked.
    complete: Callable[[], Positions] | None = field(default=None, compare=False, repr=False)

    def locate(self, path: Path) -> tuple[int, int]:
        """Position of `path`, or of its closest ancestor that has one."""
        probe = tuple(path)
        if self.complete is not None and probe not in self.by_path:
            self._complete()
        while probe not in self.by_path and probe:
            probe = probe[:-1]
        return self.by_path.get(probe, (1, 1))

    def locate_key(self, path: Path) -> tuple[int, int]:
        """Position of the key that names `path` (its last element), falling back to `locate`."""
        probe = tuple(path)
        if self.complete is not None and probe not in self.keys:
            self._complete()
        return self.keys.get(probe) or self.locate(path)

    def _complete(self) -> None:
        assert self.complete is not None
        every = self.complete()
        self.by_path, self.keys, self.complete = every.by_path, every.keys, None


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


# libyaml parses the same events (same marks) many times faster. The fast reader builds data and
# positions straight from those events, without a node tree; it takes only documents it is sure of:
# on any error or anything unusual the checked reader below reads the text again, so every message
# and position a user sees comes from one reader.
_FAST_PARSER: type[Any] | None = getattr(getattr(yaml, "cyaml", None), "CParser", None)


def read_yaml(text: str) -> tuple[Any, Positions]:
    """Parse one YAML document into plain data plus the position of every value."""
    fast = _read_fast(text, every_value=False)
    if fast is not None:
        return fast
    root = _compose_checked(text)
    positions = Positions()
    builder = _Builder(positions)
    try:
        data = builder.build(root, ())
    finally:
        builder.close()
    return data, positions


def _read_fast(text: str, every_value: bool = True) -> tuple[Any, Positions] | None:
    if _FAST_PARSER is None:
        return None
    parser = _FAST_PARSER(text)
    reader = _EventReader(parser, every_value)
    try:
        data, positions = reader.document()
    except (_Unsure, YamlProblem, yaml.YAMLError, ValueError, RecursionError):
        return None
    finally:
        parser.dispose()
        reader.checks.close()
    if not every_value:
        positions.complete = lambda: _complete_positions(text)
    return data, positions


def _complete_positions(text: str) -> Positions:
    """Every position of a document the fast reader took: it reads the same text the same way again."""
    again = _read_fast(text)
    assert again is not None  # the same text, read by the same reader
    return again[1]


def _compose_checked(text: str) -> yaml.Node:
    try:
        loader = _ScalarConstructor(text)
    except yaml.reader.ReaderError as exc:  # a control character; the reader checks the whole text up front
        line = text.count("\n", 0, exc.position) + 1
        column = exc.position - (text.rfind("\n", 0, exc.position) + 1) + 1
        raise YamlProblem(line, column, f"control character U+{exc.character:04X} is not allowed in YAML; remove it") from None
    try:
        root = loader.get_single_node()
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        line, col = (mark.line + 1, mark.column + 1) if mark else (1, 1)
        problem = exc.problem or exc.context or "invalid YAML"
        problem += next((hint for start, hint in _SYNTAX_HINTS if problem.startswith(start)), "")
        if exc.problem and exc.context and exc.context_mark and exc.context_mark.line + 1 != line:
            problem += f" ({exc.context} that starts on line {exc.context_mark.line + 1})"
        raise YamlProblem(line, col, f"YAML syntax error: {problem}") from None
    except yaml.YAMLError as exc:
        raise YamlProblem(1, 1, f"YAML syntax error: {exc}") from None
    except RecursionError:  # PyYAML composes recursively
        mark = loader.get_mark()
        raise YamlProblem(mark.line + 1, mark.column + 1, f"the document nests more than {MAX_DEPTH} levels deep") from None
    finally:
        loader.dispose()
    if root is None:
        raise YamlProblem(1, 1, "the file is empty; a map is a YAML mapping starting with `format: regmap/1`")
    node: yaml.Node = root
    return node


class _Builder:
    def __init__(self, positions: Positions) -> None:
        self.positions = positions
        self.expanded = 0  # nodes built again through an alias
        self.built: set[int] = set()  # ids of the nodes built once (the tree holds them, so ids stay unique)
        self.open: list[yaml.Node] = []  # collections being built, outermost first
        self.constructor = yaml.SafeLoader("")

    def close(self) -> None:
        """Let the constructor go with this builder: PyYAML's parser state points back at the loader (a cycle, which a
        generate run's rare collector passes would leave holding every node the constructor built and remembers)."""
        self.constructor.dispose()

    def build(self, node: yaml.Node, path: Path) -> Any:
        if id(node) in self.built:
            self.expanded += 1
            if self.expanded > MAX_NODES:
                line, col = _mark(node)
                raise YamlProblem(line, col, f"the document expands to more than {MAX_NODES} values (alias bomb?)")
        else:
            self.built.add(id(node))
        self.positions.by_path.setdefault(path, _mark(node))
        if not isinstance(node, yaml.MappingNode | yaml.SequenceNode):
            return self.scalar(node)
        line, col = _mark(node)
        if node.tag not in _PLAIN_TAGS:
            raise YamlProblem(line, col, f"unsupported YAML tag {_tag(node.tag)}; a map holds only plain values")
        if any(node is outer for outer in self.open):
            raise YamlProblem(line, col, "an alias refers to a collection that contains it (a recursive structure)")
        if len(self.open) >= MAX_DEPTH:
            raise YamlProblem(line, col, f"the document nests more than {MAX_DEPTH} levels deep")
        self.open.append(node)
        try:
            if isinstance(node, yaml.MappingNode):
                return self._mapping(node, path)
            return [self.build(item, (*path, i)) for i, item in enumerate(node.value)]
        finally:
            self.open.pop()

    def _mapping(self, node: yaml.MappingNode, path: Path) -> dict[str, Any]:
        result: dict[str, Any] = {}
        for key_node, value_node in node.value:
            if key_node.tag == "tag:yaml.org,2002:merge":
                line, col = _mark(key_node)
                raise YamlProblem(line, col, "YAML merge keys (<<) are not supported in maps")
            key = self.scalar(key_node)
            line, col = _mark(key_node)
            if not isinstance(key, str):
                raise YamlProblem(line, col, f"mapping key {key_node.value!r} is read as {_reading(key)}; quote it to make it text")
            first = self.positions.keys.setdefault((*path, key), (line, col))
            if key in result:
                raise YamlProblem(line, col, f"duplicate key {key!r} (first defined on line {first[0]})")
            if not isinstance(value_node, yaml.ScalarNode) and value_node.start_mark.line != key_node.start_mark.line:
                # A block collection starts on the next line, at its first child; a problem with the
                # collection as a whole (a missing key, say) reads better at the key that names it.
                self.positions.by_path.setdefault((*path, key), (line, col))
            result[key] = self.build(value_node, (*path, key))
        return result

    def scalar(self, node: yaml.Node) -> Any:
        line, col = _mark(node)
        if not isinstance(node, yaml.ScalarNode):
            raise YamlProblem(line, col, "a mapping key must be a plain scalar")
        text = str(node.value)
        if node.tag == "tag:yaml.org,2002:int" and len(text) > MAX_INT_CHARS:
            raise YamlProblem(line, col, f"integer of {len(text)} characters is too large (limit {MAX_INT_CHARS})")
        if node.tag == "tag:yaml.org,2002:int" and _AMBIGUOUS_INT.match(text):
            reading = self.constructor.construct_yaml_int(node)
            radix = "base 60" if ":" in text else "octal"
            raise YamlProblem(line, col, f"ambiguous integer {text!r}: YAML 1.1 reads it as {reading} ({radix}); quote it if it is text")
        if node.tag == "tag:yaml.org,2002:timestamp":
            raise YamlProblem(line, col, f"{text!r} reads as a YAML date; quote it if it is text")
        if node.tag not in _SCALAR_TAGS:
            raise YamlProblem(line, col, f"unsupported YAML tag {_tag(node.tag)}; a map holds only plain values")
        try:
            value = self.constructor.construct_object(node, deep=True)
        except (yaml.constructor.ConstructorError, ValueError, KeyError):  # an explicit tag on text it cannot read
            raise YamlProblem(line, col, f"{text!r} is not a valid YAML {node.tag.rsplit(':', 1)[-1]}") from None
        if isinstance(value, float) and not math.isfinite(value):
            raise YamlProblem(line, col, f"number {text!r} is not finite (too large for a 64-bit float, or .inf/.nan)")
        return value


class _Unsure(Exception):
    """The fast reader met what only the checked reader reports exactly (a problem, a tag, a bound)."""


@dataclass
class _Anchored:
    """What an anchor names, for its aliases: the value, the position records of its subtree, where it starts."""

    value: Any
    records: list[tuple[int, Path, tuple[int, int]]]  # (_VALUE, _KEY or _KEY_LINE, path below the anchor, position)
    mark: tuple[int, int]
    collection: bool


_VALUE, _KEY, _KEY_LINE = 0, 1, 2


class _EventReader:
    """Data and positions from libyaml's events, recording exactly what `_Builder` records for the same document."""

    def __init__(self, parser: Any, every_value: bool) -> None:
        self.get = parser.get_event
        # Keys and scalar values below the top two levels are located only when a diagnostic asks (`Positions.complete`).
        self.every_value = every_value
        self.positions = Positions()
        self.by_path = self.positions.by_path
        self.checks = _Builder(self.positions)  # the scalar rules, shared with the checked reader
        self.resolver = yaml.resolver.Resolver()
        self.plain_tags: dict[str, str] = {}  # a plain scalar's tag depends on its text alone
        self.str_texts: set[str] = set()  # the texts of plain_tags that read as strings: one lookup answers most scalars
        # The resolver tries only the patterns listed under a text's first character (a name's letter has none): any
        # other text is a string, with no pattern to match, unless a pattern is listed for every text (None) or by path.
        self.patterns: dict[str | None, Any] = self.resolver.yaml_implicit_resolvers
        self.resolve_every = None in self.patterns or bool(self.resolver.yaml_path_resolvers)
        self.scalars: dict[tuple[str, str], Any] = {}  # (tag, text) -> value, for the tags other than str
        self.anchors: dict[Any, _Anchored | None] = {}  # None: the anchored collection is still open
        self.recording: list[tuple[int, list[tuple[int, Path, tuple[int, int]]]]] = []  # (depth of the anchor's path, records)
        self.depth = 0
        self.expanded = 0

    def document(self) -> tuple[Any, Positions]:
        get = self.get
        if type(get()) is not yaml.StreamStartEvent or type(get()) is not yaml.DocumentStartEvent:
            raise _Unsure
        data = self.value(get(), ())
        if type(get()) is not yaml.DocumentEndEvent or type(get()) is not yaml.StreamEndEvent:
            raise _Unsure
        return data, self.positions

    def record(self, kind: int, path: Path, mark: tuple[int, int]) -> None:
        (self.positions.keys if kind == _KEY else self.by_path).setdefault(path, mark)
        for base, records in self.recording:
            records.append((kind, path[base:], mark))

    def value(self, event: Any, path: Path) -> Any:
        kind = type(event)
        if kind is yaml.AliasEvent:
            return self.alias(event, path)
        start = event.start_mark
        mark = (start.line + 1, start.column + 1)
        anchor = event.anchor
        if anchor is not None:
            if anchor in self.anchors:  # PyYAML refuses an anchor given twice
                raise _Unsure
            self.anchors[anchor] = None  # an alias inside its own anchor's collection is a recursion: refused
            records: list[tuple[int, Path, tuple[int, int]]] = []
            self.recording.append((len(path), records))
        if self.recording:
            self.record(_VALUE, path, mark)
        else:
            self.by_path.setdefault(path, mark)
        if kind is yaml.ScalarEvent:
            result = self.scalar(event)
        elif kind is yaml.MappingStartEvent or kind is yaml.SequenceStartEvent:
            if (event.tag is not None and event.tag not in _PLAIN_TAGS) or self.depth >= MAX_DEPTH:
                raise _Unsure
            self.depth += 1
            result = self.mapping(path) if kind is yaml.MappingStartEvent else self.sequence(path)
            self.depth -= 1
        else:
            raise _Unsure
        if anchor is not None:
            self.recording.pop()
            self.anchors[anchor] = _Anchored(result, records, mark, kind is not yaml.ScalarEvent)
        return result

    def alias(self, event: Any, path: Path) -> Any:
        anchored = self.anchors.get(event.anchor)
        if anchored is None:
            raise _Unsure
        for kind, below, mark in anchored.records:
            if kind == _VALUE:
                self.expanded += 1
            self.record(kind, path + below, mark)
        if self.expanded > MAX_NODES:
            raise _Unsure
        return copy.deepcopy(anchored.value)

    def mapping(self, path: Path) -> dict[str, Any]:
        result: dict[str, Any] = {}
        get, keys, by_path, str_texts = self.get, self.positions.keys, self.by_path, self.str_texts
        scalar_event = yaml.ScalarEvent
        recording = bool(self.recording)  # an anchor's value below this mapping is recorded, and done with, in `value`
        scalars_too = self.every_value or len(path) < 2
        while True:
            event = get()
            kind = type(event)
            if kind is not scalar_event:
                if kind is yaml.MappingEndEvent:
                    return result
                raise _Unsure
            key = event.value
            if event.anchor is not None or event.tag is not None or key in result:
                raise _Unsure  # a tagged key, an anchored one or one given twice: the checked reader says what is wrong
            if key not in str_texts and event.implicit[0] and self._plain_tag(key) != _STR_TAG:
                raise _Unsure  # a plain key that reads as a number, a boolean, null or `<<`
            start = event.start_mark
            line = start.line
            key_path = path + (key,)  # noqa: RUF005 (one tuple built, not a list turned into one)
            key_mark = (line + 1, start.column + 1)
            if recording:
                self.record(_KEY, key_path, key_mark)
            elif scalars_too:
                keys.setdefault(key_path, key_mark)
            value = get()
            kind = type(value)
            if kind is scalar_event and value.anchor is None and not recording:
                # the common case, what `value` does for it without the call: its position, then its value
                if scalars_too:
                    start = value.start_mark
                    by_path.setdefault(key_path, (start.line + 1, start.column + 1))
                text = value.value
                if value.tag is None and (text in str_texts or not value.implicit[0] or self._plain_tag(text) == _STR_TAG):
                    result[key] = text  # `scalar`'s first answer: a quoted text, or a plain one that reads as a string
                else:
                    result[key] = self.scalar(value)
                continue
            if kind is yaml.AliasEvent:
                anchored = self.anchors.get(value.anchor)
                starts, collection = (anchored.mark[0] - 1, anchored.collection) if anchored else (line, False)
            else:
                starts, collection = value.start_mark.line, kind is not scalar_event
            if collection and starts != line:
                if recording:
                    self.record(_KEY_LINE, key_path, key_mark)
                else:
                    by_path.setdefault(key_path, key_mark)
            result[key] = self.value(value, key_path)

    def sequence(self, path: Path) -> list[Any]:
        result: list[Any] = []
        get, by_path, str_texts = self.get, self.by_path, self.str_texts
        scalar_event = yaml.ScalarEvent
        recording = bool(self.recording)
        scalars_too = self.every_value or len(path) < 2
        while True:
            event = get()
            kind = type(event)
            if kind is yaml.SequenceEndEvent:
                return result
            item_path = path + (len(result),)  # noqa: RUF005 (as in mapping)
            if kind is scalar_event and event.anchor is None and not recording:
                # a plain item, as in mapping: its position, then its value
                if scalars_too:
                    start = event.start_mark
                    by_path.setdefault(item_path, (start.line + 1, start.column + 1))
                text = event.value
                if event.tag is None and (text in str_texts or not event.implicit[0] or self._plain_tag(text) == _STR_TAG):
                    result.append(text)
                else:
                    result.append(self.scalar(event))
                continue
            result.append(self.value(event, item_path))

    def _plain_tag(self, text: str) -> str:
        tag = self.plain_tags.get(text)
        if tag is None:
            if text and text[0] not in self.patterns and not self.resolve_every:
                tag = self.plain_tags[text] = _STR_TAG
            else:
                tag = self.plain_tags[text] = str(self.resolver.resolve(yaml.ScalarNode, text, (True, False)))  # type: ignore[no-untyped-call]
            if tag == _STR_TAG:
                self.str_texts.add(text)
        return tag

    def scalar(self, event: Any) -> Any:
        tag: str | None = event.tag
        text: str = event.value
        if tag is None or tag == "!":
            if not event.implicit[0]:
                return text  # quoted: a string, as the resolver says for every non-plain scalar
            tag = self.plain_tags.get(text) or self._plain_tag(text)
        if tag == _STR_TAG:
            return text  # what the checks and SafeConstructor make of any string
        key = (tag, text)
        try:
            return self.scalars[key]
        except KeyError:
            pass
        if tag == _INT_TAG and len(text) <= MAX_INT_CHARS:
            # A decimal or hexadecimal integer without `_` is what SafeConstructor reads it as, and breaks no rule of
            # `scalar` (no octal or base-60 look): most of a map's numbers, read without building a node for them.
            if _DECIMAL.fullmatch(text):
                value = self.scalars[key] = int(text)
                return value
            if _HEXADECIMAL.fullmatch(text):
                value = self.scalars[key] = int(text, 16)
                return value
        node = yaml.ScalarNode(tag, text, event.start_mark, event.end_mark, event.style)
        value = self.scalars[key] = self.checks.scalar(node)  # a problem: _Unsure's reader, the checked one, says it
        return value


_STR_TAG = _YAML_TAG + "str"
_INT_TAG = _YAML_TAG + "int"
_DECIMAL = re.compile(r"[-+]?(?:0|[1-9][0-9]*)")
_HEXADECIMAL = re.compile(r"[-+]?0x[0-9a-fA-F]+")
_MERGE_TAG = "tag:yaml.org,2002:merge"


def _tag(tag: str) -> str:
    """A tag as it is written in the file: !!python/object:x rather than tag:yaml.org,2002:python/object:x."""
    return "!!" + tag.removeprefix(_YAML_TAG) if tag.startswith(_YAML_TAG) else tag


def _reading(value: Any) -> str:
    """How YAML read a plain scalar, in YAML's own spelling."""
    if value is None:
        return "null"
    if isinstance(value, bool):
        return f"the boolean {str(value).lower()}"
    return f"the {'integer' if isinstance(value, int) else 'number'} {value}"
