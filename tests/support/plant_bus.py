"""Test buses for plants: several simulated devices behind one pty (RTU) or one TCP socket (MBAP).

Until the simulator serves several units on one port, each device is the simulator's own register store and
dispatcher (`regmap.tools.simulator`: the map's strictness, its exceptions) behind a small router that hands a
request to the store of its slave id and stays silent for any other id. Every exchange is time-stamped where
the bytes cross the line (the pty's master side), so a test measures the timing the bus master kept.
"""

from __future__ import annotations

import os
import select
import socket
import struct
import subprocess
import threading
import time
import tty
from dataclasses import dataclass
from pathlib import Path

from regmap.model import Device
from regmap.tools.simulator.pdu import Dispatcher, rtu_request_length
from regmap.tools.simulator.store import DeviceStore
from regmap_runtime.rtu import crc_ok, with_crc


@dataclass(frozen=True)
class Exchange:
    """One request as the line saw it: when its first and last byte arrived, and when the answer was written."""

    slave: int
    function: int
    start: int
    count: int
    request_first: float
    request_last: float
    answered: float | None  # when the answer's write began; None: no answer (another id, a broadcast)


class _Units:
    def __init__(self, devices: dict[int, Device]) -> None:
        self.stores = {slave: DeviceStore(device, slave) for slave, device in devices.items()}
        self.dispatchers = {slave: Dispatcher(device, self.stores[slave]) for slave, device in devices.items()}
        self.exchanges: list[Exchange] = []
        self.lock = threading.Lock()

    def answer(self, unit: int, pdu: bytes) -> bytes | None:
        dispatcher = self.dispatchers.get(unit)
        return None if dispatcher is None else dispatcher.answer(pdu)

    def record(self, unit: int, pdu: bytes, first: float, last: float, answered: float | None) -> None:
        start, count = struct.unpack(">HH", pdu[1:5]) if len(pdu) >= 5 else (0, 0)
        with self.lock:
            self.exchanges.append(Exchange(unit, pdu[0], start, count, first, last, answered))


class PtyBus(_Units):
    """An RS-485 line on two linked pseudo-terminals (socat: a plain pty refuses parity settings): the client
    opens `path`; one thread answers at the other end as the devices would."""

    def __init__(self, devices: dict[int, Device], socat: str, directory: Path) -> None:
        super().__init__(devices)
        ours, self.path = directory / "bus-devices", str(directory / "bus-master")
        self.socat = subprocess.Popen(
            [socat, "-d", f"pty,raw,echo=0,link={ours}", f"pty,raw,echo=0,link={self.path}"],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
        deadline = time.monotonic() + 10
        while not (ours.exists() and Path(self.path).exists()):
            if time.monotonic() > deadline:
                self.socat.terminate()
                raise RuntimeError("socat made no pseudo-terminals within 10 s")
            time.sleep(0.05)
        self.master = os.open(ours, os.O_RDWR | os.O_NOCTTY)
        tty.setraw(self.master)
        self.stopping = False
        self.thread = threading.Thread(target=self._serve, daemon=True)
        self.thread.start()

    def _serve(self) -> None:
        buf = b""
        first = 0.0
        while not self.stopping:
            ready, _, _ = select.select([self.master], [], [], 0.05)
            if not ready:
                continue
            try:
                chunk = os.read(self.master, 4096)
            except OSError:
                return
            now = time.monotonic()
            if not buf:
                first = now
            buf += chunk
            while (length := rtu_request_length(buf)) and len(buf) >= length:
                frame, buf = buf[:length], buf[length:]
                if not crc_ok(frame):
                    continue
                answer = self.answer(frame[0], frame[1:-2])
                answered = None
                if answer is not None:
                    answered = time.monotonic()  # before the write: the master cannot have seen the answer earlier
                    os.write(self.master, with_crc(bytes([frame[0]]) + answer))
                self.record(frame[0], frame[1:-2], first, now, answered)
                first = now

    def close(self) -> None:
        self.stopping = True
        self.thread.join(timeout=2)
        os.close(self.master)
        self.socat.terminate()
        self.socat.wait(timeout=10)


class TcpBus(_Units):
    """A Modbus TCP gateway on 127.0.0.1: the unit id picks the device; `connections` counts the clients that connected."""

    def __init__(self, devices: dict[int, Device]) -> None:
        super().__init__(devices)
        self.server = socket.create_server(("127.0.0.1", 0))
        self.port = self.server.getsockname()[1]
        self.connections = 0
        self.thread = threading.Thread(target=self._accept, daemon=True)
        self.thread.start()

    def _accept(self) -> None:
        while True:
            try:
                conn, _ = self.server.accept()
            except OSError:
                return
            self.connections += 1
            threading.Thread(target=self._serve, args=(conn,), daemon=True).start()

    def _serve(self, conn: socket.socket) -> None:
        buf = b""
        with conn:
            while True:
                try:
                    chunk = conn.recv(4096)
                except OSError:
                    return
                if not chunk:
                    return
                now = time.monotonic()
                buf += chunk
                while len(buf) >= 7 and len(buf) >= 6 + struct.unpack(">H", buf[4:6])[0]:
                    length = 6 + struct.unpack(">H", buf[4:6])[0]
                    adu, buf = buf[:length], buf[length:]
                    unit, pdu = adu[6], adu[7:]
                    answer = self.answer(unit, pdu)
                    answered = None
                    if answer is not None:
                        answered = time.monotonic()
                        conn.sendall(adu[:4] + struct.pack(">HB", len(answer) + 1, unit) + answer)
                    self.record(unit, pdu, now, now, answered)

    def close(self) -> None:
        self.server.close()
