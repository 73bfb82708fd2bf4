"""Live-bus safety and field habits of the command line (issue 16): nothing the map forbids is sent,
no bit the caller did not change is changed, two frames never disagree, and user mistakes are
one line with a documented exit status."""

from __future__ import annotations

import dataclasses
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from regmap.core.decoding import carried
from regmap.diagnostics import ExitCode, UsageError
from regmap.frontend import load_map
from regmap.tools.frames import read_words_frame, write_words_frames
from regmap.tools.wordcheck import check_word_runs
from regmap_runtime.rtu import parse_frame, to_hex, with_crc
from regmap_runtime.spaces import SPACES

from conftest import MAPS, ROOT, SimulatorFactory
from support.clients import client_module

IDM = "maps/idm_rs.yaml"
C630S = "maps/c630s.yaml"
FIXTURES = sorted((ROOT / "tests" / "maps" / "fixtures").glob("*.yaml"))


def regmap(*args: str, env: dict[str, str] | None = None, timeout: float = 60) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "regmap", *args], cwd=ROOT, capture_output=True, text=True, check=False, timeout=timeout, env=env
    )


def one_line_error(result: subprocess.CompletedProcess[str], code: int, *needles: str) -> None:
    assert result.returncode == code, (result.returncode, result.stdout, result.stderr)
    assert len(result.stderr.strip().splitlines()) == 1, result.stderr
    assert "Traceback" not in result.stderr + result.stdout and "internal error" not in result.stderr
    for needle in needles:
        assert needle in result.stderr, result.stderr


# -- 1. enum values are checked on every path ----------------------------------------------


def test_frame_refuses_a_value_the_enum_lacks() -> None:
    result = regmap("frame", IDM, "write", "loop_mode=1")
    one_line_error(result, ExitCode.USAGE, "loop_mode", "1 is not one of open_loop=0, closed_loop=2")
    assert result.stdout == ""
    raw = regmap("frame", IDM, "write", "loop_mode=1", "--raw")
    one_line_error(raw, ExitCode.USAGE, "is not one of")


def test_write_refuses_it_before_opening_the_port() -> None:
    # Port 1 refuses connections: a value that passed the checks would fail with a bus error (4).
    result = regmap("write", IDM, "loop_mode=1", "--tcp", "127.0.0.1:1")
    one_line_error(result, ExitCode.USAGE, "is not one of open_loop=0, closed_loop=2")


def test_a_bitfield_enum_field_is_checked() -> None:
    result = regmap("frame", IDM, "write", "di3_function=function:9,normally_closed:0")
    one_line_error(result, ExitCode.USAGE, "di3_function", "9 is not one of")


def test_enum_names_are_case_insensitive_and_listed_on_error() -> None:
    assert (
        regmap("frame", IDM, "write", "loop_mode=CLOSED_LOOP").stdout.strip() == regmap("frame", IDM, "write", "loop_mode=2").stdout.strip()
    )
    result = regmap("frame", IDM, "write", "loop_mode=closed")
    one_line_error(result, ExitCode.USAGE, "open_loop=0", "closed_loop=2")


# -- 2. a bitfield value keeps the bits no field describes ---------------------------------


def test_bitfield_value_keeps_undescribed_bits() -> None:
    idm = client_module("idm_rs")
    value = idm.FaultDetectionMaskBits.from_raw(0xFFFF)
    assert value.to_raw() == 0xFFFF
    assert dataclasses.replace(value, eeprom=False).to_raw() == 0xFFDF
    assert idm.FaultDetectionMaskBits(overcurrent=True).to_raw() == 0x0001  # built from fields alone: the rest is 0


def test_read_change_one_flag_write_changes_only_that_flag(simulator: SimulatorFactory) -> None:
    sim = simulator(ROOT / IDM)
    assert sim.port is not None
    idm = client_module("idm_rs")
    with idm.IdmRs.tcp("127.0.0.1", sim.port, timeout=2) as drive:
        mask = drive.read_fault_detection_mask()
        assert mask.raw == 0xFFFF
        drive.write_fault_detection_mask(dataclasses.replace(mask, eeprom=False))
        assert drive.read_raw(idm.FAULT_DETECTION_MASK.address, 1) == [0xFFDF]
        drive.update(idm.FAULT_DETECTION_MASK, eeprom=True)
        assert drive.read_raw(idm.FAULT_DETECTION_MASK.address, 1) == [0xFFFF]


# -- 3. naming some fields is read-modify-write --------------------------------------------


def test_partial_bitfield_write_keeps_the_other_fields(simulator: SimulatorFactory) -> None:
    sim = simulator(ROOT / IDM)
    assert sim.port is not None
    tcp = ["--tcp", f"127.0.0.1:{sim.port}"]
    idm = client_module("idm_rs")
    address = idm.DI3_FUNCTION.address
    with idm.IdmRs.tcp("127.0.0.1", sim.port, timeout=2) as drive:
        drive.write_raw(address, [0x00A8])
    result = regmap("write", IDM, "di3_function=function:ctrg", *tcp)
    assert result.returncode == 0, result.stderr
    assert "function=ctrg normally_closed=1" in result.stdout and "(verified)" in result.stdout
    with idm.IdmRs.tcp("127.0.0.1", sim.port, timeout=2) as drive:
        assert drive.read_raw(address, 1) == [0x00A0]
    replaced = regmap("write", IDM, "di3_function=function:ctrg", "--replace", *tcp)
    assert replaced.returncode == 0, replaced.stderr
    with idm.IdmRs.tcp("127.0.0.1", sim.port, timeout=2) as drive:
        assert drive.read_raw(address, 1) == [0x0020]


def test_frame_asks_for_every_field_or_a_base_word() -> None:
    result = regmap("frame", IDM, "write", "di3_function=function:ctrg")
    one_line_error(result, ExitCode.USAGE, "missing: normally_closed", "--replace")
    based = regmap("frame", IDM, "write", "di3_function=0x00A8,function:ctrg")
    assert based.returncode == 0, based.stderr
    assert parse_frame(bytes.fromhex(based.stdout.replace(" ", "").strip())).words == (0x00A0,)
    assert "base word 0x00A8" in based.stderr
    every = regmap("frame", IDM, "write", "di3_function=function:ctrg,normally_closed:1")
    assert parse_frame(bytes.fromhex(every.stdout.replace(" ", "").strip())).words == (0x00A0,)
    assert "bits no field describes are 0" in every.stderr
    help_text = regmap("frame", "--help").stdout + regmap("write", "--help").stdout
    assert "field:value,field:value" in help_text


# -- 4. two values for one word ------------------------------------------------------------


def test_the_issues_conflicting_command_prints_nothing() -> None:
    result = regmap("frame", IDM, "write", "0x6201=0", "0x6202=10000", "--raw")
    one_line_error(result, ExitCode.USAGE, "0x6202")
    assert result.stdout == ""


@pytest.mark.parametrize(
    "items",
    [
        ("--words", "0x6201=0,0", "0x6202=10000"),
        ("pr_path_0_position=0", "Pr9.01=5"),
        ("Pr4.03=0x28", "Pr4.03=0x29", "--raw"),
    ],
)
def test_two_values_for_one_word_name_both_arguments(items: tuple[str, ...]) -> None:
    result = regmap("frame", IDM, "write", *items)
    args = [i for i in items if not i.startswith("--")]
    one_line_error(result, ExitCode.USAGE, *[repr(a) for a in args], "both set the word")
    assert result.stdout == ""


# -- 5. the word order of a drive whose word-order register changed ------------------------


def test_word_order_auto_reads_the_drive_and_a_wrong_order_is_marked(simulator: SimulatorFactory) -> None:
    sim = simulator(ROOT / C630S)
    assert sim.port is not None
    tcp = ["--tcp", f"127.0.0.1:{sim.port}"]
    assert regmap("write", C630S, "P0C-26=high_first", *tcp).returncode == 0
    auto = regmap("read", C630S, "P05-02", *tcp)
    assert auto.returncode == 0, auto.stderr
    assert auto.stdout.strip() == "P05-02 pulses_per_revolution = 10000 P/r"
    wrong = regmap("read", C630S, "P05-02", "--word-order", "low_first", "--json", *tcp)
    row = json.loads(wrong.stdout)[0]
    assert row["raw"] == 655360000 and row["in_range"] is False
    assert "OUTSIDE the map's range" in row["text"]
    write = regmap("write", C630S, "P05-02=20000", *tcp)
    assert write.returncode == 0, write.stderr
    assert "20000 P/r  (verified)" in write.stdout
    fixed = regmap("read", IDM, "peak_current", "--word-order", "low_first", *tcp)
    one_line_error(fixed, ExitCode.USAGE, "has no word-order register")


# -- word-level frames, as the manuals print them ------------------------------------------


@pytest.mark.parametrize("map_path", MAPS + FIXTURES, ids=lambda p: p.stem)
def test_frame_words_expresses_every_request_a_manual_prints(map_path: Path) -> None:
    """Every request example, rebuilt from its address and words (bits) in its own space, as mbpoll's -t would send it."""
    device = load_map(map_path)
    checked = 0
    for example in device.examples:
        if example.direction != "request":
            continue
        frame = parse_frame(example.wire_frame, "request")
        if not frame.crc_valid or frame.address is None or frame.space is None:
            continue
        if frame.function not in device.transport.function_codes:
            continue  # printed to show the exception a device answers to it (iDM-RS 5.4.1's 0x02)
        bits = SPACES[frame.space].bits
        t = device.transport
        if frame.kind == "read_request" and frame.count is not None and frame.count <= (t.max_read_coils if bits else t.max_read_registers):
            built = read_words_frame(device, f"0x{frame.address:04X}", frame.count, frame.slave, frame.space)
        elif frame.kind in ("write_single", "write_multiple_request") and len(carried(frame)) <= (
            t.max_write_coils if bits else t.max_write_registers
        ):
            if frame.kind == "write_multiple_request" and len(carried(frame)) == 1:
                continue  # a one-word 0x10: mbpoll would send 0x06 for it too
            words = ",".join(str(w) if bits else f"0x{w:04X}" for w in carried(frame))
            [built] = (
                write_words_frames(device, [f"0x{frame.address:04X}={words}"], frame.slave, frame.space)
                if frame.slave != device.transport.broadcast_id
                else [example.wire_frame]
            )
        else:
            continue
        assert to_hex(built) == to_hex(example.wire_frame), example.id
        checked += 1
    assert checked > 0


def test_frame_words_cli_and_count_help() -> None:
    assert regmap("frame", IDM, "write", "--words", "0x6209=0xFFFC").stdout.strip() == "01 06 62 09 FF FC 07 C1"
    assert regmap("frame", IDM, "write", "--words", "0x620A=0xF2C0").stdout.strip() == "01 06 62 0A F2 C0 F3 40"
    assert regmap("frame", C630S, "read", "--words", "0x0B11", "2").stdout.strip() == "01 03 0B 11 00 02 96 2A"
    assert regmap("frame", IDM, "read", "--words", "0x5000", "2").returncode == 0  # undocumented: still a frame
    one_line_error(regmap("frame", IDM, "read", "--words", "0x0191", "48"), ExitCode.USAGE, "at most 47")
    assert "COUNT of the map's readable registers" in regmap("frame", "--help").stdout


# -- decoding captures ---------------------------------------------------------------------


def test_decode_a_read_response_without_its_request_shows_every_word() -> None:
    result = regmap("decode", IDM, to_hex(with_crc(bytes.fromhex("010304FFFCF2C0"))))
    assert result.returncode == 0, result.stdout + result.stderr
    assert "word 0: 0xFFFC = 65532 unsigned, -4 signed" in result.stdout
    assert "word 1: 0xF2C0 = 62144 unsigned, -3392 signed" in result.stdout
    assert "could be a read from 0x6006 Pr8.06 positive_soft_limit" in result.stdout
    edge = regmap("decode", IDM, to_hex(with_crc(bytes.fromhex("0103028000"))))
    assert "word 0: 0x8000 = 32768 unsigned, -32768 signed" in edge.stdout


def test_decode_a_response_with_one_junk_byte_is_not_a_request_for_5689_registers() -> None:
    result = regmap("decode", IDM, "01 03 02 00 16 39 8A 39")
    assert result.returncode == ExitCode.BAD_FRAME
    assert "read response" in result.stdout and "5689" not in result.stdout
    assert "trailing junk" in result.stdout


@pytest.mark.parametrize(
    ("frame", "problem"),
    [
        ("01 03 04 00 16", "byte count says 4"),
        ("01 03 01 91 00 7E", "outside Modbus's 1..125"),
        ("01 03 01 91 00 30", "limit of 47 per read"),
    ],
)
def test_decode_problems_exit_non_zero(frame: str, problem: str) -> None:
    result = regmap("decode", IDM, to_hex(with_crc(bytes.fromhex(frame.replace(" ", "")))))
    assert result.returncode == ExitCode.BAD_FRAME, result.stdout
    assert problem in result.stdout


def test_decode_capture_formats_stdin_and_bad_lines() -> None:
    capture = "\n".join(
        [
            "12:00:00.001 TX: 01 03 01 91 00 01 D4 1B",
            "[2024-05-01 12:00:00.002] RX: 01 03 02 00 16 39 8A",
            "TX> 01 03 01 BC 00 06 05 D0",
            "2024-05-01T12:00:00.003Z RX 01 03 0C 00 00 00 04 00 00 00 01 00 00 00 04 9D B3",
            "12:00:01.000 TX: this is no frame",
            "RX 01 83 08 40 F6",
        ]
    )
    result = subprocess.run(
        [sys.executable, "-m", "regmap", "decode", IDM, "--file", "-", "--json"],
        cwd=ROOT,
        input=capture,
        capture_output=True,
        text=True,
        check=False,
    )
    assert result.returncode == ExitCode.BAD_FRAME
    frames = json.loads(result.stdout)
    assert [f["line"] for f in frames] == [1, 2, 3, 4, 5, 6]
    assert frames[4]["ok"] is False and "not hex bytes" in frames[4]["error"]
    assert {v["param"]: v["value"] for v in frames[1]["values"]} == {"Pr5.00": 2.2}
    assert frames[1]["values"][0]["address"] == 0x0191 and frames[1]["values"][0]["address_hex"] == "0x0191"
    assert "-:5:" in result.stderr and "not hex bytes" in result.stderr


# -- user mistakes are never internal errors -----------------------------------------------


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (("read", IDM, "peak_current", "--slave", "0", "--tcp", "127.0.0.1:1"), "cannot read"),
        (("dump", IDM, "--slave", "0", "--tcp", "127.0.0.1:1"), "cannot read"),
        (("read", IDM, "peak_current", "--timeout", "-1", "--tcp", "127.0.0.1:1"), "--timeout"),
        (("read", IDM, "peak_current", "--retries", "-3", "--tcp", "127.0.0.1:1"), "--retries"),
        (("generate", "--out", "README.md"), "not a directory"),
        (("generate", "--out", "/nonexistent/dir/out"), "does not exist"),
        (("frame", IDM, "read", "peak_curent"), "did you mean peak_current?"),
        (("frame", IDM, "command", "save_all_parameter"), "did you mean save_all_parameters?"),
    ],
)
def test_user_mistakes_are_one_line(args: tuple[str, ...], needle: str) -> None:
    result = regmap(*args)
    assert result.returncode == ExitCode.USAGE, result.stderr
    assert needle in result.stderr
    assert "Traceback" not in result.stderr and "internal error" not in result.stderr


def test_a_terminal_that_cannot_show_chinese() -> None:
    result = regmap("show", IDM, "Pr5.00", env={**os.environ, "PYTHONIOENCODING": "ascii"})
    assert result.returncode == 0, result.stderr
    assert "\\u" in result.stdout


def test_options_anywhere_and_subcommand_usage() -> None:
    assert regmap("frame", IDM, "write", "--raw", "0x0191=20").stdout.strip() == "01 06 01 91 00 14 D9 D4"
    assert regmap("decode", IDM, "--json", "01", "03", "01", "91", "00", "01", "D4", "1B").returncode == 0
    bad = regmap("frame", IDM, "fly")
    assert bad.returncode == ExitCode.USAGE and bad.stderr.startswith("usage: regmap frame")


def test_selectors_are_case_insensitive() -> None:
    expected = "01 03 01 91 00 01 D4 1B"
    for selector in ("PEAK_CURRENT", "pr5.00", "0191h"):
        assert regmap("frame", IDM, "read", selector).stdout.strip() == expected, selector


def test_a_missing_map_is_the_same_code_everywhere() -> None:
    for args in (("validate", "maps/nope.yaml"), ("frame", "maps/nope.yaml", "read", "x"), ("show", "maps/nope.yaml")):
        assert regmap(*args).returncode == ExitCode.INVALID_MAP, args


def test_every_subcommand_has_a_description_and_examples() -> None:
    from regmap.cli import SUBCOMMANDS

    for name in SUBCOMMANDS:
        text = regmap(name, "--help").stdout
        assert "usage: regmap " + name in text, name
        assert "examples:" in text, name


# -- bus errors say what happened ----------------------------------------------------------


@pytest.mark.parametrize(
    ("fault", "needle"),
    [("no_answer", "no answer from slave 1"), ("bad_crc", "CRC"), ("wrong_slave", "slave 2"), ("exception", "exception 0x04")],
)
def test_bus_errors_are_told_apart(simulator: SimulatorFactory, fault: str, needle: str) -> None:
    sim = simulator(ROOT / IDM, "--fault", fault, "--rtu-over-tcp")
    assert sim.port is not None
    result = regmap("read", IDM, "peak_current", "--tcp", f"127.0.0.1:{sim.port}", "--rtu-over-tcp", "--timeout", "0.3", "--retries", "0")
    one_line_error(result, ExitCode.BUS, needle)
    assert result.stderr.startswith("regmap read:")


def test_a_failing_multi_register_write_says_what_went_through(simulator: SimulatorFactory) -> None:
    sim = simulator(ROOT / IDM, "--fault", "exception", "--fault-after", "1")
    assert sim.port is not None
    result = regmap("write", IDM, "Pr5.00=1.5", "Pr0.01=closed_loop", "--tcp", f"127.0.0.1:{sim.port}")
    one_line_error(result, ExitCode.BUS, "failed", "written before it:")


def test_a_dead_port_gives_the_os_reason() -> None:
    result = regmap("read", IDM, "peak_current", "--tcp", "127.0.0.1:1")
    one_line_error(result, ExitCode.BUS, "Connection refused")
    serial = regmap("read", IDM, "peak_current", "--serial", "/dev/no-such-port")
    one_line_error(serial, ExitCode.BUS, "No such file or directory")


def test_ctrl_c_during_dump_prints_what_was_read(simulator: SimulatorFactory) -> None:
    sim = simulator(ROOT / IDM, "--fault", "delay", "--fault-after", "3", "--fault-delay", "20")
    assert sim.port is not None
    process = subprocess.Popen(
        [sys.executable, "-m", "regmap", "dump", IDM, "--tcp", f"127.0.0.1:{sim.port}", "--timeout", "30", "--json"],
        cwd=ROOT,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    time.sleep(3)
    process.send_signal(signal.SIGINT)
    out, err = process.communicate(timeout=30)
    assert process.returncode == ExitCode.INTERRUPTED, err
    rows = json.loads(out)
    assert rows and "stopped after" in err and "not read:" in err


# -- output formats ------------------------------------------------------------------------


def test_read_output_formats(simulator: SimulatorFactory) -> None:
    sim = simulator(ROOT / IDM)
    assert sim.port is not None
    tcp = ["--tcp", f"127.0.0.1:{sim.port}"]
    text = regmap("read", IDM, "run_status", "peak_current", "di1_function", *tcp)
    assert [line.split(" = ")[0] for line in text.stdout.splitlines()] == ["run_status", "Pr5.00 peak_current", "Pr4.02 di1_function"]
    rows = json.loads(regmap("read", IDM, "di1_function", "peak_current", "--json", *tcp).stdout)
    assert [r["register"] for r in rows] == ["di1_function", "peak_current"]
    assert rows[0]["address"] == 0x0145 and rows[0]["fields"] == {"function": "servo_on", "normally_closed": 1}
    csv_out = regmap("read", IDM, "di1_function", "peak_current", "--csv", *tcp).stdout.splitlines()
    assert csv_out[0].endswith(",function,normally_closed")
    assert csv_out[1].startswith("di1_function,Pr4.02,325,0x0145,136,136,") and csv_out[1].endswith(",servo_on,1")


def test_show_and_command(simulator: SimulatorFactory) -> None:
    shown = regmap("show", IDM)
    assert shown.returncode == 0 and "0x0191 Pr5.00" in shown.stdout and "commands (14):" in shown.stdout
    sim = simulator(ROOT / IDM)
    assert sim.port is not None
    sent = regmap("command", IDM, "save_all_parameters", "--tcp", f"127.0.0.1:{sim.port}")
    assert sent.returncode == 0, sent.stderr
    assert sent.stdout.strip() == "sent save_all_parameters: 0x2211 to control_word (0x1801)"


# -- validate runs every back end's checks -------------------------------------------------


def test_validate_reports_a_back_end_clash_at_its_line(tmp_path: Path) -> None:
    text = (ROOT / IDM).read_text(encoding="utf-8").replace("{name: zero_speed_threshold,", "{name: all,", 1)
    assert "{name: all," in text
    bad = tmp_path / "idm_rs.yaml"
    bad.write_text(text, encoding="utf-8")
    line = next(i for i, row in enumerate(text.splitlines(), 1) if "{name: all," in row)
    result = regmap("validate", str(bad))
    assert result.returncode == ExitCode.INVALID_MAP
    assert f"{bad}:{line}:" in result.stderr and "'read_all' would shadow" in result.stderr


def test_a_broadcast_write_needs_no_answer_and_a_broadcast_cannot_read_modify_write(simulator: SimulatorFactory) -> None:
    sim = simulator(ROOT / IDM)
    assert sim.port is not None
    tcp = ["--tcp", f"127.0.0.1:{sim.port}"]
    sent = regmap("write", IDM, "Pr5.00=1.1", "--slave", "0", *tcp)
    assert sent.returncode == 0, sent.stderr
    assert sent.stdout.strip() == "wrote 1 value(s) in 1 request(s)"
    assert "1.1 A" in regmap("read", IDM, "Pr5.00", *tcp).stdout
    partial = regmap("write", IDM, "di3_function=function:ctrg", "--slave", "0", *tcp)
    one_line_error(partial, ExitCode.USAGE, "broadcast")


def test_a_port_that_refuses_the_line_settings_says_so(monkeypatch: pytest.MonkeyPatch) -> None:
    """A Linux pseudo-terminal refuses even parity with termios.error (no OSError): the message names the settings."""
    import termios

    import serial

    from regmap.frontend import load_map
    from regmap.tools.link import Link
    from regmap.tools.live import _why_unreachable

    def refuse(*args: object, **kwargs: object) -> None:
        raise termios.error(22, "Invalid argument")

    monkeypatch.setattr(serial, "Serial", refuse)
    text = _why_unreachable(Link(serial="/dev/pts/9"), load_map(ROOT / "tests" / "maps" / "fixtures" / "remote_io.yaml"))
    assert (
        text
        == "the port refuses 19200 baud, even parity, 1 stop bit(s): Invalid argument (a pseudo-terminal may refuse parity: try --parity none)"
    )


# -- write --words on a live bus ---------------------------------------------------------------


def _words_refusals(path: Path) -> list[tuple[str, str, list[int]]]:
    """(--words item, what the error must say, addresses to watch) for each way raw words could break the map's rules,
    each taken from the map: a destructive command's value, a read-only register, a value its enum lacks, half of a
    32-bit register, a pair's high word alone and a pair's high word that is not the sign extension."""
    device = load_map(path)
    holding = [r for r in device.registers if r.space == "holding"]
    destructive = next(c for c in device.commands if c.destructive and c.argument is None)
    read_only = next(r for r in holding if not r.access.writable and not r.paired and r.words == 1)
    enum_reg = next(r for r in holding if r.access.writable and r.enum is not None and not r.bitfields and not r.paired)
    assert enum_reg.enum is not None
    missing = max(m.value for m in enum_reg.enum.members) + 1
    wide = next(r for r in holding if r.access.writable and r.words == 2)
    pair = next(r for r in holding if r.access.writable and r.paired and r.type.value == "u16" and r.scale == 1 and r.min is not None)
    low = int(pair.min or 0)  # a value the low word may hold: only the high word is wrong
    return [
        (
            f"0x{destructive.register.address:04X}=0x{destructive.value:04X}",
            f"{destructive.name} is destructive",
            [destructive.register.address],
        ),
        (f"0x{read_only.address:04X}=1", f"{read_only.label} is read-only", [read_only.address]),
        (f"0x{enum_reg.address:04X}={missing}", f"{missing} is not one of", [enum_reg.address]),
        (f"0x{wide.address:04X}=0", f"writes 1 of the 2 word(s) of {wide.label}", [wide.address, wide.address + 1]),
        (f"0x{pair.first_address:04X}=0", f"the unused high word of {pair.label}; write it together", [pair.first_address, pair.address]),
        (
            f"0x{pair.first_address:04X}=0xFFFF,{low}",
            "sign extension of its low word: 0x0000, not 0xFFFF",
            [pair.first_address, pair.address],
        ),
    ]


def test_write_words_sends_nothing_the_map_forbids_at_a_register_it_lists(simulator: SimulatorFactory, tmp_path: Path) -> None:
    """--words reaches any address, but words landing on a listed register pass the register's checks, as a named
    write would: each refusal is one line (exit 2) and the simulator's request log shows nothing sent; a valid
    write of a pair (high word 0, as the manual's 0x10 frames send it) goes out."""
    log = tmp_path / "requests.log"
    sim = simulator(ROOT / IDM, "--log", str(log))
    assert sim.port is not None
    tcp = ["--tcp", f"127.0.0.1:{sim.port}"]
    for item, needle, _ in _words_refusals(ROOT / IDM):
        one_line_error(regmap("write", IDM, *tcp, "--words", item), ExitCode.USAGE, needle, "nothing was sent")
    assert not log.exists() or "PDU" not in log.read_text(encoding="utf-8"), "a refused --words write reached the drive"
    device = load_map(ROOT / IDM)
    pair = next(r for r in device.registers if r.access.writable and r.paired and r.type.value == "u16" and r.scale == 1 and r.max)
    allowed = int(pair.max or 0)
    result = regmap("write", IDM, *tcp, "--words", f"0x{pair.first_address:04X}=0,{allowed}")
    assert result.returncode == 0, result.stderr
    idm = client_module("idm_rs")
    with idm.IdmRs.tcp("127.0.0.1", sim.port, timeout=2) as drive:
        assert drive.read_raw(pair.address, 1) == [allowed]


def test_frame_words_stays_raw_so_the_manuals_frames_print_as_printed() -> None:
    """Printing bytes sends nothing: `frame --words` builds a destructive command's frame as the manual prints it."""
    device = load_map(ROOT / IDM)
    destructive = next(c for c in device.commands if c.destructive and c.argument is None)
    result = regmap("frame", IDM, "write", "--words", f"0x{destructive.register.address:04X}=0x{destructive.value:04X}")
    assert result.returncode == 0, result.stderr
    assert result.stdout.split()[4:6] == [f"{destructive.value >> 8:02X}", f"{destructive.value & 0xFF:02X}"]


def test_write_words_on_a_drive_whose_word_order_can_change_is_checked_in_the_order_it_reads(simulator: SimulatorFactory) -> None:
    """C630S's 32-bit parameters follow P0C-26: as a named write does, `write --words` reads P0C-26 and checks the
    words in that order before sending (a value in range one way round and not the other goes out only when the drive
    reads it in range); without a drive (the plan) the check waits for the order."""
    device = load_map(ROOT / C630S)
    reg = next(r for r in device.registers if r.param == "P05-02")
    control = device.transport.word_order_register
    assert control is not None and reg.words == 2 and not reg.word_order_fixed and reg.max is not None
    small = (int(reg.max) >> 16) + 1  # in range as one word; shifted into the high word it exceeds the maximum
    assert check_word_runs(device, reg.space, [(reg.address, (small, 0))]) is True  # left until the order is read
    with pytest.raises(UsageError, match=r"outside .* \(read high first, the drive's word order\); nothing was sent"):
        check_word_runs(device, reg.space, [(reg.address, (small, 0))], "high_first", order_read=True)
    assert check_word_runs(device, reg.space, [(reg.address, (small, 0))], "low_first", order_read=True) is False
    sim = simulator(ROOT / C630S)
    assert sim.port is not None
    tcp = ["--tcp", f"127.0.0.1:{sim.port}"]
    order = "low_first" if control.register.default == control.low_first else "high_first"
    in_order = (small, 0) if order == "low_first" else (0, small)
    reversed_words = in_order[::-1]
    refused = regmap("write", C630S, *tcp, "--words", f"0x{reg.address:04X}={reversed_words[0]},{reversed_words[1]}")
    one_line_error(refused, ExitCode.USAGE, f"(read {order.replace('_', ' ')}, the drive's word order)", "nothing was sent")
    sent = regmap("write", C630S, *tcp, "--words", f"0x{reg.address:04X}={in_order[0]},{in_order[1]}")
    assert sent.returncode == 0, sent.stderr
    shown = regmap("read", C630S, *tcp, reg.param or reg.name)
    assert f"= {small} " in shown.stdout, shown.stdout
