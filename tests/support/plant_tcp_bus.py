"""A plant's TCP bus served for tests: `regmap simulate PLANT --bus NAME --tcp ...`, every device of the bus
on one Modbus TCP port at its slave id (a unit id no device has gets no answer, as on a serial line).
The simulator logs its requests (`--log`); `writes()` reads one device's writes back from that log.
"""

from __future__ import annotations

import re
import shutil
import socket
import subprocess
import sys
import time
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

from regmap.plant import Bus, Plant

ROOT = Path(__file__).resolve().parents[2]
MBAP_HEADER = 7  # transaction, protocol, length (2 bytes each), unit
REGMAP = str(Path(sys.executable).parent / "regmap")
STARTUP_S = 30.0  # a simulator's port opens well within this on a loaded machine


def free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        port: int = sock.getsockname()[1]
        return port


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
    log: Path  # the bus simulator's request log
    slaves: dict[str, int]  # device name -> its slave id

    def writes(self, device: str) -> list[tuple[int, int, int, bytes]]:
        """The write requests the bus received for the device: (unit, function, address, the rest of the PDU)."""
        out = []
        text = self.log.read_text(encoding="utf-8") if self.log.exists() else ""
        for match in _REQUEST.finditer(text):
            pdu = bytes.fromhex(match["pdu"])
            if int(match["unit"]) == self.slaves[device] and pdu[0] in (0x05, 0x06, 0x0F, 0x10):
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
def serve_bus(plant: Plant, bus: Bus, work: Path, states: dict[str, Path] | None = None) -> Iterator[ServedBus]:
    """Serve every device of the TCP bus `bus` at the bus's port (127.0.0.1) with one
    `regmap simulate PLANT --bus NAME`; `states` gives a device a state file to start from."""
    assert bus.tcp is not None, f"{bus.name} is not a TCP bus"
    state_dir = work / f"{bus.name}-states"
    state_dir.mkdir(exist_ok=True)
    for name, path in (states or {}).items():
        shutil.copyfile(path, state_dir / f"{name}.json")
    log = work / f"{bus.name}.log"
    argv = [REGMAP, "simulate", plant.source_path, "--bus", bus.name, "--tcp", f"127.0.0.1:{bus.tcp.port}", "--log", str(log)]
    argv += ["--state-dir", str(state_dir)]
    with (work / f"{bus.name}.stderr").open("wb") as err:
        process = subprocess.Popen(argv, cwd=ROOT, stdout=subprocess.DEVNULL, stderr=err)
    try:
        _wait_port(bus.tcp.port, process, f"the simulator of bus {bus.name}")
        yield ServedBus(bus.tcp.port, log, {dev.name: dev.slave for dev in bus.devices})
    finally:
        process.terminate()
        try:
            process.wait(timeout=10)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait()
