"""The generated Python tree's packaging: the vendored runtime under its digest name, and ruff format."""

from __future__ import annotations

import functools
import hashlib
import subprocess
import sys
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
    try:
        from ruff.__main__ import find_ruff_bin
    except ImportError:  # pragma: no cover - ruff is a declared dependency
        raise UsageError("ruff is not installed; it formats the generated Python (pip install ruff)") from None
    files = sorted(str(p) for p in directory.rglob("*.py") if skip not in p.relative_to(directory).parts)
    if not files:
        return
    config = ["--config", "line-length = 120", "--config", "target-version = 'py311'"]
    result = subprocess.run(
        [find_ruff_bin(), "format", "--quiet", "--no-cache", "--isolated", *config, *files],
        capture_output=True,
        text=True,
        check=False,
    )
    if result.returncode != 0:
        sys.stderr.write(result.stderr)
        raise UsageError("ruff could not format the generated Python (a template bug): see above")


def _post(directory: Path) -> None:
    ruff_format(directory, skip=runtime_package())


def post(directory: Path) -> None:
    ruff_format(directory, skip=runtime_package())
