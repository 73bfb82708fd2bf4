"""`regmap simulate` serves all four Modbus tables as the Modbus Application Protocol v1.1b3 says.

The remote IO fixture holds the spec's own worked examples (§6.1 read coils 20-38, §6.2 discrete
inputs 197-218, §6.4 input register 9, §6.5 write coil 173, §6.11 write coils 20-29): its state is
set from the spec's prose (the bit patterns as printed, MSB first), the requests are the spec's
bytes, and the answers must be the spec's bytes, over Modbus TCP and RTU over TCP. Then the
exceptions per space (0x01, 0x02, 0x03), the power meter's floats and strings, the firmware gates,
and independent masters: mbpoll (-t 0/1/3/4, :float, -B) and pymodbus.
"""

from __future__ import annotations

import json
import struct
import subprocess
from collections.abc import Iterator
from pathlib import Path

import pytest
from pymodbus.client import ModbusTcpClient

from regmap_runtime.rtu import with_crc

from conftest import ROOT, PtyPair, RunningSimulator, SimulatorFactory, require_tool
from support.simulator_wire import Line, mbap

FIXTURES = ROOT / "tests" / "maps" / "fixtures"
REMOTE_IO = FIXTURES / "remote_io.yaml"
POWER_METER = FIXTURES / "power_meter.yaml"
SWAPPED = FIXTURES / "swapped_gated.yaml"


def spec_bits(first: int, *printed: str) -> dict[int, int]:
    """Bits as the spec prints them: each byte in binary, its highest-numbered point first (MSB) and
    the lowest last (LSB); `first` is the point number of the first byte's LSB."""
    bits: dict[int, int] = {}
    point = first
    for byte in printed:
        for char in reversed(byte.replace(" ", "")):
            bits[point] = int(char)
            point += 1
    return bits


# §6.1: "outputs 27-20 ... CD hex, or binary 1100 1101"; 35-28 6B = 0110 1011; 38-36 05 = 0000 0101 (3 of its bits).
COILS = spec_bits(20, "1100 1101", "0110 1011", "101")
# §6.2: inputs 204-197 AC = 1010 1100; 212-205 DB = 1101 1011; 218-213 35 = 0011 0101 (6 of its bits).
INPUTS = spec_bits(197, "1010 1100", "1101 1011", "110101")


def spec_state(path: Path) -> Path:
    """A simulator state file with the spec examples' table contents (coil n at address n-1)."""
    registers: dict[str, object] = {f"relay_{n}_on": bit for n, bit in COILS.items()}
    registers |= {f"input_{n}_active": bit for n, bit in INPUTS.items()}
    registers |= {"analog_in_9": 10, "config_108": 0x022B, "config_109": 0, "config_110": 0x64}  # §6.3, §6.4
    path.write_text(json.dumps({"device": "fixture_remote_io", "map_version": "0.1.0", "registers": registers}), encoding="utf-8")
    return path


def pdu(text: str) -> bytes:
    return bytes.fromhex(text)


# (what, request PDU, exact answer PDU): the spec's examples, then the exceptions per space.
SPEC_EXAMPLES = [
    ("§6.1 read coils 20-38", "01 00 13 00 13", "01 03 CD 6B 05"),
    ("§6.2 read discrete inputs 197-218", "02 00 C4 00 16", "02 03 AC DB 35"),
    ("§6.3 read holding registers 108-110", "03 00 6B 00 03", "03 06 02 2B 00 00 00 64"),
    ("§6.4 read input register 9", "04 00 08 00 01", "04 02 00 0A"),
    ("§6.5 write coil 173 on", "05 00 AC FF 00", "05 00 AC FF 00"),
    ("§6.11 write coils 20-29", "0F 00 13 00 0A 02 CD 01", "0F 00 13 00 0A"),
]
# The same requests and answers as the fixture prints them as RTU frames (spec PDU, slave 1, CRC).
SPEC_RTU = [
    ("01 01 00 13 00 13 8C 02", "01 01 03 CD 6B 05 42 82"),
    ("01 02 00 C4 00 16 B8 39", "01 02 03 AC DB 35 22 88"),
    ("01 04 00 08 00 01 B0 08", "01 04 02 00 0A 39 37"),
    ("01 05 00 AC FF 00 4C 1B", "01 05 00 AC FF 00 4C 1B"),
    ("01 0F 00 13 00 0A 02 CD 01 72 CB", "01 0F 00 13 00 0A 24 09"),
]
REFUSALS = [
    # 0x03: quantity out of range, a coil value other than FF 00 / 00 00, a byte count that disagrees
    ("read coils, quantity 0", "01 00 13 00 00", "81 03"),
    ("read coils, quantity 2001", "01 00 13 07 D1", "81 03"),
    ("read discrete inputs, quantity 0", "02 00 C4 00 00", "82 03"),
    ("read discrete inputs, quantity 2001", "02 00 C4 07 D1", "82 03"),
    ("read input registers, quantity 0", "04 00 08 00 00", "84 03"),
    ("read input registers, quantity 126", "04 00 08 00 7E", "84 03"),
    ("write coil 0x1234", "05 00 AC 12 34", "85 03"),
    ("write coil 0x00FF", "05 00 AC 00 FF", "85 03"),
    ("write coils, quantity 0", "0F 00 13 00 00 00", "8F 03"),
    ("write coils, byte count 1 for 10 coils", "0F 00 13 00 0A 01 CD", "8F 03"),
    ("write coils, byte count 3 for 10 coils", "0F 00 13 00 0A 03 CD 01 00", "8F 03"),
    ("write coils, 1969 coils", "0F 00 13 07 B1 F7 " + "00 " * 0xF7, "8F 03"),
    # 0x02: an address the map does not document in that space (the other spaces do not count)
    ("read coil 0x0000", "01 00 00 00 01", "81 02"),
    ("read coils past the last one", "01 00 13 00 14", "81 02"),
    ("read coils past 0xFFFF", "01 FF FF 00 02", "81 02"),
    ("read discrete input at the input register's address", "02 00 08 00 01", "82 02"),
    ("read discrete inputs past the last one", "02 00 C4 00 17", "82 02"),
    ("read input register at a holding register's address", "04 00 6B 00 01", "84 02"),
    ("read holding register at the input register's address", "03 00 08 00 01", "83 02"),
    ("write coil at a discrete input's address", "05 00 C4 FF 00", "85 02"),
    ("write coils over an undocumented coil", "0F 00 12 00 02 01 03", "8F 02"),
    ("write single register at the input register's address", "06 00 08 00 01", "86 02"),
    # 0x01: no function writes input registers or discrete inputs; functions outside §6.1-§6.12
    ("read/write multiple registers", "17 00 6B 00 01 00 6B 00 01 02 00 00", "97 01"),
    ("read device identification", "2B 0E 01 00", "AB 01"),
]


@pytest.fixture(params=["tcp", "rtu-over-tcp"])
def remote_io(request: pytest.FixtureRequest, simulator: SimulatorFactory, tmp_path: Path) -> Iterator[tuple[str, Line]]:
    extra = ["--rtu-over-tcp"] if request.param == "rtu-over-tcp" else []
    sim = simulator(REMOTE_IO, "--state", str(spec_state(tmp_path / "io.json")), *extra)
    assert sim.port is not None
    line = Line.tcp(sim.port)
    yield request.param, line
    line.close()


def exchange(framing: str, line: Line, request: bytes, transaction: int) -> tuple[bytes, bytes]:
    """(the answer that came, the frame it must be byte for byte) for one request PDU."""
    if framing == "tcp":
        line.send(mbap(transaction, request))
        head = line.read(7)
        length = int.from_bytes(head[4:6], "big") if len(head) == 7 else 0
        return head + line.read(length - 1), b""
    line.send(with_crc(bytes([1]) + request))
    return line.read(None, timeout=2.0), b""


def expected(framing: str, answer: bytes, transaction: int) -> bytes:
    return mbap(transaction, answer) if framing == "tcp" else with_crc(bytes([1]) + answer)


def test_the_specs_examples_and_refusals_byte_for_byte(remote_io: tuple[str, Line]) -> None:
    framing, line = remote_io
    for number, (what, request, answer) in enumerate(SPEC_EXAMPLES + REFUSALS, 1):
        got, _ = exchange(framing, line, pdu(request), number)
        assert got == expected(framing, pdu(answer), number), what
    # The writes took: coils 20-29 now hold §6.11's CD 01 (on, off, on, on, off, off, on, on, on, off).
    got, _ = exchange(framing, line, pdu("01 00 13 00 0A"), 99)
    assert got == expected(framing, pdu("01 02 CD 01"), 99)
    # Refused writes changed nothing: coil 173 is still on, input register 9 still 10.
    got, _ = exchange(framing, line, pdu("01 00 AC 00 01"), 100)
    assert got == expected(framing, pdu("01 01 01"), 100)
    got, _ = exchange(framing, line, pdu("04 00 08 00 01"), 101)
    assert got == expected(framing, pdu("04 02 00 0A"), 101)


@pytest.mark.parametrize("transport", ["rtu-over-tcp", "pty"])
def test_rtu_frames_are_the_fixtures_printed_frames(
    simulator: SimulatorFactory, tmp_path: Path, transport: str, request: pytest.FixtureRequest
) -> None:
    state = str(spec_state(tmp_path / "io.json"))
    if transport == "pty":
        pair: PtyPair = request.getfixturevalue("pty_pair")
        simulator(REMOTE_IO, "--state", state, serial=pair.device)
        line = Line.pty(pair.client)
    else:
        sim = simulator(REMOTE_IO, "--state", state, "--rtu-over-tcp")
        assert sim.port is not None
        line = Line.tcp(sim.port)
    try:
        for sent, answer in SPEC_RTU:
            line.send(bytes.fromhex(sent))
            assert line.read(len(bytes.fromhex(answer))) == bytes.fromhex(answer), sent
            assert line.read(None) == b"", f"{sent}: more than one answer"
    finally:
        line.close()


def test_bit_answers_pad_with_zeros(simulator: SimulatorFactory, tmp_path: Path) -> None:
    """Coils 20-27 are CD (1100 1101): three of them read as 0000 0101, the five after them not in the byte."""
    sim = simulator(REMOTE_IO, "--state", str(spec_state(tmp_path / "io.json")))
    assert sim.port is not None
    line = Line.tcp(sim.port)
    try:
        got, _ = exchange("tcp", line, pdu("01 00 13 00 03"), 1)
        assert got == mbap(1, pdu("01 01 05"))
        got, _ = exchange("tcp", line, pdu("02 00 C4 00 09"), 2)  # 197-205: AC, then 205 = 1
        assert got == mbap(2, pdu("02 02 AC 01"))
    finally:
        line.close()


def test_the_maps_bit_limits_narrow_the_specs(simulator: SimulatorFactory, tmp_path: Path) -> None:
    narrow = tmp_path / "narrow_io.yaml"
    text = REMOTE_IO.read_text(encoding="utf-8").replace("max_read_coils: 2000", "max_read_coils: 16")
    narrow.write_text(text.replace("max_write_coils: 1968", "max_write_coils: 8"), encoding="utf-8")
    sim = simulator(narrow)
    assert sim.port is not None
    line = Line.tcp(sim.port)
    try:
        for number, (request, answer) in enumerate(
            [
                ("01 00 13 00 10", "01 02 00 00"),  # 16 coils: at the limit
                ("01 00 13 00 11", "81 03"),  # 17: over it
                ("02 00 C4 00 11", "82 03"),
                ("0F 00 13 00 08 01 FF", "0F 00 13 00 08"),
                ("0F 00 13 00 09 02 FF 01", "8F 03"),
            ],
            1,
        ):
            got, _ = exchange("tcp", line, pdu(request), number)
            assert got == mbap(number, pdu(answer)), request
    finally:
        line.close()


def test_a_device_without_the_bit_functions_answers_0x01(simulator: SimulatorFactory) -> None:
    sim = simulator(POWER_METER)  # functions 0x03 0x04 0x06 0x10
    assert sim.port is not None
    line = Line.tcp(sim.port)
    try:
        for number, (request, answer) in enumerate(
            [("01 00 00 00 01", "81 01"), ("02 00 00 00 01", "82 01"), ("05 00 00 FF 00", "85 01"), ("0F 00 00 00 01 01 01", "8F 01")], 1
        ):
            got, _ = exchange("tcp", line, pdu(request), number)
            assert got == mbap(number, pdu(answer)), request
    finally:
        line.close()


def test_broadcast_coil_write_applies_without_a_reply(simulator: SimulatorFactory) -> None:
    sim = simulator(REMOTE_IO, "--rtu-over-tcp")
    assert sim.port is not None
    line = Line.tcp(sim.port)
    try:
        line.send(with_crc(bytes.fromhex("00 05 00 AC FF 00")))
        assert line.read(None) == b""
        line.send(with_crc(bytes.fromhex("01 01 00 AC 00 01")))
        assert line.read(6) == with_crc(bytes.fromhex("01 01 01 01"))
    finally:
        line.close()


# -- floats, strings, wide values ------------------------------------------------------------


def f32_words(value: float, order: str = "ABCD") -> bytes:
    """An IEEE 754 single as the wire carries it: ABCD, or CDAB (words swapped)."""
    packed = struct.pack(">f", value)
    return packed if order == "ABCD" else packed[2:] + packed[:2]


def test_defaults_of_every_type_and_checked_writes(simulator: SimulatorFactory) -> None:
    sim = simulator(POWER_METER)
    assert sim.port is not None
    line = Line.tcp(sim.port)
    cases = [
        ("demand_period default 900.0", "03 01 22 00 02", bytes([3, 4]) + f32_words(900.0)),
        ("meter_label default empty: NULs", "03 01 26 00 04", bytes([3, 8]) + bytes(8)),
        ("ct_ratio default 1", "03 01 20 00 01", pdu("03 02 00 01")),
        ("voltage_alarm, CDAB, written 250.5", "10 01 24 00 02 04" + f32_words(250.5, "CDAB").hex(), pdu("10 01 24 00 02")),
        ("voltage_alarm reads back", "03 01 24 00 02", bytes([3, 4]) + f32_words(250.5, "CDAB")),
        ("demand_period 0.5 is below its min 1.0", "10 01 22 00 02 04" + f32_words(0.5).hex(), pdu("90 03")),
        ("demand_period NaN", "10 01 22 00 02 04 7F C0 00 00", pdu("90 03")),
        ("half of demand_period", "06 01 22 44 61", pdu("86 02")),
        ("meter_label 'abc' (UTF-8)", "10 01 26 00 04 08" + b"abc".ljust(8, b"\0").hex(), pdu("10 01 26 00 04")),
        ("meter_label reads back", "03 01 26 00 04", bytes([3, 8]) + b"abc".ljust(8, b"\0")),
        ("meter_label: bytes that are no UTF-8", "10 01 26 00 04 08 FF FE 00 00 00 00 00 00", pdu("90 03")),
        ("half of meter_label", "10 01 26 00 02 04 61 62 63 64", pdu("90 02")),
        ("the model name is read-only", "10 01 00 00 08 10" + b"X".ljust(16, b"\0").hex(), pdu("90 03")),
        ("an input register cannot be written (0x06 addresses holding registers)", "06 00 00 00 01", pdu("86 02")),
    ]
    try:
        for number, (what, request, answer) in enumerate(cases, 1):
            got, _ = exchange("tcp", line, pdu(request), number)
            assert got == mbap(number, answer), what
    finally:
        line.close()


def test_byte_swapped_defaults(simulator: SimulatorFactory) -> None:
    """SW-2: bytes low first and words low first (DCBA); gain overrides bytes high first (CDAB)."""
    sim = simulator(SWAPPED)
    assert sim.port is not None
    line = Line.tcp(sim.port)
    try:
        got, _ = exchange("tcp", line, pdu("03 00 05 00 02"), 1)
        assert got == mbap(1, bytes([3, 4]) + f32_words(1.0, "CDAB"))
        got, _ = exchange("tcp", line, pdu("03 00 10 00 01"), 2)  # torque limit 100 = 0x0064, its bytes swapped
        assert got == mbap(2, pdu("03 02 64 00"))
    finally:
        line.close()


# -- firmware --------------------------------------------------------------------------------


def answers_over_tcp(sim: RunningSimulator, cases: list[tuple[str, str]]) -> None:
    """Each (request PDU, answer PDU) pair, exchanged in turn over Modbus TCP."""
    assert sim.port is not None
    line = Line.tcp(sim.port)
    try:
        for number, (request, answer) in enumerate(cases, 1):
            got, _ = exchange("tcp", line, pdu(request), number)
            assert got == mbap(number, pdu(answer)), request
    finally:
        line.close()


@pytest.mark.parametrize(
    ("map_path", "firmware", "cases"),
    [
        (
            POWER_METER,
            "1.25",
            [
                ("03 01 10 00 01", "03 02 00 7D"),  # the firmware register reports 125 (2 decimals)
                ("03 01 22 00 02", "03 04" + f32_words(900.0).hex()),  # demand_period: from 1.20
                ("04 00 40 00 02", "84 02"),  # thd_voltage_l1: from 2.00, absent
            ],
        ),
        (POWER_METER, "1.10", [("03 01 10 00 01", "03 02 00 6E"), ("03 01 22 00 02", "83 02"), ("10 01 22 00 02 04 44 61 00 00", "90 02")]),
        (POWER_METER, "2.00", [("03 01 10 00 01", "03 02 00 C8"), ("04 00 40 00 02", "04 04 00 00 00 00")]),
        (
            SWAPPED,
            "2.3",
            [
                ("03 00 00 00 01", "03 02 03 02"),  # major_minor 0x0203, its bytes swapped (the fixture's example)
                ("03 00 10 00 01", "03 02 64 00"),  # torque_limit: from 2.0
                ("03 00 11 00 01", "83 02"),  # legacy_mode: until 2.0
                ("03 00 20 00 04", "83 02"),  # diagnostics: from 2.5
                ("03 00 10 00 02", "83 02"),  # a read across the missing register
            ],
        ),
        (SWAPPED, "1.9", [("03 00 00 00 01", "03 02 09 01"), ("03 00 10 00 01", "83 02"), ("03 00 11 00 01", "03 02 00 00")]),
    ],
    ids=["meter-1.25", "meter-1.10", "meter-2.00", "sw2-2.3", "sw2-1.9"],
)
def test_firmware_sets_the_register_and_hides_what_it_lacks(
    simulator: SimulatorFactory, map_path: Path, firmware: str, cases: list[tuple[str, str]]
) -> None:
    sim = simulator(map_path, "--firmware", firmware)
    answers_over_tcp(sim, cases)
    assert f"firmware {firmware}" in sim.stop()


@pytest.mark.parametrize(
    ("map_path", "cases", "banner"),
    [
        # PM-3000: its firmware register's default (125) is played: 1.25, without the power-quality registers of 2.00.
        (POWER_METER, [("03 01 10 00 01", "03 02 00 7D"), ("04 00 40 00 02", "84 02")], "firmware 1.25"),
        # SW-2: gates from 2.0, until 2.0, from 2.5: 2.5 (0x0205, bytes swapped) has no legacy_mode.
        (SWAPPED, [("03 00 00 00 01", "03 02 05 02"), ("03 00 11 00 01", "83 02"), ("03 00 20 00 04", "03 08" + "00" * 8)], "firmware 2.5"),
        # No gates, no firmware register: no firmware in particular.
        (REMOTE_IO, [("04 00 08 00 01", "04 02 00 00")], "on 127.0.0.1"),
    ],
    ids=["meter", "sw2", "remote-io"],
)
def test_without_firmware_the_register_default_or_else_the_newest_gate_is_played(
    simulator: SimulatorFactory, map_path: Path, cases: list[tuple[str, str]], banner: str
) -> None:
    sim = simulator(map_path)
    answers_over_tcp(sim, cases)
    out = sim.stop()
    assert banner in out and ("firmware" in out) == (map_path != REMOTE_IO)


@pytest.mark.parametrize(
    ("map_path", "firmware", "message"),
    [
        (SWAPPED, "2.3.4", "--firmware 2.3.4: firmware reports MAJOR.MINOR, each 0..255 (major_minor)"),
        (SWAPPED, "2.300", "--firmware 2.300: firmware reports MAJOR.MINOR, each 0..255 (major_minor)"),
        (POWER_METER, "1.100", "--firmware 1.100: firmware_version reports MAJOR.MINOR with MINOR below 100 (decimal, 2 decimals)"),
        (POWER_METER, "v2", "--firmware 'v2' is not a version (numbers with dots: 2, 2.10, 1.2.3)"),
    ],
)
def test_a_firmware_the_register_cannot_report_is_refused(map_path: Path, firmware: str, message: str) -> None:
    import sys

    result = subprocess.run(
        [sys.executable, "-m", "regmap", "simulate", str(map_path), "--firmware", firmware, "--tcp", "127.0.0.1:1"],
        cwd=ROOT,
        capture_output=True,
        text=True,
        check=False,
        timeout=30,
    )
    assert (result.returncode, result.stdout, result.stderr) == (2, "", f"regmap simulate: error: {message}\n")


# -- the request log -------------------------------------------------------------------------


def test_request_log_decodes_the_bit_functions(simulator: SimulatorFactory, tmp_path: Path) -> None:
    log = tmp_path / "io.log"
    sim = simulator(REMOTE_IO, "--state", str(spec_state(tmp_path / "io.json")), "--log", str(log))
    assert sim.port is not None
    line = Line.tcp(sim.port)
    try:
        for number, (_, request, _answer) in enumerate(SPEC_EXAMPLES, 1):
            exchange("tcp", line, pdu(request), number)
        exchange("tcp", line, pdu("05 00 AC 12 34"), 50)
    finally:
        line.close()
    sim.stop()
    text = log.read_text(encoding="utf-8")
    assert "function 0x01 read coils (response)" in text
    assert "0x0013 relay_20_on = on" in text and "0x0014 relay_21_on = off" in text and "0x0025 relay_38_on = on" in text
    assert "0x00D9 input_218_active = on" in text and "0x00C4 input_197_active = off" in text
    assert "0x0008 analog_in_9 = 10 mV" in text
    assert "0x00AC alarm_output = on" in text
    assert "problem: a coil write carries FF 00 (on) or 00 00 (off), not 12 34" in text
    assert "exception 0x03: Illegal data value" in text


# -- independent masters ---------------------------------------------------------------------


def mbpoll(port: int, *args: str) -> subprocess.CompletedProcess[str]:
    tool = require_tool("mbpoll")
    return subprocess.run(
        [tool, "-1", "-0", "-o", "2", "-m", "tcp", "-p", str(port), "-a", "1", *args],
        capture_output=True,
        text=True,
        check=False,
        timeout=30,
    )


def mbpoll_values(output: str) -> dict[int, str]:
    """mbpoll prints `[19]: 	1` per value."""
    found = {}
    for text in output.splitlines():
        if text.startswith("[") and "]:" in text:
            ref, _, value = text.partition("]:")
            found[int(ref[1:])] = value.strip()
    return found


def test_mbpoll_reads_and_writes_every_table(simulator: SimulatorFactory, tmp_path: Path) -> None:
    sim = simulator(REMOTE_IO, "--state", str(spec_state(tmp_path / "io.json")))
    assert sim.port is not None
    coils = mbpoll(sim.port, "-t", "0", "-r", "19", "-c", "19", "127.0.0.1")
    assert mbpoll_values(coils.stdout) == {n - 1: str(bit) for n, bit in COILS.items()}, coils.stdout + coils.stderr
    inputs = mbpoll(sim.port, "-t", "1", "-r", "196", "-c", "22", "127.0.0.1")
    assert mbpoll_values(inputs.stdout) == {n - 1: str(bit) for n, bit in INPUTS.items()}, inputs.stdout + inputs.stderr
    register = mbpoll(sim.port, "-t", "3", "-r", "8", "127.0.0.1")
    assert mbpoll_values(register.stdout) == {8: "10"}, register.stdout
    wrote = mbpoll(sim.port, "-t", "0", "-r", "19", "127.0.0.1", "0", "0", "1")  # three coils: one 0x0F
    assert wrote.returncode == 0, wrote.stdout + wrote.stderr
    one = mbpoll(sim.port, "-t", "0", "-r", "172", "127.0.0.1", "1")  # one coil: 0x05
    assert one.returncode == 0, one.stdout + one.stderr
    again = mbpoll(sim.port, "-t", "0", "-r", "19", "-c", "3", "127.0.0.1")
    assert mbpoll_values(again.stdout) == {19: "0", 20: "0", 21: "1"}, again.stdout
    undocumented = mbpoll(sim.port, "-t", "0", "-r", "0", "127.0.0.1")
    assert undocumented.returncode != 0 and "Illegal data address" in undocumented.stdout + undocumented.stderr
    wrong_space = mbpoll(sim.port, "-t", "1", "-r", "19", "127.0.0.1")  # coil addresses are no discrete inputs
    assert wrong_space.returncode != 0 and "Illegal data address" in wrong_space.stdout + wrong_space.stderr


def test_mbpoll_reads_coils_over_rtu(simulator: SimulatorFactory, pty_pair: PtyPair, tmp_path: Path) -> None:
    simulator(REMOTE_IO, "--state", str(spec_state(tmp_path / "io.json")), serial=pty_pair.device)
    tool = require_tool("mbpoll")
    rtu = [tool, "-1", "-0", "-o", "2", "-m", "rtu", "-b", "19200", "-P", "even", "-a", "1"]
    coils = subprocess.run(
        [*rtu, "-t", "0", "-r", "19", "-c", "19", pty_pair.client], capture_output=True, text=True, check=False, timeout=30
    )
    assert mbpoll_values(coils.stdout) == {n - 1: str(bit) for n, bit in COILS.items()}, coils.stdout + coils.stderr
    inputs = subprocess.run(
        [*rtu, "-t", "1", "-r", "196", "-c", "22", pty_pair.client], capture_output=True, text=True, check=False, timeout=30
    )
    assert mbpoll_values(inputs.stdout) == {n - 1: str(bit) for n, bit in INPUTS.items()}, inputs.stdout + inputs.stderr


def test_mbpoll_reads_and_writes_floats_in_both_word_orders(simulator: SimulatorFactory, tmp_path: Path) -> None:
    state = tmp_path / "meter.json"
    state.write_text(json.dumps({"registers": {"voltage_l1": 230.5, "current_l1": 12.25}}), encoding="utf-8")
    sim = simulator(POWER_METER, "--state", str(state))
    assert sim.port is not None
    high_first = mbpoll(sim.port, "-t", "3:float", "-B", "-r", "0", "127.0.0.1")  # -B: big-endian word order (ABCD)
    assert mbpoll_values(high_first.stdout) == {0: "230.5"}, high_first.stdout + high_first.stderr
    low_first = mbpoll(sim.port, "-t", "3:float", "-r", "2", "127.0.0.1")  # mbpoll's default: low word first (CDAB)
    assert mbpoll_values(low_first.stdout) == {2: "12.25"}, low_first.stdout
    demand = mbpoll(sim.port, "-t", "4:float", "-B", "-r", "290", "127.0.0.1")
    assert mbpoll_values(demand.stdout) == {290: "900"}, demand.stdout
    write = mbpoll(sim.port, "-t", "4:float", "-B", "-r", "290", "127.0.0.1", "60.5")
    assert write.returncode == 0, write.stdout + write.stderr
    refused = mbpoll(sim.port, "-t", "4:float", "-B", "-r", "290", "127.0.0.1", "4000")  # over its max 3600
    assert refused.returncode != 0 and "Illegal data value" in refused.stdout + refused.stderr
    alarm = mbpoll(sim.port, "-t", "4:float", "-r", "292", "127.0.0.1", "250.5")  # voltage_alarm is CDAB
    assert alarm.returncode == 0, alarm.stdout + alarm.stderr
    with ModbusTcpClient("127.0.0.1", port=sim.port, timeout=2) as modbus:
        words = modbus.read_holding_registers(290, count=4, device_id=1).registers
        assert words == list(struct.unpack(">4H", f32_words(60.5) + f32_words(250.5, "CDAB")))
        as_float = modbus.convert_from_registers(words[:2], data_type=modbus.DATATYPE.FLOAT32, word_order="big")
        assert as_float == 60.5


def test_pymodbus_reads_and_writes_the_bit_tables(simulator: SimulatorFactory, tmp_path: Path) -> None:
    sim = simulator(REMOTE_IO, "--state", str(spec_state(tmp_path / "io.json")))
    assert sim.port is not None
    with ModbusTcpClient("127.0.0.1", port=sim.port, timeout=2) as modbus:
        coils = modbus.read_coils(0x13, count=19, device_id=1)
        assert [int(b) for b in coils.bits[:19]] == [COILS[n] for n in range(20, 39)]
        assert not any(coils.bits[19:]), "padding bits must be zero"
        inputs = modbus.read_discrete_inputs(0xC4, count=22, device_id=1)
        assert [int(b) for b in inputs.bits[:22]] == [INPUTS[n] for n in range(197, 219)]
        pattern = [True, False, True, True, False, False, True, True, True, False]  # §6.11
        assert not modbus.write_coils(0x13, pattern, device_id=1).isError()
        assert [bool(b) for b in modbus.read_coils(0x13, count=10, device_id=1).bits[:10]] == pattern
        assert not modbus.write_coil(0xAC, False, device_id=1).isError()
        assert modbus.read_coils(0xAC, count=1, device_id=1).bits[0] is False
        refused = modbus.read_coils(0x00, count=1, device_id=1)
        assert refused.isError() and refused.exception_code == 0x02
        assert modbus.read_input_registers(0x08, count=1, device_id=1).registers == [10]
