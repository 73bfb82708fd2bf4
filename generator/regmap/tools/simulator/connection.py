"""One Modbus TCP client connection of the simulator: MBAP or RTU framing, its own buffer and timers."""

from __future__ import annotations

import asyncio
import time
from collections.abc import Callable
from typing import TYPE_CHECKING

from .framing import MBAP_HEADER, MBAP_MAX_LENGTH, TCP_PARTIAL_TIMEOUT_S, MbapError, MbapReceiver, RtuReceiver

if TYPE_CHECKING:
    from .server import Simulator

RECEIVE_BUFFER = 4096  # bytes one read from a TCP connection takes; a request is at most 260


class TcpConnection(asyncio.BufferedProtocol):
    """One TCP client: MBAP or RTU framing, its own buffer, closed on its own garbage only.

    A buffered protocol: the transport receives into this connection's own small buffer, where a plain
    protocol would have asyncio allocate (and free) 256 KiB for every segment, each request."""

    def __init__(self, sim: Simulator, rtu: bool) -> None:
        self.sim = sim
        self._received = memoryview(bytearray(RECEIVE_BUFFER))
        self.rtu_framing = rtu
        self.transport: asyncio.Transport | None = None
        self.peer = "tcp"
        self.rtu: RtuReceiver | None = None
        self.mbap = MbapReceiver()
        self.partial_timer: asyncio.TimerHandle | None = None
        self.idle_timer: asyncio.TimerHandle | None = None
        self.last_heard = 0.0
        self.clock: Callable[[], float] = time.monotonic

    def connection_made(self, transport: asyncio.BaseTransport) -> None:
        assert isinstance(transport, asyncio.Transport)
        self.transport = transport
        peer = transport.get_extra_info("peername")
        self.peer = f"{peer[0]}:{peer[1]}" if isinstance(peer, tuple) else "tcp"
        self.clock = asyncio.get_running_loop().time
        self.last_heard = self.clock()
        self.sim.make_room(self.peer)
        self.sim.connections.add(self)
        self.sim.stats.connections += 1
        self._arm_idle_timer(self.sim.tcp_policy.idle_timeout_s)
        if self.rtu_framing:
            sim = self.sim
            self.rtu = RtuReceiver(
                asyncio.get_running_loop(),
                sim.tcp_gap_s,
                sim.ours,
                lambda f: sim.rtu_frame(f, self.send, self.peer),
                lambda f: sim.rtu_bad_frame(f, self.send, self.peer),
                lambda b: sim.dropped(b, self.peer),
            )

    def get_buffer(self, sizehint: int) -> memoryview:
        return self._received

    def buffer_updated(self, nbytes: int) -> None:
        received = self._received
        if (
            self.rtu is None
            and not self.mbap.buffer
            and MBAP_HEADER < nbytes <= MBAP_HEADER - 1 + MBAP_MAX_LENGTH
            and received[2] == 0 == received[3]
            and received[4] << 8 | received[5] == nbytes - (MBAP_HEADER - 1)
        ):  # one whole request with a sound header, nothing before it: the common case, not cut by MbapReceiver
            self.last_heard = self.clock()
            self.sim.tcp_frame(bytes(received[:nbytes]), self.send, self.peer)
            return
        self.data_received(bytes(received[:nbytes]))

    def data_received(self, data: bytes) -> None:
        self.last_heard = self.clock()
        if self.rtu is not None:
            self.rtu.feed(data)
            return
        try:
            adus = self.mbap.feed(data)
        except MbapError as exc:
            self.sim.refuse_connection(self.peer, str(exc), len(self.mbap.buffer))
            self.close()
            return
        for adu in adus:
            self.sim.tcp_adu(adu, self.send, self.peer)
        partial = self.mbap.partial
        if self.partial_timer is not None and (adus or not partial):
            self._cancel_partial()
        if partial and self.partial_timer is None:
            self.partial_timer = asyncio.get_running_loop().call_later(TCP_PARTIAL_TIMEOUT_S, self._partial_expired)

    def _partial_expired(self) -> None:
        self.partial_timer = None
        self.sim.refuse_connection(self.peer, f"request incomplete for {TCP_PARTIAL_TIMEOUT_S:g} s", len(self.mbap.buffer))
        self.close()

    def _arm_idle_timer(self, delay: float | None) -> None:
        if delay is not None:
            self.idle_timer = asyncio.get_running_loop().call_later(delay, self._idle_check)

    def _idle_check(self) -> None:
        """Close the connection if it has been silent for the idle timeout; else look again when it could be."""
        self.idle_timer = None
        timeout = self.sim.tcp_policy.idle_timeout_s
        assert timeout is not None
        silent = asyncio.get_running_loop().time() - self.last_heard
        if silent < timeout:
            self._arm_idle_timer(timeout - silent)
            return
        self.sim.stats.connections_idle_closed += 1
        self.sim.connection_event(self.peer, f"closing the connection: no request for {timeout:g} s (--idle-timeout)")
        self.close()

    def _cancel_partial(self) -> None:
        if self.partial_timer is not None:
            self.partial_timer.cancel()
            self.partial_timer = None

    def send(self, data: bytes) -> None:
        if self.transport is not None and not self.transport.is_closing():
            self.transport.write(data)

    def close(self) -> None:
        if self.transport is not None:
            self.transport.close()

    def pause_writing(self) -> None:  # a client that does not read its answers stops being read
        if self.transport is not None:
            self.transport.pause_reading()

    def resume_writing(self) -> None:
        if self.transport is not None:
            self.transport.resume_reading()

    def connection_lost(self, exc: Exception | None) -> None:
        self._cancel_partial()
        if self.idle_timer is not None:
            self.idle_timer.cancel()
            self.idle_timer = None
        if self.rtu is not None:
            self.rtu.close()
        self.sim.connections.discard(self)
