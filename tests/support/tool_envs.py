"""The third-party tools the tests judge generated output with, each in an environment of its own.

`make tools` (which `make test` runs first) builds them; the tests only look them up, so no install ever
runs inside a timed test. Each environment is rebuilt only when its pins change: it lives under a cache
directory outside the work tree (`$REGMAP_TOOLS_DIR`, default `~/.cache/regmap/tools`), named by a digest
of its pins, so every clone on the machine shares it. A stamp written last marks an environment complete;
one without its stamp (an interrupted build) is removed and built again.

    python tests/support/tool_envs.py install [NAME ...]   # build what is missing; exit 1 under CI=true if any fails
    python tests/support/tool_envs.py status               # one line per tool: ready, missing, or why it cannot be built
"""

from __future__ import annotations

import argparse
import hashlib
import os
import shutil
import subprocess
import sys
import tarfile
import tempfile
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
# ../shared beside the clone; REGMAP_SHARED_DIR points elsewhere (a worktree nested one level deeper).
SHARED_TOOLS = Path(os.environ.get("REGMAP_SHARED_DIR") or ROOT.parent / "shared") / "tools"
MATIEC_TARBALL = SHARED_TOOLS / "matiec" / "matiec-6bb2c33.tar.gz"
STAMP = ".regmap-complete"


@dataclass(frozen=True)
class VenvTool:
    """A PyPI tool in a venv of its own (its pins are not regmap's)."""

    name: str
    executable: str  # relative to the venv
    pins: tuple[str, ...]
    why: str

    def digest(self) -> str:
        return hashlib.sha256("\n".join((sys.version.split()[0], *self.pins)).encode()).hexdigest()[:12]


@dataclass(frozen=True)
class SourceTool:
    """A tool built from a tarball under ../shared/tools (no registry serves it)."""

    name: str
    tarball: Path
    executables: tuple[str, ...]
    why: str

    def digest(self) -> str:
        if not self.tarball.exists():
            return "absent"
        return hashlib.sha256(self.tarball.read_bytes()).hexdigest()[:12]


# Newest releases that install on the Python regmap supports (3.11): ESPHome 2026.6.5; Home Assistant
# 2024.3.3 (2024.4 needs 3.12). pymodbus is the modbus integration's own pin (its manifest), colorlog
# the check_config script's, SQLAlchemy, fnv-hash-fast and psutil-home-assistant the recorder's (the running-HA
# test reads the states it records), so neither the check nor a run installs anything.
VENV_TOOLS = {
    tool.name: tool
    for tool in (
        VenvTool("esphome", "bin/esphome", ("esphome==2026.6.5",), "validates the generated ESPHome packages"),
        VenvTool(
            "hass",
            "bin/hass",
            (
                "homeassistant==2024.3.3",
                "pymodbus==3.6.6",
                "colorlog==6.8.2",
                "SQLAlchemy==2.0.27",
                "fnv-hash-fast==0.5.0",
                "psutil-home-assistant==0.0.1",
            ),
            "checks and runs the generated Home Assistant configuration",
        ),
        VenvTool(
            "st",
            "bin/python",
            ("blark==0.8.3", "tree-sitter-iec61131-3-st==0.1.2", "tree-sitter>=0.23"),
            "parses the generated Structured Text (TwinCAT's grammar and the plain standard's)",
        ),
        VenvTool("plcopen", "bin/python", ("lxml==6.0.2",), "validates the generated PLCopen XML against the TC6 XML v2.01 schema"),
        VenvTool(
            "sunspec",
            "bin/python",
            ("pysunspec2==1.3.7",),
            "ships the SunSpec model definitions and decodes and scans SunSpec devices (the cross-check of the SunSpec maps)",
        ),
    )
}
SOURCE_TOOLS = {
    "matiec": SourceTool(
        "matiec", MATIEC_TARBALL, ("iec2c", "iec2iec"), "compiles the generated IEC 61131-3 ST (OpenPLC's and Beremiz's compiler)"
    ),
}
NAMES = (*VENV_TOOLS, *SOURCE_TOOLS)


class ToolUnavailable(Exception):
    """A tool that is not built here, with the reason."""


def tools_dir() -> Path:
    configured = os.environ.get("REGMAP_TOOLS_DIR")
    if configured:
        return Path(configured)
    cache = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(cache) / "regmap" / "tools"


def location(name: str) -> Path:
    tool = VENV_TOOLS.get(name) or SOURCE_TOOLS[name]
    return tools_dir() / f"{name}-{tool.digest()}"


def _complete(path: Path, name: str) -> bool:
    stamp = path / STAMP
    return stamp.is_file() and stamp.read_text(encoding="utf-8") == name


def find(name: str) -> Path:
    """The tool's executable (for matiec: the directory holding iec2c, iec2iec and lib/), or ToolUnavailable."""
    if name in SOURCE_TOOLS and not SOURCE_TOOLS[name].tarball.exists():
        raise ToolUnavailable(f"{name}: its source {SOURCE_TOOLS[name].tarball} is absent (a clone outside the shared layout)")
    path = location(name)
    if not _complete(path, name):
        raise ToolUnavailable(f"{name} is not built in {path}: run `make tools`")
    if name in VENV_TOOLS:
        return path / VENV_TOOLS[name].executable
    return path


def _run(argv: Sequence[str], cwd: Path | None = None) -> None:
    result = subprocess.run(list(argv), cwd=cwd, capture_output=True, text=True, check=False)
    if result.returncode != 0:
        tail = "\n".join((result.stdout + result.stderr).strip().splitlines()[-15:])
        raise ToolUnavailable(f"`{' '.join(argv)}` failed (exit {result.returncode}):\n{tail}")


def _build_venv(tool: VenvTool, path: Path) -> None:
    _run([sys.executable, "-m", "venv", str(path)])
    _run([str(path / "bin" / "pip"), "install", "--quiet", "--disable-pip-version-check", *tool.pins])


def _build_source(tool: SourceTool, path: Path) -> None:
    missing = [program for program in ("flex", "bison", "autoreconf", "make", "g++") if shutil.which(program) is None]
    if missing:
        raise ToolUnavailable(f"{tool.name} needs {', '.join(missing)} to build (Debian: flex bison autoconf automake g++ make)")
    with tempfile.TemporaryDirectory(prefix=f"regmap-{tool.name}-") as scratch, tarfile.open(tool.tarball) as archive:
        archive.extractall(scratch, filter="data")
        (source,) = [entry for entry in Path(scratch).iterdir() if entry.is_dir()]
        _run(["autoreconf", "-i"], cwd=source)
        _run(["./configure"], cwd=source)
        _run(["make", f"-j{os.cpu_count() or 2}"], cwd=source)
        path.mkdir(parents=True)
        for executable in tool.executables:
            shutil.copy2(source / executable, path / executable)
        shutil.copytree(source / "lib", path / "lib")


def install(name: str) -> Path:
    """Build the tool unless a complete build with the same pins is there; its location."""
    path = location(name)
    if _complete(path, name):
        return path
    if path.exists():
        shutil.rmtree(path)  # an interrupted build: never taken for a finished one
    path.parent.mkdir(parents=True, exist_ok=True)
    try:
        if name in VENV_TOOLS:
            _build_venv(VENV_TOOLS[name], path)
        else:
            tool = SOURCE_TOOLS[name]
            if not tool.tarball.exists():
                raise ToolUnavailable(f"{name}: its source {tool.tarball} is absent (a clone outside the shared layout)")
            _build_source(tool, path)
    except BaseException:
        shutil.rmtree(path, ignore_errors=True)
        raise
    (path / STAMP).write_text(name, encoding="utf-8")
    return path


def _stale(name: str) -> list[Path]:
    """Builds of this tool with other pins, left by an earlier version of this file."""
    current = location(name)
    return [entry for entry in tools_dir().glob(f"{name}-*") if entry != current and entry.is_dir()]


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="tests/support/tool_envs.py", description=__doc__.split("\n\n")[0])
    parser.add_argument("action", choices=("install", "status"))
    parser.add_argument("names", nargs="*", metavar="NAME", help=f"default: all of {', '.join(NAMES)}")
    args = parser.parse_args(argv)
    unknown = [name for name in args.names if name not in NAMES]
    if unknown:
        parser.error(f"unknown tool {', '.join(unknown)} (known: {', '.join(NAMES)})")
    names = args.names or list(NAMES)
    failed = 0
    for name in names:
        if args.action == "status":
            try:
                print(f"{name}: ready: {find(name)}")
            except ToolUnavailable as exc:
                print(f"{name}: {exc}")
            continue
        try:
            print(f"tools: {name}: {install(name)}", flush=True)
        except ToolUnavailable as exc:
            failed += 1
            print(f"tools: {name}: not available, the tests that need it will skip ({exc})", file=sys.stderr, flush=True)
            continue
        for old in _stale(name):
            shutil.rmtree(old, ignore_errors=True)
    if failed and os.environ.get("CI") == "true":
        print(f"tools: {failed} tool(s) could not be built, and CI=true needs them all", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
