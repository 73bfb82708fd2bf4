"""Reading an ESPHome or Home Assistant YAML file as data, never as code.

Their files carry tags (`!secret`, `!lambda`, `!include`, `!extend`, `!env_var`, `!input`): each is read as a
`Tagged` value holding its text, and nothing a tag names is opened, looked up or run. Everything else is
read by the front end's safe reader (frontend/yamlsource.py: bounded, duplicate keys refused, plain types
only), so every value keeps its line and column for the messages.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Any

import yaml

from regmap.diagnostics import Diagnostic, at
from regmap.frontend import yamlsource
from regmap.frontend.yamlsource import Path, Positions, YamlProblem


@dataclass(frozen=True)
class Tagged:
    """A tagged node: the tag as written (`!secret`) and its value (text, or the list/mapping under it)."""

    tag: str
    value: Any

    def __str__(self) -> str:
        return f"{self.tag} {self.value}"


class ConfigError(Exception):
    """Problems in the input config, each at file:line:col."""

    def __init__(self, diagnostics: list[Diagnostic]) -> None:
        super().__init__("\n".join(str(d) for d in diagnostics))
        self.diagnostics = diagnostics


class _TaggedBuilder(yamlsource._Builder):
    def build(self, node: yaml.Node, path: Path) -> Any:
        if node.tag.startswith("!") and not node.tag.startswith("!!"):
            self.positions.by_path.setdefault(path, yamlsource._mark(node))
            if isinstance(node, yaml.ScalarNode):
                return Tagged(node.tag, str(node.value))
            plain = yaml.MappingNode if isinstance(node, yaml.MappingNode) else yaml.SequenceNode
            untagged = plain(
                "tag:yaml.org,2002:" + ("map" if plain is yaml.MappingNode else "seq"), node.value, node.start_mark, node.end_mark
            )
            return Tagged(node.tag, super().build(untagged, path))
        return super().build(node, path)


@dataclass
class Config:
    """One config file: its data, where each value is, and its name for messages."""

    name: str
    data: Any
    positions: Positions

    @property
    def file_name(self) -> str:
        """The file's own name, which the map's `source` cites (`meter.yaml:42`)."""
        return self.name.replace("\\", "/").rsplit("/", 1)[-1]

    def error(self, path: Path, message: str) -> Diagnostic:
        return at(self.name, self.positions.locate(path), message)


# libyaml composes the same node tree (same resolver, same marks) many times faster, and reads JSON that indents
# with tabs (pysunspec2's model files do). Only a valid document is taken from it: on any error the checked
# composer runs again, so every message and position comes from one parser.
_FAST_LOADER: type[Any] | None = getattr(yaml, "CSafeLoader", None)


def _compose_fast(text: str) -> yaml.Node | None:
    if _FAST_LOADER is None:
        return None
    try:
        loader = _FAST_LOADER(text)
        try:
            node: yaml.Node | None = loader.get_single_node()
            return node
        finally:
            loader.dispose()
    except (yaml.YAMLError, RecursionError, ValueError):
        return None


def read_config(text: str, name: str) -> Config:
    """The file's data; a YAML error raises ConfigError at its position."""
    try:
        root = _compose_fast(text) or yamlsource._compose_checked(text)
        positions = Positions()
        data = _TaggedBuilder(positions).build(root, ())
    except YamlProblem as exc:
        message = exc.message if text.strip() else "the file is empty"
        raise ConfigError([at(name, (exc.line, exc.column), message)]) from None
    return Config(name, data, positions)


_SUBSTITUTION = re.compile(r"\$\{([A-Za-z_][A-Za-z0-9_]*)\}|\$([A-Za-z_][A-Za-z0-9_]*)")


def substitute(value: Any, substitutions: dict[str, str], unresolved: set[str]) -> Any:
    """`value` with ESPHome's `${name}` and `$name` replaced where the file gives `name`; names it does not
    give are left as written and collected in `unresolved`. A value that is only one substitution takes the
    substitution's YAML reading (`address: ${slave}` with `slave: '3'` is the integer 3)."""
    if isinstance(value, dict):
        return {k: substitute(v, substitutions, unresolved) for k, v in value.items()}
    if isinstance(value, list):
        return [substitute(v, substitutions, unresolved) for v in value]
    if not isinstance(value, str) or "$" not in value:
        return value

    def one(match: re.Match[str]) -> str:
        key = match.group(1) or match.group(2)
        if key in substitutions:
            return substitutions[key]
        unresolved.add(key)
        return match.group(0)

    whole = _SUBSTITUTION.fullmatch(value)
    text = _SUBSTITUTION.sub(one, value)
    if whole and text != value:
        return _plain_reading(text)
    return text


def _plain_reading(text: str) -> Any:
    """How YAML reads `text` as a plain scalar: 0x0010 an integer, 0.1 a float, anything else the text."""
    try:
        node = yaml.SafeLoader(text).get_single_node()
    except yaml.YAMLError:
        return text
    if isinstance(node, yaml.ScalarNode) and node.tag in ("tag:yaml.org,2002:int", "tag:yaml.org,2002:float", "tag:yaml.org,2002:bool"):
        return yaml.SafeLoader("").construct_object(node)
    return text


class ConfigReader:
    """What the ESPHome and Home Assistant readers share: the problems found (each at file:line:col) and the
    report (file:line of the entity: what became a note or was left out)."""

    def __init__(self, config: Config) -> None:
        self.config = config
        self.problems: list[Diagnostic] = []
        self.report: list[str] = []

    def where(self, path: Path) -> str:
        return f"{self.config.file_name}:{self.config.positions.locate(path)[0]}"

    def fail(self, path: Path, message: str) -> None:
        self.problems.append(self.config.error(path, message))


STATIC_PERIOD = 0.0  # seconds: read once at start-up, then (practically) never


def poll_class(period: float, writable: bool, normal_up_to: float) -> str:
    """The map's poll class of an entity read every `period` seconds: fast up to 5 s, normal up to the tool's
    usual period, slow beyond; a setting read seldom is still a normal register (it changes when written)."""
    if period <= STATIC_PERIOD:
        return "static"
    if period <= 5:
        return "fast"
    return "normal" if writable or period <= normal_up_to else "slow"
