"""`regmap frame` and `regmap decode` as a field engineer uses them, bad input included."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import ROOT

IDM = "maps/idm_rs.yaml"
C630S = "maps/c630s.yaml"
ID243 = "maps/id243pro.yaml"


def regmap(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "regmap", *args], cwd=ROOT, capture_output=True, text=True, check=False)


@pytest.mark.parametrize(
    ("args", "expected"),
    [
        # 4.15: peak current 1.5 A by name, by parameter id and by address (hex and decimal).
        ((IDM, "write", "peak_current=1.5"), "01 06 01 91 00 0F 99 DF"),
        ((IDM, "write", "Pr5.00=1.5"), "01 06 01 91 00 0F 99 DF"),
        ((IDM, "write", "0x0191=1.5"), "01 06 01 91 00 0F 99 DF"),
        ((IDM, "write", "401=1.5"), "01 06 01 91 00 0F 99 DF"),
        ((IDM, "write", "Pr5.00=15", "--raw"), "01 06 01 91 00 0F 99 DF"),
        ((IDM, "read", "Pr5.00"), "01 03 01 91 00 01 D4 1B"),
        # 5.2.1: three parameters from the high word of the first pair.
        ((IDM, "read", "Pr5.22", "3"), "01 03 01 BC 00 06 05 D0"),
        # 5.2.3: two contiguous pairs become one 0x10 frame; enum member names work.
        ((IDM, "write", "Pr4.03=0x28", "Pr4.04=0x29", "--raw"), "01 10 01 46 00 04 08 00 00 00 28 00 00 00 29 1C 14"),
        ((IDM, "command", "save_all_parameters"), "01 06 18 01 22 11 06 06"),
        # C630S 9.2.3: a 32-bit value, low word first.
        ((C630S, "write", "P11-12=80000"), "01 10 11 0C 00 02 04 38 80 00 01 FE E2"),
        ((C630S, "read", "P0B-17"), "01 03 0B 11 00 02 96 2A"),
        # iD243pro appendix: decimal addresses written as the manual's four-digit ids.
        ((ID243, "read", "0302"), "01 03 01 2E 00 01 E5 FF"),
        ((ID243, "write", "--words", "300=1"), "01 06 01 2C 00 01 88 3F"),
    ],
)
def test_frame_builds_the_manual_frames(args: tuple[str, ...], expected: str) -> None:
    result = regmap("frame", *args)
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip() == expected


def test_frame_write_enum_member_by_name() -> None:
    result = regmap("frame", IDM, "write", "control_word=save_all_parameters")
    assert result.stdout.strip() == "01 06 18 01 22 11 06 06", result.stderr


def test_frame_write_bitfields_by_name() -> None:
    result = regmap(
        "frame", IDM, "write", "Pr4.03=function:path_address_0,normally_closed:0", "Pr4.04=function:path_address_1,normally_closed:0"
    )
    assert result.stdout.strip() == "01 10 01 46 00 04 08 00 00 00 28 00 00 00 29 1C 14", result.stderr


def test_frame_slave_option() -> None:
    result = regmap("frame", IDM, "read", "Pr5.00", "--slave", "2")
    assert result.stdout.split()[0] == "02"


def test_decode_pairs_a_capture(tmp_path: Path) -> None:
    capture = tmp_path / "bus.log"
    capture.write_text(
        "# 5.2.1\nTX 01 03 01 BC 00 06 05 D0\nRX 01 03 0C 00 00 00 04 00 00 00 01 00 00 00 04 9D B3\n01 83 08 40 F6\n",
        encoding="utf-8",
    )
    result = regmap("decode", IDM, "--file", str(capture), "--json")
    assert result.returncode == 0, result.stderr
    frames = json.loads(result.stdout)
    assert [f["direction"] for f in frames] == ["request", "response", "response"]
    values = {v["param"]: v["raw"] for v in frames[1]["values"] if v["raw"] is not None}
    assert values == {"Pr5.22": 4, "Pr5.23": 1, "Pr5.24": 4}
    assert frames[2]["exception_code"] == 8
    assert "CRC" in frames[2]["exception"]


def test_decode_text_names_registers_units_and_bitfields() -> None:
    result = regmap("decode", IDM, "01", "03", "02", "00", "16", "39", "8A", "--request", "01 03 01 91 00 01 D4 1B")
    assert result.returncode == 0
    assert "Pr5.00 peak_current = 2.2 A (raw 22)" in result.stdout
    status = regmap("decode", IDM, "01 03 02 00 13 F9 81", "--request", "01 03 10 03 00 01 70 CA")
    assert "fault=1" in status.stdout and "enabled=1" in status.stdout, status.stdout + status.stderr


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (("decode", IDM, "01 03 zz"), "not hex bytes: 'zz'"),
        (("decode", IDM, "01 03"), "frame too short"),
        (("decode", IDM), "give the frame as HEX"),
        (("frame", IDM, "read", "no_such_register"), "unknown register 'no_such_register'"),
        (("frame", IDM, "write", "peak_current=9"), "peak_current (Pr5.00): 9 A is outside 0..8 A"),
        (("frame", IDM, "write", "peak_current=1.55"), "resolution 0.1 A"),
        (("frame", IDM, "write", "peak_current"), "write wants SELECTOR=VALUE"),
        (("frame", IDM, "write", "run_status=1", "--raw"), "is read-only"),
        (("frame", IDM, "read", "Pr5.00", "--slave", "99"), "--slave 99 is outside 1..31"),
        (("frame", IDM, "command", "fly"), "unknown command 'fly'"),
        (("frame", IDM, "command", "trigger_path", "16"), "path in 0..15"),
        (("frame", "maps/nope.yaml", "read", "x"), "cannot read the map"),
    ],
)
def test_bad_input_is_one_line_and_non_zero(args: tuple[str, ...], message: str) -> None:
    result = regmap(*args)
    assert result.returncode != 0
    assert message in result.stderr
    assert len(result.stderr.strip().splitlines()) == 1, result.stderr
    assert "Traceback" not in result.stderr + result.stdout


def test_decode_reports_a_crc_mismatch_with_exit_3() -> None:
    result = regmap("decode", ID243, "01 10 01 38 00 02 B0 3B")
    assert result.returncode == 3
    assert "CRC B0 3B MISMATCH" in result.stdout
    assert "expected C1 F9" in result.stdout
