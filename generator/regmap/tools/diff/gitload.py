"""Reading OLD and NEW: a map file, or `PATH@GITREV` read from git history."""

from __future__ import annotations

import os
import subprocess
from collections.abc import Callable
from pathlib import Path

from regmap.diagnostics import Diagnostic, MapError, UsageError
from regmap.frontend.load import load_map, load_map_bytes
from regmap.model import Device


def split_spec(spec: str) -> tuple[str, str | None]:
    """`PATH` or `PATH@GITREV`. An existing file is a path even if its name has an `@`; otherwise the
    split is at the first `@` after which the path names an existing file or ends in .yaml/.yml (so
    revisions like `HEAD@{1}` keep their own `@`), else at the first `@`."""
    if "@" not in spec or Path(spec).is_file():
        return spec, None
    at = [i for i, ch in enumerate(spec) if ch == "@"]
    for i in at:
        head = spec[:i]
        if Path(head).is_file() or head.endswith((".yaml", ".yml")):
            return head, spec[i + 1 :]
    return spec[: at[0]], spec[at[0] + 1 :]


def _git(where: Path, *args: str) -> subprocess.CompletedProcess[bytes]:
    env = {**os.environ, "LC_ALL": "C", "GIT_OPTIONAL_LOCKS": "0", "GIT_TERMINAL_PROMPT": "0"}
    try:
        return subprocess.run(["git", "-C", str(where), *args], capture_output=True, env=env, timeout=60, check=False)
    except FileNotFoundError:
        raise UsageError("git is not installed; it is needed to read a map at a git revision (PATH@GITREV)") from None
    except subprocess.TimeoutExpired:
        raise UsageError(f"git {' '.join(args)} did not answer within 60 s") from None


def read_at_revision(path: Path, rev: str) -> bytes | None:
    """The bytes of `path` as committed at `rev` (what `git show REV:PATH` prints), or None when the
    file did not exist there. Git runs in the file's directory with a `./`-relative path, which git
    resolves from the repository root, so PATH may be relative to anywhere and the repository may be
    any repository. An unknown revision or a directory outside git is a UsageError."""
    if not rev or rev.startswith("-") or any(ch in rev for ch in "\0\n\r"):
        raise UsageError(f"{rev!r} is not a git revision")
    where = path.parent
    if not where.is_dir():
        raise UsageError(f"{path}: the directory {where} does not exist")
    probe = _git(where, "rev-parse", "--verify", "--quiet", f"{rev}^{{commit}}")
    if probe.returncode != 0:
        if b"not a git repository" in probe.stderr:
            raise UsageError(f"{path} is not inside a git repository (needed for @{rev})")
        raise UsageError(f"unknown git revision {rev!r} in the repository of {path}")
    blob = f"{rev}:./{path.name}"
    if _git(where, "cat-file", "-e", blob).returncode != 0:
        return None
    shown = _git(where, "cat-file", "blob", blob)  # the stored bytes, no filters: the fingerprint matches a checkout
    if shown.returncode != 0:
        message = shown.stderr.decode("utf-8", "replace").strip().splitlines()
        raise UsageError(f"git could not read {path} at {rev}: {message[0] if message else 'unknown error'}")
    return shown.stdout


def _checked(name: str, load: Callable[[], Device]) -> Device:
    """Load a map; an invalid one is reported as `validate` reports it (every problem, exit 1)."""
    return load()


def _load_revision(path: str, rev: str, data: bytes) -> Device:
    return _checked(f"{path}@{rev}", lambda: load_map_bytes(data, f"{path}@{rev}"))


def load_spec(spec: str) -> Device:
    """The `Device` of a diff argument: a map file, or `PATH@GITREV` read from git history."""
    path, rev = split_spec(spec)
    if rev is None:
        if not Path(path).is_file():
            raise MapError([Diagnostic(path, 1, 1, "no such map file")])
        return _checked(path, lambda: load_map(path))
    data = read_at_revision(Path(path), rev)
    if data is None:
        raise MapError([Diagnostic(f"{path}@{rev}", 1, 1, f"{path} does not exist at git revision {rev}")])
    return _load_revision(path, rev, data)
