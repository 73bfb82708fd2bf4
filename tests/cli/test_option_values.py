"""Option values and messages (issue #28, items 6-8): every value the command line takes is checked
where it is parsed and refused in one line naming the option, the value and what is allowed; the
messages say what happened in regmap's words (never pymodbus's); `simulate` takes the line settings."""

from __future__ import annotations

import socket
import subprocess
import sys
import threading
from collections.abc import Iterator
from pathlib import Path

import pytest

from regmap.diagnostics import ExitCode

from conftest import ROOT, PtyPair, SimulatorFactory

IDM = "maps/idm_rs.yaml"
POWER_METER = "tests/maps/fixtures/power_meter.yaml"  # its line: 9600 baud, even parity
CLOSED_PORT = ("--tcp", "127.0.0.1:1")  # refuses connections: a value that passed the checks fails with 4, not 2


def regmap(*args: str, cwd: Path = ROOT, timeout: float = 30) -> subprocess.CompletedProcess[str]:
    """`regmap ARGS` as a process; one that is still running after `timeout` accepted what it should have refused."""
    try:
        return subprocess.run(
            [sys.executable, "-m", "regmap", *args], cwd=cwd, capture_output=True, text=True, check=False, timeout=timeout
        )
    except subprocess.TimeoutExpired:
        pytest.fail(f"regmap {' '.join(args)} was still running after {timeout} s: it accepted the value")


def one_line_error(result: subprocess.CompletedProcess[str], code: int, *needles: str) -> str:
    assert result.returncode == code, (result.returncode, result.stdout, result.stderr)
    lines = result.stderr.strip().splitlines()
    assert lines and "Traceback" not in result.stderr and "internal error" not in result.stderr, result.stderr
    for needle in needles:
        assert needle in lines[-1], lines[-1]
    return lines[-1]


# -- 6. values accepted without a word ---------------------------------------------------------


def test_baud_zero_is_refused_not_taken_for_the_maps_default() -> None:
    line = one_line_error(regmap("read", IDM, "Pr5.00", "--serial", "/dev/regmap-no-such-port", "--baud", "0"), ExitCode.USAGE)
    assert line == "regmap read: error: argument --baud: 0 is not a baud rate (a positive whole number: 9600, 38400 ...)"


def test_a_baud_rate_the_map_does_not_list_is_refused_with_the_list() -> None:
    line = one_line_error(regmap("read", IDM, "Pr5.00", "--serial", "/dev/regmap-no-such-port", "--baud", "115000"), ExitCode.USAGE)
    assert line == "regmap read: error: --baud 115000 is not a baud rate of iDM-RS (V2.0): it talks at 9600, 19200, 38400, 115200"


def test_line_settings_are_refused_over_tcp() -> None:
    one_line_error(regmap("read", IDM, "Pr5.00", "--parity", "even", *CLOSED_PORT), ExitCode.USAGE, "--parity", "--serial")


@pytest.mark.parametrize(
    ("option", "value", "needle"),
    [
        ("--fault-delay", "-1", "argument --fault-delay: -1 is not a number of seconds, 0 or more"),
        ("--fault-delay", "nan", "argument --fault-delay: nan is not a number of seconds, 0 or more"),
        ("--fault-count", "0", "argument --fault-count: 0 must be 1 or more"),
        ("--fault-exception", "0", "argument --fault-exception: 0 is not a Modbus exception code (1..255, 0x01..0xFF)"),
        ("--fault-exception", "0x100", "argument --fault-exception: 0x100 is not a Modbus exception code"),
        ("--fault-exception", "busy", "argument --fault-exception: 'busy' is not a Modbus exception code"),
        ("--max-read", "0", "argument --max-read: 0 is outside 1..125"),
    ],
)
def test_simulate_refuses_a_fault_value_that_means_nothing(option: str, value: str, needle: str) -> None:
    result = regmap("simulate", IDM, "--tcp", "127.0.0.1:0", "--fault", "delay", option, value, timeout=15)
    one_line_error(result, ExitCode.USAGE, needle)


def test_a_command_without_an_argument_refuses_one() -> None:
    result = regmap("command", IDM, "save_all_parameters", "5", *CLOSED_PORT)
    line = one_line_error(result, ExitCode.USAGE)
    assert line == "regmap command: error: command save_all_parameters takes no argument, got '5'"


# -- 7. messages that mislead ------------------------------------------------------------------


def test_a_command_that_needs_an_argument_names_it() -> None:
    line = one_line_error(regmap("command", IDM, "trigger_path", *CLOSED_PORT), ExitCode.USAGE)
    assert line == "regmap command: error: command trigger_path needs an argument: path (0..15)"


def test_a_range_error_shows_the_value_as_given() -> None:
    line = one_line_error(regmap("write", POWER_METER, "demand_period=3600.0001", *CLOSED_PORT), ExitCode.USAGE)
    assert line == "regmap write: error: demand_period: 3600.0001 s is outside 1..3600 s"


def test_probe_rate_is_requests_per_second() -> None:
    line = one_line_error(regmap("probe", IDM, "--rate", "0", *CLOSED_PORT), ExitCode.USAGE)
    assert line.endswith("argument --rate: 0 must be a positive number of requests per second")


def test_an_answer_from_another_slave_over_tcp_is_wrong_slave_as_on_rtu(simulator: SimulatorFactory) -> None:
    sim = simulator(ROOT / IDM, "--fault", "wrong_slave")
    result = regmap("read", IDM, "Pr5.00", "--tcp", f"127.0.0.1:{sim.port}", "--timeout", "0.5", "--retries", "0")
    line = one_line_error(result, ExitCode.BUS, "WrongSlave: asked slave 1, the answer came from slave 2: 00 01 00 00 00 05 02 03")
    assert "ProtocolError" not in line


@pytest.fixture
def closes_mid_answer() -> Iterator[int]:
    """A Modbus TCP server that sends the first bytes of an answer, then closes the connection."""
    server = socket.create_server(("127.0.0.1", 0))
    server.settimeout(10)

    def serve() -> None:
        for _ in range(3):  # the first try and the retries
            try:
                connection, _ = server.accept()
            except OSError:
                return
            with connection:
                request = connection.recv(260)
                connection.sendall(request[:4] + b"\x00\x05")  # MBAP: transaction, protocol, length 5 ... and no more

    thread = threading.Thread(target=serve, daemon=True)
    thread.start()
    yield int(server.getsockname()[1])
    server.close()
    thread.join(timeout=10)


def test_a_connection_closed_mid_answer_is_said_in_regmaps_words(closes_mid_answer: int) -> None:
    result = regmap("read", IDM, "Pr5.00", "--tcp", f"127.0.0.1:{closes_mid_answer}", "--timeout", "0.5", "--retries", "0")
    line = one_line_error(result, ExitCode.BUS, "ConnectionLost: the connection closed before the answer was complete")
    for pymodbus_text in ("Modbus Error", "ModbusTcpClient", "unbounded", "unexpectedly"):
        assert pymodbus_text not in line


def test_a_write_of_a_write_only_enum_register_says_what_it_wrote(simulator: SimulatorFactory) -> None:
    sim = simulator(ROOT / IDM)
    result = regmap("write", IDM, "control_word=save_all_parameters", "Pr5.00=1.5", "--tcp", f"127.0.0.1:{sim.port}")
    assert result.returncode == ExitCode.OK, result.stderr
    assert result.stdout.splitlines() == [
        "control_word = save_all_parameters (8721 = 0x2211)  (written; write-only, not read back)",
        "Pr5.00 peak_current = 1.5 A (raw 15)  (verified)",
    ]


def test_new_with_a_reserved_device_id_points_at_the_argument(tmp_path: Path) -> None:
    result = regmap("new", "class", "--vendor", "Acme", "--model", "X1", cwd=tmp_path)
    line = one_line_error(result, ExitCode.USAGE)
    assert line == (
        "regmap new: error: DEVICE_ID 'class': device id 'class' is a reserved word of the python target (a Python keyword "
        "or a package the client would shadow), the c target (a C/C++ keyword or the shared header's name) and the st target "
        "(an IEC 61131-3 or CODESYS reserved word); choose another (e.g. class_drive); nothing written"
    )
    assert not (tmp_path / "maps").exists()
    # A word only Structured Text reserves is refused too: the skeleton must validate for every target.
    iec = one_line_error(regmap("new", "end_if", "--vendor", "Acme", "--model", "X1", cwd=tmp_path), ExitCode.USAGE)
    assert iec.startswith("regmap new: error: DEVICE_ID 'end_if': device id 'end_if' is a reserved word of the st target"), iec
    assert not (tmp_path / "maps").exists()


# -- 8. simulate's line settings -----------------------------------------------------------------


def test_simulate_on_a_pty_refusing_the_maps_parity_says_so_and_parity_none_works(pty_pair: PtyPair, simulator: SimulatorFactory) -> None:
    # A Linux pty takes even parity once, then refuses it with termios.error on the next starts.
    refused = 0
    for _ in range(4):
        process = subprocess.Popen(
            [sys.executable, "-m", "regmap", "simulate", POWER_METER, "--serial", pty_pair.device],
            cwd=ROOT,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        try:
            _, stderr = process.communicate(timeout=5)
        except subprocess.TimeoutExpired:  # it serves: this start got the parity
            process.terminate()
            process.communicate(timeout=10)
            continue
        refused += 1
        assert process.returncode == ExitCode.USAGE, (process.returncode, stderr)
        assert stderr.strip() == (
            f"regmap simulate: error: cannot open {pty_pair.device}: the port refuses 9600 baud, even parity, 1 stop bit(s): "
            "Invalid argument (a pseudo-terminal may refuse parity: try --parity none)"
        )
    assert refused >= 1
    for _ in range(4):
        sim = simulator(ROOT / POWER_METER, "--parity", "none", serial=pty_pair.device)
        assert "on " + pty_pair.device in sim.banner, sim.banner
        sim.stop()
    sim = simulator(ROOT / POWER_METER, "--parity", "none", "--baud", "19200", serial=pty_pair.device)
    read = regmap("read", POWER_METER, "demand_period", "--serial", pty_pair.client, "--parity", "none", "--baud", "19200")
    assert read.returncode == ExitCode.OK, read.stderr
    assert read.stdout.strip() == "demand_period = 900 s"


def test_simulate_refuses_line_settings_without_serial_and_unlisted_baud_rates() -> None:
    one_line_error(regmap("simulate", IDM, "--tcp", "127.0.0.1:0", "--parity", "even", timeout=15), ExitCode.USAGE, "--serial")
    refused = regmap("simulate", IDM, "--serial", "/dev/regmap-no-such-port", "--baud", "115000", timeout=15)
    one_line_error(refused, ExitCode.USAGE, "--baud 115000 is not a baud rate of iDM-RS (V2.0)")


def test_a_missing_port_is_the_operating_systems_reason_not_pyserials_text() -> None:
    missing = "/dev/regmap-no-such-port"
    read = one_line_error(regmap("read", IDM, "Pr5.00", "--serial", missing), ExitCode.BUS)
    assert read == f"regmap read: bus error: cannot open {missing}: No such file or directory"
    served = one_line_error(regmap("simulate", IDM, "--serial", missing, timeout=15), ExitCode.USAGE)
    assert served == f"regmap simulate: error: cannot open {missing}: No such file or directory"


def test_a_client_that_cannot_connect_names_the_place_not_pymodbus_s_class() -> None:
    from regmap.frontend import load_map
    from regmap.runtime_bridge import runtime_device
    from regmap_runtime.client import SyncClient
    from regmap_runtime.errors import ConnectionLost

    client_class: type[SyncClient] = type("live", (SyncClient,), {"DEVICE": runtime_device(load_map(ROOT / IDM))})
    for client, where in (
        (client_class.tcp("127.0.0.1", 1, timeout=0.5, retries=0), "127.0.0.1:1"),
        (client_class.rtu("/dev/regmap-no-such-port", timeout=0.5, retries=0), "/dev/regmap-no-such-port"),
    ):
        with pytest.raises(ConnectionLost) as refused:
            client.connect()
        assert str(refused.value) == f"cannot connect to {where}"


# -- options before the command (mbpoll's order) -------------------------------------------------


def test_options_before_the_command_are_its_options_as_after_it(capsys: pytest.CaptureFixture[str]) -> None:
    from regmap.cli import main

    frame = ["frame", str(ROOT / IDM), "read", "Pr5.00"]
    assert main(["--slave", "2", *frame]) == ExitCode.OK
    before = capsys.readouterr().out
    assert main([*frame, "--slave", "2"]) == ExitCode.OK
    assert before == capsys.readouterr().out == "02 03 01 91 00 01 D4 28\n"


def test_an_options_value_before_the_command_is_not_taken_for_the_command() -> None:
    before = one_line_error(regmap(*CLOSED_PORT, "read", IDM, "Pr5.00"), ExitCode.BUS)  # the read ran: the port refused it
    assert (
        before
        == one_line_error(regmap("read", IDM, "Pr5.00", *CLOSED_PORT), ExitCode.BUS)
        == "regmap read: bus error: cannot open 127.0.0.1:1: Connection refused"
    )
    line = one_line_error(regmap("--slave", "300", "read", IDM, "Pr5.00", *CLOSED_PORT), ExitCode.USAGE)
    assert line == "regmap read: error: argument --slave: 300 is outside 0..255"


def test_a_first_word_that_names_no_command_is_refused_with_the_commands(capsys: pytest.CaptureFixture[str]) -> None:
    from regmap.cli import main

    assert main(["3", "read", str(ROOT / IDM)]) == ExitCode.USAGE
    line = capsys.readouterr().err.strip().splitlines()[-1]
    assert line.startswith("regmap: error: argument COMMAND: invalid choice: '3' (choose from 'validate',"), line
    assert main(["--version", "read"]) == ExitCode.OK  # --version before a command is still the top parser's
    assert capsys.readouterr().out.startswith("regmap ")


def test_a_bad_option_value_is_one_line_and_a_bad_shape_shows_the_usage(capsys: pytest.CaptureFixture[str]) -> None:
    from regmap.cli import main

    read = ["read", str(ROOT / IDM), "Pr5.00"]
    assert main([*read, "--slave", "300"]) == ExitCode.USAGE
    assert capsys.readouterr().err == "regmap read: error: argument --slave: 300 is outside 0..255\n"
    assert main([*read, "--parity", "bogus"]) == ExitCode.USAGE
    assert capsys.readouterr().err == "regmap read: error: argument --parity: invalid choice: 'bogus' (choose from 'none', 'even', 'odd')\n"
    for shape in (["--slave"], ["--serial", "/dev/x", "--tcp", "127.0.0.1:1"], ["--no-such-option"]):
        assert main([*read, *shape]) == ExitCode.USAGE
        assert capsys.readouterr().err.startswith("usage: regmap read"), shape


def test_options_then_a_misspelt_command_names_the_words_not_an_options_value(capsys: pytest.CaptureFixture[str]) -> None:
    from regmap.cli import main

    assert main(["--tcp", "127.0.0.1:1", "reed", str(ROOT / IDM)]) == ExitCode.USAGE
    line = capsys.readouterr().err.strip().splitlines()[-1]
    assert line.startswith(f"regmap: error: no command among '127.0.0.1:1', 'reed', '{ROOT / IDM}' (choose from 'validate',"), line
    assert "invalid choice" not in line
