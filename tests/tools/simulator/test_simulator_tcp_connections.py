"""The simulator's Modbus TCP side: which unit ids it answers, and that no client can lock the others out.

Unit ids follow the Modbus Messaging on TCP/IP Implementation Guide (§4.4.2): a device addressed by its
IP address takes 0xFF (and 0) as well as its own id; `--gateway` plays a TCP-to-serial gateway instead.
"""

from __future__ import annotations

import os
import resource
import select
import socket
import struct
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

from regmap.frontend import load_map
from regmap_runtime.rtu import with_crc

from conftest import ROOT, SimulatorFactory, free_port, wait_for
from support.libmodbus_ref import build_libmodbus_program

IDM = ROOT / "maps" / "idm_rs.yaml"
PEAK_CURRENT = load_map(IDM).register("peak_current").address
READ_PEAK = struct.pack(">BHH", 0x03, PEAK_CURRENT, 1)


def mbap(transaction: int, unit: int, pdu: bytes) -> bytes:
    return struct.pack(">HHHB", transaction, 0, len(pdu) + 1, unit) + pdu


def exchange(sock: socket.socket, frame: bytes, wait: float = 1.0) -> bytes:
    """Send `frame`; everything that arrives until `wait` seconds of silence."""
    sock.sendall(frame)
    got = b""
    while select.select([sock], [], [], wait)[0]:
        chunk = sock.recv(4096)
        if not chunk:
            break
        got += chunk
        wait = 0.2
    return got


def connect(port: int) -> socket.socket:
    return socket.create_connection(("127.0.0.1", port), timeout=5)


def test_a_direct_device_answers_units_0xff_and_0_as_its_own(simulator: SimulatorFactory) -> None:
    sim = simulator(IDM)
    assert sim.port is not None
    with connect(sim.port) as sock:
        own = exchange(sock, mbap(1, 1, READ_PEAK))
        assert own[:7] == struct.pack(">HHHB", 1, 0, len(own) - 6, 1) and own[7] == 0x03
        for transaction, unit in ((2, 0xFF), (3, 0x00)):
            answer = exchange(sock, mbap(transaction, unit, READ_PEAK))
            assert answer == struct.pack(">HHHB", transaction, 0, len(own) - 6, unit) + own[7:], f"unit {unit:#04x}"
        write = struct.pack(">BHH", 0x06, PEAK_CURRENT, 15)
        assert exchange(sock, mbap(4, 0, write)) == mbap(4, 0, write)  # answered: not a broadcast on a direct device
        assert exchange(sock, mbap(5, 1, READ_PEAK))[9:] == b"\x00\x0f"
        assert exchange(sock, mbap(6, 7, READ_PEAK), wait=0.5) == b""  # another unit id: not this device


def test_a_gateway_broadcasts_unit_0_and_answers_0x0b_for_absent_units(simulator: SimulatorFactory) -> None:
    sim = simulator(IDM, "--gateway")
    assert sim.port is not None
    with connect(sim.port) as sock:
        assert exchange(sock, mbap(1, 7, READ_PEAK)) == mbap(1, 7, bytes([0x83, 0x0B]))
        assert exchange(sock, mbap(2, 0xFF, READ_PEAK)) == mbap(2, 0xFF, bytes([0x83, 0x0B]))
        assert exchange(sock, mbap(3, 0, struct.pack(">BHH", 0x06, PEAK_CURRENT, 13)), wait=0.5) == b""  # broadcast: no reply
        assert exchange(sock, mbap(4, 0, READ_PEAK), wait=0.5) == b""  # a broadcast read is ignored
        assert exchange(sock, mbap(5, 1, READ_PEAK))[9:] == b"\x00\x0d"  # ... but the broadcast write was applied
    assert "gateway" in sim.banner or "gateway" in sim.stop()


LIBMODBUS_CLIENT = r"""
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <modbus.h>
int main(int argc, char **argv) {
    modbus_t *ctx = modbus_new_tcp("127.0.0.1", argc > 1 ? atoi(argv[1]) : 502);
    uint16_t value = 0;
    if (ctx == NULL || modbus_connect(ctx) != 0) { return 2; }
    modbus_set_response_timeout(ctx, 2, 0);
    if (modbus_read_registers(ctx, 0x0191, 1, &value) != 1) { fprintf(stderr, "%s\n", modbus_strerror(errno)); return 1; }
    printf("%u\n", value);
    modbus_close(ctx);
    modbus_free(ctx);
    return 0;
}
"""


def test_libmodbus_tcp_client_with_its_default_unit_gets_answers(simulator: SimulatorFactory, tmp_path: Path) -> None:
    source = tmp_path / "client.c"
    source.write_text(LIBMODBUS_CLIENT)
    client = build_libmodbus_program(source, tmp_path / "client")
    sim = simulator(IDM)
    result = subprocess.run([str(client), str(sim.port)], capture_output=True, text=True, timeout=20, check=False)
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip().isdigit()


def test_rtu_over_tcp_frames_longer_than_256_bytes_are_discarded(simulator: SimulatorFactory) -> None:
    sim = simulator(IDM, "--rtu-over-tcp")
    assert sim.port is not None
    too_long = with_crc(bytes([1, 0x42]) + bytes(296))
    assert len(too_long) == 300
    with connect(sim.port) as sock:
        assert exchange(sock, too_long, wait=0.5) == b""
        answer = exchange(sock, with_crc(bytes([1]) + READ_PEAK))
        assert answer[:3] == bytes([1, 0x03, 2])  # the line is still served
        longest = with_crc(bytes([1, 0x42]) + bytes(252))  # 256 bytes: an RTU frame may be that long
        assert exchange(sock, longest) == with_crc(bytes([1, 0xC2, 0x01]))


def test_an_idle_connection_is_closed_and_a_polling_one_kept(simulator: SimulatorFactory) -> None:
    sim = simulator(IDM, "--idle-timeout", "0.6")
    assert sim.port is not None
    with connect(sim.port) as idle, connect(sim.port) as polling:
        started = time.monotonic()
        while time.monotonic() - started < 1.8:
            assert exchange(polling, mbap(1, 1, READ_PEAK), wait=1.0)[7] == 0x03
            time.sleep(0.2)
        idle.settimeout(2)
        assert idle.recv(16) == b""  # the server closed it
    assert "no request for 0.6 s" in sim.stop()


def test_past_the_connection_cap_the_longest_idle_is_closed(simulator: SimulatorFactory) -> None:
    sim = simulator(IDM, "--max-connections", "2")
    assert sim.port is not None
    time.sleep(0.3)  # the fixture's probe connection has gone
    with connect(sim.port) as first, connect(sim.port) as second:
        assert exchange(first, mbap(1, 1, READ_PEAK))[7] == 0x03
        time.sleep(0.2)
        assert exchange(second, mbap(1, 1, READ_PEAK))[7] == 0x03  # second is now the most recently heard
        with connect(sim.port) as third:
            assert exchange(third, mbap(2, 1, READ_PEAK))[7] == 0x03
            first.settimeout(2)
            assert first.recv(16) == b""
            assert exchange(second, mbap(3, 1, READ_PEAK))[7] == 0x03
            first_port, second_port = first.getsockname()[1], second.getsockname()[1]
    out = sim.stop()
    assert f"127.0.0.1:{first_port}: closing the connection to make room" in out, out
    assert f"127.0.0.1:{second_port}: closing" not in out, out


@pytest.fixture
def limited_simulator(tmp_path: Path) -> Iterator[tuple[subprocess.Popen[str], int]]:
    """The simulator with 64 file descriptors, as `prlimit --nofile=64:64` gives it."""
    port = free_port()

    def limit() -> None:
        resource.setrlimit(resource.RLIMIT_NOFILE, (64, 64))

    process = subprocess.Popen(
        [sys.executable, "-m", "regmap", "simulate", str(IDM), "--tcp", f"127.0.0.1:{port}"],
        cwd=ROOT,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        preexec_fn=limit,
        env={**os.environ, "PYTHONUNBUFFERED": "1"},
    )

    def listening() -> bool:
        with socket.socket() as probe:
            return probe.connect_ex(("127.0.0.1", port)) == 0 or process.poll() is not None

    wait_for(listening, 20, "the simulator to listen")
    yield process, port
    process.terminate()
    process.wait(timeout=10)


def test_eighty_idle_sockets_do_not_lock_out_a_well_behaved_client(limited_simulator: tuple[subprocess.Popen[str], int]) -> None:
    process, port = limited_simulator
    hogs = []
    try:
        for _ in range(80):
            hogs.append(connect(port))
        time.sleep(1.5)  # asyncio retries an accept that ran out of descriptors after 1 s
        deadline = time.monotonic() + 10
        answer = b""
        while time.monotonic() < deadline and not answer:
            with connect(port) as client:
                answer = exchange(client, mbap(1, 1, READ_PEAK), wait=2.0)
        assert answer[7:9] == bytes([0x03, 2])
    finally:
        for sock in hogs:
            sock.close()
    process.terminate()
    _out, err = process.communicate(timeout=10)
    assert "Traceback" not in err and "out of system resource" not in err, err
    assert "to make room" in err


def test_the_power_meter_plays_the_firmware_its_map_and_example_name(simulator: SimulatorFactory) -> None:
    meter = ROOT / "tests" / "maps" / "fixtures" / "power_meter.yaml"
    example = load_map(meter).example("read_firmware_rsp")
    sim = simulator(meter)
    assert sim.port is not None
    with connect(sim.port) as sock:
        answer = exchange(sock, mbap(1, 1, struct.pack(">BHH", 0x03, 0x0110, 1)))
    assert with_crc(bytes([1]) + answer[7:]) == example.frame  # 01 03 02 00 7D: firmware 1.25


def test_requests_cut_anywhere_by_tcp_segments_are_each_answered_once(simulator: SimulatorFactory) -> None:
    """Two whole ADUs and the start of a third in one segment, the rest of the third in the next."""
    sim = simulator(IDM)
    assert sim.port is not None
    stream = mbap(1, 1, READ_PEAK) + mbap(2, 1, READ_PEAK) + mbap(3, 1, READ_PEAK)
    with connect(sim.port) as sock:
        sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        sock.sendall(stream[:-5])
        time.sleep(0.2)  # a segment of its own
        sock.sendall(stream[-5:])
        got = b""
        deadline = time.monotonic() + 5
        while len(got) < 3 * 11 and time.monotonic() < deadline:
            if select.select([sock], [], [], 0.5)[0]:
                got += sock.recv(4096)
    assert [struct.unpack(">H", got[i : i + 2])[0] for i in range(0, len(got), 11)] == [1, 2, 3]
    assert len(got) == 3 * 11
