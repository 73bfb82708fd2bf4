"""Bus time of `read_all()`: requests, bytes and wire time, counted from the frames a simulator received.

The generated client talks RTU framing over loopback TCP (`rtu_over_tcp`) to `regmap.tools.simulator.Simulator`
running in this process; the simulator's statistics (counters) count every frame and byte that
crossed. Wire time is then what those frames would take on the RS-485 line at the map's default baud.
"""

from __future__ import annotations

import asyncio
import math
import threading
from dataclasses import dataclass
from typing import Any

from bench.common import client_class, client_module, free_port, wait_for_port
from regmap.model import Device
from regmap.runtime_bridge import read_plan
from regmap.tools.simulator import Quirks, Simulator
from regmap_runtime.rtu import build_read, crc_ok, parse_frame

READ_REQUEST_BYTES = 8  # slave, function, address (2), count (2), CRC (2)
READ_RESPONSE_OVERHEAD = 5  # slave, function, byte count, CRC (2); plus 2 bytes per register word


@dataclass(frozen=True)
class Line:
    """The RS-485 line at the map's default settings and the device's turnaround."""

    baud: int
    bits_per_char: int
    char_s: float
    gap_s: float  # 3.5 character times of silence that end a frame
    turnaround_s: float  # end of request -> start of response
    idle_s: float  # end of response -> the device listens again (next request may start)
    turnaround_source: str
    manual_t1_s: float | None = None  # the manual's time from start of request to end of answer, where given

    @property
    def model_t1_s(self) -> float:
        """The model's start of a one-register read request to the end of its answer (8 + 7 bytes)."""
        return (READ_REQUEST_BYTES + READ_RESPONSE_OVERHEAD + 2) * self.char_s + self.turnaround_s

    def exchange_s(self, request_bytes: int, response_bytes: int) -> float:
        return (request_bytes + response_bytes) * self.char_s + self.turnaround_s + self.idle_s

    def traffic_s(self, requests: int, bytes_total: int) -> float:
        return bytes_total * self.char_s + requests * (self.turnaround_s + self.idle_s)


def line_of(device: Device) -> Line:
    """Character time from the frame format (start + data + parity + stop bits); the manual's
    turnaround where it gives one: the iDM-RS 5.1 table (T2 wait after reception, T3 back to
    receiving) or a map's `response_delay_ms`; never less than the 3.5-character gap."""
    t = device.transport
    bits = 1 + t.data_bits + (0 if t.parity == "none" else 1) + t.stop_bits
    char_s = bits / t.baud
    gap_s = 3.5 * char_s
    turnaround_s, idle_s, source = gap_s, gap_s, "3.5-character gaps only (the manual gives no turnaround)"
    row = next((r for r in t.timing if r.baud == t.baud), None)
    manual_t1_s = None
    if row is not None:
        manual_t1_s = None if row.receive_to_send_ms is None else row.receive_to_send_ms / 1000
        wait = (row.wait_after_receive_ms or 0.0) / 1000
        back = (row.send_to_receive_ms or 0.0) / 1000
        turnaround_s, idle_s = max(gap_s, wait), max(gap_s, back)
        source = (
            f"manual timing table at {t.baud} bit/s: T2 wait after reception {row.wait_after_receive_ms} ms, "
            f"T3 back to receiving {row.send_to_receive_ms} ms (each at least the 3.5-character gap)"
        )
    elif t.response_delay_ms is not None:
        turnaround_s = max(gap_s, t.response_delay_ms / 1000)
        source = f"manual response delay {t.response_delay_ms:g} ms before each answer; 3.5-character gap after it"
    return Line(t.baud, bits, char_s, gap_s, turnaround_s, idle_s, source, manual_t1_s)


@dataclass(frozen=True)
class Traffic:
    requests: int
    bytes_out: int  # master -> device (requests)
    bytes_in: int  # device -> master (responses)
    wire_s: float

    @property
    def bytes_total(self) -> int:
        return self.bytes_out + self.bytes_in


def traffic(line: Line, requests: int, bytes_out: int, bytes_in: int) -> Traffic:
    return Traffic(requests, bytes_out, bytes_in, line.traffic_s(requests, bytes_out + bytes_in))


def effective_read_limit(device: Device) -> int:
    """Registers per read the device allows: max_read_registers, and max_message_bytes for the answer."""
    t = device.transport
    limit = t.max_read_registers
    if t.max_message_bytes is not None:
        limit = min(limit, (t.max_message_bytes - READ_RESPONSE_OVERHEAD) // 2)
    return limit


def lower_bound(device: Device, line: Line) -> Traffic:
    """No plan can beat this: every readable word travels once, in requests filled to the device's
    limit, with no gap or pair-high words (address layout ignored)."""
    words = sum(r.words for r in device.registers if r.access.readable)
    requests = math.ceil(words / effective_read_limit(device))
    return traffic(line, requests, requests * READ_REQUEST_BYTES, requests * READ_RESPONSE_OVERHEAD + 2 * words)


class SimulatorThread:
    """`regmap.tools.simulator.Simulator` serving RTU framing on loopback TCP from a background thread."""

    def __init__(self, device: Device, quirks: Quirks | None = None) -> None:
        self.simulator = Simulator(device, keep_requests=4096, quirks=quirks)  # the whole per-register pass stays inspectable
        self.port = free_port()
        self.loop = asyncio.new_event_loop()
        self.thread = threading.Thread(target=self._run, name=f"simulator-{device.id}", daemon=True)

    def _run(self) -> None:
        asyncio.set_event_loop(self.loop)
        self.loop.run_until_complete(self.simulator.serve_tcp("127.0.0.1", self.port, rtu_over_tcp=True))

    def __enter__(self) -> SimulatorThread:
        self.thread.start()
        wait_for_port(self.port)
        return self

    def __exit__(self, *exc: object) -> None:
        asyncio.run_coroutine_threadsafe(self.simulator.stop(), self.loop).result(timeout=10)
        self.thread.join(timeout=10)
        self.loop.close()

    def reset(self) -> None:
        stats = self.simulator.stats
        stats.frames_received = stats.bytes_received = stats.frames_sent = stats.bytes_sent = 0
        stats.requests.clear()


@dataclass(frozen=True)
class BusResult:
    device_id: str
    model: str
    line: Line
    registers: int  # readable registers
    words: int  # their own words
    plan: Traffic
    per_register: Traffic
    bound: Traffic
    plan_matches_frames: bool  # the frames received are exactly read_plan(device), byte for byte

    @property
    def speedup(self) -> float:
        return self.per_register.wire_s / self.plan.wire_s


def _count(sim: SimulatorThread, client: Any, line: Line) -> Traffic:
    stats = sim.simulator.stats
    if stats.frames_received != client.requests_sent:
        raise AssertionError(f"simulator saw {stats.frames_received} frames, the client sent {client.requests_sent}")
    for frame in stats.requests:
        parsed = parse_frame(frame, "request")
        if not crc_ok(frame) or parsed.kind != "read_request" or parsed.problems:
            raise AssertionError(f"the simulator received a frame that is not one whole read request: {frame.hex(' ')}")
    if stats.frames_sent != stats.frames_received:
        raise AssertionError(f"{stats.frames_received} requests but {stats.frames_sent} answers")
    return traffic(line, stats.frames_received, stats.bytes_received, stats.bytes_sent)


def measure(device: Device) -> BusResult:
    """Drive the simulator with the generated client's read_all(), then with one read per register."""
    line = line_of(device)
    module = client_module(device.id)
    cls = client_class(module)
    readable = [spec for spec in module.DEVICE.registers if spec.readable]
    with SimulatorThread(device) as sim, cls.tcp("127.0.0.1", sim.port, slave=1, timeout=5, rtu_over_tcp=True) as client:
        sim.reset()
        client.requests_sent = 0
        values = client.read_all()
        plan = _count(sim, client, line)
        expected = [build_read(1, b.address, b.count) for b in read_plan(device)]
        matches = list(sim.simulator.stats.requests) == expected and len(values) == len(readable)
        sim.reset()
        client.requests_sent = 0
        for spec in readable:
            client.read(spec)
        per_register = _count(sim, client, line)
    words = sum(spec.words for spec in readable)
    return BusResult(device.id, device.info.model, line, len(readable), words, plan, per_register, lower_bound(device, line), matches)


@dataclass(frozen=True)
class ProfileResult:
    """read_all() on a drive that answers reads across gaps, before and after `regmap probe` learned it."""

    device_id: str
    line: Line
    probe_requests: int
    without: Traffic  # the map's plan
    learned: Traffic  # the plan the learned profile allows
    bound: Traffic
    gap_runs: int  # undocumented address runs the profile proved readable


def measure_profile(device: Device) -> ProfileResult:
    """Probe a lenient simulator (`--answer-gaps`), then read_all() with and without the profile it learned."""
    from regmap.tools.link import Link
    from regmap.tools.live import connect
    from regmap.tools.probe import Options, probe

    line = line_of(device)
    cls = client_class(client_module(device.id))
    with SimulatorThread(device, Quirks(answer_gaps=True)) as sim:
        link = Link(tcp=f"127.0.0.1:{sim.port}", rtu_over_tcp=True, timeout=5)
        prober = connect(device, link, reading=True)
        try:
            found, profile = probe(device, prober, link.where, Options(budget_s=120))
        finally:
            prober.close()
        results = []
        for chosen in (None, profile):
            with cls.tcp("127.0.0.1", sim.port, slave=1, timeout=5, rtu_over_tcp=True, profile=chosen) as client:
                sim.reset()
                client.requests_sent = 0
                client.read_all()
                results.append(_count(sim, client, line))
    return ProfileResult(device.id, line, found.requests, results[0], results[1], lower_bound(device, line), len(profile.readable_gaps))
