"""`regmap simulate` under load, side by side with a libmodbus server in the same run.

Both servers are separate processes on loopback TCP: `regmap simulate maps/idm_rs.yaml` and
bench/c/modbus_server.c (libmodbus `modbus_receive`/`modbus_reply`, select() over clients). The
load generator is bench/c/modbus_load.c: N threads, each its own libmodbus connection, each
sending one read of Pr5.00 (1 register) at a time. Both servers run at once and the load goes to
each in turn, `repeats` rounds per level, so a busy machine slows both alike: each level reports
the median round of each server and the median of the rounds' ratios. RSS is the server's VmRSS
after a warm-up and after a further 100k requests.

`python -m bench.simload [--repeats N]` (`make bench-sim`) runs this part alone and prints the ratios.
"""

from __future__ import annotations

import argparse
import shutil
import statistics
import subprocess
import sys
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

from bench.common import ROOT, free_port, wait_for_port

C_DIR = ROOT / "bench" / "c"
ADDRESS = 0x0191  # iDM-RS Pr5.00 peak_current; any address serves on the libmodbus side
LEVELS = (1, 10, 50)
REPEATS = 8
SERVERS = ("regmap simulate", "libmodbus")


@dataclass(frozen=True)
class LoadRun:
    server: str
    clients: int
    requests: int
    errors: int
    seconds: float
    p50_us: float
    p99_us: float

    @property
    def rate(self) -> float:
        return self.requests / self.seconds


@dataclass
class SimLoad:
    runs: list[LoadRun] = field(default_factory=list)  # per server and level: the median round
    ratios: dict[int, float] = field(default_factory=dict)  # clients -> median of the rounds' simulate/libmodbus rates
    rounds: int = 0
    rss_kb: dict[str, tuple[int, int]] = field(default_factory=dict)  # server -> (before, after)
    rss_requests: int = 0
    blocked: str | None = None

    def run(self, server: str, clients: int) -> LoadRun | None:
        return next((r for r in self.runs if r.server == server and r.clients == clients), None)


def rss_kb(pid: int) -> int:
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1])
    raise RuntimeError(f"no VmRSS for process {pid}")


def _build(work: Path) -> tuple[Path, Path]:
    cc, pkg = shutil.which("cc"), shutil.which("pkg-config")
    if cc is None or pkg is None:
        raise RuntimeError("cc and pkg-config are needed (libmodbus-dev)")
    flags = subprocess.run([pkg, "--cflags", "--libs", "libmodbus"], capture_output=True, text=True, check=False)
    if flags.returncode != 0:
        raise RuntimeError("libmodbus-dev is not installed")
    out = []
    for name in ("modbus_server", "modbus_load"):
        binary = work / name
        cmd = [cc, "-O2", "-Wall", "-Wextra", "-Werror", "-o", str(binary), str(C_DIR / f"{name}.c"), *flags.stdout.split(), "-lpthread"]
        built = subprocess.run(cmd, capture_output=True, text=True, check=False, timeout=120)
        if built.returncode != 0:
            raise RuntimeError(f"{name}.c does not build: {built.stderr.strip()}")
        out.append(binary)
    return out[0], out[1]


def _start(server: str, binary: Path, port: int) -> subprocess.Popen[str]:
    if server == "libmodbus":
        cmd = [str(binary), str(port)]
    else:
        idm = ROOT / "maps" / "idm_rs.yaml"
        cmd = [sys.executable, "-m", "regmap", "simulate", str(idm), "--tcp", f"127.0.0.1:{port}"]
    process = subprocess.Popen(cmd, cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, text=True)
    try:
        wait_for_port(port)
    except BaseException:
        process.kill()
        process.wait()
        raise
    return process


def _load(tool: Path, server: str, port: int, clients: int, requests: int) -> LoadRun:
    per_client = max(1, requests // clients)
    cmd = [str(tool), str(port), str(clients), str(per_client), hex(ADDRESS), "1"]
    result = subprocess.run(cmd, capture_output=True, text=True, check=False, timeout=300)
    if result.returncode != 0:
        raise RuntimeError(f"modbus_load failed: {result.stderr.strip()}")
    words = result.stdout.split()
    values = dict(zip(words[0::2], words[1::2], strict=True))
    return LoadRun(
        server,
        clients,
        int(values["requests"]),
        int(values["errors"]),
        float(values["seconds"]),
        float(values["p50_us"]),
        float(values["p99_us"]),
    )


def _median_run(runs: list[LoadRun]) -> LoadRun:
    return sorted(runs, key=lambda r: r.rate)[len(runs) // 2]


def measure(requests: int = 20_000, rss_requests: int = 100_000, warmup: int = 2_000, repeats: int = REPEATS) -> SimLoad:
    """Every level, `repeats` rounds, the servers in turn; then the RSS run. A missing tool blocks the section, not the bench."""
    result = SimLoad(rss_requests=rss_requests, rounds=repeats)
    with tempfile.TemporaryDirectory(prefix="regmap-simload-") as tmp:
        try:
            server_binary, load_tool = _build(Path(tmp))
        except RuntimeError as exc:
            result.blocked = str(exc)
            return result
        ports = {server: free_port() for server in SERVERS}
        processes: dict[str, subprocess.Popen[str]] = {}
        try:
            for server in SERVERS:
                processes[server] = _start(server, server_binary, ports[server])
                _load(load_tool, server, ports[server], 10, warmup)
            for clients in LEVELS:
                rounds = [
                    {server: _load(load_tool, server, ports[server], clients, requests) for server in SERVERS} for _ in range(repeats)
                ]
                result.runs += [_median_run([r[server] for r in rounds]) for server in SERVERS]
                result.ratios[clients] = statistics.median(r["regmap simulate"].rate / r["libmodbus"].rate for r in rounds)
            for server in SERVERS:
                before = rss_kb(processes[server].pid)
                _load(load_tool, server, ports[server], 10, rss_requests)
                result.rss_kb[server] = (before, rss_kb(processes[server].pid))
        finally:
            for process in processes.values():
                process.terminate()
                try:
                    process.wait(timeout=10)
                except subprocess.TimeoutExpired:
                    process.kill()
                    process.wait()
    return result


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m bench.simload", description="the simulator beside libmodbus, alone")
    parser.add_argument("--repeats", type=int, default=REPEATS, help="rounds per level (default %(default)s)")
    parser.add_argument("--requests", type=int, default=20_000, help="requests per round (default %(default)s)")
    args = parser.parse_args(argv)
    result = measure(args.requests, rss_requests=20_000, repeats=args.repeats)
    if result.blocked is not None:
        print(f"blocked: {result.blocked}", file=sys.stderr)
        return 1
    for clients in LEVELS:
        ours, theirs = result.run("regmap simulate", clients), result.run("libmodbus", clients)
        assert ours is not None and theirs is not None
        print(
            f"{clients:>3} clients: simulate {ours.rate:>8,.0f} req/s, libmodbus {theirs.rate:>8,.0f} req/s,"
            f" ratio {result.ratios[clients]:.2f} (median of {result.rounds} rounds)"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
