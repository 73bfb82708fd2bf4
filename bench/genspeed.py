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
    profile_label: str = ""
    profile: list[tuple[str, int, float, float]] = field(default_factory=list)  # function, calls, own s, cumulative s

    def synthetic_run(self, registers: int) -> GenRun | None:
        return next((r for r in self.synthetic if r.registers == registers), None)

    def targets_met(self, size: int) -> bool:
        """The generation targets as far as measured: maps < 1 s, 10k < 3 s, 1k -> 10k growth <= 12x."""
        run = self.synthetic_run(size)
        growth = self.growth(1000, 10000)
        return (
            self.three_maps.wall < 1.0
            and (run is None or (run.timed_out_after is None and (size != 10000 or run.wall < 3.0)))
            and (growth is None or growth <= 12.0)
        )

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
        self.env["REGMAP_NO_CACHE"] = "1"  # every run renders: the output cache's warm figure is bench/floor.py's

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
        spent, _ = self._phases(maps, profile=False)
        return spent

    def profile(self, maps: list[Path]) -> list[tuple[str, int, float, float]]:
        _, top = self._phases(maps, profile=True)
        return top

    def _phases(self, maps: list[Path], profile: bool) -> tuple[dict[str, float], list[tuple[str, int, float, float]]]:
        out = Path(tempfile.mkdtemp(prefix="phases-", dir=self.work))
        flags = ["--profile"] if profile else []
        cmd = [sys.executable, "-m", "bench.phases", *flags, str(out / "generated"), *(str(m) for m in maps)]
        result = subprocess.run(cmd, cwd=ROOT, env=self.env, capture_output=True, text=True, check=False)
        shutil.rmtree(out, ignore_errors=True)
        lines = result.stdout.strip().splitlines()
        if result.returncode != 0 or not lines:
            raise RuntimeError(f"bench.phases failed:\n{result.stdout}{result.stderr}")
        found = json.loads(lines[-1])
        spent: dict[str, float] = found["spent"]
        return spent, [(str(f), int(c), float(o), float(u)) for f, c, o, u in found["top"]]


def registers_in(maps: list[Path]) -> int:
    from regmap.frontend import load_map

    return sum(len(load_map(m).registers) for m in maps)


def measure(
    sizes: tuple[int, ...] = (1000, 2000, 5000, 10000, 20000, 50000),
    repeats: int = 5,
    budget_s: float = 180.0,
    maps: list[Path] | None = None,
) -> GenSpeed:
    """The maps (default: the three) `repeats` times; each synthetic size fewer times as it grows;
    the stage breakdown of the maps and of 10k registers. Sizes above 10k run once and are stopped
    when this section's time budget runs out (at most 60 s each), so `make bench` stays short."""
    started = time.perf_counter()
    maps = list(MAPS) if maps is None else maps
    label = "the three maps" if maps == list(MAPS) else ", ".join(m.stem for m in maps)
    with tempfile.TemporaryDirectory(prefix="regmap-bench-gen-") as tmp:
        work = Path(tmp)
        runner = Runner(work)
        runner.once(maps)  # warm-up: fills the bytecode cache
        speed = GenSpeed(runner.runs(label, registers_in(maps), maps, repeats))
        speed.phases[label] = runner.phases(maps)
        for size in sizes:
            path = write_synthetic_map(work, size)
            if size > 10000:
                left = budget_s - (time.perf_counter() - started)
                speed.synthetic.append(runner.runs(f"synthetic {size}", size, [path], 1, timeout=max(1.0, min(60.0, left))))
            else:
                count = repeats if size <= 1000 else 3 if size in (2000, 10000) else 1
                speed.synthetic.append(runner.runs(f"synthetic {size}", size, [path], count))
            if size == 10000:
                speed.phases[f"synthetic {size}"] = runner.phases([path])
                if not speed.targets_met(size):  # a missed target: profile the case that shows it most
                    speed.profile_label, speed.profile = f"synthetic {size}", runner.profile([path])
        return speed
