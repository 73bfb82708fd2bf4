"""The simulator's own Modbus server on asyncio: Modbus TCP, RTU over TCP, RTU on a serial port or pty.

Nothing per request is kept: `Stats` are counters plus a short ring of the latest request frames
(for tests and the bench); the full record is the opt-in request log.
"""

from __future__ import annotations

import asyncio
import contextlib
import os
import sys
from collections import deque
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from regmap.diagnostics import UsageError
from regmap.model import Device
from regmap.tools.link import Line, port_reason
from regmap_runtime.rtu import EXCEPTION_FLAG, with_crc

from .answers import READ_FUNCTIONS, AnswerCache
from .connection import Poller, TcpConnection, TcpListener, listen
from .faults import ANSWER_FAULTS, FaultPlan, damage_rtu, damage_tcp
from .framing import MBAP_HEADER, MBAP_HEADER_STRUCT, Adu, RtuReceiver, mbap, rtu_gap_s
from .log import RequestLog
from .pdu import Dispatcher, exception_pdu
from .policy import DIRECT_UNITS, TcpPolicy
from .quirks import Quirks
from .store import DeviceStore, slave_refusal

GATEWAY_TARGET_FAILED = 0x0B  # exception: a gateway found no answer from the addressed device
PTY_GAP_S = 0.02  # a pty or a socket delivers bytes in bursts, not at the line's pace: a longer silence ends a frame
TCP_RTU_GAP_S = 0.05
KEEP_REQUESTS = 64
AFTER_TRANSACTION = 2  # a kept request and its answer are the frames after their transaction ids

Send = Callable[[bytes], None]


@dataclass
class Stats:
    """Counters; `requests` holds only the latest request frames (a ring of `keep` entries)."""

    frames_received: int = 0
    bytes_received: int = 0
    frames_sent: int = 0
    bytes_sent: int = 0
    exceptions_sent: int = 0
    bad_crc_frames: int = 0
    bytes_dropped: int = 0
    connections: int = 0
    connections_refused: int = 0  # closed on an MBAP header that cannot be in step
    connections_idle_closed: int = 0  # closed after --idle-timeout without a request
    connections_evicted: int = 0  # closed, oldest idle first, to make room for a new one (--max-connections)
    keep: int = KEEP_REQUESTS
    requests: deque[bytes] = field(init=False)

    def __post_init__(self) -> None:
        self.requests = deque(maxlen=self.keep)

    def summary(self) -> str:
        return (
            f"{self.frames_received} requests, {self.frames_sent} answers ({self.exceptions_sent} exceptions), "
            f"{self.bad_crc_frames} bad CRC, {self.bytes_dropped} bytes dropped, {self.connections_refused} connections closed on bad headers"
            + (f", {self.connections_idle_closed} closed idle" if self.connections_idle_closed else "")
            + (f", {self.connections_evicted} closed to make room" if self.connections_evicted else "")
        )


def is_pty(path: str) -> bool:
    """Unix98 pseudo-terminal slaves have major numbers 136-143."""
    try:
        return os.major(os.stat(path).st_rdev) in range(136, 144)
    except OSError:
        return False


@dataclass(frozen=True)
class Unit:
    """One device on the server: its store (memory and rules) and the dispatcher answering its requests."""

    store: DeviceStore
    dispatcher: Dispatcher
    functions: frozenset[int]  # the function codes its map lists

    @classmethod
    def of(cls, store: DeviceStore) -> Unit:
        return cls(store, Dispatcher(store.device, store, store.quirks), frozenset(store.device.transport.function_codes))


class Simulator:
    """Simulated devices on one TCP port or serial line, with fault injection and frame statistics.

    `Simulator(device, slave, ...)` plays one device; `Simulator.serving(units, ...)` several on one
    port, each slave id its own `DeviceStore` (see the package docstring)."""

    def __init__(
        self,
        device: Device,
        slave: int = 1,
        state_file: Path | None = None,
        faults: FaultPlan | None = None,
        *,
        log: RequestLog | None = None,
        keep_requests: int = KEEP_REQUESTS,
        rtu_gap_s: float | None = None,
        quirks: Quirks | None = None,
        tcp_policy: TcpPolicy | None = None,
    ) -> None:
        store = DeviceStore(device, slave, state_file, quirks or Quirks())
        self._start_units({slave: store}, faults, log, keep_requests, rtu_gap_s, tcp_policy)

    @classmethod
    def serving(
        cls,
        units: Mapping[int, DeviceStore],
        *,
        faults: FaultPlan | None = None,
        log: RequestLog | None = None,
        keep_requests: int = KEEP_REQUESTS,
        rtu_gap_s: float | None = None,
        tcp_policy: TcpPolicy | None = None,
    ) -> Simulator:
        """Several devices on one port: slave id -> its store (each with its own map, state file, quirks)."""
        if not units:
            raise ValueError("a simulator serves at least one device")
        for slave, store in units.items():
            refused = slave_refusal(store.device, slave)
            if refused is not None:
                raise ValueError(refused)
            if store.slave != slave:
                raise ValueError(f"the store of {store.device.id} was made for slave {store.slave}, not {slave}")
        simulator = cls.__new__(cls)
        simulator._start_units(units, faults, log, keep_requests, rtu_gap_s, tcp_policy)
        return simulator

    def _start_units(
        self,
        units: Mapping[int, DeviceStore],
        faults: FaultPlan | None,
        log: RequestLog | None,
        keep_requests: int,
        rtu_gap_s: float | None,
        tcp_policy: TcpPolicy | None,
    ) -> None:
        self.units = {slave: Unit.of(store) for slave, store in units.items()}
        # A broadcast id (each map's own, usually 0) reaches every device whose map has it.
        broadcasts: dict[int, list[Unit]] = {}
        for slave, unit in self.units.items():
            broadcast = unit.store.device.transport.broadcast_id
            if broadcast is not None and broadcast != slave:
                broadcasts.setdefault(broadcast, []).append(unit)
        self.broadcasts = {b: tuple(receivers) for b, receivers in broadcasts.items()}
        self.tcp_policy = tcp_policy or TcpPolicy()
        self.faults = faults or FaultPlan()
        for unit in self.units.values():
            unit.store.faults = self.faults
        self.stats = Stats(keep=keep_requests)
        self.answers = AnswerCache()
        self.log = log
        self.rtu_gap_override = rtu_gap_s
        self.tcp_gap_s = rtu_gap_s if rtu_gap_s is not None else TCP_RTU_GAP_S
        self.listeners: list[TcpListener] = []
        self.connections: set[TcpConnection] = set()
        self.poller: Poller | None = None
        self.serial: Any = None
        self.serial_receiver: RtuReceiver | None = None
        self.failure: str | None = None
        self.stopped = asyncio.Event()

    # The one device of a single-device simulator (the first one of several).
    @property
    def slave(self) -> int:
        return next(iter(self.units))

    @property
    def store(self) -> DeviceStore:
        return self.units[self.slave].store

    @property
    def device(self) -> Device:
        return self.store.device

    @property
    def dispatcher(self) -> Dispatcher:
        return self.units[self.slave].dispatcher

    # -- what comes in -----------------------------------------------------------------------

    def ours(self, unit: int, function: int) -> bool:
        """A request some device here would take (the RTU receiver's resynchronisation asks)."""
        target = self.units.get(unit)
        if target is not None:
            return function in target.functions
        return any(function in receiver.functions for receiver in self.broadcasts.get(unit, ()))

    def _not_ours(self) -> str:
        if len(self.units) == 1:
            return f"not for slave {self.slave}"
        return f"not for slaves {', '.join(map(str, sorted(self.units)))}"

    def _answer(self, unit: int, pdu: bytes) -> tuple[bytes | None, str]:
        """The answer PDU, or None with the reason there is none (the serial line's rules)."""
        target = self.units.get(unit)
        if target is not None:
            return target.dispatcher.answer(pdu), ""
        receivers = self.broadcasts.get(unit)
        if receivers is not None:
            if not Dispatcher.writes(pdu):
                return None, "broadcast of a request that is not a write: ignored"
            for receiver in receivers:
                receiver.dispatcher.answer(pdu)
            return None, "broadcast"
        return None, self._not_ours()

    def _tcp_answer(self, unit: int, pdu: bytes) -> tuple[bytes | None, str]:
        """Modbus TCP: the device addressed by its IP address, or a gateway with the devices behind it."""
        if self.tcp_policy.gateway:
            if unit in self.units or unit in self.broadcasts:
                return self._answer(unit, pdu)
            if not pdu:
                return None, "empty request"
            return exception_pdu(pdu[0], GATEWAY_TARGET_FAILED), f"no device {unit} behind this gateway"
        target = self.units.get(unit)
        if target is not None:
            return target.dispatcher.answer(pdu), ""
        if len(self.units) == 1 and unit in DIRECT_UNITS:  # several devices: only their own unit ids tell them apart
            return self.dispatcher.answer(pdu), f"unit {unit:#04x}: the device addressed directly"
        return None, self._not_ours()

    def _received(self, frame: bytes) -> None:
        stats = self.stats
        stats.frames_received += 1
        stats.bytes_received += len(frame)
        stats.requests.append(frame)

    def rtu_frame(self, frame: bytes, send: Send, peer: str) -> None:
        self._received(frame)
        unit = frame[0]
        answer, note = self._answer(unit, frame[1:-2])
        reply = with_crc(bytes([unit]) + answer) if answer is not None else None
        if self.log is not None:
            self.log.rtu(peer, frame, reply, note)
        if answer is not None and reply is not None:
            self._send(send, reply, answer, damage_rtu)

    def rtu_bad_frame(self, frame: bytes, send: Send, peer: str) -> None:
        self.stats.bad_crc_frames += 1
        self.stats.bytes_received += len(frame)
        target = self.units.get(frame[0])
        policy = (target.store.device if target is not None else self.device).transport.bad_crc
        reply = None
        if policy.reply == "exception" and policy.code is not None and target is not None:
            reply = with_crc(bytes([frame[0], (frame[1] | EXCEPTION_FLAG) & 0xFF, policy.code]))
        if self.log is not None:
            self.log.rtu(peer, frame, reply, "bad CRC" + ("" if reply else f", {policy.reply}"))
        if reply is not None:
            self._send(send, reply, reply[1:-2], damage_rtu)

    def tcp_frame(self, raw: bytes, send: Send, peer: str) -> None:
        """One whole Modbus TCP request whose header is checked."""
        transaction, _, _, unit = MBAP_HEADER_STRUCT.unpack_from(raw)
        self.tcp_adu(Adu(transaction, 0, unit, raw[MBAP_HEADER:], raw), send, peer)

    def tcp_adu(self, adu: Adu, send: Send, peer: str) -> None:
        if not self.answer_kept(adu.raw, send):
            self._received(adu.raw)
            self._work_out(adu, send, peer)

    def answer_kept(self, raw: bytes, send: Send) -> bool:
        """Answer `raw` from the answer cache when it can be (True), counting it in and its answer out.

        The cache is keyed by all of a request after its transaction id, so `raw` can be a TCP segment
        as it came: equal to a kept key, it is one whole request with a sound header. With a request
        log or an injected fault nothing is kept (`_work_out`), so nothing is found."""
        kept = self.answers.get(raw[AFTER_TRANSACTION:])
        if kept is None:
            return False
        answer, exception = kept
        reply = raw[:AFTER_TRANSACTION] + answer  # a read answered before, the device's memory unchanged since
        stats = self.stats
        stats.frames_received += 1
        stats.bytes_received += len(raw)
        stats.requests.append(raw)
        stats.exceptions_sent += exception
        stats.frames_sent += 1
        stats.bytes_sent += len(reply)
        send(reply)
        return True

    def _work_out(self, adu: Adu, send: Send, peer: str) -> None:
        stats, raw = self.stats, adu.raw
        plain = self.log is None and self.faults.kind == "none"
        transaction, unit, pdu = adu.transaction, adu.unit, adu.pdu
        store = self._read_store(unit, pdu) if plain else None
        generation = store.generation if store is not None else 0
        answer, note = self._tcp_answer(unit, pdu)
        if self.log is not None:
            self.log.tcp(peer, transaction, unit, pdu, answer, note)
        if answer is None:
            return
        reply = mbap(transaction, unit, answer)
        if store is not None and store.generation == generation:
            self.answers.keep(raw[AFTER_TRANSACTION:], store, generation, reply[AFTER_TRANSACTION:])
        if self.faults.kind != "none":
            self._send(send, reply, answer, damage_tcp)
            return
        if answer[0] & EXCEPTION_FLAG:
            stats.exceptions_sent += 1
        stats.frames_sent += 1
        stats.bytes_sent += len(reply)
        send(reply)

    def _read_store(self, unit: int, pdu: bytes) -> DeviceStore | None:
        """The one store a read addressed to `unit` answers from, when its answer may be kept (AnswerCache)."""
        if not pdu or pdu[0] not in READ_FUNCTIONS:
            return None
        target = self.units.get(unit)
        if target is None and not self.tcp_policy.gateway and len(self.units) == 1 and unit in DIRECT_UNITS:
            target = self.units[self.slave]
        # A read that changes memory (a value that changes on being read) moves the generation: never kept.
        return None if target is None else target.store

    def dropped(self, data: bytes, peer: str) -> None:
        self.stats.bytes_dropped += len(data)
        if self.log is not None:
            self.log.event(
                peer, f"dropped {len(data)} bytes that are no request: {data[:32].hex(' ').upper()}{' ...' if len(data) > 32 else ''}"
            )

    def refuse_connection(self, peer: str, reason: str, buffered: int) -> None:
        self.stats.connections_refused += 1
        self.stats.bytes_dropped += buffered
        if self.log is not None:
            self.log.event(peer, f"closing the connection: {reason}")

    def connection_event(self, peer: str, text: str) -> None:
        """One line per connection refused or closed by the server, in the log (or on stderr without one)."""
        if self.log is not None:
            self.log.event(peer, text)
        else:
            print(f"regmap simulate: {peer}: {text}", file=sys.stderr, flush=True)

    def make_room(self, peer: str) -> None:
        """At the connection cap, close the connections idle the longest until the new one fits."""
        cap = self.tcp_policy.connection_cap()
        while len(self.connections) >= cap:
            oldest = min(self.connections, key=lambda c: c.last_heard)
            self.connections.discard(oldest)
            self.stats.connections_evicted += 1
            self.connection_event(oldest.peer, f"closing the connection to make room for {peer} (at most {cap} connections)")
            oldest.close()

    # -- what goes out -----------------------------------------------------------------------

    def _send(self, send: Send, data: bytes, pdu: bytes, damage: Callable[[str, bytes], bytes]) -> None:
        fault = "none" if self.faults.kind == "none" else self.faults.take(ANSWER_FAULTS)
        if fault == "no_answer":
            return
        if pdu and pdu[0] & EXCEPTION_FLAG:
            self.stats.exceptions_sent += 1
        out = data if fault == "none" else damage(fault, data)
        if fault == "delay":
            asyncio.get_running_loop().call_later(self.faults.delay_s, self._deliver, send, out)
        else:
            self._deliver(send, out)

    def _deliver(self, send: Send, data: bytes) -> None:
        # Counted first: a client in another thread may look at the counters as soon as it has the answer.
        self.stats.frames_sent += 1
        self.stats.bytes_sent += len(data)
        send(data)

    # -- serving -----------------------------------------------------------------------------

    def tcp_poller(self) -> Poller:
        """What watches every TCP connection's socket; made in the running event loop on first use."""
        if self.poller is None:
            self.poller = Poller(asyncio.get_running_loop())
        return self.poller

    async def start_tcp(self, host: str, port: int, *, rtu_over_tcp: bool = False) -> None:
        """Listen (raises OSError when the address cannot be had); requests are answered from now on."""
        self.listeners += [TcpListener(self, sock, rtu_over_tcp) for sock in await listen(host, port)]

    async def start_serial(self, port: str, line: Line | None = None) -> None:
        """Open the port with the map's line settings, or `line` (`--baud`, `--parity`, `--stop-bits`)."""
        import serial

        t = self.device.transport
        line = line or Line(t.baud, t.parity, t.stop_bits)
        try:
            handle = serial.Serial(
                port=port,
                baudrate=line.baud,
                bytesize=t.data_bits,
                parity={"none": "N", "even": "E", "odd": "O"}[line.parity],
                stopbits=line.stop_bits,
                timeout=0,
                write_timeout=2,
            )
        except (serial.SerialException, ValueError) as exc:
            raise UsageError(f"cannot open {port}: {port_reason(exc)}") from None
        except Exception as exc:  # termios.error (no OSError): the port refuses the line settings
            raise UsageError(f"cannot open {port}: {line.refused(str(exc.args[-1] if exc.args else exc))}") from None
        self.serial = handle
        bits = 1 + t.data_bits + (line.parity != "none") + line.stop_bits
        gap = self.rtu_gap_override if self.rtu_gap_override is not None else PTY_GAP_S if is_pty(port) else rtu_gap_s(line.baud, bits)
        self.serial_receiver = RtuReceiver(
            asyncio.get_running_loop(),
            gap,
            self.ours,
            lambda f: self.rtu_frame(f, self._serial_write, port),
            lambda f: self.rtu_bad_frame(f, self._serial_write, port),
            lambda b: self.dropped(b, port),
        )
        asyncio.get_running_loop().add_reader(handle.fileno(), self._serial_readable)

    def _serial_readable(self) -> None:
        try:
            data = os.read(self.serial.fileno(), 4096)
        except BlockingIOError:
            return
        except OSError as exc:
            self._serial_failed(f"{self.serial.port}: {exc.strerror or exc}")
            return
        if not data:
            self._serial_failed(f"{self.serial.port}: end of file")
            return
        assert self.serial_receiver is not None
        self.serial_receiver.feed(data)

    def _serial_failed(self, reason: str) -> None:
        asyncio.get_running_loop().remove_reader(self.serial.fileno())
        self.failure = reason
        self.stopped.set()

    def _serial_write(self, data: bytes) -> None:
        import serial

        try:
            self.serial.write(data)
        except serial.SerialTimeoutException:
            if self.log is not None:
                self.log.event(self.serial.port, "answer not sent: the port did not take it within 2 s")

    async def serve_tcp(self, host: str, port: int, *, rtu_over_tcp: bool = False) -> None:
        await self.start_tcp(host, port, rtu_over_tcp=rtu_over_tcp)
        await self.stopped.wait()

    async def serve_serial(self, port: str, line: Line | None = None) -> None:
        await self.start_serial(port, line)
        await self.stopped.wait()

    async def stop(self) -> None:
        for connection in list(self.connections):
            connection.close()
        for listener in self.listeners:
            listener.close()
        self.listeners.clear()
        if self.poller is not None:
            self.poller.close()
            self.poller = None
        if self.serial is not None:
            with contextlib.suppress(Exception):
                asyncio.get_running_loop().remove_reader(self.serial.fileno())
            if self.serial_receiver is not None:
                self.serial_receiver.close()
            self.serial.close()
            self.serial = None
        self.stopped.set()


async def serve(
    units: Mapping[int, DeviceStore],
    *,
    tcp: tuple[str, int] | None = None,
    serial: str | None = None,
    rtu_over_tcp: bool = False,
    line: Line | None = None,
    faults: FaultPlan | None = None,
    log: RequestLog | None = None,
    tcp_policy: TcpPolicy | None = None,
    started: Callable[[Simulator], None] | None = None,
) -> Simulator:
    """Serve several devices on one port until `Simulator.stopped` is set (see the package docstring).

    Exactly one of `tcp` ((host, port)) and `serial` (a port or pty path); `started` is called once the
    port is open (with the simulator, to stop it or read its stats). Returns the stopped simulator."""
    if (tcp is None) == (serial is None):
        raise ValueError("serve() takes one of tcp=(host, port) and serial=PATH")
    simulator = Simulator.serving(units, faults=faults, log=log, tcp_policy=tcp_policy)
    if serial is not None:
        await simulator.start_serial(serial, line)
    else:
        assert tcp is not None
        await simulator.start_tcp(tcp[0], tcp[1], rtu_over_tcp=rtu_over_tcp)
    if started is not None:
        started(simulator)
    try:
        await simulator.stopped.wait()
    finally:
        await simulator.stop()
    return simulator
