"""Soak: 10 concurrent Modbus TCP clients, 20,000 requests, each client writing and reading back its
own registers. Zero errors, zero lost writes, and the simulator's memory does not grow with the
requests. Nothing is timed: speed is the bench's business (`make bench`)."""

from __future__ import annotations

import socket
import struct
import threading
from pathlib import Path

from regmap.frontend import load_map
from regmap.model import Register

from conftest import ROOT, SimulatorFactory

IDM = ROOT / "maps" / "idm_rs.yaml"
CLIENTS = 10
REQUESTS = 20_000  # half writes (0x06), half reads (0x03) of what was just written
RSS_GROWTH_LIMIT_KB = 8 * 1024  # the old simulator grew by ~4 KiB per request: 80 MB here


def rss_kb(pid: int) -> int:
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1])
    raise AssertionError("no VmRSS in /proc")


def soak_registers() -> list[Register]:
    """Writable 16-bit registers without enums or commands, with room for many distinct values."""
    device = load_map(IDM)
    commanded = {c.register.name for c in device.commands}
    found = [
        r
        for r in device.registers
        if r.access.readable
        and r.access.writable
        and r.words == 1
        and r.enum is None
        and not r.bitfields
        and r.name not in commanded
        and r.min is not None
        and r.max is not None
        and r.min >= 0
        and r.max - r.min >= 50
    ]
    assert len(found) >= CLIENTS, [r.name for r in found]
    return found[:CLIENTS]


class Client(threading.Thread):
    def __init__(self, port: int, index: int, reg: Register, pairs: int) -> None:
        super().__init__(name=f"soak-{index}", daemon=True)
        self.port, self.index, self.reg, self.pairs = port, index, reg, pairs
        self.errors: list[str] = []
        self.lost = 0
        self.done = 0

    def exchange(self, sock: socket.socket, transaction: int, pdu: bytes) -> bytes:
        sock.sendall(struct.pack(">HHHB", transaction, 0, len(pdu) + 1, 1) + pdu)
        header = self.receive(sock, 7)
        got_transaction, protocol, length, _ = struct.unpack(">HHHB", header)
        if got_transaction != transaction or protocol != 0:
            raise AssertionError(f"answer to transaction {got_transaction}, protocol {protocol}; asked {transaction}")
        return self.receive(sock, length - 1)

    @staticmethod
    def receive(sock: socket.socket, n: int) -> bytes:
        out = b""
        while len(out) < n:
            chunk = sock.recv(n - len(out))
            if not chunk:
                raise AssertionError("connection closed")
            out += chunk
        return out

    def run(self) -> None:
        reg = self.reg
        assert reg.min is not None and reg.max is not None
        span = reg.max - reg.min + 1
        try:
            with socket.create_connection(("127.0.0.1", self.port), timeout=10) as sock:
                for i in range(self.pairs):
                    value = reg.min + (i * 7 + self.index) % span
                    echo = self.exchange(sock, (2 * i) & 0xFFFF, struct.pack(">BHH", 0x06, reg.address, value))
                    if echo != struct.pack(">BHH", 0x06, reg.address, value):
                        self.errors.append(f"write {value}: answer {echo.hex(' ')}")
                    answer = self.exchange(sock, (2 * i + 1) & 0xFFFF, struct.pack(">BHH", 0x03, reg.address, 1))
                    if answer != struct.pack(">BBH", 0x03, 2, value):
                        self.lost += 1
                        self.errors.append(f"wrote {value}, read back {answer.hex(' ')}")
                    self.done += 2
        except (OSError, AssertionError) as exc:
            self.errors.append(f"{type(exc).__name__}: {exc}")


def run_clients(port: int, registers: list[Register], requests: int) -> list[Client]:
    clients = [Client(port, i, reg, requests // (2 * CLIENTS)) for i, reg in enumerate(registers)]
    for client in clients:
        client.start()
    for client in clients:
        client.join(timeout=120)
    assert not any(c.is_alive() for c in clients), "a soak client is stuck"
    return clients


def test_soak_ten_clients_twenty_thousand_requests(simulator: SimulatorFactory) -> None:
    sim = simulator(IDM)
    assert sim.port is not None
    registers = soak_registers()
    run_clients(sim.port, registers, 2_000)  # warm-up: imports, allocator pools, connection objects
    before = rss_kb(sim.process.pid)
    clients = run_clients(sim.port, registers, REQUESTS)
    after = rss_kb(sim.process.pid)
    errors = [e for c in clients for e in c.errors]
    assert errors == [], errors[:10]
    assert sum(c.lost for c in clients) == 0
    assert sum(c.done for c in clients) == REQUESTS
    assert after - before < RSS_GROWTH_LIMIT_KB, f"RSS grew from {before} kB to {after} kB over {REQUESTS} requests"
    print(f"soak: {REQUESTS} requests from {CLIENTS} clients, RSS {before} kB -> {after} kB ({after - before:+d} kB)")
    assert "22000 requests" in sim.stop()
