"""`regmap simulate` fails exactly where the drive would, byte for byte, and survives garbage.

Driven by raw sockets and raw pty bytes (exact frames), by mbpoll and by a libmodbus C client
(tests/c/sim_client.c), over Modbus TCP, RTU over TCP and RTU on a pty. iDM-RS limits: 47
registers per read, 45 per write, 100-byte messages, functions 0x03/0x06/0x10, bad CRC answered
with 0x08 (5.4.1). C630S: bad CRC unanswered (its manual says nothing, the map says silent).
"""

from __future__ import annotations

import os
import random
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

from conftest import ROOT, PtyPair, SimulatorFactory, free_port, require_tool
from support.simulator_wire import Line, mbap

IDM = ROOT / "maps" / "idm_rs.yaml"
C630S = ROOT / "maps" / "c630s.yaml"
C630S_FIRST = load_map(C630S).registers[0].address
PEAK_CURRENT = 0x0191  # Pr5.00, default 22 (2.2 A)
PR_TABLE = 0x6200  # 128 plain 16-bit registers: room for the largest read and write
READ_COUNTS = (0, 48, 125, 126, 200, 0xFFFF)


def read_request(address: int, count: int, slave: int = 1) -> bytes:
    return with_crc(struct.pack(">BBHH", slave, 0x03, address, count))


def write_multiple(address: int, words: list[int], slave: int = 1) -> bytes:
    count = len(words)
    body = struct.pack(">BBHHB", slave, 0x10, address, count, 2 * count)
    return with_crc(body + b"".join(struct.pack(">H", w) for w in words))


def exception(function: int, code: int, slave: int = 1) -> bytes:
    return with_crc(bytes([slave, function | 0x80, code]))


def rtu_cases() -> list[tuple[str, bytes, bytes]]:
    """(what, request, exact answer) for iDM-RS, as RTU frames."""
    cases = [(f"read of {n} registers", read_request(PEAK_CURRENT, n), exception(0x03, 0x03)) for n in READ_COUNTS]
    too_many = write_multiple(PR_TABLE, [0] * 46)
    cases += [
        ("write of 46 registers (101-byte frame)", too_many, exception(0x10, 0x03)),
        ("0x10 byte count 2 for count 2", with_crc(struct.pack(">BBHHBH", 1, 0x10, PR_TABLE + 8, 2, 2, 0)), exception(0x10, 0x03)),
        ("0x10 byte count 6 for count 2", with_crc(struct.pack(">BBHHB3H", 1, 0x10, PR_TABLE + 8, 2, 6, 0, 0, 0)), exception(0x10, 0x03)),
        ("function 0x2B read device identification", with_crc(bytes([1, 0x2B, 0x0E, 0x01, 0x00])), exception(0x2B, 0x01)),
        ("function 0x04 read input registers", with_crc(struct.pack(">BBHH", 1, 0x04, PEAK_CURRENT, 1)), exception(0x04, 0x01)),
        # 5.4.1's own example, byte for byte: a bad CRC (D5 CA is right) answered with 0x08.
        ("bad CRC (5.4.1 example)", bytes.fromhex("01 03 00 01 00 01 D5 C1"), bytes.fromhex("01 83 08 40 F6")),
        ("read of 1 register", read_request(PEAK_CURRENT, 1), with_crc(bytes([1, 3, 2, 0, 22]))),
        ("read of 47 registers", read_request(PR_TABLE, 47), b""),  # checked by length below
    ]
    return cases


# -- exact bytes ----------------------------------------------------------------------------


@pytest.fixture(params=["rtu-over-tcp", "pty"])
def idm_rtu_line(request: pytest.FixtureRequest, simulator: SimulatorFactory) -> Iterator[Line]:
    if request.param == "pty":
        pair: PtyPair = request.getfixturevalue("pty_pair")
        simulator(IDM, serial=pair.device)
        line = Line.pty(pair.client)
    else:
        sim = simulator(IDM, "--rtu-over-tcp")
        assert sim.port is not None
        line = Line.tcp(sim.port)
    yield line
    line.close()


def test_rtu_refusals_are_exact_frames(idm_rtu_line: Line) -> None:
    for what, request, expected in rtu_cases():
        idm_rtu_line.send(request)
        if what == "read of 47 registers":
            answer = idm_rtu_line.read(5 + 2 * 47)
            assert answer[:3] == bytes([1, 3, 94]) and answer == with_crc(answer[:-2]), what
            continue
        assert idm_rtu_line.read(len(expected)) == expected, what
        assert idm_rtu_line.read(None) == b"", f"{what}: more than one answer"


def test_tcp_refusals_are_exact_adus(simulator: SimulatorFactory) -> None:
    sim = simulator(IDM)
    assert sim.port is not None
    line = Line.tcp(sim.port)
    try:
        for i, (what, request, expected) in enumerate(rtu_cases()):
            if what.startswith("bad CRC"):
                continue  # TCP has no CRC
            transaction = 0x1200 + i
            line.send(mbap(transaction, request[1:-2]))
            if what == "read of 47 registers":
                answer = line.read(9 + 94)
                assert answer[:9] == mbap(transaction, bytes([3, 94]) + bytes(94))[:9] and len(answer) == 9 + 94, what
                continue
            assert line.read(6 + 1 + len(expected) - 3) == mbap(transaction, expected[1:-2]), what
    finally:
        line.close()


def test_bad_crc_is_unanswered_when_the_map_says_silent(simulator: SimulatorFactory) -> None:
    sim = simulator(C630S, "--rtu-over-tcp")
    assert sim.port is not None
    line = Line.tcp(sim.port)
    try:
        good = read_request(C630S_FIRST, 1)
        line.send(good[:-2] + bytes([good[-2] ^ 0x55, good[-1]]))
        assert line.read(None, timeout=1.0) == b""
        line.send(good)
        assert line.read(7)[:3] == bytes([1, 3, 2])
    finally:
        line.close()


@pytest.mark.parametrize(("map_path", "after_truncated"), [(IDM, bytes.fromhex("01 83 08 40 F6")), (C630S, b"")], ids=["idm_rs", "c630s"])
def test_truncated_frame_costs_only_itself(simulator: SimulatorFactory, pty_pair: PtyPair, map_path: Path, after_truncated: bytes) -> None:
    """A frame cut short, then a valid one after a gap: the valid one is answered. The cut frame
    ends at the silence and is a bad-CRC frame: the map's bad_crc says whether it is answered."""
    simulator(map_path, serial=pty_pair.device)
    line = Line.pty(pty_pair.client)
    try:
        good = read_request(C630S_FIRST if map_path == C630S else PEAK_CURRENT, 1)
        line.send(good[:5])
        time.sleep(0.2)  # longer than the pty's frame gap
        assert line.read(len(after_truncated) or None, timeout=1.0) == after_truncated
        line.send(good)
        answer = line.read(7)
        assert answer[:3] == bytes([1, 3, 2]) and answer == with_crc(answer[:-2])
        # Back to back, no gap at all: the good frame after the stub is still found.
        line.send(good[:5] + good)
        assert line.read(7) == answer
        assert line.read(None) == b""
    finally:
        line.close()


def test_rtu_over_tcp_resynchronises_after_garbage(simulator: SimulatorFactory) -> None:
    sim = simulator(IDM, "--rtu-over-tcp")
    assert sim.port is not None
    line = Line.tcp(sim.port)
    try:
        garbage = bytes(random.Random(17).randrange(256) for _ in range(64))
        line.send(garbage + read_request(PEAK_CURRENT, 1))
        assert line.read(7) == with_crc(bytes([1, 3, 2, 0, 22]))
        assert line.read(None) == b""
    finally:
        line.close()


GARBAGE = {
    "64 bytes of 0xFF": b"\xff" * 64,
    "64 zero bytes": b"\x00" * 64,
    "MBAP protocol id 1": mbap(7, bytes([3, 1, 0x91, 0, 1]), protocol=1),
}


@pytest.mark.parametrize("garbage", GARBAGE.values(), ids=GARBAGE.keys())
def test_tcp_garbage_closes_that_connection_only(simulator: SimulatorFactory, garbage: bytes) -> None:
    sim = simulator(IDM)
    assert sim.port is not None
    read = mbap(9, bytes([3, 1, 0x91, 0, 1]))
    answer = mbap(9, bytes([3, 2, 0, 22]))
    bad, other = Line.tcp(sim.port), Line.tcp(sim.port)
    try:
        bad.send(garbage + read)
        assert bad.closed_by_peer(), "the connection that sent garbage neither answered nor closed"
        other.send(read)
        assert other.read(len(answer)) == answer
        fresh = Line.tcp(sim.port)
        fresh.send(read)
        assert fresh.read(len(answer)) == answer
        fresh.close()
    finally:
        bad.close()
        other.close()
    assert "connections closed on bad headers" in sim.stop()


# -- independent masters --------------------------------------------------------------------


@pytest.fixture(scope="module")
def sim_client(tmp_path_factory: pytest.TempPathFactory) -> str:
    cc = require_tool("cc")
    pkg = require_tool("pkg-config")
    flags = subprocess.run([pkg, "--cflags", "--libs", "libmodbus"], capture_output=True, text=True, check=False)
    if flags.returncode != 0:
        if os.environ.get("CI") == "true":
            pytest.fail("libmodbus-dev is not installed (.ci/run installs it)")
        pytest.skip("libmodbus-dev is not installed")
    out = tmp_path_factory.mktemp("c") / "sim_client"
    src = ROOT / "tests" / "c" / "sim_client.c"
    build = subprocess.run(
        [cc, "-Wall", "-Wextra", "-Werror", "-O2", "-o", str(out), str(src), *flags.stdout.split()], capture_output=True, text=True
    )
    assert build.returncode == 0, build.stderr
    return str(out)


def libmodbus_ops(pr: list[int]) -> list[tuple[list[str], str]]:
    """(operation, expected output line) for iDM-RS; `pr` is the PR table as read."""
    ops = [
        (["read", hex(PEAK_CURRENT), "1"], "ok 22"),
        (["read", hex(PR_TABLE), "47"], "ok " + " ".join(map(str, pr[:47]))),
        (["read", hex(PR_TABLE), "48"], "exception 3"),
        (["read", hex(PR_TABLE), "125"], "exception 3"),
        (["write", hex(PR_TABLE + 8), ",".join(map(str, pr[8 : 8 + 45]))], "ok 45"),
        (["write", hex(PR_TABLE), ",".join(["0"] * 46)], "exception 3"),
        (["write1", hex(PEAK_CURRENT), "900"], "exception 3"),  # out of range
        (["read", "0x5000", "1"], "exception 2"),  # undocumented
        (["raw", "012b0e0100"], "raw 01ab01"),
        (["raw", "010401910001"], "raw 018401"),
        (["raw", "011062080002020000"], "raw 019003"),  # byte count 2 for 2 registers
    ]
    ops += [(["raw", f"01030191{n:04x}"], "raw 018303") for n in READ_COUNTS]
    return ops


@pytest.mark.parametrize("transport", ["tcp", "rtu"])
def test_libmodbus_master_sees_the_drives_refusals(
    simulator: SimulatorFactory, sim_client: str, transport: str, request: pytest.FixtureRequest
) -> None:
    if transport == "rtu":
        pair: PtyPair = request.getfixturevalue("pty_pair")
        simulator(IDM, serial=pair.device)
        where = ["rtu", pair.client, "38400", "1"]
    else:
        sim = simulator(IDM)
        where = ["tcp", "127.0.0.1", str(sim.port), "1"]
    first = subprocess.run(
        [sim_client, *where, "read", hex(PR_TABLE), "47", "read", hex(PR_TABLE + 47), "6"],
        capture_output=True,
        text=True,
        timeout=30,
        check=False,
    )
    assert first.stdout.startswith("ok "), first.stdout + first.stderr
    pr = [int(w) for w in first.stdout.replace("ok", "").split()]
    ops = libmodbus_ops(pr)
    result = subprocess.run(
        [sim_client, *where, *(arg for op, _ in ops for arg in op)], capture_output=True, text=True, timeout=60, check=False
    )
    assert result.returncode == 0, result.stderr
    assert result.stdout.splitlines() == [expected for _, expected in ops]


def mbpoll(*args: str) -> subprocess.CompletedProcess[str]:
    tool = require_tool("mbpoll")
    return subprocess.run([tool, "-1", "-0", "-o", "1", *args], capture_output=True, text=True, check=False, timeout=30)


@pytest.mark.parametrize("transport", ["tcp", "rtu"])
def test_mbpoll_sees_the_limits(simulator: SimulatorFactory, transport: str, request: pytest.FixtureRequest) -> None:
    if transport == "rtu":
        pair: PtyPair = request.getfixturevalue("pty_pair")
        simulator(IDM, serial=pair.device)
        where = ["-m", "rtu", "-b", "38400", "-P", "none", "-a", "1"]
        target = pair.client
    else:
        sim = simulator(IDM)
        where = ["-m", "tcp", "-p", str(sim.port), "-a", "1"]
        target = "127.0.0.1"
    ok = mbpoll(*where, "-r", str(PR_TABLE), "-c", "47", "-t", "4", target)
    assert ok.returncode == 0 and ok.stdout.count("]:") == 47, ok.stdout + ok.stderr
    for count in ("48", "125"):
        refused = mbpoll(*where, "-r", str(PR_TABLE), "-c", count, "-t", "4", target)
        assert refused.returncode != 0 and "Illegal data value" in refused.stdout + refused.stderr, refused.stdout
    write = mbpoll(*where, "-r", str(PR_TABLE), "-t", "4", target, *(["0"] * 46))
    assert write.returncode != 0 and "Illegal data value" in write.stdout + write.stderr, write.stdout


# -- start-up -------------------------------------------------------------------------------


def regmap_simulate(*args: str, timeout: float = 30) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "regmap", "simulate", *args], cwd=ROOT, capture_output=True, text=True, check=False, timeout=timeout
    )


def test_busy_port_is_one_line_before_serving() -> None:
    with socket.socket() as holder:
        holder.bind(("127.0.0.1", 0))
        holder.listen()
        port = holder.getsockname()[1]
        result = regmap_simulate(str(IDM), "--tcp", f"127.0.0.1:{port}")
    assert result.returncode == 2
    assert result.stdout == ""
    assert result.stderr == f"regmap simulate: error: cannot listen on 127.0.0.1:{port}: address already in use\n"


def test_a_host_that_does_not_resolve_is_one_line_with_the_resolver_s_reason() -> None:
    result = regmap_simulate(str(IDM), "--tcp", "no-such-host.invalid:5020")
    assert result.returncode == 2 and result.stdout == ""
    assert result.stderr == "regmap simulate: error: cannot listen on no-such-host.invalid:5020: name or service not known\n"


def test_an_ipv6_address_in_brackets_is_served_and_read() -> None:
    """`--tcp [::1]:PORT`, as URLs write it, for the simulator and for the live commands alike."""
    if not socket.has_ipv6:
        pytest.skip("no IPv6 on this machine")
    with socket.socket(socket.AF_INET6) as probe:
        probe.bind(("::1", 0))
        port = probe.getsockname()[1]
    process = subprocess.Popen(
        [sys.executable, "-m", "regmap", "simulate", str(IDM), "--tcp", f"[::1]:{port}"], cwd=ROOT, stdout=subprocess.PIPE, text=True
    )
    try:
        assert process.stdout is not None and f"on ::1:{port}" in process.stdout.readline()
        result = subprocess.run(
            [sys.executable, "-m", "regmap", "read", str(IDM), "peak_current", "--tcp", f"[::1]:{port}"],
            cwd=ROOT,
            capture_output=True,
            text=True,
            check=False,
            timeout=60,
        )
        assert result.returncode == 0 and result.stdout.startswith("Pr5.00 peak_current = "), result.stderr
    finally:
        process.terminate()
        process.wait(timeout=10)


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--slave", "32"], "--slave 32 is outside 1..31, the slave ids of iDM-RS (V2.0)"),
        (["--slave", "0"], "--slave 0 is outside 1..31, the slave ids of iDM-RS (V2.0) (0 is the broadcast id)"),
        (["--state", "/nonexistent-dir/drive.json"], "--state /nonexistent-dir/drive.json: the directory /nonexistent-dir does not exist"),
        (
            ["--gateway", "--rtu-over-tcp"],
            "--gateway plays a Modbus TCP gateway: it takes neither --serial nor --rtu-over-tcp (RTU keeps the serial line's rules)",
        ),
    ],
)
def test_start_up_refusals(args: list[str], message: str) -> None:
    result = regmap_simulate(str(IDM), "--tcp", f"127.0.0.1:{free_port()}", *args)
    assert (result.returncode, result.stdout, result.stderr) == (2, "", f"regmap simulate: error: {message}\n")


def test_request_log_names_registers(simulator: SimulatorFactory, tmp_path: Path) -> None:
    log = tmp_path / "requests.log"
    sim = simulator(IDM, "--log", str(log), "-v")
    assert sim.port is not None
    line = Line.tcp(sim.port)
    try:
        line.send(mbap(1, bytes([3, 1, 0x91, 0, 1])))
        assert line.read(11) == mbap(1, bytes([3, 2, 0, 22]))
        line.send(mbap(2, bytes([3, 1, 0x91, 0, 48])))
        assert line.read(9) == mbap(2, bytes([0x83, 3]))
    finally:
        line.close()
    printed = sim.stop()
    text = log.read_text(encoding="utf-8")
    assert "> MBAP transaction 1, unit 1, PDU 03 01 91 00 01" in text
    assert "0x0191 Pr5.00 peak_current = 2.2 A (raw 22)" in text
    assert "< MBAP transaction 2, unit 1, PDU 83 03" in text and "exception 0x03: Wrong data" in text
    assert "0x0191 Pr5.00 peak_current = 2.2 A (raw 22)" in printed  # -v: the same log on stderr


def test_rtu_request_log_marks_bad_crc(simulator: SimulatorFactory, tmp_path: Path) -> None:
    log = tmp_path / "rtu.log"
    sim = simulator(IDM, "--rtu-over-tcp", "--log", str(log))
    assert sim.port is not None
    line = Line.tcp(sim.port)
    try:
        line.send(bytes.fromhex("01 03 00 01 00 01 D5 C1"))
        assert line.read(5) == bytes.fromhex("01 83 08 40 F6")
    finally:
        line.close()
    sim.stop()
    text = log.read_text(encoding="utf-8")
    assert "> 01 03 00 01 00 01 D5 C1" in text and "CRC D5 C1 MISMATCH" in text
    assert "< 01 83 08 40 F6  (bad CRC)" in text and "exception 0x08: Wrong CRC" in text
