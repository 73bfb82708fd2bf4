"""A plant's `read_all()`: one poll cycle over every device of a bus, beside each device's own `read_all()`.

examples/plants/cell1.yaml (two iDM-RS and a C630S on one RS-485 line) is generated as a Python plant with its
bus moved to loopback Modbus TCP and polled against `regmap simulate`'s multi-unit server in this process. The
simulator counts the requests; the wire time is what those exchanges take on the plant's serial line: each RTU
request and answer at the line's character time, the addressed device's turnaround and the 3.5-character silence.
Then each device's own client runs its `read_all()` alone on the same server: the plant's cycle should cost the
sum of those, not more (interleaving changes the order, never the requests).
"""

from __future__ import annotations

import asyncio
import importlib
import subprocess
import sys
import tempfile
import threading
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from bench.common import ROOT, free_port, wait_for_port
from regmap.frontend.plant import load_plant
from regmap.plant import Bus
from regmap.runtime_bridge import plant_schedule
from regmap.tools.simulator import DeviceStore, Simulator

PLANT = ROOT / "examples" / "plants" / "cell1.yaml"
MBAP_OVERHEAD = 4  # an MBAP frame is its RTU frame less slave id and CRC (3 bytes) plus the 7-byte header


@dataclass(frozen=True)
class PlantRun:
    plant_id: str
    bus: str
    line: str  # the serial settings the wire time is counted at
    devices: int
    plant_requests: int
    plant_wire_s: float  # the plant's read_all(), one cycle
    single_requests: int
    single_wire_s: float  # the sum of every device's own read_all()
    budget_s: float | None  # the schedule's worst-case cycle (runtime_bridge.plant_schedule), for reference
    order_matches: bool  # the simulator saw exactly the schedule's order of slave ids


def _tcp_copy(plant_file: Path, port: int, out: Path) -> Path:
    """The plant file with its first bus moved to 127.0.0.1:port, maps resolved against the original."""
    plant = load_plant(plant_file)
    bus = plant.buses[0]
    lines = ["format: regmap-plant/1", f"plant: {{id: {plant.id}, title: {plant.id}}}", "buses:", f"  - name: {bus.name}"]
    lines += [f"    tcp: {{host: 127.0.0.1, port: {port}}}", "    devices:"]
    for dev in bus.devices:
        path = (plant_file.parent / dev.map_path).resolve()
        lines.append(f"      - {{name: {dev.name}, map: {path}, slave: {dev.slave}}}")
    copy = out / plant_file.name
    copy.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return copy


def _wire_s(bus: Bus, frames: list[bytes]) -> float:
    """The exchanges' time on the plant's serial line: request and answer bytes (RTU), turnaround, silence."""
    line = bus.serial
    assert line is not None
    char_s = line.character_bits / line.baud
    by_slave = {dev.slave: dev for dev in bus.devices}
    total = 0.0
    for frame in frames:
        unit, count = frame[6], int.from_bytes(frame[10:12], "big")
        request_bytes = len(frame) - MBAP_OVERHEAD
        answer_bytes = 5 + 2 * count
        total += (request_bytes + answer_bytes) * char_s + by_slave[unit].turnaround_s(line.baud) + line.silence_s
    return total


class _BusThread:
    def __init__(self, bus: Bus, port: int) -> None:
        units = {dev.slave: DeviceStore(dev.device, dev.slave) for dev in bus.devices}
        self.simulator = Simulator.serving(units, keep_requests=100_000)
        self.port = port
        self.loop = asyncio.new_event_loop()
        self.thread = threading.Thread(target=self._run, name="plant-bus", daemon=True)

    def _run(self) -> None:
        asyncio.set_event_loop(self.loop)

        async def serve() -> None:
            await self.simulator.start_tcp("127.0.0.1", self.port)
            await self.simulator.stopped.wait()

        self.loop.run_until_complete(serve())

    def __enter__(self) -> _BusThread:
        self.thread.start()
        wait_for_port(self.port)
        return self

    def __exit__(self, *exc: object) -> None:
        asyncio.run_coroutine_threadsafe(self.simulator.stop(), self.loop).result(timeout=10)
        self.loop.call_soon_threadsafe(self.simulator.stopped.set)
        self.thread.join(timeout=10)

    def take(self) -> list[bytes]:
        frames = list(self.simulator.stats.requests)
        self.simulator.stats.requests.clear()
        return frames


def _forget_modules_under(folder: Path, before: dict[str, Any]) -> None:
    """Unload what was imported from `folder` (the plant and its device modules, about to be deleted) and put back
    the modules of the same names imported before, so a later import of `c630s` finds the committed one."""
    for name, module in list(sys.modules.items()):
        if Path(getattr(module, "__file__", None) or "/").is_relative_to(folder):
            del sys.modules[name]
    sys.modules.update(before)


def measure(plant_file: Path = PLANT) -> PlantRun:
    original = load_plant(plant_file)
    bus = original.buses[0]
    assert bus.serial is not None, f"{plant_file}: the bench counts wire time on a serial bus"
    port = free_port()
    with tempfile.TemporaryDirectory(prefix="regmap-bench-plant-") as tmp:
        out = Path(tmp)
        copy = _tcp_copy(plant_file, port, out)
        command = [sys.executable, "-m", "regmap", "generate", str(copy), "--target", "python", "--out", str(out / "gen")]
        subprocess.run(command, cwd=ROOT, check=True, capture_output=True)
        name = f"{original.id}_plant"
        before = dict(sys.modules)  # the committed plant and its devices, imported before: not these ones
        sys.modules.pop(name, None)
        sys.path.insert(0, str(out / "gen" / "python"))
        try:
            module: Any = importlib.import_module(name)
            cls = getattr(module, "".join(part.capitalize() for part in original.id.split("_")))
            with _BusThread(load_plant(copy).buses[0], port) as served, cls(**{f"{bus.name}_port": port}, timeout=5.0) as plant:
                plant.read_all()
                cycle = served.take()
                single: list[bytes] = []
                for dev in bus.devices:
                    getattr(plant, dev.name).read_all()
                    single += served.take()
        finally:
            sys.path.remove(str(out / "gen" / "python"))
            _forget_modules_under(out, before)
    (schedule,) = plant_schedule(original)[:1]
    line = bus.serial
    return PlantRun(
        original.id,
        bus.name,
        f"{line.baud} baud, {line.data_bits}{line.parity[0].upper()}{line.stop_bits}",
        len(bus.devices),
        len(cycle),
        _wire_s(bus, cycle),
        len(single),
        _wire_s(bus, single),
        schedule.cycle_s,
        [frame[6] for frame in cycle] == [entry.slave for entry in schedule.entries],
    )


if __name__ == "__main__":
    run = measure()
    print(
        f"{run.plant_id} {run.bus} ({run.line}, {run.devices} devices): plant read_all() {run.plant_requests} requests, "
        f"{run.plant_wire_s * 1000:.1f} ms on the wire; sum of the devices' own read_all() {run.single_requests} requests, "
        f"{run.single_wire_s * 1000:.1f} ms; schedule budget {run.budget_s and run.budget_s * 1000:.1f} ms; order as scheduled: {run.order_matches}"
    )
