"""Generation speed: whole-process wall time of `regmap generate`, for the three maps and for
synthetic maps of growing size, plus a per-stage breakdown of the slowest case.

Every run writes into a fresh temp directory. Runs use a bytecode cache in a temp dir (and one
untimed warm-up), so the figures are those of an installed regmap even where PYTHONDONTWRITEBYTECODE
is set; nothing is written into the checkout.
"""

from __future__ import annotations

import json
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

from bench.common import MAPS, ROOT, median, regmap_command
from bench.synth import write_synthetic_map


@dataclass(frozen=True)
class GenRun:
    label: str
    registers: int
    maps: int
    wall_s: tuple[float, ...]  # one per run
    cpu_s: tuple[float, ...]  # user + system of the child process
    files: int
    timed_out_after: float | None = None  # set when the run was stopped

    @property
    def wall(self) -> float:
        return median(list(self.wall_s)) if self.wall_s else float("nan")

    @property
    def cpu(self) -> float:
        return median(list(self.cpu_s)) if self.cpu_s else float("nan")


@dataclass
class GenSpeed:
    three_maps: GenRun
    synthetic: list[GenRun] = field(default_factory=list)
    phases: dict[str, dict[str, float]] = field(default_factory=dict)  # label -> stage -> seconds

    def synthetic_run(self, registers: int) -> GenRun | None:
        return next((r for r in self.synthetic if r.registers == registers), None)

    def growth(self, small: int, large: int) -> float | None:
        a, b = self.synthetic_run(small), self.synthetic_run(large)
        if a is None or b is None or b.timed_out_after is not None:
            return None
        return b.wall / a.wall


class Runner:
    """Runs `regmap generate` as a user would, with a private bytecode cache."""

    def __init__(self, work: Path) -> None:
        self.work = work
        self.env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
        self.env["PYTHONPYCACHEPREFIX"] = str(work / "pycache")

    def once(self, maps: list[Path], timeout: float | None = None) -> tuple[float, float, int] | None:
        """(wall seconds, cpu seconds, files written), or None when stopped at `timeout`."""
        out = Path(tempfile.mkdtemp(prefix="out-", dir=self.work))
        cmd = [*regmap_command(), "generate", *(str(m) for m in maps), "--out", str(out / "generated")]
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        start = time.perf_counter()
        try:
            result = subprocess.run(cmd, cwd=ROOT, env=self.env, capture_output=True, text=True, timeout=timeout, check=False)
        except subprocess.TimeoutExpired:
            shutil.rmtree(out, ignore_errors=True)
            return None
        wall = time.perf_counter() - start
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        if result.returncode != 0:
            raise RuntimeError(f"{' '.join(cmd)} failed ({result.returncode}):\n{result.stdout}{result.stderr}")
        files = sum(1 for p in (out / "generated").rglob("*") if p.is_file())
        shutil.rmtree(out, ignore_errors=True)
        cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
        return wall, cpu, files

    def runs(self, label: str, registers: int, maps: list[Path], repeats: int, timeout: float | None = None) -> GenRun:
        walls: list[float] = []
        cpus: list[float] = []
        files = 0
        for _ in range(repeats):
            measured = self.once(maps, timeout)
            if measured is None:
                assert timeout is not None
                return GenRun(label, registers, len(maps), tuple(walls), tuple(cpus), files, timed_out_after=timeout)
            wall, cpu, files = measured
            walls.append(wall)
            cpus.append(cpu)
        return GenRun(label, registers, len(maps), tuple(walls), tuple(cpus), files)

    def phases(self, maps: list[Path]) -> dict[str, float]:
        out = Path(tempfile.mkdtemp(prefix="phases-", dir=self.work))
        cmd = [sys.executable, "-m", "bench.phases", str(out / "generated"), *(str(m) for m in maps)]
        result = subprocess.run(cmd, cwd=ROOT, env=self.env, capture_output=True, text=True, check=False)
        shutil.rmtree(out, ignore_errors=True)
        lines = result.stdout.strip().splitlines()
        if result.returncode != 0 or not lines:
            raise RuntimeError(f"bench.phases failed:\n{result.stdout}{result.stderr}")
        spent: dict[str, float] = json.loads(lines[-1])["spent"]
        return spent


def registers_in(maps: list[Path]) -> int:
    from regmap.frontend import load_map

    return sum(len(load_map(m).registers) for m in maps)


def measure(sizes: tuple[int, ...] = (1000, 10000, 50000), repeats: int = 5, big_timeout: float = 90.0) -> GenSpeed:
    """Three maps `repeats` times; each synthetic size fewer times as it grows (the largest once,
    stopped after `big_timeout` seconds); then the stage breakdown of the three maps and of 10k."""
    with tempfile.TemporaryDirectory(prefix="regmap-bench-gen-") as tmp:
        work = Path(tmp)
        runner = Runner(work)
        runner.once(list(MAPS))  # warm-up: fills the bytecode cache
        speed = GenSpeed(runner.runs("the three maps", registers_in(list(MAPS)), list(MAPS), repeats))
        speed.phases["the three maps"] = runner.phases(list(MAPS))
        for size in sizes:
            path = write_synthetic_map(work, size)
            if size >= 50000:
                speed.synthetic.append(runner.runs(f"synthetic {size}", size, [path], 1, timeout=big_timeout))
            else:
                count = repeats if size <= 1000 else max(1, repeats - 2)
                speed.synthetic.append(runner.runs(f"synthetic {size}", size, [path], count))
            if size == 10000:
                speed.phases[f"synthetic {size}"] = runner.phases([path])
        return speed
