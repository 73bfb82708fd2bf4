"""The client's functions beyond reads and writes, against `regmap simulate` on the power-meter fixture:
0x08 return query data (`echo`), 0x11 (`report_server_id`), 0x17 (`write_and_read`: the write's checks, sent
once), 0x2B/0x0E (`read_identification`, "more follows" followed); each request byte-exact (struct, MBAP §6),
through the client built from the map and through the generated one."""

from __future__ import annotations

import struct
from pathlib import Path
from typing import Any

import pytest

from regmap.frontend import load_map

from conftest import ROOT, SimulatorFactory
from support.fixture_clients import FLAVOURS, POWER, REMOTE, flavour

METER = ROOT / "tests" / "maps" / "fixtures" / "power_meter.yaml"
METER_MAP = load_map(METER)
CT_RATIO = METER_MAP.register("ct_ratio")
FIRMWARE = METER_MAP.register("firmware_version")
assert METER_MAP.transport.identification is not None and METER_MAP.transport.server_id is not None
OBJECTS = dict(METER_MAP.transport.identification.objects)
SERVER = METER_MAP.transport.server_id


def meter_client(simulator: SimulatorFactory, name: str, *extra: str, map_path: Path = METER, **options: Any) -> tuple[Any, Any, Any]:
    sim = simulator(map_path, *extra)
    f = flavour(name, POWER)
    assert sim.port is not None
    client, recorder = f.client(sim.port, **options)
    client.connect()
    return f, client, recorder


@pytest.mark.parametrize("name", FLAVOURS)
def test_echo_server_id_and_identification(simulator: SimulatorFactory, name: str) -> None:
    _f, client, recorder = meter_client(simulator, name)
    try:
        assert client.echo(0x1234) == 0x1234
        report = client.report_server_id()
        assert report.data == SERVER.id + b"\xff" + SERVER.additional_data.encode("ascii")
        assert report.split(len(SERVER.id)) == (SERVER.id, True, SERVER.additional_data.encode("ascii"))
        assert client.read_identification("basic") == {i: OBJECTS[i] for i in (0, 1, 2)}
        assert client.read_identification() == OBJECTS
    finally:
        client.close()
    assert recorder.pdus() == [
        struct.pack(">BHH", 0x08, 0x0000, 0x1234),
        bytes([0x11]),
        bytes([0x2B, 0x0E, 0x01, 0x00]),
        bytes([0x2B, 0x0E, 0x02, 0x00]),
    ]


@pytest.mark.parametrize("name", FLAVOURS)
def test_write_and_read_checks_the_write_and_sends_one_request(simulator: SimulatorFactory, name: str) -> None:
    f, client, recorder = meter_client(simulator, name)
    try:
        values = client.write_and_read({f.spec("ct_ratio"): 7}, [f.spec("ct_ratio")])
        assert values == {"ct_ratio": 7}
        assert recorder.pdus() == [struct.pack(">BHHHHBH", 0x17, CT_RATIO.address, 1, CT_RATIO.address, 1, 2, 7)]
        with pytest.raises(ValueError, match=r"outside 1\.\.10000"):  # the codec's RangeError, of either runtime
            client.write_and_read({f.spec("ct_ratio"): 0}, [f.spec("ct_ratio")])  # the map's 1..10000
        with pytest.raises(ValueError, match="one run"):
            client.write_and_read({f.spec("ct_ratio"): 2, f.spec("voltage_alarm"): 5.0}, [f.spec("ct_ratio")])  # 0x0121 between
        assert len(recorder.sent) == 1  # refused before anything went out
    finally:
        client.close()


@pytest.mark.parametrize("name", FLAVOURS)
def test_a_lost_write_and_read_answer_is_outcome_unknown_sent_once(simulator: SimulatorFactory, name: str) -> None:
    f, client, recorder = meter_client(simulator, name, "--fault", "no_answer", "--fault-count", "1", retries=2)
    try:
        with pytest.raises(f.errors.OutcomeUnknown) as info:
            client.write_and_read({f.spec("ct_ratio"): 9}, [f.spec("ct_ratio")])
        assert info.value.registers == ("ct_ratio",)
        assert len(recorder.sent) == 1
        assert client.read(f.spec("ct_ratio")) == 9  # it did happen: the caller reads back, as the error says
    finally:
        client.close()


def test_functions_the_map_does_not_list_are_refused_before_sending(simulator: SimulatorFactory) -> None:
    sim = simulator(ROOT / "tests" / "maps" / "fixtures" / "remote_io.yaml")
    f = flavour("runtime", REMOTE)
    assert not {0x08, 0x11, 0x17, 0x2B} & set(f.device.transport.function_codes)
    assert sim.port is not None
    client, recorder = f.client(sim.port)
    try:
        for call in (client.echo, client.report_server_id, client.read_identification):
            with pytest.raises(f.errors.AccessError, match="does not list function"):
                call()
    finally:
        client.close()
    assert recorder.sent == []


def test_identification_follows_more_follows_to_the_end(simulator: SimulatorFactory, tmp_path: Path) -> None:
    # Objects too long for one answer (a PDU is at most 253 bytes): the simulator splits the stream (MBAP §6.21).
    long = {"vendor_name": "V" * 120, "product_code": "P" * 120, "revision": "R" * 120}
    text = METER.read_text(encoding="utf-8")
    start = text.index("  identification:")
    end = text.index("\n", start)
    fields = ", ".join(f"{k}: {v}" for k, v in long.items())
    path = tmp_path / "long_identification.yaml"
    path.write_text(text[:start] + f"  identification: {{{fields}, source: test}}" + text[end:], encoding="utf-8")
    _f, client, recorder = meter_client(simulator, "runtime", map_path=path)
    try:
        assert client.read_identification("basic") == {0: long["vendor_name"], 1: long["product_code"], 2: long["revision"]}
    finally:
        client.close()
    assert recorder.pdus() == [bytes([0x2B, 0x0E, 0x01, 0x00]), bytes([0x2B, 0x0E, 0x01, 0x02])]
