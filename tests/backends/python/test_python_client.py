"""Generated Python clients against the simulator: over Modbus TCP and over RTU on a pty pair."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

from conftest import MAPS, ROOT, PtyPair, SimulatorFactory, generated_runtime, generated_runtime_name, mypy_strict
from support import docstrings
from support.clients import client_module

_errors = generated_runtime("errors")
DeviceException = _errors.DeviceException
DeviceTimeout = _errors.DeviceTimeout

IDM = ROOT / "maps" / "idm_rs.yaml"
C630S = ROOT / "maps" / "c630s.yaml"
ID243 = ROOT / "maps" / "id243pro.yaml"


def test_generated_clients_pass_mypy_strict() -> None:
    packages = [p.stem for p in MAPS]
    result = mypy_strict(*(f"-p{p}" for p in packages), f"-p{generated_runtime_name()}")
    assert result.returncode == 0, result.stdout + result.stderr


def test_each_register_is_documented_once_at_its_constant() -> None:
    """A register's full text (address, type, range, source) is the docstring under its constant, nowhere else;
    its sync and async methods carry one line that names the constant and the title, so help() still tells them apart."""
    for path in MAPS:
        module = client_module(path.stem)
        under, written = docstrings.constant_docs(module), docstrings.written(module)
        clients = [c for c in vars(module).values() if isinstance(c, type) and c.__module__ == module.__name__ and hasattr(c, "DEVICE")]
        assert len(clients) == 2, clients  # the sync and the async client
        for spec in module.DEVICE.registers:
            constant = spec.name.upper()
            assert written[under[constant]] == 1, f"{path.stem}: {constant}'s documentation is written {written[under[constant]]} times"
            for client in clients:
                method = getattr(client, f"read_{spec.name}", None)
                if method is not None:
                    assert method.__doc__.startswith(f"Read {constant}: "), (client.__name__, method.__doc__)


def test_read_only_register_has_no_write_path_that_type_checks(tmp_path: Path) -> None:
    program = tmp_path / "misuse.py"
    program.write_text(
        "from idm_rs import IdmRs, RUN_STATUS\ndef f(d: IdmRs) -> None:\n    d.write(RUN_STATUS, 1)\n    d.write_run_status(1)\n",
        encoding="utf-8",
    )
    result = mypy_strict(str(program))
    assert result.returncode == 1
    assert 'incompatible type "ReadOnly[RunStatusBits]"' in result.stdout
    assert '"IdmRs" has no attribute "write_run_status"' in result.stdout


def test_idm_rs_over_tcp(simulator: SimulatorFactory) -> None:
    sim = simulator(IDM)
    idm = client_module("idm_rs")
    assert sim.port is not None
    with idm.IdmRs.tcp("127.0.0.1", sim.port, slave=1, timeout=2) as drive:
        # Scaled value: raw 22 reads as 2.2 A; writing 1.5 A sends raw 15.
        assert drive.read_peak_current() == pytest.approx(2.2)
        drive.write_peak_current(1.5)
        assert drive.read_raw(0x0191, 1) == [15]
        # A range violation sends nothing.
        before = drive.requests_sent
        with pytest.raises(ValueError, match=r"peak_current \(Pr5\.00\).*outside 0\.\.8 A"):
            drive.write_peak_current(9.5)
        with pytest.raises(ValueError, match="resolution"):
            drive.write_peak_current(1.55)
        assert drive.requests_sent == before
        # 32-bit value, high word first (PR path position, 7.4: -200000 = FFFC F2C0).
        path = drive.pr_path(3)
        path.write_position(-200000)
        assert drive.read_raw(0x6200 + 3 * 8 + 1, 2) == [0xFFFC, 0xF2C0]
        assert path.read_position() == -200000
        with pytest.raises(IndexError):
            drive.pr_path(16)
        # Enum and bitfields.
        assert drive.read_save_status() == idm.SaveStatus.INITIAL
        di = drive.read_di2_function()
        drive.write_di2_function(idm.Di2FunctionBits(function=idm.DiFunction(0x20), normally_closed=True))
        assert drive.read_raw(0x0147, 1) == [0xA0]
        assert drive.read_di2_function().normally_closed is True
        assert isinstance(di, idm.Di2FunctionBits)
        status = drive.read_run_status()
        assert isinstance(status, idm.RunStatusBits)
        # Commands: save, then the status word reads 0x5555 once and 0x1111 after.
        drive.save_all_parameters()
        assert drive.read_save_status() == idm.SaveStatus(0x5555)
        assert drive.read_save_status() == idm.SaveStatus(0x1111)
        drive.trigger_path(2)
        assert drive.read_raw(0x6002, 1) == [0x12]
        with pytest.raises(ValueError):
            drive.trigger_path(16)
        # Exception response from the device, with the manual's meaning.
        with pytest.raises(DeviceException) as info:
            drive.read_raw(0x5000, 1)
        assert info.value.code == 0x02
        # read_all issues exactly the planned number of requests.
        before = drive.requests_sent
        values = drive.read_all()
        assert drive.requests_sent - before == idm.READ_PLAN_REQUESTS
        assert values["peak_current"] == pytest.approx(1.5)
        readable = [r for r in idm.DEVICE.registers if r.readable]
        assert set(values) == {r.name for r in readable}


def test_write_many_groups_contiguous_pairs_like_the_manual(simulator: SimulatorFactory) -> None:
    """5.2.3 writes DI2/DI3 as two 32-bit pairs in one 0x10 request from 0x0146."""
    idm = client_module("idm_rs")
    sim = simulator(IDM)
    assert sim.port is not None
    with idm.IdmRs.tcp("127.0.0.1", sim.port, timeout=2) as drive:
        blocks = drive.plan_writes({idm.DI2_FUNCTION: 0x28, idm.DI3_FUNCTION: 0x29})
        assert [(b.address, b.words) for b in blocks] == [(0x0146, (0, 0x28, 0, 0x29))]
        before = drive.requests_sent
        drive.write_many({idm.DI2_FUNCTION: 0x28, idm.DI3_FUNCTION: 0x29})
        assert drive.requests_sent - before == 1
        assert drive.read_raw(0x0146, 4) == [0, 0x28, 0, 0x29]


def test_c630s_word_order_follows_p0c_26(simulator: SimulatorFactory) -> None:
    """32-bit values low word first by default; the client can follow a drive set to high word first."""
    c630s = client_module("c630s")
    sim = simulator(C630S)
    assert sim.port is not None
    with c630s.C630s.tcp("127.0.0.1", sim.port, timeout=2) as drive:
        drive.write_gear1_numerator(80000)  # 0x00013880
        assert drive.read_raw(c630s.GEAR1_NUMERATOR.address, 2) == [0x3880, 0x0001]
        assert drive.read_gear1_numerator() == 80000
    with c630s.C630s.tcp("127.0.0.1", sim.port, timeout=2, word_order="high_first") as drive:
        # Told "high first" while the drive is still low first, the client reads the words swapped ...
        assert drive.read_gear1_numerator() == 0x38800001
    with c630s.C630s.tcp("127.0.0.1", sim.port, timeout=2) as drive:
        # ... until P0C-26 is set to 0 (high word first): the drive re-lays its 32-bit values.
        drive.write_modbus_word_order(0)
        assert drive.read_raw(c630s.GEAR1_NUMERATOR.address, 2) == [0x0001, 0x3880]
    with c630s.C630s.tcp("127.0.0.1", sim.port, timeout=2, word_order="high_first") as drive:
        assert drive.read_gear1_numerator() == 80000
        drive.write_gear1_numerator(123456789)
        assert drive.read_raw(c630s.GEAR1_NUMERATOR.address, 2) == [0x075B, 0xCD15]


def test_id243pro_32bit_low_word_first(simulator: SimulatorFactory) -> None:
    """Appendix example 2: 10000 travels as 27 10 00 00 (low word first)."""
    id243 = client_module("id243pro")
    sim = simulator(ID243)
    assert sim.port is not None
    with id243.Id243pro.tcp("127.0.0.1", sim.port, timeout=2) as drive:
        spec = id243.TARGET_DISTANCE
        drive.write(spec, 10000)
        assert drive.read_raw(spec.address, 2) == [0x2710, 0x0000]
        assert drive.read(spec) == 10000


def test_timeout_when_nobody_answers(simulator: SimulatorFactory) -> None:
    idm = client_module("idm_rs")
    sim = simulator(IDM)
    assert sim.port is not None
    with idm.IdmRs.tcp("127.0.0.1", sim.port, slave=7, timeout=0.5, retries=0) as drive, pytest.raises(DeviceTimeout):
        drive.read_peak_current()


def test_rtu_over_pty(simulator: SimulatorFactory, pty_pair: PtyPair) -> None:
    idm = client_module("idm_rs")
    simulator(IDM, serial=pty_pair.device)
    with idm.IdmRs.rtu(pty_pair.client, slave=1, timeout=2) as drive:
        assert drive.read_peak_current() == pytest.approx(2.2)
        drive.write_peak_current(1.0)
        assert drive.read_peak_current() == pytest.approx(1.0)
        position: Any = drive.pr_path(0)
        position.write_position(123456)
        assert position.read_position() == 123456
        with pytest.raises(DeviceException):
            drive.read_raw(0x5000, 1)


def test_async_client_same_surface(simulator: SimulatorFactory) -> None:
    import asyncio

    idm = client_module("idm_rs")
    sim = simulator(IDM)
    assert sim.port is not None

    async def main() -> None:
        async with idm.AsyncIdmRs.tcp("127.0.0.1", sim.port, timeout=2) as drive:
            assert await drive.read_peak_current() == pytest.approx(2.2)
            await drive.write_peak_current(2.0)
            assert await drive.read_peak_current() == pytest.approx(2.0)
            await drive.pr_path(1).write_speed(300)
            assert await drive.pr_path(1).read_speed() == 300
            values = await drive.read_all()
            assert values["peak_current"] == pytest.approx(2.0)

    asyncio.run(main())
