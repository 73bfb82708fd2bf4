"""`regmap decode` on what a field engineer hands it: a request typed beside a response, and capture
files as serial monitors, mbpoll and Windows tools write them (issue #28, item 5)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

from regmap.diagnostics import ExitCode
from regmap_runtime.rtu import crc_bytes, to_hex, with_crc

from conftest import ROOT

IDM = "maps/idm_rs.yaml"
READ_PEAK_CURRENT = "01 03 01 91 00 01 D4 1B"  # manual 4.15
PEAK_CURRENT_IS_2_2_A = "01 03 02 00 16 39 8A"


def regmap(*args: str, stdin: bytes | None = None) -> subprocess.CompletedProcess[str]:
    result = subprocess.run([sys.executable, "-m", "regmap", *args], cwd=ROOT, input=stdin, capture_output=True, check=False)
    return subprocess.CompletedProcess(result.args, result.returncode, result.stdout.decode(), result.stderr.decode())


def test_a_request_with_a_bad_crc_makes_the_answer_a_bad_frame() -> None:
    body = bytes.fromhex("010301920001")
    result = regmap("decode", IDM, PEAK_CURRENT_IS_2_2_A, "--request", to_hex(body) + " 00 00")
    assert result.returncode == ExitCode.BAD_FRAME, result.stdout
    problems = [line.strip() for line in result.stdout.splitlines() if line.strip().startswith("problem:")]
    assert problems == [f"problem: --request {to_hex(body)} 00 00: CRC mismatch: frame carries 00 00, expected {to_hex(crc_bytes(body))}"]
    good = regmap("decode", IDM, PEAK_CURRENT_IS_2_2_A, "--request", to_hex(with_crc(body)))
    assert good.returncode == ExitCode.OK, good.stdout


def test_a_malformed_request_makes_the_answer_a_bad_frame() -> None:
    swapped = regmap("decode", IDM, PEAK_CURRENT_IS_2_2_A, "--request", PEAK_CURRENT_IS_2_2_A)
    assert swapped.returncode == ExitCode.BAD_FRAME
    assert "read request carries 3 data bytes, expected 4" in swapped.stdout
    exception = regmap("decode", IDM, PEAK_CURRENT_IS_2_2_A, "--request", "01 83 02 C0 F1", "--json")
    assert exception.returncode == ExitCode.BAD_FRAME
    [decoded] = json.loads(exception.stdout)
    assert decoded["ok"] is False
    assert decoded["problems"] == ["--request 01 83 02 C0 F1: function 0x83 is no request"]


def test_an_empty_capture_says_so_in_one_line(tmp_path: Path) -> None:
    for name, content in (("empty.log", ""), ("comments.log", "# nothing was on the bus\n\n   \n")):
        capture = tmp_path / name
        capture.write_text(content, encoding="utf-8")
        result = regmap("decode", IDM, "--file", str(capture))
        assert (result.returncode, result.stdout, result.stderr) == (ExitCode.BAD_FRAME, "", f"regmap decode: {capture}: no frames\n")
        as_json = regmap("decode", IDM, "--file", str(capture), "--json")
        no_frames = {"line": None, "text": "", "error": "no frames", "ok": False}
        assert (as_json.returncode, json.loads(as_json.stdout)) == (ExitCode.BAD_FRAME, [no_frames])


def test_a_line_that_is_not_utf8_names_the_file_line_and_byte_offset(tmp_path: Path) -> None:
    capture = tmp_path / "cp1252.log"
    first = f"TX {READ_PEAK_CURRENT}   # Stromst\xe4rke\r\n".encode("cp1252")  # a Windows comment: its frame still decodes
    second = b"RX 01 03 02 \xff\xfe 39 8A\r\n"
    capture.write_bytes(first + second)
    result = regmap("decode", IDM, "--file", str(capture))
    assert result.returncode == ExitCode.BAD_FRAME
    assert "line 1: " + READ_PEAK_CURRENT in result.stdout
    offset = len(first) + second.index(b"\xff")
    assert result.stderr == f"regmap decode: {capture}:2: not UTF-8 text: byte 0xFF at byte offset {offset}\n"


def test_a_powershell_capture_in_utf16_decodes(tmp_path: Path) -> None:
    capture = tmp_path / "powershell.log"
    capture.write_bytes(f"12:00:00.001 TX: {READ_PEAK_CURRENT}\r\n12:00:00.020 RX: {PEAK_CURRENT_IS_2_2_A}\r\n".encode("utf-16"))
    result = regmap("decode", IDM, "--file", str(capture))
    assert result.returncode == ExitCode.OK, result.stderr
    assert "0x0191 Pr5.00 peak_current = 2.2 A (raw 22)" in result.stdout


def test_a_binary_capture_is_refused_with_a_hint(tmp_path: Path) -> None:
    capture = tmp_path / "bus.bin"
    capture.write_bytes(bytes.fromhex(READ_PEAK_CURRENT.replace(" ", "")))
    result = regmap("decode", IDM, "--file", str(capture))
    assert result.returncode == ExitCode.USAGE
    assert result.stdout == ""
    assert result.stderr == (
        f"regmap decode: error: {capture}: a binary file, not a text capture (byte offset 4 is 0x00); "
        "decode wants text, one frame a line in hex, as serial monitors and `mbpoll -v` print them\n"
    )


def test_json_reports_every_line_the_bad_ones_with_an_error() -> None:
    capture = f"TX {READ_PEAK_CURRENT}\nthis is no frame\nRX {PEAK_CURRENT_IS_2_2_A}\n01 03\n".encode()
    result = regmap("decode", IDM, "--file", "-", "--json", stdin=capture)
    assert result.returncode == ExitCode.BAD_FRAME
    entries = json.loads(result.stdout)
    assert [(e["line"], e["ok"], "error" in e) for e in entries] == [(1, True, False), (2, False, True), (3, True, False), (4, False, True)]
    assert entries[1] == {
        "line": 2,
        "text": "this is no frame",
        "error": "not hex bytes: 'this' (write bytes as two hex digits each)",
        "ok": False,
    }
    assert entries[3]["error"].startswith("frame too short")


def test_mbpoll_verbose_frames_decode_as_request_and_answer() -> None:
    # `mbpoll -v -m rtu -a 1 -b 19200 -P even -r 402 -c 1 -1` against `regmap simulate`: libmodbus's debug lines.
    capture = b"[01][03][01][91][00][01][D4][1B]\n<01><03><02><00><16><39><8A>\n"
    result = regmap("decode", IDM, "--file", "-", stdin=capture)
    assert result.returncode == ExitCode.OK, result.stderr
    assert "(request), CRC D4 1B ok" in result.stdout
    assert "0x0191 Pr5.00 peak_current = 2.2 A (raw 22)" in result.stdout


def test_a_request_beside_a_capture_is_refused_not_ignored(tmp_path: Path) -> None:
    capture = tmp_path / "bus.log"
    capture.write_text(f"RX {PEAK_CURRENT_IS_2_2_A}\n", encoding="utf-8")
    result = regmap("decode", IDM, "--file", str(capture), "--request", READ_PEAK_CURRENT)
    assert (result.returncode, result.stdout) == (ExitCode.USAGE, "")
    assert result.stderr == (
        "regmap decode: error: --request goes with one HEX frame; a capture pairs each response with the request before it\n"
    )


def test_pymodbus_frame_logging_decodes() -> None:
    # pymodbus 3.16 at DEBUG (pymodbus_apply_logging_config) against `regmap simulate`: its frame log
    # (`send:`, and `recv: ... extra data:` as 2.x spelled it in capitals) and what it received (`Processing:`).
    capture = (
        b"2026-12-02 00:57:34,880 DEBUG logging:103 send: 0x1 0x3 0x1 0x91 0x0 0x1 0xd4 0x1b\n"
        b"2026-12-02 00:57:34,887 DEBUG base:76 Processing: 0x1 0x3 0x2 0x0 0x16 0x39 0x8a\n"
        b"DEBUG:pymodbus.logging:SEND: 0x1 0x3 0x1 0x91 0x0 0x1 0xd4 0x1b\n"
        b"DEBUG:pymodbus.logging:RECV: 0x1 0x3 0x2 0x0 0x16 0x39 0x8a extra data: \n"
    )
    result = regmap("decode", IDM, "--file", "-", "--json", stdin=capture)
    assert result.returncode == ExitCode.OK, result.stderr
    entries = json.loads(result.stdout)
    assert [(e["hex"], e["direction"]) for e in entries] == [(READ_PEAK_CURRENT, "request"), (PEAK_CURRENT_IS_2_2_A, "response")] * 2
    assert [[v["value"] for v in e["values"]] for e in entries[1::2]] == [[2.2], [2.2]]
