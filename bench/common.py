"""What every benchmark shares: paths, repeated timing with medians, machine facts, helpers."""

from __future__ import annotations

import importlib
import os
import platform
import re
import shutil
import socket
import statistics
import subprocess
import sys
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from types import ModuleType
from typing import Any

ROOT = Path(__file__).resolve().parent.parent
MAPS = sorted((ROOT / "maps").glob("*.yaml"))
FIXTURE_MAPS = sorted((ROOT / "tests" / "maps" / "fixtures").glob("*.yaml"))
"""Issue #19's made-up devices (spaces, poll classes, firmware gates): read-plan optimality only."""
GENERATED = ROOT / "generated"
GENERATED_PY = GENERATED / "python"


def use_generated_python() -> None:
    """Import the committed generated clients (and their versioned copy of regmap_runtime), as a user would."""
    if str(GENERATED_PY) not in sys.path:
        sys.path.insert(0, str(GENERATED_PY))


def client_module(device_id: str) -> ModuleType:
    use_generated_python()
    return importlib.import_module(device_id)


def client_class(module: ModuleType) -> Any:
    """The blocking client class a generated module defines (the one `DEVICE` belongs to)."""
    from regmap.backends.python import runtime_package

    SyncClient = importlib.import_module(f"{runtime_package()}.client").SyncClient

    for value in vars(module).values():
        if isinstance(value, type) and issubclass(value, SyncClient) and value is not SyncClient and value.__module__ == module.__name__:
            return value
    raise LookupError(f"{module.__name__} defines no SyncClient subclass")


def median(values: list[float]) -> float:
    return statistics.median(values)


def spread(values: list[float]) -> tuple[float, float]:
    return min(values), max(values)


def time_call(fn: Callable[[], object], repeats: int, number: int = 1) -> list[float]:
    """Seconds per call of `fn`, one sample per repeat (each the mean of `number` calls)."""
    samples = []
    for _ in range(repeats):
        start = time.perf_counter()
        for _ in range(number):
            fn()
        samples.append((time.perf_counter() - start) / number)
    return samples


@dataclass(frozen=True)
class Pair:
    """Interleaved samples of two callables: wall and process-CPU seconds per call of each."""

    wall_a: tuple[float, ...]
    wall_b: tuple[float, ...]
    cpu_a: tuple[float, ...]
    cpu_b: tuple[float, ...]


def side_by_side(a: Callable[[], object], b: Callable[[], object], repeats: int, number: int = 1) -> Pair:
    """Time `a` and `b` alternately (ABBA order, so drift and warm-up hit both alike)."""
    samples: dict[str, list[float]] = {"wall_a": [], "wall_b": [], "cpu_a": [], "cpu_b": []}
    for i in range(repeats):
        order = (("a", a), ("b", b)) if i % 2 == 0 else (("b", b), ("a", a))
        for key, fn in order:
            cpu = time.process_time()
            start = time.perf_counter()
            for _ in range(number):
                fn()
            samples[f"wall_{key}"].append((time.perf_counter() - start) / number)
            samples[f"cpu_{key}"].append((time.process_time() - cpu) / number)
    return Pair(**{k: tuple(v) for k, v in samples.items()})


def calibrate(fn: Callable[[], object], target_s: float = 0.02) -> int:
    """Calls per sample so one sample lasts about `target_s` (timer resolution stops mattering)."""
    number = 1
    while True:
        start = time.perf_counter()
        for _ in range(number):
            fn()
        elapsed = time.perf_counter() - start
        if elapsed >= target_s or number >= 1 << 20:
            return number
        number = max(number * 2, int(number * target_s / max(elapsed, 1e-9)))


def free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        return int(sock.getsockname()[1])


def wait_for_port(port: int, timeout: float = 20.0) -> None:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        with socket.socket() as sock:
            sock.settimeout(0.2)
            if sock.connect_ex(("127.0.0.1", port)) == 0:
                return
        time.sleep(0.02)
    raise TimeoutError(f"nothing listens on 127.0.0.1:{port} after {timeout} s")


def regmap_command() -> list[str]:
    """How a user runs regmap from this checkout: the venv's console script."""
    script = Path(sys.executable).parent / "regmap"
    return [str(script)] if script.exists() else [sys.executable, "-m", "regmap"]


@contextmanager
def stage(name: str) -> Iterator[None]:
    """Print how long a stage of `make bench` took (stderr, so the report stays clean)."""
    start = time.perf_counter()
    print(f"bench: {name} ...", file=sys.stderr, flush=True)
    yield
    print(f"bench: {name} done in {time.perf_counter() - start:.1f} s", file=sys.stderr, flush=True)


@dataclass(frozen=True)
class Machine:
    cpu: str
    cores: int
    os: str
    python: str
    packages: tuple[tuple[str, str], ...]
    tools: tuple[tuple[str, str], ...]
    load_before: str
    notes: tuple[str, ...]


def _cpu_model() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text(encoding="utf-8").splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def _version(module: str) -> str:
    try:
        from importlib.metadata import version

        return version(module)
    except Exception:
        return "not installed"


def _tool_version(tool: str) -> str:
    path = shutil.which(tool)
    if path is None:
        return "not installed"
    try:
        out = subprocess.run([path, "--version"], capture_output=True, text=True, timeout=20, check=False).stdout
    except (OSError, subprocess.TimeoutExpired):
        return "unknown"
    first = out.splitlines()[0] if out else "unknown"
    found = re.search(r"\d+\.\d+(\.\d+)?", first)
    return found.group(0) if found else first


def machine() -> Machine:
    import yaml

    notes = []
    if os.environ.get("PYTHONDONTWRITEBYTECODE"):
        notes.append(
            "PYTHONDONTWRITEBYTECODE is set here, so regmap's own modules are compiled from source on every run; "
            "the whole-process generation times below are measured with a bytecode cache (PYTHONPYCACHEPREFIX in a temp dir), "
            "as an installed regmap would run."
        )
    load = " / ".join(f"{x:.2f}" for x in os.getloadavg())
    return Machine(
        cpu=_cpu_model(),
        cores=os.cpu_count() or 1,
        os=f"{platform.system()} {platform.release()} ({platform.machine()})",
        python=f"{platform.python_implementation()} {platform.python_version()}",
        packages=(
            ("pymodbus", _version("pymodbus")),
            ("PyYAML", f"{_version('PyYAML')} (libyaml {'available' if yaml.__with_libyaml__ else 'missing'})"),
            ("Jinja2", _version("Jinja2")),
            ("jsonschema", _version("jsonschema")),
            ("ruff", _version("ruff")),
        ),
        tools=tuple((t, _tool_version(t)) for t in ("gcc", "arm-none-eabi-gcc")),
        load_before=load,
        notes=tuple(notes),
    )
