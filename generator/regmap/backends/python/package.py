"""The generated Python tree's packaging: the vendored runtime under its digest name, and ruff format."""

from __future__ import annotations

import functools
import hashlib
import os
import signal
import sys
import sysconfig
from pathlib import Path
from typing import Any

import regmap_runtime
from regmap.diagnostics import UsageError
from regmap.target import Files

RUNTIME_MODULES = (
    "__init__.py",
    "align.py",
    "base.py",
    "bits.py",
    "client.py",
    "codec.py",
    "errors.py",
    "line.py",
    "plan.py",
    "plant.py",
    "profile.py",
    "rtu.py",
    "scaling.py",
    "spaces.py",
    "spec.py",
    "timestamps.py",
    "types.py",
    "wire.py",
)


def _runtime_source() -> Path:
    """The runtime's own directory (as the output cache reads it; importlib.resources would cost a generate run
    the import of it and its readers)."""
    return Path(regmap_runtime.__file__ or "").parent


@functools.cache
def runtime_package() -> str:
    """The name the vendored runtime gets in a generated tree: `regmap_runtime_` and a digest of its
    source, so two generated trees from different regmap versions on one sys.path cannot shadow each
    other's runtime (and two of the same version share one, identical, copy)."""
    source = _runtime_source()
    digest = hashlib.sha256()
    for module in RUNTIME_MODULES:
        digest.update(module.encode() + b"\0" + (source / module).read_bytes() + b"\0")
    return f"regmap_runtime_{digest.hexdigest()[:10]}"


def render_shared(devices: Any) -> Files:
    """The runtime, copied byte for byte (its modules import each other relatively)."""
    package = runtime_package()
    files: Files = {f"{package}/py.typed": ""}
    source = _runtime_source()
    for module in RUNTIME_MODULES:
        files[f"{package}/{module}"] = (source / module).read_text(encoding="utf-8")
    return files


def ruff_format(directory: Path, *, skip: str) -> None:
    """Format generated Python with ruff (a dependency of regmap, so output is the same everywhere); the vendored
    runtime (`skip`) stays byte for byte its source."""
    files = sorted(str(p) for p in directory.rglob("*.py") if skip not in p.relative_to(directory).parts)
    if not files:
        return
    config = ["--config", "line-length = 120", "--config", "target-version = 'py311'"]
    returncode, stderr = _run([_ruff_bin(), "format", "--quiet", "--no-cache", "--isolated", *config, *files])
    if returncode != 0:
        sys.stderr.write(stderr)
        raise UsageError("ruff could not format the generated Python (a template bug): see above")


def _ruff_bin() -> str:
    """The binary ruff's own `find_ruff_bin()` finds. Its first choice, the running environment's scripts directory,
    is looked at here without sysconfig's configuration variables: loading them cost a cold run about 7 ms."""
    scheme = sysconfig.get_preferred_scheme("prefix")
    if os.name == "posix" and sys.platform != "cygwin" and sysconfig.get_path("scripts", scheme, expand=False) == "{base}/bin":
        first_choice = os.path.join(os.path.normpath(sys.prefix), "bin", "ruff")
        if os.path.isfile(first_choice):
            return first_choice
    try:
        from ruff.__main__ import find_ruff_bin
    except ImportError:  # pragma: no cover - ruff is a declared dependency
        raise UsageError("ruff is not installed; it formats the generated Python (pip install ruff)") from None
    found: str = find_ruff_bin()
    return found


def _run(argv: list[str]) -> tuple[int, str]:
    """Run `argv` and return its exit status and what it wrote to standard error (its standard output is dropped).
    Spawned directly where the system can: importing subprocess cost a cold run about 5 ms."""
    if not hasattr(os, "posix_spawn"):  # pragma: no cover - Windows
        import subprocess

        result = subprocess.run(argv, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, check=False)
        return result.returncode, result.stderr
    read_end, write_end = os.pipe()  # both close on exec: the child gets only the copy made its standard error
    try:
        actions = [(os.POSIX_SPAWN_OPEN, 1, os.devnull, os.O_WRONLY, 0), (os.POSIX_SPAWN_DUP2, write_end, 2)]
        pid = os.posix_spawn(argv[0], argv, os.environ, file_actions=actions)
    except BaseException:
        os.close(read_end)
        raise
    finally:
        os.close(write_end)
    try:
        with os.fdopen(read_end, "rb") as errors:
            stderr = errors.read()
        _, status = os.waitpid(pid, 0)
    except BaseException:  # interrupted: no ruff left running, as subprocess.run would leave none
        os.kill(pid, signal.SIGKILL)
        os.waitpid(pid, 0)
        raise
    return os.waitstatus_to_exitcode(status), stderr.decode("utf-8", "replace")


def post(directory: Path) -> None:
    ruff_format(directory, skip=runtime_package())
