"""The simulator's Modbus TCP side: the listening sockets and each client connection (MBAP or RTU framing).

The sockets are read and written directly (`recv`, `send`), not through asyncio transports and protocols, and
every client connection is watched by one epoll that the event loop watches as a single reader (`Poller`): a
wake-up serves every connection that has a request in one callback, with no event loop handle per request.
A repeated read that holds is answered before its header is even cut (`Simulator.answer_kept`).
"""

from __future__ import annotations

import asyncio
import contextlib
import errno
import select
import socket
import time
from collections.abc import Callable
from typing import TYPE_CHECKING

from .framing import TCP_PARTIAL_TIMEOUT_S, MbapError, MbapReceiver, RtuReceiver

if TYPE_CHECKING:
    from .server import Simulator

RECEIVE_BUFFER = 4096  # bytes one read from a TCP connection takes; a request is at most 260
EVENTS_PER_WAKEUP = 64  # more ready connections than this wake the loop again at once
ROUNDS_PER_WAKEUP = 8  # then the event loop runs its timers (idle, partial request, RTU gap) and accepts
LISTEN_BACKLOG = 100  # asyncio's default
ACCEPTS_PER_WAKEUP = 100
ACCEPT_RETRY_S = 1.0  # out of descriptors: listen again after this long (asyncio's delay)
OUT_OF_RESOURCES = (errno.EMFILE, errno.ENFILE, errno.ENOBUFS, errno.ENOMEM)


async def listen(host: str, port: int) -> list[socket.socket]:
    """Non-blocking listening sockets on every address `host` names (raises OSError when one cannot be had)."""
    loop = asyncio.get_running_loop()
    infos = await loop.getaddrinfo(host or None, port, type=socket.SOCK_STREAM, flags=socket.AI_PASSIVE)
    sockets: list[socket.socket] = []
    try:
        for family, kind, proto, _name, address in dict.fromkeys(infos):
            sock = socket.socket(family, kind, proto)
            sockets.append(sock)
            sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
            if family == socket.AF_INET6:
                sock.setsockopt(socket.IPPROTO_IPV6, socket.IPV6_V6ONLY, 1)
            sock.bind(address)
            sock.listen(LISTEN_BACKLOG)
            sock.setblocking(False)
    except OSError:
        for sock in sockets:
            sock.close()
        raise
    return sockets


class Poller:
    """Client sockets watched for reading or for writing, each with the one callback to run when it is ready.

    On Linux they share one epoll, which the event loop watches as one reader; elsewhere each is the
    event loop's own reader or writer."""

    def __init__(self, loop: asyncio.AbstractEventLoop, *, use_epoll: bool = hasattr(select, "epoll")) -> None:
        self.loop = loop
        self.handlers: dict[int, Callable[[], None]] = {}
        self.epoll = select.epoll() if use_epoll else None
        if self.epoll is not None:
            loop.add_reader(self.epoll.fileno(), self._ready)

    def _ready(self) -> None:
        """Serve the ready sockets, then look again: with several busy clients the next requests are in by then
        (most of the time with 10), each round far cheaper than a turn of the event loop."""
        assert self.epoll is not None
        handlers, poll = self.handlers, self.epoll.poll
        for _ in range(ROUNDS_PER_WAKEUP):
            ready = poll(0, EVENTS_PER_WAKEUP)
            if not ready:
                return
            for fd, _events in ready:
                handlers[fd]()  # a handler closes only its own connection: every other fd here is still watched

    def read(self, fd: int, handler: Callable[[], None]) -> None:
        """Call `handler` whenever `fd` has something to read (or has failed); it is no longer watched for writing."""
        if self.epoll is None:
            self.loop.remove_writer(fd)
            self.loop.add_reader(fd, handler)
        else:
            self._epoll_watch(fd, select.EPOLLIN)
        self.handlers[fd] = handler

    def write(self, fd: int, handler: Callable[[], None]) -> None:
        """Call `handler` whenever `fd` takes more to send (or has failed); it is no longer watched for reading."""
        if self.epoll is None:
            self.loop.remove_reader(fd)
            self.loop.add_writer(fd, handler)
        else:
            self._epoll_watch(fd, select.EPOLLOUT)
        self.handlers[fd] = handler

    def _epoll_watch(self, fd: int, events: int) -> None:
        assert self.epoll is not None
        if fd in self.handlers:
            self.epoll.modify(fd, events)
        else:
            self.epoll.register(fd, events)

    def forget(self, fd: int) -> None:
        """No longer watch `fd` (before it is closed)."""
        if self.handlers.pop(fd, None) is None:
            return
        if self.epoll is None:
            self.loop.remove_reader(fd)
            self.loop.remove_writer(fd)
        else:
            self.epoll.unregister(fd)

    def close(self) -> None:
        for fd in list(self.handlers):
            self.forget(fd)
        if self.epoll is not None:
            self.loop.remove_reader(self.epoll.fileno())
            self.epoll.close()


class TcpListener:
    """One listening socket: each client it accepts becomes a `TcpConnection`."""

    def __init__(self, sim: Simulator, sock: socket.socket, rtu: bool) -> None:
        self.sim = sim
        self.sock = sock
        self.rtu = rtu
        self.loop = asyncio.get_running_loop()
        self.retry: asyncio.TimerHandle | None = None
        self.loop.add_reader(sock.fileno(), self._accept)

    def _accept(self) -> None:
        for _ in range(ACCEPTS_PER_WAKEUP):
            try:
                client, address = self.sock.accept()
            except (BlockingIOError, InterruptedError, ConnectionAbortedError):
                return
            except OSError as exc:
                if exc.errno not in OUT_OF_RESOURCES:
                    raise
                # One line per refusal, then a pause: the pending client waits in the backlog, no busy loop.
                self.sim.connection_event("tcp", f"cannot accept a connection: {exc.strerror or exc} (try a lower --max-connections)")
                self.loop.remove_reader(self.sock.fileno())
                self.retry = self.loop.call_later(ACCEPT_RETRY_S, self._listen_again)
                return
            client.setblocking(False)
            if client.family in (socket.AF_INET, socket.AF_INET6):
                client.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
            TcpConnection(self.sim, self.rtu, client, address).start()

    def _listen_again(self) -> None:
        self.retry = None
        self.loop.add_reader(self.sock.fileno(), self._accept)

    def close(self) -> None:
        if self.retry is not None:
            self.retry.cancel()
        self.loop.remove_reader(self.sock.fileno())
        self.sock.close()


class TcpConnection:
    """One TCP client: MBAP or RTU framing, its own buffer, closed on its own garbage only.

    Answers the client has not taken yet wait in `unsent`; while any wait, the client is not read (a client
    that does not read its answers stops being served: what waits is at most the answers to one segment it sent)."""

    def __init__(self, sim: Simulator, rtu: bool, sock: socket.socket, address: object) -> None:
        self.sim = sim
        self.sock = sock
        self.fd = sock.fileno()
        self.loop = asyncio.get_running_loop()
        self.poller = sim.tcp_poller()
        self._received = memoryview(bytearray(RECEIVE_BUFFER))
        self.unsent = bytearray()
        self.closed = False
        self.rtu_framing = rtu
        self.peer = f"{address[0]}:{address[1]}" if isinstance(address, tuple) else "tcp"
        self.rtu: RtuReceiver | None = None
        self.mbap = MbapReceiver()
        self.partial_timer: asyncio.TimerHandle | None = None
        self.idle_timer: asyncio.TimerHandle | None = None
        self.last_heard = self.clock()

    # The event loop's clock (asyncio's BaseEventLoop.time is this), called without the loop's method in between.
    clock = staticmethod(time.monotonic)

    def start(self) -> None:
        sim = self.sim
        sim.make_room(self.peer)
        sim.connections.add(self)
        sim.stats.connections += 1
        self._arm_idle_timer(sim.tcp_policy.idle_timeout_s)
        if self.rtu_framing:
            self.rtu = RtuReceiver(
                self.loop,
                sim.tcp_gap_s,
                sim.ours,
                lambda f: sim.rtu_frame(f, self.send, self.peer),
                lambda f: sim.rtu_bad_frame(f, self.send, self.peer),
                lambda b: sim.dropped(b, self.peer),
            )
        self.poller.read(self.fd, self._readable)

    def _readable(self) -> None:
        try:
            nbytes = self.sock.recv_into(self._received)
        except (BlockingIOError, InterruptedError):
            return
        except OSError:  # reset by the client
            self.close()
            return
        if not nbytes:  # the client closed its side
            self.close()
            return
        data = self._received[:nbytes].tobytes()
        self.last_heard = self.clock()
        # The common case: a repeated read, whole and alone, with nothing of another request buffered before it.
        if self.rtu is None and not self.mbap.buffer and self.sim.answer_kept(data, self.send):
            return
        self.data_received(data)

    def data_received(self, data: bytes) -> None:
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
            self.partial_timer = self.loop.call_later(TCP_PARTIAL_TIMEOUT_S, self._partial_expired)

    def _partial_expired(self) -> None:
        self.partial_timer = None
        self.sim.refuse_connection(self.peer, f"request incomplete for {TCP_PARTIAL_TIMEOUT_S:g} s", len(self.mbap.buffer))
        self.close()

    def _arm_idle_timer(self, delay: float | None) -> None:
        if delay is not None:
            self.idle_timer = self.loop.call_later(delay, self._idle_check)

    def _idle_check(self) -> None:
        """Close the connection if it has been silent for the idle timeout; else look again when it could be."""
        self.idle_timer = None
        timeout = self.sim.tcp_policy.idle_timeout_s
        assert timeout is not None
        silent = self.clock() - self.last_heard
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
        if self.closed:
            return
        if self.unsent:
            self.unsent += data
            return
        try:
            sent = self.sock.send(data)
        except (BlockingIOError, InterruptedError):
            sent = 0
        except OSError:
            self.close()
            return
        if sent < len(data):
            self.unsent += data[sent:]
            self.poller.write(self.fd, self._writable)  # not read again until it has taken its answers

    def _writable(self) -> None:
        try:
            sent = self.sock.send(self.unsent)
        except (BlockingIOError, InterruptedError):
            return
        except OSError:
            self.close()
            return
        del self.unsent[:sent]
        if not self.unsent:
            self.poller.read(self.fd, self._readable)

    def close(self) -> None:
        if self.closed:
            return
        self.closed = True
        self.poller.forget(self.fd)
        if self.unsent:  # what the socket takes now still goes out, as a transport's close would send it
            with contextlib.suppress(OSError):
                self.sock.send(self.unsent)
        self.sock.close()
        self.connection_lost()

    def connection_lost(self) -> None:
        self._cancel_partial()
        if self.idle_timer is not None:
            self.idle_timer.cancel()
            self.idle_timer = None
        if self.rtu is not None:
            self.rtu.close()
        self.sim.connections.discard(self)
