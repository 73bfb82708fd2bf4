"""The functions beyond reads and writes, served as the Modbus Application Protocol v1.1b3 says:
0x08 diagnostics (return query data), 0x11 report server id, 0x17 read/write multiple registers,
0x2B/0x0E read device identification; each answer byte-exact, built here with struct from the spec,
over Modbus TCP, RTU over TCP and a pty, and through libmodbus's own client calls."""

from __future__ import annotations

import os
import select
import socket
import struct
import subprocess
import time
from collections.abc import Callable
from pathlib import Path

import pytest

from regmap.diagnostics import MapError
from regmap.frontend import load_map, load_map_text
from regmap_runtime.rtu import with_crc

from conftest import ROOT, PtyPair, SimulatorFactory
from support.libmodbus_ref import build_libmodbus_program

METER = ROOT / "tests" / "maps" / "fixtures" / "power_meter.yaml"
METER_MAP = load_map(METER)
CT_RATIO = METER_MAP.register("ct_ratio").address  # u16 1..10000, default 1
FIRMWARE = METER_MAP.register("firmware_version").address  # u16, default 125
assert METER_MAP.transport.identification is not None and METER_MAP.transport.server_id is not None
OBJECTS = dict(METER_MAP.transport.identification.objects)  # the map's text; the framing below is the spec's
SERVER = METER_MAP.transport.server_id


def ident_object(object_id: int) -> bytes:
    text = OBJECTS[object_id]
    return struct.pack(">BB", object_id, len(text)) + text.encode("ascii")


BASIC = ident_object(0) + ident_object(1) + ident_object(2)
MODEL = ident_object(5)
SERVER_DATA = SERVER.id + b"\xff" + SERVER.additional_data.encode("ascii")  # the run indicator: ON

# (what, request PDU, answer PDU): a sequence, run in order on a fresh simulator.
CASES: list[tuple[str, bytes, bytes]] = [
    ("0x08 return query data echoes", bytes([0x08, 0x00, 0x00, 0xA5, 0x37]), bytes([0x08, 0x00, 0x00, 0xA5, 0x37])),
    ("0x08 another sub-function", bytes([0x08, 0x00, 0x0A, 0x00, 0x00]), bytes([0x88, 0x01])),
    ("0x11 report server id", bytes([0x11]), bytes([0x11, len(SERVER_DATA)]) + SERVER_DATA),
    (
        "0x17 writes 7 to ct_ratio, then reads it and the firmware",
        struct.pack(">BHHHHBH", 0x17, FIRMWARE, 1, CT_RATIO, 1, 2, 7),
        struct.pack(">BBH", 0x17, 2, 125),
    ),
    ("0x17 read back", struct.pack(">BHHHHBH", 0x17, CT_RATIO, 1, CT_RATIO, 1, 2, 9), struct.pack(">BBH", 0x17, 2, 9)),
    ("0x17 write quantity 0", struct.pack(">BHHHHB", 0x17, CT_RATIO, 1, CT_RATIO, 0, 0), bytes([0x97, 0x03])),
    ("0x17 read quantity 126", struct.pack(">BHHHHBH", 0x17, CT_RATIO, 126, CT_RATIO, 1, 2, 9), bytes([0x97, 0x03])),
    ("0x17 byte count wrong", struct.pack(">BHHHHBH", 0x17, CT_RATIO, 1, CT_RATIO, 1, 4, 9), bytes([0x97, 0x03])),
    ("0x17 write out of range", struct.pack(">BHHHHBH", 0x17, CT_RATIO, 1, CT_RATIO, 1, 2, 0), bytes([0x97, 0x03])),
    ("0x17 read undocumented: nothing written", struct.pack(">BHHHHBH", 0x17, 0x7000, 1, CT_RATIO, 1, 2, 5), bytes([0x97, 0x02])),
    ("0x03 after the refusals: still the 9 written before", struct.pack(">BHH", 0x03, CT_RATIO, 1), struct.pack(">BBH", 0x03, 2, 9)),
    ("0x2B basic stream", bytes([0x2B, 0x0E, 0x01, 0x00]), bytes([0x2B, 0x0E, 0x01, 0x82, 0x00, 0x00, 3]) + BASIC),
    ("0x2B regular stream", bytes([0x2B, 0x0E, 0x02, 0x00]), bytes([0x2B, 0x0E, 0x02, 0x82, 0x00, 0x00, 4]) + BASIC + MODEL),
    (
        "0x2B stream from an unknown object restarts at 0",
        bytes([0x2B, 0x0E, 0x01, 0x09]),
        bytes([0x2B, 0x0E, 0x01, 0x82, 0x00, 0x00, 3]) + BASIC,
    ),
    ("0x2B one object", bytes([0x2B, 0x0E, 0x04, 0x01]), bytes([0x2B, 0x0E, 0x04, 0x82, 0x00, 0x00, 1]) + ident_object(1)),
    ("0x2B one absent object", bytes([0x2B, 0x0E, 0x04, 0x03]), bytes([0xAB, 0x02])),
    ("0x2B read device id code 5", bytes([0x2B, 0x0E, 0x05, 0x00]), bytes([0xAB, 0x03])),
    ("0x2B another MEI type", bytes([0x2B, 0x0D, 0x00, 0x00]), bytes([0xAB, 0x01])),
]


def receive(fd: int, wait: float = 1.0) -> bytes:
    got = b""
    while select.select([fd], [], [], wait)[0]:
        chunk = os.read(fd, 4096)
        if not chunk:
            break
        got += chunk
        wait = 0.15
    return got


def run_cases(send: Callable[[int, bytes], bytes]) -> None:
    for number, (what, request, answer) in enumerate(CASES, 1):
        assert send(number, request) == answer, what


def test_over_modbus_tcp(simulator: SimulatorFactory) -> None:
    sim = simulator(METER)
    assert sim.port is not None
    with socket.create_connection(("127.0.0.1", sim.port), timeout=5) as sock:

        def send(number: int, pdu: bytes) -> bytes:
            sock.sendall(struct.pack(">HHHB", number, 0, len(pdu) + 1, 1) + pdu)
            got = receive(sock.fileno())
            assert got[:7] == struct.pack(">HHHB", number, 0, len(got) - 6, 1)
            return got[7:]

        run_cases(send)


def rtu_sender(write: Callable[[bytes], None], fd: int) -> Callable[[int, bytes], bytes]:
    def send(_number: int, pdu: bytes) -> bytes:
        write(with_crc(bytes([1]) + pdu))
        got = receive(fd)
        assert got == with_crc(got[:-2]) and got[0] == 1
        return got[1:-2]

    return send


def test_over_rtu_over_tcp(simulator: SimulatorFactory) -> None:
    sim = simulator(METER, "--rtu-over-tcp")
    assert sim.port is not None
    with socket.create_connection(("127.0.0.1", sim.port), timeout=5) as sock:
        run_cases(rtu_sender(sock.sendall, sock.fileno()))


def test_over_a_pty(simulator: SimulatorFactory, pty_pair: PtyPair) -> None:
    simulator(METER, "--parity", "none", serial=pty_pair.device)
    fd = os.open(pty_pair.client, os.O_RDWR | os.O_NOCTTY)
    try:
        import termios
        import tty

        tty.setraw(fd)
        termios.tcflush(fd, termios.TCIOFLUSH)

        def write(frame: bytes) -> None:
            os.write(fd, frame)
            time.sleep(0.03)  # the line's silence ends each frame

        run_cases(rtu_sender(write, fd))
    finally:
        os.close(fd)


LIBMODBUS_CALLS = r"""
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <modbus.h>
int main(int argc, char **argv) {
    modbus_t *ctx = modbus_new_tcp("127.0.0.1", argc > 1 ? atoi(argv[1]) : 502);
    uint8_t id[64];
    uint16_t write[1] = {42}, read[2] = {0, 0};
    int n, i;
    if (ctx == NULL || modbus_set_slave(ctx, 1) != 0 || modbus_connect(ctx) != 0) { return 2; }
    n = modbus_report_slave_id(ctx, sizeof id, id);
    if (n < 0) { fprintf(stderr, "report: %s\n", modbus_strerror(errno)); return 1; }
    printf("id");
    for (i = 0; i < n; i++) printf(" %02X", id[i]);
    printf("\n");
    n = modbus_write_and_read_registers(ctx, 0x0120, 1, write, 0x0120, 1, read);
    if (n != 1) { fprintf(stderr, "rw: %s\n", modbus_strerror(errno)); return 1; }
    printf("rw %u\n", read[0]);
    n = modbus_write_and_read_registers(ctx, 0x0120, 1, write, 0x7000, 1, read);
    printf("refused %d %s\n", n, n < 0 && errno == EMBXILADD ? "EMBXILADD" : "?");
    modbus_close(ctx);
    modbus_free(ctx);
    return 0;
}
"""


def test_libmodbus_client_calls(simulator: SimulatorFactory, tmp_path: Path) -> None:
    (tmp_path / "calls.c").write_text(LIBMODBUS_CALLS)
    calls = build_libmodbus_program(tmp_path / "calls.c", tmp_path / "calls")
    sim = simulator(METER)
    result = subprocess.run([str(calls), str(sim.port)], capture_output=True, text=True, timeout=30, check=False)
    assert result.returncode == 0, result.stderr
    expected_id = " ".join(f"{b:02X}" for b in SERVER_DATA)
    assert result.stdout.splitlines() == [f"id {expected_id}", "rw 42", "refused -1 EMBXILADD"]


def test_the_map_model_carries_what_the_functions_report() -> None:
    transport = load_map(METER).transport
    assert transport.identification is not None and transport.server_id is not None
    assert dict(transport.identification.objects)[2] == "1.25" and transport.identification.conformity_level == 0x82
    assert transport.server_id.id == b"PM" and transport.server_id.running


def meter_text(codes: str, extra: str = "") -> str:
    text = METER.read_text(encoding="utf-8")
    start = text.index("  function_codes:")
    end = text.index("  max_read_registers:")
    return text[:start] + f"  function_codes: [{codes}]\n{extra}" + text[end:]


@pytest.mark.parametrize(
    ("codes", "extra", "message"),
    [
        ("0x03, 0x04, 0x06, 0x10, 0x42", "", "function 0x42 is not one regmap can serve"),
        ("0x03, 0x04, 0x06, 0x10, 0x14", "", "function 0x14 is not one regmap can serve"),
        ("0x03, 0x04, 0x06, 0x10, 0x2B", "", "transport.identification says what the device answers"),
        ("0x03, 0x04, 0x06, 0x10, 0x11", "", "transport.server_id says what the device answers"),
    ],
)
def test_validate_refuses_a_function_regmap_cannot_serve(codes: str, extra: str, message: str) -> None:
    with pytest.raises(MapError) as info:
        load_map_text(meter_text(codes, extra), "meter.yaml")
    found = [d for d in info.value.diagnostics if message in d.message]
    assert found and found[0].line > 20, [d.message for d in info.value.diagnostics]
