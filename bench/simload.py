"""`regmap simulate` under load, side by side with a libmodbus server in the same run.

Both servers are separate processes on loopback TCP: `regmap simulate maps/idm_rs.yaml` and
bench/c/modbus_server.c (libmodbus `modbus_receive`/`modbus_reply`, select() over clients). The
load generator is bench/c/modbus_load.c: N threads, each its own libmodbus connection, each
sending one read of Pr5.00 (1 register) at a time. RSS is the server's VmRSS after a warm-up and
after a further 100k requests.
"""

from __future__ import annotations

import shutil
import subprocess
import sys
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

from bench.common import ROOT, free_port, wait_for_port

C_DIR = ROOT / "bench" / "c"
ADDRESS = 0x0191  # iDM-RS Pr5.00 peak_current; any address serves on the libmodbus side
LEVELS = (1, 10, 50)
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
    runs: list[LoadRun] = field(default_factory=list)
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


def measure(requests: int = 20_000, rss_requests: int = 100_000, warmup: int = 2_000) -> SimLoad:
    """Every level for each server, then the RSS run; a missing tool blocks the section, not the bench."""
    result = SimLoad(rss_requests=rss_requests)
    with tempfile.TemporaryDirectory(prefix="regmap-simload-") as tmp:
        try:
            server_binary, load_tool = _build(Path(tmp))
        except RuntimeError as exc:
            result.blocked = str(exc)
            return result
        for server in SERVERS:
            port = free_port()
            process = _start(server, server_binary, port)
            try:
                _load(load_tool, server, port, 10, warmup)
                before = rss_kb(process.pid)
                _load(load_tool, server, port, 10, rss_requests)
                result.rss_kb[server] = (before, rss_kb(process.pid))
                result.runs += [_load(load_tool, server, port, clients, requests) for clients in LEVELS]
            finally:
                process.terminate()
                try:
                    process.wait(timeout=10)
                except subprocess.TimeoutExpired:
                    process.kill()
                    process.wait()
    return result
