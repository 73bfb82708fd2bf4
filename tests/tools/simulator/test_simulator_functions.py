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
from collections.abc import Callable, Iterator
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

UNDOCUMENTED = 0x7000
MASKED = (0xFF00, 0x0010)  # AND, OR: ct_ratio (1 after start-up) becomes (1 & 0xFF00) | 0x0010 = 16


def exc(function: int, code: int) -> bytes:
    return struct.pack(">BB", function | 0x80, code)


def rw(read_at: int, read_count: int, write_at: int, words: list[int], byte_count: int | None = None) -> bytes:
    body = struct.pack(f">{len(words)}H", *words)
    return struct.pack(">BHHHHB", 0x17, read_at, read_count, write_at, len(words), len(body) if byte_count is None else byte_count) + body


# (what, request PDU, answer PDU): a sequence, run in order on a fresh simulator of SERVED (the meter with 0x16
# listed too). Per function the normal answers, then the exceptions in the order MBAP §6 checks them: 01 (a
# function or sub-function the device lacks), 03 (quantity, byte count, length), 02 (address); a request wrong
# in two ways gets the earlier check's code. 04 (device failure) is FAULT_CASES; 01 for a function the map
# does not list at all is UNLISTED_CASES.
CASES: list[tuple[str, bytes, bytes]] = [
    ("0x08 return query data echoes", bytes([0x08, 0x00, 0x00, 0xA5, 0x37]), bytes([0x08, 0x00, 0x00, 0xA5, 0x37])),
    ("0x08 01: another sub-function", bytes([0x08, 0x00, 0x0A, 0x00, 0x00]), exc(0x08, 0x01)),
    ("0x08 03: no sub-function", bytes([0x08, 0x00]), exc(0x08, 0x03)),
    ("0x11 report server id", bytes([0x11]), bytes([0x11, len(SERVER_DATA)]) + SERVER_DATA),
    ("0x11 03: data after the function", bytes([0x11, 0x00]), exc(0x11, 0x03)),
    ("0x16 mask write echoes", struct.pack(">BHHH", 0x16, CT_RATIO, *MASKED), struct.pack(">BHHH", 0x16, CT_RATIO, *MASKED)),
    ("0x16 the register after it", struct.pack(">BHH", 0x03, CT_RATIO, 1), struct.pack(">BBH", 0x03, 2, 16)),
    ("0x16 03: a mask missing", struct.pack(">BHH", 0x16, CT_RATIO, 0xFFFF), exc(0x16, 0x03)),
    ("0x16 03 before 02: short and undocumented", struct.pack(">BHH", 0x16, UNDOCUMENTED, 0xFFFF), exc(0x16, 0x03)),
    ("0x16 02: undocumented", struct.pack(">BHHH", 0x16, UNDOCUMENTED, 0xFFFF, 0), exc(0x16, 0x02)),
    ("0x16 03: the read-only firmware register", struct.pack(">BHHH", 0x16, FIRMWARE, 0xFFFF, 0), exc(0x16, 0x03)),
    ("0x16 03: the result out of range (0)", struct.pack(">BHHH", 0x16, CT_RATIO, 0x0000, 0x0000), exc(0x16, 0x03)),
    ("0x17 writes 7 to ct_ratio, then reads it and the firmware", rw(FIRMWARE, 1, CT_RATIO, [7]), struct.pack(">BBH", 0x17, 2, 125)),
    ("0x17 read back", rw(CT_RATIO, 1, CT_RATIO, [9]), struct.pack(">BBH", 0x17, 2, 9)),
    ("0x17 03: write quantity 0", rw(CT_RATIO, 1, CT_RATIO, []), exc(0x17, 0x03)),
    ("0x17 03: write quantity 122", struct.pack(">BHHHHBH", 0x17, CT_RATIO, 1, CT_RATIO, 122, 2, 9), exc(0x17, 0x03)),
    ("0x17 03: read quantity 0", rw(CT_RATIO, 0, CT_RATIO, [9]), exc(0x17, 0x03)),
    ("0x17 03: read quantity 126", rw(CT_RATIO, 126, CT_RATIO, [9]), exc(0x17, 0x03)),
    ("0x17 03: byte count wrong", rw(CT_RATIO, 1, CT_RATIO, [9], byte_count=4), exc(0x17, 0x03)),
    ("0x17 03 before 02: quantity 0 past 0xFFFF", rw(0xFFFF, 0, CT_RATIO, [9]), exc(0x17, 0x03)),
    ("0x17 02: read past 0xFFFF", rw(0xFFFF, 2, CT_RATIO, [9]), exc(0x17, 0x02)),
    ("0x17 02: write past 0xFFFF", rw(CT_RATIO, 1, 0xFFFF, [9, 9]), exc(0x17, 0x02)),
    ("0x17 02: read undocumented, nothing written", rw(UNDOCUMENTED, 1, CT_RATIO, [5]), exc(0x17, 0x02)),
    ("0x17 03: write out of range", rw(CT_RATIO, 1, CT_RATIO, [0]), exc(0x17, 0x03)),
    ("0x03 after the refusals: still the 9 written before", struct.pack(">BHH", 0x03, CT_RATIO, 1), struct.pack(">BBH", 0x03, 2, 9)),
    ("0x2B basic stream", bytes([0x2B, 0x0E, 0x01, 0x00]), bytes([0x2B, 0x0E, 0x01, 0x82, 0x00, 0x00, 3]) + BASIC),
    ("0x2B regular stream", bytes([0x2B, 0x0E, 0x02, 0x00]), bytes([0x2B, 0x0E, 0x02, 0x82, 0x00, 0x00, 4]) + BASIC + MODEL),
    (
        "0x2B stream from an unknown object restarts at 0",
        bytes([0x2B, 0x0E, 0x01, 0x09]),
        bytes([0x2B, 0x0E, 0x01, 0x82, 0x00, 0x00, 3]) + BASIC,
    ),
    ("0x2B one object", bytes([0x2B, 0x0E, 0x04, 0x01]), bytes([0x2B, 0x0E, 0x04, 0x82, 0x00, 0x00, 1]) + ident_object(1)),
    ("0x2B 01: another MEI type", bytes([0x2B, 0x0D, 0x00, 0x00]), exc(0x2B, 0x01)),
    ("0x2B 03: read device id code 5", bytes([0x2B, 0x0E, 0x05, 0x00]), exc(0x2B, 0x03)),
    ("0x2B 03: read device id code 0", bytes([0x2B, 0x0E, 0x00, 0x00]), exc(0x2B, 0x03)),
    ("0x2B 03: no object id", bytes([0x2B, 0x0E, 0x04]), exc(0x2B, 0x03)),
    ("0x2B 02: one absent object", bytes([0x2B, 0x0E, 0x04, 0x03]), exc(0x2B, 0x02)),
]
# --fault exception (device failure 0x04): after the checks of 01, 03 and 02, as MBAP §6's diagrams place it.
FAULT_CASES: list[tuple[str, bytes, bytes]] = [
    ("0x03 02 before 04", struct.pack(">BHH", 0x03, UNDOCUMENTED, 1), exc(0x03, 0x02)),
    ("0x03 04", struct.pack(">BHH", 0x03, CT_RATIO, 1), exc(0x03, 0x04)),
    ("0x08 04", bytes([0x08, 0x00, 0x00, 0xA5, 0x37]), exc(0x08, 0x04)),
    ("0x08 01 before 04", bytes([0x08, 0x00, 0x0A, 0x00, 0x00]), exc(0x08, 0x01)),
    ("0x11 04", bytes([0x11]), exc(0x11, 0x04)),
    ("0x11 03 before 04", bytes([0x11, 0x00]), exc(0x11, 0x03)),
    ("0x16 04", struct.pack(">BHHH", 0x16, CT_RATIO, *MASKED), exc(0x16, 0x04)),
    ("0x16 02 before 04", struct.pack(">BHHH", 0x16, UNDOCUMENTED, 0xFFFF, 0), exc(0x16, 0x02)),
    ("0x17 04", rw(CT_RATIO, 1, CT_RATIO, [9]), exc(0x17, 0x04)),
    ("0x17 03 before 04", rw(CT_RATIO, 126, CT_RATIO, [9]), exc(0x17, 0x03)),
    ("0x17 02 before 04", rw(UNDOCUMENTED, 1, CT_RATIO, [9]), exc(0x17, 0x02)),
    ("0x2B 04", bytes([0x2B, 0x0E, 0x01, 0x00]), exc(0x2B, 0x04)),
    ("0x2B 02 before 04", bytes([0x2B, 0x0E, 0x04, 0x03]), exc(0x2B, 0x02)),
]
# The remote-I/O fixture lists none of these functions: 01 for each, whatever else is wrong with the request.
UNLISTED_CASES: list[tuple[str, bytes, bytes]] = [
    ("0x08 01", bytes([0x08, 0x00, 0x00, 0xA5, 0x37]), exc(0x08, 0x01)),
    ("0x11 01", bytes([0x11, 0x00]), exc(0x11, 0x01)),
    ("0x16 01", struct.pack(">BHH", 0x16, UNDOCUMENTED, 0), exc(0x16, 0x01)),
    ("0x17 01", rw(0xFFFF, 0, 0, []), exc(0x17, 0x01)),
    ("0x2B 01", bytes([0x2B, 0x0E, 0x05, 0x00]), exc(0x2B, 0x01)),
]
REMOTE_IO = ROOT / "tests" / "maps" / "fixtures" / "remote_io.yaml"
assert not {0x08, 0x11, 0x16, 0x17, 0x2B} & set(load_map(REMOTE_IO).transport.function_codes)


def served_map(tmp_path: Path) -> Path:
    """The meter fixture with mask write register (0x16) listed as well."""
    path = tmp_path / "meter_with_0x16.yaml"
    listed = "  function_codes: [0x03, 0x04, 0x06, 0x08, 0x10, 0x11, 0x17, 0x2B]\n"
    text = METER.read_text(encoding="utf-8")
    assert listed in text
    path.write_text(text.replace(listed, listed.replace("0x11, 0x17", "0x11, 0x16, 0x17")), encoding="utf-8")
    return path


def receive(fd: int, wait: float = 1.0) -> bytes:
    got = b""
    while select.select([fd], [], [], wait)[0]:
        chunk = os.read(fd, 4096)
        if not chunk:
            break
        got += chunk
        wait = 0.15
    return got


def run_cases(send: Callable[[int, bytes], bytes], cases: list[tuple[str, bytes, bytes]]) -> None:
    for number, (what, request, answer) in enumerate(cases, 1):
        assert send(number, request) == answer, what


def rtu_sender(write: Callable[[bytes], None], fd: int) -> Callable[[int, bytes], bytes]:
    def send(_number: int, pdu: bytes) -> bytes:
        write(with_crc(bytes([1]) + pdu))
        got = receive(fd)
        assert got == with_crc(got[:-2]) and got[0] == 1
        return got[1:-2]

    return send


def over(
    transport: str, simulator: SimulatorFactory, pty_pair: Callable[[], PtyPair], path: Path, *extra: str
) -> Iterator[Callable[[int, bytes], bytes]]:
    """A sender of request PDUs to a fresh simulator of `path` over `transport`, answering the answer PDU."""
    if transport == "pty":
        pair = pty_pair()
        simulator(path, "--parity", "none", *extra, serial=pair.device)
        fd = os.open(pair.client, os.O_RDWR | os.O_NOCTTY)
        try:
            import termios
            import tty

            tty.setraw(fd)
            termios.tcflush(fd, termios.TCIOFLUSH)

            def write(frame: bytes) -> None:
                os.write(fd, frame)
                time.sleep(0.03)  # the line's silence ends each frame

            yield rtu_sender(write, fd)
        finally:
            os.close(fd)
        return
    sim = simulator(path, *(["--rtu-over-tcp"] if transport == "rtu-over-tcp" else []), *extra)
    assert sim.port is not None
    with socket.create_connection(("127.0.0.1", sim.port), timeout=5) as sock:
        if transport == "rtu-over-tcp":
            yield rtu_sender(sock.sendall, sock.fileno())
            return

        def send(number: int, pdu: bytes) -> bytes:
            sock.sendall(struct.pack(">HHHB", number, 0, len(pdu) + 1, 1) + pdu)
            got = receive(sock.fileno())
            assert got[:7] == struct.pack(">HHHB", number, 0, len(got) - 6, 1)
            return got[7:]

        yield send


TRANSPORTS = ["tcp", "rtu-over-tcp", "pty"]


@pytest.fixture
def pty_factory(request: pytest.FixtureRequest) -> Callable[[], PtyPair]:
    return lambda: request.getfixturevalue("pty_pair")


@pytest.mark.parametrize("transport", TRANSPORTS)
def test_answers_and_exceptions_in_the_specs_order(
    transport: str, simulator: SimulatorFactory, pty_factory: Callable[[], PtyPair], tmp_path: Path
) -> None:
    for send in over(transport, simulator, pty_factory, served_map(tmp_path)):
        run_cases(send, CASES)


@pytest.mark.parametrize("transport", TRANSPORTS)
def test_device_failure_comes_after_the_other_checks(
    transport: str, simulator: SimulatorFactory, pty_factory: Callable[[], PtyPair], tmp_path: Path
) -> None:
    for send in over(transport, simulator, pty_factory, served_map(tmp_path), "--fault", "exception"):
        run_cases(send, FAULT_CASES)


@pytest.mark.parametrize("transport", TRANSPORTS)
def test_a_map_without_the_functions_answers_illegal_function(
    transport: str, simulator: SimulatorFactory, pty_factory: Callable[[], PtyPair]
) -> None:
    for send in over(transport, simulator, pty_factory, REMOTE_IO):
        run_cases(send, UNLISTED_CASES)


LIBMODBUS_CALLS = r"""
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <modbus.h>
static const char *code(int n) {
    if (n >= 0) return "ok";
    return errno == EMBXILADD ? "EMBXILADD" : errno == EMBXILVAL ? "EMBXILVAL" : errno == EMBXILFUN ? "EMBXILFUN" : "?";
}
int main(int argc, char **argv) {
    /* calls tcp PORT CT_RATIO UNDOCUMENTED, or calls rtu DEVICE CT_RATIO UNDOCUMENTED */
    if (argc != 5) { return 2; }
    modbus_t *ctx = strcmp(argv[1], "tcp") == 0 ? modbus_new_tcp("127.0.0.1", atoi(argv[2])) : modbus_new_rtu(argv[2], 9600, 'N', 8, 1);
    int ct_ratio = (int)strtol(argv[3], NULL, 0), undocumented = (int)strtol(argv[4], NULL, 0);
    uint8_t id[64];
    uint16_t write[1] = {42}, zero[1] = {0}, read[2] = {0, 0};
    int n, i;
    if (ctx == NULL || modbus_set_slave(ctx, 1) != 0 || modbus_connect(ctx) != 0) { return 2; }
    modbus_set_response_timeout(ctx, 2, 0);
    n = modbus_report_slave_id(ctx, sizeof id, id);
    if (n < 0) { fprintf(stderr, "report: %s\n", modbus_strerror(errno)); return 1; }
    printf("id");
    for (i = 0; i < n; i++) printf(" %02X", id[i]);
    printf("\n");
    n = modbus_mask_write_register(ctx, ct_ratio, 0xFF00, 0x0010);
    printf("mask %s\n", code(n));
    n = modbus_read_registers(ctx, ct_ratio, 1, read);
    printf("masked %d %u\n", n, read[0]);
    n = modbus_mask_write_register(ctx, undocumented, 0xFFFF, 0x0000);
    printf("mask undocumented %s\n", code(n));
    n = modbus_mask_write_register(ctx, ct_ratio, 0x0000, 0x0000);
    printf("mask to 0 %s\n", code(n));
    n = modbus_write_and_read_registers(ctx, ct_ratio, 1, write, ct_ratio, 1, read);
    printf("rw %d %u\n", n, read[0]);
    n = modbus_write_and_read_registers(ctx, ct_ratio, 1, write, undocumented, 1, read);
    printf("rw undocumented %s\n", code(n));
    n = modbus_write_and_read_registers(ctx, ct_ratio, 1, zero, ct_ratio, 1, read);
    printf("rw 0 %s\n", code(n));
    modbus_close(ctx);
    modbus_free(ctx);
    return 0;
}
"""


@pytest.mark.parametrize("transport", ["tcp", "pty"])
def test_libmodbus_client_calls(transport: str, simulator: SimulatorFactory, pty_factory: Callable[[], PtyPair], tmp_path: Path) -> None:
    """libmodbus's own modbus_report_slave_id, modbus_mask_write_register and modbus_write_and_read_registers."""
    (tmp_path / "calls.c").write_text(LIBMODBUS_CALLS)
    calls = build_libmodbus_program(tmp_path / "calls.c", tmp_path / "calls")
    if transport == "pty":
        pair = pty_factory()
        simulator(served_map(tmp_path), "--parity", "none", serial=pair.device)
        where = pair.client
    else:
        where = str(simulator(served_map(tmp_path)).port)
    command = [str(calls), "rtu" if transport == "pty" else "tcp", where, hex(CT_RATIO), hex(UNDOCUMENTED)]
    result = subprocess.run(command, capture_output=True, text=True, timeout=60, check=False)
    assert result.returncode == 0, result.stderr
    expected_id = " ".join(f"{b:02X}" for b in SERVER_DATA)
    assert result.stdout.splitlines() == [
        f"id {expected_id}",
        "mask ok",
        "masked 1 16",  # (1 AND FF00) OR (0010 AND NOT FF00)
        "mask undocumented EMBXILADD",
        "mask to 0 EMBXILVAL",  # below ct_ratio's 1..10000
        "rw 1 42",
        "rw undocumented EMBXILADD",
        "rw 0 EMBXILVAL",
    ]


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
