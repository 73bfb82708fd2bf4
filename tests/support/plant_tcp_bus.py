"""A plant's TCP bus served for tests: one Modbus TCP port, every device of the bus behind it at its slave id.

Until `regmap simulate PLANT --bus NAME --tcp ...` serves a whole bus, `serve_bus` starts one
`regmap simulate MAP --tcp --slave N` per device and a `UnitRouter` in front of them that hands each MBAP
request to the simulator of its unit id (a unit id no device has gets no answer, as on a serial line).
Each simulator logs its requests (`--log`); `writes()` reads the writes back from those logs.
"""

from __future__ import annotations

import re
import socket
import socketserver
import subprocess
import sys
import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

from regmap.plant import Bus

ROOT = Path(__file__).resolve().parents[2]
MBAP_HEADER = 7  # transaction, protocol, length (2 bytes each), unit
REGMAP = str(Path(sys.executable).parent / "regmap")
STARTUP_S = 30.0  # a simulator's port opens well within this on a loaded machine


def free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        port: int = sock.getsockname()[1]
        return port


def _read_exactly(sock: socket.socket, n: int) -> bytes | None:
    data = b""
    while len(data) < n:
        chunk = sock.recv(n - len(data))
        if not chunk:
            return None
        data += chunk
    return data


def _read_frame(sock: socket.socket) -> bytes | None:
    """One whole MBAP frame (header and PDU), or None when the peer closed."""
    header = _read_exactly(sock, MBAP_HEADER)
    if header is None:
        return None
    body = _read_exactly(sock, int.from_bytes(header[4:6], "big") - 1)
    return None if body is None else header + body


class UnitRouter(socketserver.ThreadingTCPServer):
    """Listens on one port and forwards each request, by its unit id, to the TCP server of that unit."""

    daemon_threads = True
    allow_reuse_address = True

    def __init__(self, port: int, units: dict[int, int]) -> None:
        self.units = units  # unit id -> the port of its simulator
        super().__init__(("127.0.0.1", port), _RouterConnection)


class _RouterConnection(socketserver.BaseRequestHandler):
    def handle(self) -> None:
        assert isinstance(self.server, UnitRouter)
        upstream: dict[int, socket.socket] = {}
        try:
            while (frame := _read_frame(self.request)) is not None:
                port = self.server.units.get(frame[6])
                if port is None:
                    continue  # nobody at that slave id: silence
                if frame[6] not in upstream:
                    upstream[frame[6]] = socket.create_connection(("127.0.0.1", port), timeout=10)
                upstream[frame[6]].sendall(frame)
                answer = _read_frame(upstream[frame[6]])
                if answer is not None:
                    self.request.sendall(answer)
        except OSError:
            pass  # the client went away
        finally:
            for sock in upstream.values():
                sock.close()


MAPS = ROOT / "maps"
PlantLine = tuple[str, str, list[tuple[str, Path, int]]]  # bus name, its line ("tcp: {host: ...}"), devices (name, map, slave)


def write_plant(path: Path, plant_id: str, buses: list[PlantLine]) -> Path:
    """A plant file at `path`; the n-th device of the first bus is at line 6 + n."""
    lines = ["format: regmap-plant/1", f"plant: {{id: {plant_id}, title: {plant_id}}}", "buses:"]
    for name, line, devices in buses:
        lines += [f"  - name: {name}", f"    {line}", "    devices:"]
        lines += [f"      - {{name: {dev}, map: {map_path}, slave: {slave}}}" for dev, map_path, slave in devices]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


@dataclass(frozen=True)
class ServedBus:
    port: int  # where the bus listens (127.0.0.1)
    logs: dict[str, Path]  # device name -> its simulator's request log

    def writes(self, device: str) -> list[tuple[int, int, int, bytes]]:
        """The write requests the device's simulator received: (unit, function, address, the rest of the PDU)."""
        out = []
        text = self.logs[device].read_text(encoding="utf-8") if self.logs[device].exists() else ""
        for match in _REQUEST.finditer(text):
            pdu = bytes.fromhex(match["pdu"])
            if pdu[0] in (0x05, 0x06, 0x0F, 0x10):
                out.append((int(match["unit"]), pdu[0], int.from_bytes(pdu[1:3], "big"), pdu[3:]))
        return out


_REQUEST = re.compile(r"> MBAP transaction \d+, unit (?P<unit>\d+), PDU (?P<pdu>[0-9a-fA-F ]+)$", re.MULTILINE)


def _wait_port(port: int, process: subprocess.Popen[bytes], what: str) -> None:
    deadline = time.monotonic() + STARTUP_S
    while time.monotonic() < deadline:
        if process.poll() is not None:
            raise RuntimeError(f"{what} exited with {process.returncode} before opening port {port}")
        try:
            socket.create_connection(("127.0.0.1", port), timeout=1).close()
            return
        except OSError:
            time.sleep(0.1)
    raise RuntimeError(f"{what} did not open port {port} within {STARTUP_S:.0f} s")


@contextmanager
def serve_bus(bus: Bus, work: Path, states: dict[str, Path] | None = None) -> Iterator[ServedBus]:
    """Serve every device of the TCP bus `bus` at the bus's port (127.0.0.1); `states` gives a device a
    `--state` file to start from.
    (With the multi-unit simulator: one `regmap simulate PLANT --bus NAME --tcp 127.0.0.1:PORT` in place of
    the per-device processes and the router.)"""
    assert bus.tcp is not None, f"{bus.name} is not a TCP bus"
    processes: list[subprocess.Popen[bytes]] = []
    units: dict[int, int] = {}
    logs: dict[str, Path] = {}
    try:
        for dev in bus.devices:
            port = free_port()
            logs[dev.name] = work / f"{dev.name}.log"
            argv = [REGMAP, "simulate", dev.device.source_path, "--tcp", f"127.0.0.1:{port}", "--slave", str(dev.slave)]
            argv += ["--log", str(logs[dev.name])]
            if states and dev.name in states:
                argv += ["--state", str(states[dev.name])]
            err = (work / f"{dev.name}.stderr").open("wb")
            processes.append(subprocess.Popen(argv, cwd=ROOT, stdout=subprocess.DEVNULL, stderr=err))
            err.close()
            _wait_port(port, processes[-1], f"the simulator of {dev.name}")
            units[dev.slave] = port
        router = UnitRouter(bus.tcp.port, units)
        thread = threading.Thread(target=router.serve_forever, daemon=True)
        thread.start()
        try:
            yield ServedBus(router.server_address[1], logs)
        finally:
            router.shutdown()
            router.server_close()
    finally:
        for process in processes:
            process.terminate()
        for process in processes:
            try:
                process.wait(timeout=10)
            except subprocess.TimeoutExpired:
                process.kill()
                process.wait()
