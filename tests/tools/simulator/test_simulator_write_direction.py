"""The simulator answers a write of a state the device only reports as the drive answers any value it
cannot take: exception 0x03 (illegal data value), nothing stored; a command value is taken."""

from __future__ import annotations

import select
import socket
import struct
import time

from regmap.frontend import load_map
from regmap.tools.simulator.store import ILLEGAL_VALUE, DeviceStore
from regmap_runtime.rtu import with_crc

from conftest import ROOT, SimulatorFactory

IDM = ROOT / "maps" / "idm_rs.yaml"
PR_TRIGGER = 0x6002


def test_the_store_refuses_every_reported_state_and_keeps_its_value() -> None:
    device = load_map(IDM)
    store = DeviceStore(device, 1)
    reg = device.register("pr_trigger")
    for raw in (0x0005, 0x0000, 0x000F, 0x0100, 0x0103, 0x0200, 0x020F):
        assert store.write(PR_TRIGGER, [raw]) == ILLEGAL_VALUE, hex(raw)
    assert store.raw_of(reg) == 0  # its default, untouched
    assert store.write(PR_TRIGGER, [0x0013]) is None
    assert store.raw_of(reg) == 0x0013
    assert store.write(PR_TRIGGER, [0x0105]) == ILLEGAL_VALUE
    assert store.raw_of(reg) == 0x0013  # the command written before stays


def exchange(sock: socket.socket, request: bytes, want: int) -> bytes:
    sock.sendall(request)
    out = b""
    deadline = time.monotonic() + 5
    while len(out) < want and time.monotonic() < deadline:
        if select.select([sock], [], [], 0.2)[0]:
            out += sock.recv(256)
    return out


def test_the_reproduction_frame_gets_exception_03(simulator: SimulatorFactory) -> None:
    sim = simulator(IDM, "--rtu-over-tcp")
    assert sim.port is not None
    with socket.create_connection(("127.0.0.1", sim.port), timeout=5) as sock:
        # The frame `regmap frame maps/idm_rs.yaml write pr_trigger=done_path_5` used to build.
        assert exchange(sock, bytes.fromhex("01 06 60 02 00 05 F6 09"), 5) == with_crc(bytes([1, 0x86, 0x03]))
        running = with_crc(struct.pack(">BBHHBH", 1, 0x10, PR_TRIGGER, 1, 2, 0x0105))
        assert exchange(sock, running, 5) == with_crc(bytes([1, 0x90, 0x03]))
        read = with_crc(struct.pack(">BBHH", 1, 0x03, PR_TRIGGER, 1))
        assert exchange(sock, read, 7) == with_crc(bytes([1, 0x03, 2, 0, 0]))  # still "done", its default
        start = with_crc(struct.pack(">BBHH", 1, 0x06, PR_TRIGGER, 0x0015))
        assert exchange(sock, start, 8) == start  # start path 5: echoed
