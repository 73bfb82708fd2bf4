"""Shared fixtures: paths, tool requirements, simulators on loopback TCP and on pseudo-terminals."""

from __future__ import annotations

import os
import select
import shutil
import socket
import subprocess
import sys
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any, NoReturn

import pytest
from hypothesis import settings

# Hypothesis' per-example deadline is a timing assertion: on a busy machine it fails tests whose subject is not speed
# (speed lives in `make bench`).
settings.register_profile("regmap", deadline=None)
settings.load_profile("regmap")

# Every test, and every `regmap` a test starts, renders from the maps: a stale output cache must not be able to hide a
# drift, and no test writes into the user's cache. tests/backends/test_generate_cache.py turns it on in a temp dir.
os.environ["REGMAP_NO_CACHE"] = "1"

ROOT = Path(__file__).resolve().parent.parent
MAPS = sorted((ROOT / "maps").glob("*.yaml"))
SMALL_MAPS = sorted((ROOT / "tests" / "maps" / "small").glob("*.yaml"))
FIXTURE_MAPS = sorted((ROOT / "tests" / "maps" / "fixtures").glob("*.yaml"))
"""Made-up devices (issue #19): input registers, coils, floats, strings, byte swaps, firmware gates."""
GENERATED = ROOT / "generated"
GENERATED_PY = GENERATED / "python"

if str(GENERATED_PY) not in sys.path:
    sys.path.insert(0, str(GENERATED_PY))


def generated_runtime_name() -> str:
    """The versioned name of the runtime copy in generated/python (regmap_runtime_<digest>)."""
    from regmap.backends.python import runtime_package

    return runtime_package()


def generated_runtime(module: str) -> Any:
    """A module of the runtime copy the committed generated clients import (their errors are its errors)."""
    import importlib

    return importlib.import_module(f"{generated_runtime_name()}.{module}")


_SMALL_PY: list[Path] = []


def small_maps_python() -> Path:
    """Python clients of the small fixture maps (not committed under generated/), made once per run."""
    if not _SMALL_PY:
        import tempfile

        from regmap.frontend import load_map
        from regmap.generate import generate

        out = Path(tempfile.mkdtemp(prefix="regmap-small-")) / "generated"
        generate([load_map(p) for p in SMALL_MAPS], out, ["python"], complete=True)
        _SMALL_PY.append(out / "python")
        sys.path.append(str(out / "python"))
    return _SMALL_PY[0]


_FIXTURES_OUT: list[Path] = []


def fixture_maps_generated() -> Path:
    """Every target generated for the fixture maps (not committed under generated/), made once per run;
    its python/ directory is importable."""
    if not _FIXTURES_OUT:
        import tempfile

        from regmap.frontend import load_map
        from regmap.generate import generate, target_names

        out = Path(tempfile.mkdtemp(prefix="regmap-fixtures-")) / "generated"
        generate([load_map(p) for p in FIXTURE_MAPS], out, target_names(), complete=True)
        _FIXTURES_OUT.append(out)
        sys.path.append(str(out / "python"))
    return _FIXTURES_OUT[0]


def require_tool(name: str) -> str:
    """Path of a system tool; skip without it, except under CI=true where its absence is a failure."""
    path = shutil.which(name)
    if path is None:
        skip_or_fail(f"{name} is not installed (.ci/run installs it)")
    return path


def mypy_strict(*targets: str, cwd: Path = GENERATED_PY) -> subprocess.CompletedProcess[str]:
    """mypy --strict on generated code, with the generated packages (and nothing else) importable."""
    return subprocess.run(
        [sys.executable, "-m", "mypy", "--strict", "--no-incremental", *targets],
        cwd=cwd,
        capture_output=True,
        text=True,
        check=False,
        env={"MYPYPATH": str(cwd), "PATH": "/usr/bin:/bin"},
    )


def free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        return int(sock.getsockname()[1])


def wait_for(condition: Callable[[], bool], timeout: float, what: str) -> None:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if condition():
            return
        time.sleep(0.05)
    raise AssertionError(f"timed out waiting for {what}")


def _port_open(port: int) -> bool:
    with socket.socket() as sock:
        sock.settimeout(0.2)
        return sock.connect_ex(("127.0.0.1", port)) == 0


@dataclass
class RunningSimulator:
    process: subprocess.Popen[str]
    port: int | None = None
    serial: str | None = None
    banner: str = ""  # the "serving" line, read before the test starts

    def stop(self) -> str:
        if self.process.poll() is None:
            self.process.terminate()
            try:
                self.process.wait(timeout=10)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()
        out = self.process.stdout.read() if self.process.stdout else ""
        return self.banner + out


SimulatorFactory = Callable[..., RunningSimulator]


@pytest.fixture
def simulator(tmp_path: Path) -> Iterator[SimulatorFactory]:
    """Start `regmap simulate` as a real process; stopped at the end of the test."""
    running: list[RunningSimulator] = []

    def start(map_path: Path, *extra: str, serial: str | None = None, slave: int = 1) -> RunningSimulator:
        cmd = [sys.executable, "-m", "regmap", "simulate", str(map_path), "--slave", str(slave), *extra]
        port = None
        if serial is None:
            port = free_port()
            cmd += ["--tcp", f"127.0.0.1:{port}"]
        else:
            cmd += ["--serial", serial]
        process = subprocess.Popen(cmd, cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        sim = RunningSimulator(process, port, serial)
        running.append(sim)
        if port is not None:
            wait_for(lambda: _port_open(port) or process.poll() is not None, 20, "the simulator to listen")
        else:
            # No port to poll: the simulator prints its "serving" line once the pty is open.
            deadline = time.monotonic() + 20
            while time.monotonic() < deadline and process.poll() is None and process.stdout is not None:
                if select.select([process.stdout], [], [], 0.1)[0]:
                    sim.banner = process.stdout.readline()
                    break
        if process.poll() is not None:
            raise AssertionError(f"simulator exited: {sim.stop()}")
        return sim

    yield start
    for sim in running:
        sim.stop()


@dataclass
class PtyPair:
    device: str  # the simulator's end
    client: str  # the client's end


@pytest.fixture
def pty_pair(tmp_path: Path) -> Iterator[PtyPair]:
    """Two linked pseudo-terminals from socat: an RS-485 line on one machine."""
    socat = require_tool("socat")
    a, b = tmp_path / "dev-a", tmp_path / "dev-b"
    process = subprocess.Popen(
        [socat, "-d", f"pty,raw,echo=0,link={a}", f"pty,raw,echo=0,link={b}"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL
    )
    try:
        wait_for(lambda: a.exists() and b.exists(), 10, "socat's pseudo-terminals")
        yield PtyPair(str(a), str(b))
    finally:
        process.terminate()
        process.wait(timeout=10)


# -- the third-party tools (ESPHome, Home Assistant, the ST parsers, matiec), built by `make tools` --------


def skip_or_fail(message: str) -> NoReturn:
    """A test that cannot run here: a skip with the reason, except under CI=true, where .ci/run provides
    everything and a missing tool is a failure."""
    if os.environ.get("CI") == "true":
        pytest.fail(message)
    pytest.skip(message)


def built_tool(name: str) -> Path:
    """A tool from tests/support/tool_envs.py, built beforehand by `make tools`; never installed here."""
    from support import tool_envs

    try:
        return tool_envs.find(name)
    except tool_envs.ToolUnavailable as exc:
        skip_or_fail(str(exc))


SHARED = Path(os.environ.get("REGMAP_SHARED_DIR") or ROOT.parent / "shared")  # as tests/support/tool_envs.py
MANUALS = SHARED / "manuals"


def manual(name: str) -> Path:
    """A manual's text from ../shared/manuals; a clone outside that layout skips the test (CI=true fails it)."""
    path = MANUALS / name
    if not path.is_file():
        skip_or_fail(f"{path} is absent: the manuals are beside the repository only in the shared layout")
    return path


@pytest.fixture(scope="session")
def esphome() -> Path:
    return built_tool("esphome")


@pytest.fixture(scope="session")
def hass() -> Path:
    return built_tool("hass")
