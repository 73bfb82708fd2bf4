"""`regmap simulate` driven by the generated clients and by an independent master (mbpoll)."""

from __future__ import annotations

import json
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from regmap.frontend import load_map

from conftest import ROOT, PtyPair, SimulatorFactory, generated_runtime, require_tool
from support.clients import client_module

_errors = generated_runtime("errors")
DeviceException = _errors.DeviceException

IDM = ROOT / "maps" / "idm_rs.yaml"
C630S = ROOT / "maps" / "c630s.yaml"


def mbpoll(*args: str) -> subprocess.CompletedProcess[str]:
    tool = require_tool("mbpoll")
    return subprocess.run([tool, "-1", "-0", "-o", "2", *args], capture_output=True, text=True, check=False, timeout=30)


def tcp_args(port: int) -> list[str]:
    return ["-m", "tcp", "-p", str(port), "-a", "1"]


def values_of(output: str) -> dict[int, str]:
    """mbpoll prints `[401]: 	22` per value."""
    found = {}
    for line in output.splitlines():
        if line.startswith("[") and "]:" in line:
            ref, _, value = line.partition("]:")
            found[int(ref[1:])] = value.strip()
    return found


def test_mbpoll_reads_defaults_and_32bit_word_orders(simulator: SimulatorFactory) -> None:
    sim = simulator(IDM)
    assert sim.port is not None
    result = mbpoll(*tcp_args(sim.port), "-r", "401", "-c", "1", "-t", "4", "127.0.0.1")
    assert values_of(result.stdout) == {401: "22"}, result.stdout + result.stderr
    # PR path 3 position: write through the client, read as a big-endian (high word first) 32-bit int.
    idm = client_module("idm_rs")
    with idm.IdmRs.tcp("127.0.0.1", sim.port, timeout=2) as drive:
        drive.pr_path(3).write_position(-200000)
    address = 0x6200 + 3 * 8 + 1
    result = mbpoll(*tcp_args(sim.port), "-r", str(address), "-c", "1", "-t", "4:int", "-B", "127.0.0.1")
    assert values_of(result.stdout) == {address: "-200000"}, result.stdout


def test_mbpoll_reads_c630s_low_word_first_default(simulator: SimulatorFactory) -> None:
    sim = simulator(C630S)
    assert sim.port is not None
    c630s = client_module("c630s")
    address = c630s.GEAR1_NUMERATOR.address
    result = mbpoll(*tcp_args(sim.port), "-r", str(address), "-t", "4:int", "127.0.0.1")  # mbpoll's default: low word first
    assert values_of(result.stdout) == {address: "1048576"}, result.stdout


def test_refusals_carry_the_manuals_exception_codes(simulator: SimulatorFactory) -> None:
    sim = simulator(IDM)
    assert sim.port is not None
    out_of_range = mbpoll(*tcp_args(sim.port), "-r", "401", "-t", "4", "127.0.0.1", "900")
    assert out_of_range.returncode != 0
    assert "Illegal data value" in out_of_range.stdout + out_of_range.stderr
    undocumented = mbpoll(*tcp_args(sim.port), "-r", str(0x5000), "-t", "4", "127.0.0.1", "1")
    assert undocumented.returncode != 0
    assert "Illegal data address" in undocumented.stdout + undocumented.stderr
    idm = client_module("idm_rs")
    with idm.IdmRs.tcp("127.0.0.1", sim.port, timeout=2) as drive:
        with pytest.raises(DeviceException) as info:
            drive.write_raw(0x0191, [900])
        assert info.value.code == 0x03
        wrong_data = load_map(IDM).transport.exception(0x03)
        assert wrong_data is not None and info.value.meaning == wrong_data.title  # 5.4.1's meaning, from the map
        with pytest.raises(DeviceException) as info:
            drive.write_raw(0x1003, [1])  # run status is read-only
        assert info.value.code == 0x03
        assert drive.read_peak_current() == pytest.approx(2.2)  # nothing changed


def test_save_survives_a_restart_and_factory_reset_restores(simulator: SimulatorFactory, tmp_path: Path) -> None:
    state = tmp_path / "drive.json"
    idm = client_module("idm_rs")
    sim = simulator(IDM, "--state", str(state))
    assert sim.port is not None
    with idm.IdmRs.tcp("127.0.0.1", sim.port, timeout=2) as drive:
        drive.write_peak_current(1.5)
        drive.save_all_parameters()
        drive.write_peak_current(1.2)  # changed after the save: lost at power-off
    sim.stop()
    saved = json.loads(state.read_text(encoding="utf-8"))
    assert saved["registers"]["peak_current"] == 15
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".state-")], "a temporary state file was left behind"
    sim = simulator(IDM, "--state", str(state))
    assert sim.port is not None
    with idm.IdmRs.tcp("127.0.0.1", sim.port, timeout=2) as drive:
        assert drive.read_peak_current() == pytest.approx(1.5)
        drive.restore_factory_defaults(confirm="restore_factory_defaults")
        assert drive.read_peak_current() == pytest.approx(2.2)


def test_mbpoll_over_rtu_pty(simulator: SimulatorFactory, pty_pair: PtyPair) -> None:
    simulator(IDM, serial=pty_pair.device)
    result = mbpoll("-m", "rtu", "-b", "19200", "-P", "none", "-a", "1", "-r", "401", "-t", "4", pty_pair.client)
    assert values_of(result.stdout) == {401: "22"}, result.stdout + result.stderr
    result = mbpoll("-m", "rtu", "-b", "19200", "-P", "none", "-a", "1", "-r", "401", "-t", "4", pty_pair.client, "12")
    assert result.returncode == 0, result.stdout + result.stderr
    result = mbpoll("-m", "rtu", "-b", "19200", "-P", "none", "-a", "1", "-r", "401", "-t", "4", pty_pair.client)
    assert values_of(result.stdout) == {401: "12"}


def test_broadcast_write_applies_without_a_reply(simulator: SimulatorFactory) -> None:
    idm = client_module("idm_rs")
    sim = simulator(IDM, "--gateway")  # a device addressed directly over TCP answers unit 0; a gateway broadcasts it
    assert sim.port is not None
    with idm.IdmRs.tcp("127.0.0.1", sim.port, slave=0, timeout=1) as everyone:
        everyone.write_peak_current(1.1)  # no answer is expected, none comes
    with idm.IdmRs.tcp("127.0.0.1", sim.port, slave=1, timeout=2) as drive:
        assert drive.read_peak_current() == pytest.approx(1.1)


def test_ctrl_c_stops_cleanly(simulator: SimulatorFactory) -> None:
    sim = simulator(IDM)
    sim.process.send_signal(signal.SIGINT)
    assert sim.process.wait(timeout=10) == 0
    assert "stopped after" in sim.stop()


def test_live_cli_against_the_simulator(simulator: SimulatorFactory) -> None:
    sim = simulator(IDM)
    assert sim.port is not None
    tcp = ["--tcp", f"127.0.0.1:{sim.port}"]

    def regmap(*args: str) -> subprocess.CompletedProcess[str]:
        return subprocess.run([sys.executable, "-m", "regmap", *args], cwd=ROOT, capture_output=True, text=True, check=False, timeout=60)

    read = regmap("read", str(IDM), "peak_current", "Pr5.22", *tcp)
    assert read.returncode == 0, read.stderr
    assert "Pr5.00 peak_current = 2.2 A (raw 22)" in read.stdout
    write = regmap("write", str(IDM), "Pr5.00=1.7", *tcp)
    assert write.returncode == 0, write.stderr
    assert "1.7 A (raw 17)  (verified)" in write.stdout
    refused = regmap("write", str(IDM), "Pr5.00=17", *tcp)
    assert refused.returncode == 2
    assert refused.stderr.strip() == "regmap write: error: peak_current (Pr5.00): 17 A is outside 0..8 A"
    dump = regmap("dump", str(IDM), "--json", *tcp)
    assert dump.returncode == 0, dump.stderr
    rows = json.loads(dump.stdout)
    assert {r["register"] for r in rows} >= {"peak_current", "save_status", "run_status"}
    csv_dump = regmap("dump", str(IDM), "--csv", *tcp)
    assert csv_dump.stdout.splitlines()[0].startswith("register,param,address,address_hex,raw,value,unit,in_range,text,space,function,")
    dead = regmap("read", str(IDM), "peak_current", "--tcp", "127.0.0.1:1")
    assert dead.returncode == 4
    assert len(dead.stderr.strip().splitlines()) == 1, dead.stderr
    silent = regmap("read", str(IDM), "peak_current", *tcp, "--slave", "9", "--timeout", "0.3", "--retries", "0")
    assert silent.returncode == 4
    assert "DeviceTimeout" in silent.stderr and "not read: peak_current" in silent.stderr
    assert len(silent.stderr.strip().splitlines()) == 1, silent.stderr
