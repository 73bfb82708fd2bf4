"""Raw lines to `regmap simulate`: bytes sent and read as they are, over a TCP socket or a pty."""

from __future__ import annotations

import os
import select
import socket
import struct
import time
import tty

QUIET_S = 0.4  # how long "no answer" is waited for


class Line:
    """A byte pipe to the simulator (TCP socket or pty) that reads what arrives within a time."""

    def __init__(self, fd: int, closer: object) -> None:
        self.fd = fd
        self.closer = closer

    @classmethod
    def tcp(cls, port: int) -> Line:
        sock = socket.create_connection(("127.0.0.1", port), timeout=5)
        sock.setblocking(False)
        return cls(sock.fileno(), sock)

    @classmethod
    def pty(cls, path: str) -> Line:
        fd = os.open(path, os.O_RDWR | os.O_NOCTTY | os.O_NONBLOCK)
        tty.setraw(fd)
        return cls(fd, None)

    def send(self, data: bytes) -> None:
        if isinstance(self.closer, socket.socket):
            self.closer.sendall(data)
        else:
            os.write(self.fd, data)

    def read(self, want: int | None = None, timeout: float = 3.0) -> bytes:
        """Bytes until `want` have come (or, with want None, until QUIET_S of silence), or `timeout`."""
        out = b""
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline and (want is None or len(out) < want):
            ready, _, _ = select.select([self.fd], [], [], QUIET_S if want is None else max(0.0, deadline - time.monotonic()))
            if not ready:
                if want is None:
                    break
                continue
            try:
                chunk = os.read(self.fd, 4096)
            except BlockingIOError:
                continue
            except ConnectionResetError:
                break
            if not chunk:
                break  # closed by the simulator
            out += chunk
        return out

    def closed_by_peer(self, timeout: float = 3.0) -> bool:
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            ready, _, _ = select.select([self.fd], [], [], 0.1)
            if ready:
                try:
                    if os.read(self.fd, 4096) == b"":
                        return True
                except ConnectionResetError:
                    return True
        return False

    def close(self) -> None:
        if isinstance(self.closer, socket.socket):
            self.closer.close()
        else:
            os.close(self.fd)


def mbap(transaction: int, pdu: bytes, unit: int = 1, protocol: int = 0) -> bytes:
    return struct.pack(">HHHB", transaction, protocol, len(pdu) + 1, unit) + pdu
