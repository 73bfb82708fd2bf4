"""`regmap simulate PLANT --bus NAME` plays each device as the variant the plant file names: two float meters on one
TCP bus, the single-phase one at slave 1 answers exception 0x02 for voltage_l2 (only the three-phase model has it),
the three-phase one at slave 3 answers it; every register both models have answers at both."""

from __future__ import annotations

import socket
from pathlib import Path

from regmap.frontend.plant import load_plant

from conftest import free_port
from support.plant_tcp_bus import serve_bus
from support.plants import write_meter_plant


def _mbap(sock: socket.socket, unit: int, pdu: bytes) -> bytes:
    sock.sendall(b"\x00\x01\x00\x00" + (len(pdu) + 1).to_bytes(2, "big") + bytes([unit]) + pdu)
    header = sock.recv(7)
    return sock.recv(int.from_bytes(header[4:6], "big") - 1)


def _read_input(address: int, count: int) -> bytes:
    return bytes([0x04]) + address.to_bytes(2, "big") + count.to_bytes(2, "big")


def test_only_the_single_phase_meter_answers_0x02_for_voltage_l2(tmp_path: Path) -> None:
    plant = load_plant(write_meter_plant(tmp_path, "meters", f"tcp: {{host: 127.0.0.1, port: {free_port()}}}"))
    (bus,) = plant.buses
    l1, l2 = (bus.device("m1").device.register(name) for name in ("voltage_l1", "voltage_l2"))
    assert l2.variants == ("three_phase",) and l1.variants == ()
    with serve_bus(plant, bus, tmp_path) as served, socket.create_connection(("127.0.0.1", served.port), timeout=5) as sock:
        assert _mbap(sock, 1, _read_input(l2.address, 2)) == b"\x84\x02"  # single-phase: no such register
        three = _mbap(sock, 3, _read_input(l2.address, 2))
        assert three[:2] == b"\x04\x04" and len(three) == 6  # three-phase: its 2 words
        for unit in (1, 3):
            answer = _mbap(sock, unit, _read_input(l1.address, 2))
            assert answer[:2] == b"\x04\x04", (unit, answer)
    log = served.log.read_text(encoding="utf-8")
    assert "unit 1, PDU 84 02" in log and "unit 3, PDU 84" not in log, log
