"""Map file -> `Device`: safe YAML, JSON Schema, elaboration, cross-reference checks, each a stage of its own.

Every problem in a file is collected (errors are values here) and raised together as one
`MapError`, each as `file:line:col: message`.
"""

from __future__ import annotations

import hashlib
from pathlib import Path as FsPath

from regmap.diagnostics import Diagnostic, MapError
from regmap.frontend.crossrefs import check_references
from regmap.frontend.elaborate import elaborate
from regmap.frontend.schema import _kind, _schema_problems
from regmap.frontend.stages import MapSource
from regmap.frontend.yamlsource import YamlProblem, read_yaml
from regmap.model import Device

MAX_MAP_BYTES = 8 * 1024 * 1024


def load_map(path: str | FsPath, display_name: str | None = None) -> Device:
    """Read, check and elaborate one map file; raises MapError listing every problem."""
    name = display_name or str(path)
    try:
        data = FsPath(path).read_bytes()
    except OSError as exc:
        raise MapError([Diagnostic(name, 1, 1, f"cannot read the map: {exc.strerror or exc}")]) from None
    return load_map_bytes(data, name)


def load_map_bytes(data: bytes, name: str) -> Device:
    return load_map_text(decoded(data, name), name, fingerprint=hashlib.sha256(data).hexdigest()[:16])


def decoded(data: bytes, name: str, what: str = "map") -> str:
    """A map's (or a plant file's) text: at most MAX_MAP_BYTES, UTF-8, a leading byte-order mark dropped."""
    if len(data) > MAX_MAP_BYTES:
        raise MapError([Diagnostic(name, 1, 1, f"the {what} is {len(data)} bytes; larger than {MAX_MAP_BYTES} bytes is refused")])
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = data[: exc.start].count(b"\n") + 1
        column = exc.start - (data.rfind(b"\n", 0, exc.start) + 1) + 1
        raise MapError(
            [Diagnostic(name, line, column, f"the {what} is not valid UTF-8 (byte 0x{data[exc.start]:02X}); save it as UTF-8")]
        ) from None
    return text.removeprefix("\ufeff")


def load_map_text(text: str, name: str, fingerprint: str | None = None) -> Device:
    """The stages in turn: YAML and schema, elaboration, cross-reference checks; raises MapError listing every problem."""
    if fingerprint is None:
        fingerprint = hashlib.sha256(text.encode("utf-8")).hexdigest()[:16]
    return check_references(elaborate(read_source(text, name, fingerprint)))


def read_source(text: str, name: str, fingerprint: str) -> MapSource:
    """The YAML and schema stages: the map's data with its positions, or a MapError."""
    try:
        raw, positions = read_yaml(text)
    except YamlProblem as exc:
        raise MapError([Diagnostic(name, exc.line, exc.column, exc.message)]) from None
    if not isinstance(raw, dict):
        line, col = positions.locate(())
        raise MapError([Diagnostic(name, line, col, f"the map must be a YAML mapping at the top level, not a {_kind(raw)}")])
    problems = _schema_problems(raw, positions, name)
    if problems:
        raise MapError(problems)
    return MapSource(raw, positions, name, fingerprint)
