"""Function 0x16 (mask write register): where a map lists it, a bitfield change is one atomic request, not a
read-modify-write, and the simulator applies it as MBAP §6.16 says. Fixture: tests/maps/protocol/mask_write.yaml (kept
out of tests/maps/fixtures/, whose maps every back end's tests take up with their own expectations)."""

from __future__ import annotations

import asyncio
import functools
import importlib
import re
import socket
import struct
import sys
import tempfile
from pathlib import Path
from typing import Any

from conftest import ROOT, SimulatorFactory

MASK_MAP = ROOT / "tests" / "maps" / "protocol" / "mask_write.yaml"
IDM = ROOT / "maps" / "idm_rs.yaml"


def _functions(log: Path) -> list[str]:
    """The function codes of the requests the simulator received, in order."""
    return re.findall(r"function (0x[0-9A-F]{2}) .*\(request\)", log.read_text(encoding="utf-8"))


@functools.cache
def _module() -> Any:
    """The generated client of the fixture (generated once per run, importable from then on)."""
    from regmap.frontend import load_map
    from regmap.generate import generate

    out = Path(tempfile.mkdtemp(prefix="regmap-mask-write-")) / "generated"
    generate([load_map(MASK_MAP)], out, ["python"], complete=True)
    sys.path.append(str(out / "python"))
    return importlib.import_module("fixture_mask_write")


def _tcp_exchange(port: int, pdu: bytes) -> bytes:
    """One Modbus TCP request (transaction 1, unit 1) and the answer's PDU."""
    with socket.create_connection(("127.0.0.1", port), timeout=5) as sock:
        sock.sendall(struct.pack(">HHHB", 1, 0, len(pdu) + 1, 1) + pdu)
        head = sock.recv(7)
        (length,) = struct.unpack(">H", head[4:6])
        body = b""
        while len(body) < length - 1:
            body += sock.recv(260)
        return body


def test_the_simulator_applies_the_specs_mask_write_example(simulator: SimulatorFactory) -> None:
    # MBAP §6.16: register 5 holds 0x0012; AND 0x00F2, OR 0x0025 -> 0x0017; the answer echoes the request.
    sim = simulator(MASK_MAP)
    assert sim.port is not None
    request = bytes.fromhex("16 0004 00F2 0025")
    assert _tcp_exchange(sim.port, request) == request
    assert _tcp_exchange(sim.port, bytes.fromhex("03 0004 0001")) == bytes.fromhex("03 02 0017")


def test_a_device_without_0x16_answers_illegal_function(simulator: SimulatorFactory) -> None:
    sim = simulator(IDM)
    assert sim.port is not None
    assert _tcp_exchange(sim.port, bytes.fromhex("16 6002 00F2 0025")) == bytes.fromhex("96 01")


def test_a_bitfield_change_is_one_mask_write_and_keeps_every_other_bit(simulator: SimulatorFactory, tmp_path: Path) -> None:
    module = _module()
    log = tmp_path / "requests.log"
    sim = simulator(MASK_MAP, "--log", str(log))
    assert sim.port is not None
    with module.FixtureMaskWrite.tcp("127.0.0.1", sim.port, timeout=2) as io:
        io.write_raw(0x0004, [0x1012])  # bit 12 is no field's: it must stay too
        before = len(_functions(log))
        new = io.update(module.OUTPUT_WORD, enable=True, mode=module.OutputMode.RUNNING)
        assert _functions(log)[before:] == ["0x16", "0x03"]  # one mask write, then the read-back: no read before it
        assert new.raw == 0x1113
        assert (new.enable, new.reverse, new.step, new.mode) == (True, True, 1, module.OutputMode.RUNNING)
        assert io.read_raw(0x0004, 1) == [0x1113]
        io.update(module.OUTPUT_WORD, reverse=False, step=0)
        assert io.read_raw(0x0004, 1) == [0x1101]
    assert _functions(log).count("0x16") == 2


def test_the_async_client_uses_the_mask_write_too(simulator: SimulatorFactory, tmp_path: Path) -> None:
    module = _module()
    log = tmp_path / "requests.log"
    sim = simulator(MASK_MAP, "--log", str(log))
    assert sim.port is not None

    async def run() -> Any:
        async with module.AsyncFixtureMaskWrite.tcp("127.0.0.1", sim.port, timeout=2) as io:
            return await io.update(module.OUTPUT_WORD, step=15)

    new = asyncio.run(run())
    assert new.raw == 0x00F2
    assert _functions(log) == ["0x16", "0x03"]


def test_a_field_value_the_map_forbids_sends_nothing(simulator: SimulatorFactory, tmp_path: Path) -> None:
    module = _module()
    log = tmp_path / "requests.log"
    sim = simulator(MASK_MAP, "--log", str(log))
    assert sim.port is not None
    with module.FixtureMaskWrite.tcp("127.0.0.1", sim.port, timeout=2) as io:
        for bad in ({"mode": 3}, {"step": 16}):  # not a member of output_mode; wider than 4 bits
            try:
                io.update(module.OUTPUT_WORD, **bad)
            except ValueError:
                continue
            raise AssertionError(f"{bad} was accepted")
    assert not log.exists() or _functions(log) == []
