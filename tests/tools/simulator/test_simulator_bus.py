"""Several devices on one port (`regmap.tools.simulator.serve`): each slave id answers from its own map's
store and rules, other ids stay silent, a broadcast write reaches every device whose map has the
broadcast id and gets no reply; over Modbus TCP, RTU over TCP and (the gateway rules) TCP unit 0."""

from __future__ import annotations

import asyncio
import struct
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

import pytest

from regmap.frontend import load_map
from regmap.tools.link import Line as SerialLine
from regmap.tools.simulator import DeviceStore, Simulator, TcpPolicy, serve
from regmap_runtime.rtu import with_crc

from conftest import ROOT, PtyPair, free_port
from support.simulator_wire import Line, mbap

METER_MAP = load_map(ROOT / "tests" / "maps" / "fixtures" / "power_meter.yaml")
IDM_MAP = load_map(ROOT / "maps" / "idm_rs.yaml")
CT_RATIO = METER_MAP.register("ct_ratio").address  # u16 1..10000, default 1
PEAK_CURRENT = IDM_MAP.register("peak_current")
assert METER_MAP.transport.broadcast_id == 0


def read_pdu(address: int) -> bytes:
    return struct.pack(">BHH", 0x03, address, 1)


def word_answer(value: int) -> bytes:
    return struct.pack(">BBH", 0x03, 2, value)


@contextmanager
def bus(**options: Any) -> Iterator[tuple[int, Simulator]]:
    """Meters at 5 and 7, the iDM-RS drive at 1, served by `serve` from a thread; yields (port, simulator)
    (the port is 0 when `serial` is among the options)."""
    units = {5: DeviceStore(METER_MAP, 5), 7: DeviceStore(METER_MAP, 7), 1: DeviceStore(IDM_MAP, 1)}
    port = 0 if "serial" in options else free_port()
    where: dict[str, Any] = {} if "serial" in options else {"tcp": ("127.0.0.1", port)}
    loop = asyncio.new_event_loop()
    ready = threading.Event()
    running: list[Simulator] = []

    def started(simulator: Simulator) -> None:
        running.append(simulator)
        ready.set()

    thread = threading.Thread(target=lambda: loop.run_until_complete(serve(units, started=started, **where, **options)), daemon=True)
    thread.start()
    assert ready.wait(20), "the bus did not start"
    try:
        yield port, running[0]
    finally:
        loop.call_soon_threadsafe(running[0].stopped.set)
        thread.join(10)
        loop.close()


def tcp_exchange(line: Line, transaction: int, unit: int, pdu: bytes) -> bytes | None:
    """The answer PDU, checked to carry the request's transaction and unit; None for silence."""
    line.send(mbap(transaction, pdu, unit=unit))
    got = line.read()
    if not got:
        return None
    assert got[:7] == struct.pack(">HHHB", transaction, 0, len(got) - 6, unit)
    return got[7:]


def test_each_unit_answers_from_its_own_map_and_others_are_silent() -> None:
    with bus() as (port, simulator):
        line = Line.tcp(port)
        try:
            write = struct.pack(">BHH", 0x06, CT_RATIO, 30)
            assert tcp_exchange(line, 1, 5, write) == write
            assert tcp_exchange(line, 2, 5, read_pdu(CT_RATIO)) == word_answer(30)
            assert tcp_exchange(line, 3, 7, read_pdu(CT_RATIO)) == word_answer(1)  # its own store: untouched
            assert tcp_exchange(line, 4, 7, struct.pack(">BHH", 0x06, CT_RATIO, 0)) == bytes([0x86, 0x03])  # its own range
            default = PEAK_CURRENT.default
            assert isinstance(default, int)
            assert tcp_exchange(line, 5, 1, read_pdu(PEAK_CURRENT.address)) == word_answer(default)
            assert tcp_exchange(line, 6, 1, read_pdu(CT_RATIO)) == bytes([0x83, 0x02])  # the drive's map has no such register
            assert tcp_exchange(line, 7, 1, bytes([0x11])) == bytes([0x91, 0x01])  # the drive lists no 0x11; the meters do
            assert tcp_exchange(line, 8, 7, bytes([0x11])) is not None
            for unit in (3, 0xFF, 0):  # no device 3; several devices: 0xFF and 0 address none of them directly
                assert tcp_exchange(line, 9, unit, read_pdu(CT_RATIO)) is None, unit
        finally:
            line.close()
        assert simulator.stats.frames_received == 11


def test_an_rtu_broadcast_write_reaches_every_device_with_that_broadcast_id_and_gets_no_reply() -> None:
    with bus(rtu_over_tcp=True) as (port, simulator):
        line = Line.tcp(port)
        try:
            line.send(with_crc(struct.pack(">BBHH", 0, 0x06, CT_RATIO, 42)))
            assert line.read() == b""
            for slave in (5, 7):
                line.send(with_crc(bytes([slave]) + read_pdu(CT_RATIO)))
                assert line.read(7) == with_crc(bytes([slave]) + word_answer(42)), slave
            line.send(with_crc(bytes([0]) + read_pdu(CT_RATIO)))  # a broadcast read is ignored
            assert line.read() == b""
            line.send(with_crc(bytes([9]) + read_pdu(CT_RATIO)))  # no device 9
            assert line.read() == b""
        finally:
            line.close()
        assert simulator.stats.frames_sent == 2


def test_one_serial_line_serves_every_device_and_a_broadcast_reaches_them(pty_pair: PtyPair) -> None:
    with bus(serial=pty_pair.device, line=SerialLine(9600, "none", 1)) as (_port, simulator):
        line = Line.pty(pty_pair.client)
        try:
            line.send(with_crc(struct.pack(">BBHH", 0, 0x06, CT_RATIO, 55)))
            assert line.read() == b""
            for slave in (5, 7):
                line.send(with_crc(bytes([slave]) + read_pdu(CT_RATIO)))
                assert line.read(7) == with_crc(bytes([slave]) + word_answer(55)), slave
            line.send(with_crc(bytes([1]) + read_pdu(PEAK_CURRENT.address)))
            assert line.read(7)[:3] == bytes([1, 0x03, 2])
            line.send(with_crc(bytes([9]) + read_pdu(CT_RATIO)))
            assert line.read() == b""
        finally:
            line.close()
        assert simulator.stats.frames_sent == 3


def test_a_gateway_broadcasts_tcp_unit_0_and_answers_absent_units_0x0b() -> None:
    with bus(tcp_policy=TcpPolicy(gateway=True)) as (port, _simulator):
        line = Line.tcp(port)
        try:
            assert tcp_exchange(line, 1, 0, struct.pack(">BHH", 0x06, CT_RATIO, 77)) is None
            assert tcp_exchange(line, 2, 5, read_pdu(CT_RATIO)) == word_answer(77)
            assert tcp_exchange(line, 3, 7, read_pdu(CT_RATIO)) == word_answer(77)
            assert tcp_exchange(line, 4, 9, read_pdu(CT_RATIO)) == bytes([0x83, 0x0B])
        finally:
            line.close()


def test_serve_refuses_ids_the_maps_do_not_allow_and_stores_made_for_another_id() -> None:
    with pytest.raises(ValueError, match=r"outside 1\.\.247"):
        Simulator.serving({0: DeviceStore(METER_MAP, 0)})
    with pytest.raises(ValueError, match="made for slave 5, not 6"):
        Simulator.serving({6: DeviceStore(METER_MAP, 5)})
    with pytest.raises(ValueError, match="one of tcp"):
        asyncio.run(serve({5: DeviceStore(METER_MAP, 5)}))
