"""The output cache of `regmap generate`: a target's finished files (post-processed), for maps that have not changed.

An entry is keyed by everything its files are made from: the target, the maps (each file's name as given and the
SHA-256 of its bytes, in order), and `code_digest()` (regmap's version, the bytes of every file of the regmap and
regmap_runtime packages, the versions of Python and of the libraries that shape the output). An entry is used only
when it parses, names the key asked for and its files hash to the digest it carries; anything else (a truncated,
corrupt or unreadable file) is a miss, and the target is rendered as if there were no cache. Entries are written to a
temporary file and renamed into place, so concurrent runs read either a whole entry or none. A cache that cannot be
written costs the next run its speed, nothing else.

Where: `$REGMAP_CACHE_DIR`, else `$XDG_CACHE_HOME/regmap/generate`, else `~/.cache/regmap/generate`.
`REGMAP_NO_CACHE=1` turns it off. Runs with target options (`--select`) or `--since`, and third-party targets,
are never cached: their output depends on more than the key holds.
"""

from __future__ import annotations

import hashlib
import json
import os
import sys
import tempfile
from collections.abc import Mapping, Sequence
from functools import cache
from pathlib import Path

ENTRY_FORMAT = 1
KEEP_ENTRIES = 64  # the newest entries kept; older ones are removed after a write
_LIBRARIES = ("Jinja2", "MarkupSafe", "PyYAML", "ruff")
NO_CACHE_VARIABLE = "REGMAP_NO_CACHE"
DIR_VARIABLE = "REGMAP_CACHE_DIR"

Files = dict[str, str]
Source = tuple[str, str]  # (the map's name as given, SHA-256 of its bytes)


def cache_dir() -> Path | None:
    """Where entries live, or None when the cache is turned off."""
    if os.environ.get(NO_CACHE_VARIABLE, "") not in ("", "0"):
        return None
    explicit = os.environ.get(DIR_VARIABLE)
    if explicit:
        return Path(explicit)
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "regmap" / "generate"


@cache
def code_digest() -> str:
    """What regmap's output depends on besides the maps: its version, its own files, the libraries that shape output."""
    from importlib.metadata import PackageNotFoundError, version

    import regmap
    import regmap_runtime

    digest = hashlib.sha256(f"regmap {regmap.__version__}\0python {sys.version}\0".encode())
    for library in _LIBRARIES:
        try:
            found = version(library)
        except PackageNotFoundError:
            found = "absent"
        digest.update(f"{library} {found}\0".encode())
    for package in (regmap, regmap_runtime):
        root = Path(package.__file__ or "").parent
        for path in sorted(p for p in root.rglob("*") if p.is_file() and "__pycache__" not in p.parts):
            digest.update(f"{path.relative_to(root.parent).as_posix()}\0".encode())
            digest.update(hashlib.sha256(path.read_bytes()).digest())
    return digest.hexdigest()


def read_sources(paths: Sequence[Path]) -> list[Source] | None:
    """Each map's name and content hash, or None when one cannot be read (the front end then says why)."""
    try:
        return [(str(path), hashlib.sha256(path.read_bytes()).hexdigest()) for path in paths]
    except OSError:
        return None


def entry_key(target: str, sources: Sequence[Source]) -> str:
    text = json.dumps({"format": ENTRY_FORMAT, "code": code_digest(), "target": target, "maps": list(sources)})
    return hashlib.sha256(text.encode()).hexdigest()


def _files_digest(files: Mapping[str, str]) -> str:
    digest = hashlib.sha256()
    for rel, content in sorted(files.items()):
        digest.update(f"{len(rel)}:{rel}{len(content)}:".encode())  # lengths first: no two file sets hash alike
        digest.update(content.encode("utf-8", "surrogatepass"))
    return digest.hexdigest()


class OutputCache:
    def __init__(self, root: Path) -> None:
        self.root = root

    @classmethod
    def from_environment(cls) -> OutputCache | None:
        """The cache the environment asks for; none when it is turned off or regmap's own files cannot be read."""
        root = cache_dir()
        if root is None:
            return None
        try:
            code_digest()
        except OSError:
            return None
        return cls(root)

    def _path(self, key: str) -> Path:
        return self.root / f"{key}.json"

    def get(self, key: str) -> Files | None:
        """The files stored under `key`, or None: missing, unreadable, corrupt or another key's entry are all misses."""
        try:
            entry = json.loads(self._path(key).read_text(encoding="utf-8"))
            files = entry["files"]
            if (
                entry["format"] != ENTRY_FORMAT
                or entry["key"] != key
                or not isinstance(files, dict)
                or not all(isinstance(k, str) and isinstance(v, str) for k, v in files.items())
                or entry["digest"] != _files_digest(files)
            ):
                return None
        except (OSError, ValueError, KeyError, TypeError):
            return None
        return files

    def put(self, key: str, files: Mapping[str, str]) -> None:
        """Store `files` under `key` atomically; a cache that cannot be written is left as it is."""
        entry = {"format": ENTRY_FORMAT, "key": key, "digest": _files_digest(files), "files": dict(files)}
        try:
            self.root.mkdir(parents=True, exist_ok=True)
            fd, temporary = tempfile.mkstemp(prefix=".entry-", suffix=".tmp", dir=self.root)
            try:
                with os.fdopen(fd, "w", encoding="utf-8") as out:
                    json.dump(entry, out, ensure_ascii=False)
                os.replace(temporary, self._path(key))
            except BaseException:
                Path(temporary).unlink(missing_ok=True)
                raise
            self._prune()
        except OSError:
            return

    def _prune(self) -> None:
        entries = sorted(self.root.glob("*.json"), key=lambda p: p.stat().st_mtime, reverse=True)
        for old in entries[KEEP_ENTRIES:]:
            old.unlink(missing_ok=True)
