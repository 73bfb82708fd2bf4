"""Issue #34's float meter (tests/maps/fixtures/float_meter.yaml) played by `regmap simulate`: a read that does
not start on an even address or cover an even count is answered with the exception the map records (0x02),
over Modbus TCP and RTU; the CT ratio, exempted, reads alone. Writing the magic float 2141.0 to the
word-order switch swaps the words of every float, and the clients' `set_word_order` follows it."""

from __future__ import annotations

import json
import struct
from pathlib import Path

import pytest

from regmap.frontend import load_map
from regmap.tools.simulator.store import DeviceStore

from conftest import ROOT, PtyPair, SimulatorFactory
from support.fixture_clients import FLAVOURS, flavour, read
from support.simulator_wire import Line, mbap

FLOAT_METER = ROOT / "tests" / "maps" / "fixtures" / "float_meter.yaml"
METER = "fixture_float_meter"
MISALIGNED = ((0x04, 0x0001, 2), (0x04, 0x0000, 3), (0x04, 0x0007, 1), (0x03, 0x0101, 2), (0x03, 0x0106, 1))
MAGIC = struct.unpack(">HH", struct.pack(">f", 2141.0))  # 45 05 D0 00


def _crc(frame: bytes) -> bytes:
    """CRC-16/MODBUS (poly 0xA001 reflected, init 0xFFFF), low byte first: written here apart from the runtime."""
    crc = 0xFFFF
    for byte in frame:
        crc ^= byte
        for _ in range(8):
            crc = (crc >> 1) ^ 0xA001 if crc & 1 else crc >> 1
    return frame + struct.pack("<H", crc)


def _state(tmp_path: Path) -> str:
    path = tmp_path / "meter.json"
    registers = {"current_l1": 5.0, "frequency": 50.0, "temperature": 230, "humidity": 500, "ct_ratio": 100}
    path.write_text(json.dumps({"device": METER, "map_version": "0.1.0", "registers": registers}), encoding="utf-8")
    return str(path)


def test_misaligned_reads_get_the_maps_exception_over_tcp(simulator: SimulatorFactory, tmp_path: Path) -> None:
    sim = simulator(FLOAT_METER, "--state", _state(tmp_path))
    assert sim.port is not None
    line = Line.tcp(sim.port)
    try:
        for tid, (function, address, count) in enumerate(MISALIGNED, 1):
            line.send(mbap(tid, struct.pack(">BHH", function, address, count)))
            assert line.read(9) == struct.pack(">HHHBBB", tid, 0, 3, 1, function | 0x80, 0x02), (function, hex(address), count)
        line.send(mbap(20, struct.pack(">BHH", 0x04, 0x0002, 2)))  # aligned: current_l1, 5.0
        assert line.read(13) == struct.pack(">HHHBBBHH", 20, 0, 7, 1, 0x04, 4, 0x40A0, 0x0000)
        line.send(mbap(21, struct.pack(">BHH", 0x03, 0x0104, 1)))  # the exempt CT ratio alone: 100
        assert line.read(11) == struct.pack(">HHHBBBH", 21, 0, 5, 1, 0x03, 2, 100)
        line.send(mbap(22, struct.pack(">BHH", 0x03, 0x0104, 2)))  # aligned, but 0x0105 is not documented
        assert line.read(9) == struct.pack(">HHHBBB", 22, 0, 3, 1, 0x83, 0x02)
    finally:
        line.close()


def test_misaligned_reads_get_the_maps_exception_over_rtu(simulator: SimulatorFactory, pty_pair: PtyPair, tmp_path: Path) -> None:
    simulator(FLOAT_METER, "--state", _state(tmp_path), serial=pty_pair.device)
    line = Line.pty(pty_pair.client)
    try:
        for function, address, count in MISALIGNED:
            line.send(_crc(struct.pack(">BBHH", 1, function, address, count)))
            assert line.read(5) == _crc(struct.pack(">BBB", 1, function | 0x80, 0x02)), (function, hex(address), count)
        line.send(_crc(struct.pack(">BBHH", 1, 0x04, 0x0006, 2)))  # temperature and humidity: 23.0 °C, 50.0 %
        assert line.read(9) == _crc(struct.pack(">BBBHH", 1, 0x04, 4, 230, 500))
    finally:
        line.close()


@pytest.mark.parametrize("name", FLAVOURS)
def test_the_magic_write_swaps_the_float_words_and_the_client_follows(name: str, simulator: SimulatorFactory, tmp_path: Path) -> None:
    sim = simulator(FLOAT_METER, "--state", _state(tmp_path))
    assert sim.port is not None
    f = flavour(name, METER)
    client, recorder = f.client(sim.port)
    with client:
        assert read(f, client, "current_l1") == 5.0
        assert client.read_raw(0x0002, 2, space="input") == [0x40A0, 0x0000]
        client.set_word_order("low_first")
        assert recorder.pdus()[-1] == struct.pack(">BHHBHH", 0x10, 0x0110, 2, 4, *MAGIC)  # 2141.0, in the order the device used
        assert client.word_order == "low_first"
        assert client.read_raw(0x0002, 2, space="input") == [0x0000, 0x40A0]  # the device swapped its words
        assert read(f, client, "current_l1") == 5.0 and read(f, client, "frequency") == 50.0
        assert read(f, client, "temperature") == 23.0  # a 16-bit register does not move
        sent = len(recorder.sent)
        client.set_word_order("low_first")  # already: nothing to write (a second swap would swap back)
        assert len(recorder.sent) == sent
        client.set_word_order("high_first")
        assert recorder.pdus()[-1] == struct.pack(">BHHBHH", 0x10, 0x0110, 2, 4, MAGIC[1], MAGIC[0])  # now written low word first
        assert client.read_raw(0x0002, 2, space="input") == [0x40A0, 0x0000]
        assert read(f, client, "current_l1") == 5.0


def test_a_lost_answer_to_the_swap_is_outcome_unknown_and_sent_once(simulator: SimulatorFactory, tmp_path: Path) -> None:
    sim = simulator(FLOAT_METER, "--state", _state(tmp_path), "--fault", "no_answer", "--fault-count", "1")
    assert sim.port is not None
    f = flavour("generated", METER)
    client, recorder = f.client(sim.port, retries=2)
    with client:
        with pytest.raises(f.errors.OutcomeUnknown):
            client.set_word_order("low_first")
        assert len(recorder.sent) == 1  # a trigger: never sent again
        assert client.word_order == "high_first"  # not assumed either way


def test_the_simulator_answers_the_code_the_map_records(tmp_path: Path) -> None:
    """A device that answers a misaligned read with 0x03 (as some float meters do) is played with 0x03."""
    path = tmp_path / "float_meter.yaml"
    path.write_text(FLOAT_METER.read_text(encoding="utf-8").replace("exception: 0x02", "exception: 0x03"), encoding="utf-8")
    store = DeviceStore(load_map(path), 1)
    assert [store.read(0x0001, 2, "input"), store.read(0x0000, 1, "input"), store.read(0x0104, 2, "holding")] == [0x03, 0x03, 0x02]
    assert store.read(0x0006, 2, "input") == [0, 0] and store.read(0x0104, 1, "holding") == [5]
