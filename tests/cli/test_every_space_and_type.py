"""`regmap frame`, `decode`, `show`, `read`, `write` and `dump` for every data space and type.

Expected frames are built independently of regmap: the Modbus spec's worked examples as printed
(tests/maps/fixtures/remote_io.yaml), register words from pymodbus's `convert_to_registers` and
`struct`, CRCs from pymodbus's RTU framer. The live commands run against `regmap simulate`, and
what they wrote is read back with pymodbus.
"""

from __future__ import annotations

import json
import math
import struct
import subprocess
import sys
from pathlib import Path

import pytest
from pymodbus.client import ModbusTcpClient
from pymodbus.client.mixin import ModbusClientMixin
from pymodbus.framer import FramerRTU

from regmap.backends.markdown.frames import example_view
from regmap.backends.markdown.views import Context
from regmap.frontend import load_map

from conftest import ROOT, SimulatorFactory

FIXTURES = ROOT / "tests" / "maps" / "fixtures"
REMOTE_IO = str(FIXTURES / "remote_io.yaml")
POWER_METER = str(FIXTURES / "power_meter.yaml")
SWAPPED = str(FIXTURES / "swapped_gated.yaml")
IDM = "maps/idm_rs.yaml"
DATATYPE = ModbusClientMixin.DATATYPE


def regmap(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "regmap", *args], cwd=ROOT, capture_output=True, text=True, check=False, timeout=60)


def rtu(*parts: bytes | int) -> str:
    """An RTU frame from its pieces (ints are single bytes), with pymodbus's CRC, as `frame` prints it."""
    body = b"".join(bytes([p]) if isinstance(p, int) else p for p in parts)
    return " ".join(f"{b:02X}" for b in body + FramerRTU.compute_CRC(body).to_bytes(2, "big"))


def words(registers: list[int]) -> bytes:
    return struct.pack(f">{len(registers)}H", *registers)


def one_line_error(result: subprocess.CompletedProcess[str], needle: str) -> None:
    assert result.returncode == 2, (result.returncode, result.stdout, result.stderr)
    assert result.stdout == ""
    assert len(result.stderr.strip().splitlines()) == 1 and "internal error" not in result.stderr, result.stderr
    assert needle in result.stderr, result.stderr


# -- frame -----------------------------------------------------------------------------------

SPEC_ON_OFF = ["on", "off", "on", "on", "off", "off", "on", "on", "on", "off"]  # §6.11: coils 20-29 = CD 01


@pytest.mark.parametrize(
    ("args", "expected"),
    [
        # The spec's own frames (§6.1, §6.2, §6.4, §6.5, §6.11), by name, by address and with mbpoll's -t numbers.
        ((REMOTE_IO, "read", "relay_20_on", "19"), "01 01 00 13 00 13 8C 02"),
        ((REMOTE_IO, "read", "input_197_active", "22"), "01 02 00 C4 00 16 B8 39"),
        ((REMOTE_IO, "read", "analog_in_9"), "01 04 00 08 00 01 B0 08"),
        ((REMOTE_IO, "write", "alarm_output=on"), "01 05 00 AC FF 00 4C 1B"),
        ((REMOTE_IO, "write", *(f"relay_{20 + i}_on={v}" for i, v in enumerate(SPEC_ON_OFF))), "01 0F 00 13 00 0A 02 CD 01 72 CB"),
        ((REMOTE_IO, "read", "--words", "-t", "0", "0x13", "19"), "01 01 00 13 00 13 8C 02"),
        ((REMOTE_IO, "read", "--words", "-t", "1", "0xC4", "22"), "01 02 00 C4 00 16 B8 39"),
        ((REMOTE_IO, "read", "--words", "--space", "discrete_input", "196", "22"), "01 02 00 C4 00 16 B8 39"),
        ((REMOTE_IO, "read", "--words", "-t", "3", "8", "1"), "01 04 00 08 00 01 B0 08"),
        ((REMOTE_IO, "write", "--words", "-t", "0", "0xAC=1"), "01 05 00 AC FF 00 4C 1B"),
        ((REMOTE_IO, "write", "--words", "-t", "coil", "0x13=1,0,1,1,0,0,1,1,1,0"), "01 0F 00 13 00 0A 02 CD 01 72 CB"),
        ((REMOTE_IO, "write", "--words", "-t", "0", "0x13=1,0,1,1", "0x17=off,off,on,on,on,off"), "01 0F 00 13 00 0A 02 CD 01 72 CB"),
        ((REMOTE_IO, "read", "0xAC"), rtu(1, 1, 0, 0xAC, 0, 1)),
        ((REMOTE_IO, "write", "alarm_output=off"), rtu(1, 5, 0, 0xAC, 0, 0)),
        ((REMOTE_IO, "write", "relay_21_on=true", "relay_20_on=false"), rtu(1, 0x0F, 0, 0x13, 0, 2, 1, 0b10)),
        ((REMOTE_IO, "write", "--raw", "relay_20_on=1"), rtu(1, 5, 0, 0x13, 0xFF, 0)),
        ((REMOTE_IO, "write", "--words", "-t", "0", "0x13=1,0,0,0,0,0,0,0,1"), rtu(1, 0x0F, 0, 0x13, 0, 9, 2, 0x01, 0x01)),
        # Input registers: 0x04, one request per run of documented registers.
        ((POWER_METER, "read", "voltage_l1"), rtu(1, 4, 0, 0, 0, 2)),
        ((POWER_METER, "read", "active_energy"), rtu(1, 4, 0, 0x10, 0, 4)),
        ((POWER_METER, "read", "voltage_l1", "3"), rtu(1, 4, 0, 0, 0, 5)),
        ((POWER_METER, "read", "model_name"), "01 03 01 00 00 08 45 F0"),
        # Floats, strings and byte-swapped words, as pymodbus and struct encode them.
        (
            (POWER_METER, "write", "demand_period=900"),
            rtu(1, 0x10, 0x01, 0x22, 0, 2, 4, words(ModbusClientMixin.convert_to_registers(900.0, DATATYPE.FLOAT32))),
        ),
        ((POWER_METER, "write", "demand_period=60.5"), rtu(1, 0x10, 0x01, 0x22, 0, 2, 4, struct.pack(">f", 60.5))),
        (
            (POWER_METER, "write", "voltage_alarm=250.5"),  # word_order low_first: CDAB
            rtu(1, 0x10, 0x01, 0x24, 0, 2, 4, words(ModbusClientMixin.convert_to_registers(250.5, DATATYPE.FLOAT32, word_order="little"))),
        ),
        (
            (POWER_METER, "write", "--raw", "voltage_alarm=0.1"),
            rtu(1, 0x10, 0x01, 0x24, 0, 2, 4, struct.pack(">f", 0.1)[2:] + struct.pack(">f", 0.1)[:2]),
        ),
        ((POWER_METER, "write", 'meter_label="abc"'), rtu(1, 0x10, 0x01, 0x26, 0, 4, 8, b"abc".ljust(8, b"\0"))),
        ((POWER_METER, "write", "meter_label=abc"), rtu(1, 0x10, 0x01, 0x26, 0, 4, 8, b"abc".ljust(8, b"\0"))),
        ((POWER_METER, "write", "meter_label=a b"), rtu(1, 0x10, 0x01, 0x26, 0, 4, 8, b"a b".ljust(8, b"\0"))),
        ((POWER_METER, "write", 'meter_label=""'), rtu(1, 0x10, 0x01, 0x26, 0, 4, 8, bytes(8))),
        ((POWER_METER, "write", "meter_label=Grüße"), rtu(1, 0x10, 0x01, 0x26, 0, 4, 8, "Grüße".encode().ljust(8, b"\0"))),
        (
            (POWER_METER, "write", "ct_ratio=5", "demand_period=1"),
            rtu(1, 6, 0x01, 0x20, 0, 5) + "\n" + rtu(1, 0x10, 0x01, 0x22, 0, 2, 4, struct.pack(">f", 1.0)),
        ),
        # SW-2: every word's bytes swapped; 32-bit values low word first (DCBA); gain CDAB.
        ((SWAPPED, "write", "speed=-1.5"), rtu(1, 6, 0, 2, struct.pack("<h", -15))),
        ((SWAPPED, "write", "position=305419896"), rtu(1, 0x10, 0, 3, 0, 2, 4, struct.pack("<i", 305419896))),
        ((SWAPPED, "write", "gain=2.5"), rtu(1, 0x10, 0, 5, 0, 2, 4, struct.pack(">f", 2.5)[2:] + struct.pack(">f", 2.5)[:2])),
    ],
)
def test_frame_builds_every_space_and_type(args: tuple[str, ...], expected: str) -> None:
    result = regmap("frame", *args)
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip() == expected


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (
            (POWER_METER, "write", "voltage_l1=230"),
            "voltage_l1 is an input register: input registers are read-only (function 0x04 reads them",
        ),
        ((REMOTE_IO, "write", "input_197_active=on"), "input_197_active is a discrete input: discrete inputs are read-only"),
        ((REMOTE_IO, "write", "--words", "-t", "1", "0xC4=1"), "discrete inputs are read-only: no function writes them"),
        ((REMOTE_IO, "write", "--words", "-t", "3", "8=1"), "input registers are read-only: no function writes them"),
        ((POWER_METER, "write", "model_name=X"), "model_name is read-only"),
        ((REMOTE_IO, "write", "alarm_output=2"), "alarm_output: '2' is not on/off"),
        ((REMOTE_IO, "write", "--words", "-t", "0", "0x13=1,2"), "a coil is 0 or 1 (on/off)"),
        ((REMOTE_IO, "read", "--words", "-t", "0", "0x13", "2001"), "COUNT 2001 is outside 1..2000"),
        ((REMOTE_IO, "read", "--words", "-t", "5", "0x13", "1"), "one of holding, input, coil, discrete_input"),
        ((REMOTE_IO, "read", "0x13", "-t", "4"), "no register at 0x0013 among the holding registers"),
        (
            (POWER_METER, "read", "--words", "-t", "0", "0", "1"),
            "has no function 0x01 (read coils); its map lists 0x03 0x04 0x06 0x08 0x10 0x11 0x17 0x2B",
        ),
        ((POWER_METER, "write", "meter_label=abcdefghi"), "'abcdefghi' is 9 bytes in utf-8; the register holds 8"),
        ((POWER_METER, "write", "demand_period=0.5"), "demand_period: 0.5 s is outside 1..3600 s"),
        ((POWER_METER, "write", "demand_period=nan"), "NaN is not a value"),
        ((POWER_METER, "write", "demand_period=1e400"), "demand_period: 1e400 is beyond any f32 value"),
        ((POWER_METER, "write", "--raw", "demand_period=inf"), "demand_period: inf s is outside 1..3600 s"),
        ((POWER_METER, "write", "--raw", "demand_period=fast"), "demand_period: 'fast' is not a number"),
        ((SWAPPED, "write", "label=AXIS"), "label is read-only"),
        ((SWAPPED, "write", "gain=101"), "gain: 101 is outside 0..100"),
    ],
)
def test_frame_refusals_are_one_line(args: tuple[str, ...], message: str) -> None:
    one_line_error(regmap("frame", *args), message)


def test_an_address_two_spaces_list_needs_the_space(tmp_path: Path) -> None:
    both = tmp_path / "both.yaml"
    text = Path(REMOTE_IO).read_text(encoding="utf-8")
    both.write_text(text.replace("config_108, address: 0x006B", "config_108, address: 0x0013"), encoding="utf-8")
    one_line_error(regmap("frame", str(both), "read", "0x13"), "is the address of holding register config_108, coil relay_20_on")
    assert regmap("frame", str(both), "read", "0x13", "-t", "0").stdout.strip() == "01 01 00 13 00 01 0C 0F"
    assert regmap("frame", str(both), "read", "0x13", "-t", "4").stdout.strip() == rtu(1, 3, 0, 0x13, 0, 1)


# -- decode ----------------------------------------------------------------------------------


def decode_json(*args: str) -> list[dict[str, object]]:
    result = regmap("decode", *args, "--json")
    assert result.returncode == 0, result.stdout + result.stderr
    frames: list[dict[str, object]] = json.loads(result.stdout)
    return frames


def values(frame: dict[str, object]) -> dict[str, object]:
    found = frame["values"]
    assert isinstance(found, list)
    return {v["register"]: v["value"] for v in found if v["raw"] is not None}


def test_decode_the_specs_bit_frames_by_name() -> None:
    [coils] = decode_json(REMOTE_IO, "01 01 03 CD 6B 05 42 82", "--request", "01 01 00 13 00 13 8C 02")
    expected = dict(zip((f"relay_{n}_on" for n in range(20, 39)), [bool(int(b)) for b in "1011001111010110101"], strict=True))
    assert values(coils) == expected and coils["space"] == "coil"
    [inputs] = decode_json(REMOTE_IO, "01 02 03 AC DB 35 22 88", "--request", "01 02 00 C4 00 16 B8 39")
    assert values(inputs)["input_197_active"] is False and values(inputs)["input_218_active"] is True
    assert len(values(inputs)) == 22 and inputs["space"] == "discrete_input"
    [single] = decode_json(REMOTE_IO, "01 05 00 AC FF 00 4C 1B")
    assert values(single) == {"alarm_output": True}
    [written] = decode_json(REMOTE_IO, "01 0F 00 13 00 0A 02 CD 01 72 CB")
    assert list(values(written).values()) == [v == "on" for v in SPEC_ON_OFF]
    [analog] = decode_json(REMOTE_IO, "01 04 02 00 0A 39 37", "--request", "01 04 00 08 00 01 B0 08")
    assert values(analog) == {"analog_in_9": 10} and analog["space"] == "input"
    text = regmap("decode", REMOTE_IO, "01 01 03 CD 6B 05 42 82").stdout
    assert "byte 0: 0xCD = bits 0..7: 1,0,1,1,0,0,1,1" in text and "give the request" in text


def test_decode_is_space_aware() -> None:
    """iDM-RS 5.4.1's example: a 0x02 request at 0x0001 reads discrete inputs, which it has none of;
    the holding register at 0x0001 (Pr0.00 pulses_per_revolution) has nothing to do with it."""
    [frame] = decode_json(IDM, "01 02 00 01 00 01 E8 0A")
    assert frame["values"] == [] and frame["space"] == "discrete_input"
    assert "iDM-RS (V2.0) has no discrete inputs in its map" in frame["notes"]  # type: ignore[operator]
    text = regmap("decode", IDM, "01 02 00 01 00 01 E8 0A").stdout
    assert "pulses_per_revolution" not in text
    [holding] = decode_json(IDM, "01 03 00 01 00 01 D5 CA")  # the same address read as a holding register
    assert holding["values"][0]["register"] == "pulses_per_revolution"  # type: ignore[index]
    [meter] = decode_json(REMOTE_IO, rtu(1, 3, 0, 8, 0, 1))  # 0x0008 is an input register, not a holding one
    assert meter["values"][0]["register"] is None  # type: ignore[index]


def test_decode_floats_wide_values_and_strings() -> None:
    current = ModbusClientMixin.convert_to_registers(12.25, DATATYPE.FLOAT32, word_order="little")
    response = rtu(1, 4, 8, words(ModbusClientMixin.convert_to_registers(230.5, DATATYPE.FLOAT32) + current))
    [measured] = decode_json(POWER_METER, response, "--request", rtu(1, 4, 0, 0, 0, 4))
    assert values(measured) == {"voltage_l1": 230.5, "current_l1": 12.25}
    energy = ModbusClientMixin.convert_to_registers(123456789012, DATATYPE.UINT64)
    reactive = ModbusClientMixin.convert_to_registers(-5, DATATYPE.INT64)
    total = ModbusClientMixin.convert_to_registers(1234.5678, DATATYPE.FLOAT64)
    [wide] = decode_json(POWER_METER, rtu(1, 4, 24, words(energy + reactive + total)), "--request", rtu(1, 4, 0, 0x10, 0, 12))
    assert values(wide) == {"active_energy": 123456789.012, "reactive_energy": -5, "energy_total": 1234.5678}
    text = regmap("decode", POWER_METER, rtu(1, 4, 24, words(energy + reactive + total)), "--request", rtu(1, 4, 0, 0x10, 0, 12)).stdout
    assert "active_energy = 123456789.012 kWh (raw 123456789012)" in text and "energy_total = 1234.5678 kWh" in text
    [label] = decode_json(POWER_METER, rtu(1, 0x10, 0x01, 0x26, 0, 4, 8, "Grüße".encode().ljust(8, b"\0")))
    assert values(label) == {"meter_label": "Grüße"}
    [nan] = decode_json(POWER_METER, rtu(1, 4, 4, b"\x7f\xc0\x00\x00"), "--request", rtu(1, 4, 0, 0, 0, 2))
    row = nan["values"][0]  # type: ignore[index]
    assert row["value"] is None and row["in_range"] is False and "NaN" in row["text"]
    [swapped] = decode_json(SWAPPED, "01 03 04 78 56 34 12 94 4E", "--request", "01 03 00 03 00 02 34 0B")
    assert values(swapped) == {"position": 305419896}
    [gain] = decode_json(SWAPPED, rtu(1, 3, 4, struct.pack(">f", 2.5)[2:] + struct.pack(">f", 2.5)[:2]), "--request", rtu(1, 3, 0, 5, 0, 2))
    assert values(gain) == {"gain": 2.5}
    [tiny] = decode_json(POWER_METER, rtu(1, 0x10, 0x01, 0x24, 0, 2, 4, struct.pack(">f", 0.1)[2:] + struct.pack(">f", 0.1)[:2]))
    assert math.isclose(values(tiny)["voltage_alarm"], 0.1, rel_tol=1e-7)  # type: ignore[arg-type]
    assert (
        "voltage_alarm = 0.1 V"
        in regmap("decode", POWER_METER, rtu(1, 0x10, 0x01, 0x24, 0, 2, 4, struct.pack(">f", 0.1)[2:] + struct.pack(">f", 0.1)[:2])).stdout
    )


@pytest.mark.parametrize(
    ("frame", "asked", "problem"),
    [
        (rtu(1, 5, 0, 0xAC, 0x12, 0x34), None, "a coil write carries FF 00 (on) or 00 00 (off), not 12 34"),
        (rtu(1, 0x0F, 0, 0x13, 0, 10, 1, 0xCD), None, "coil count says 10 but 1 data bytes follow"),
        (rtu(1, 1, 1, 0xFD), rtu(1, 1, 0, 0x13, 0, 3), "the bits after the last of 3 are not zero"),
        (rtu(1, 1, 1, 0x0D), rtu(1, 1, 0, 0x13, 0, 3), "the bits after the last of 3 are not zero"),  # only the first padding bit
        (rtu(1, 1, 2, 0x05, 0x00), rtu(1, 1, 0, 0x13, 0, 3), "3 bits take 1 data byte(s), the byte count says 2"),
        (rtu(1, 1, 0, 0x13, 0x07, 0xD1), None, "bit count 2001 is outside Modbus's 1..2000"),
        (rtu(1, 4, 0, 0, 0, 126), None, "register count 126 is outside Modbus's 1..125"),
        (rtu(1, 0x0F, 0, 0x13, 0x07, 0xB1, 0xF7, bytes(0xF7)), None, "bit count 1969 is outside Modbus's 1..1968"),
    ],
)
def test_decode_flags_what_the_spec_forbids(frame: str, asked: str | None, problem: str) -> None:
    result = regmap("decode", REMOTE_IO, frame, *(["--request", asked] if asked else []))
    assert result.returncode == 3, result.stdout + result.stderr
    assert f"problem: {problem}" in result.stdout


def test_decode_pairs_bit_frames_in_a_capture(tmp_path: Path) -> None:
    capture = tmp_path / "io.log"
    capture.write_text(
        "TX 01 01 00 13 00 13 8C 02\nRX 01 01 03 CD 6B 05 42 82\nTX 01 0F 00 13 00 0A 02 CD 01 72 CB\nRX 01 0F 00 13 00 0A 24 09\n",
        encoding="utf-8",
    )
    frames = decode_json(REMOTE_IO, "--file", str(capture))
    assert [f["direction"] for f in frames] == ["request", "response", "request", "response"]
    assert values(frames[1])["relay_38_on"] is True and len(values(frames[1])) == 19
    assert frames[3]["count"] == 10 and frames[3]["problems"] == []


# -- show and the docs' annotation -----------------------------------------------------------


def test_show_every_type_and_space() -> None:
    meter = regmap("show", POWER_METER)
    assert meter.returncode == 0, meter.stderr
    assert "voltage_l1" in meter.stdout and "[f32, input registers]" in meter.stdout
    assert "0..18446744073709551.615 kWh" in meter.stdout  # u64 x 0.001, exact
    assert 'meter_label                      string rw text of up to 8 bytes  default ""' in meter.stdout
    assert "[f32, input registers, firmware >= 2.00]" in meter.stdout
    assert "firmware version in firmware_version (decimal, 2 decimals)" in meter.stdout
    coil = regmap("show", REMOTE_IO, "alarm_output").stdout
    assert "space        coils (0x01/0x05/0x0F)" in coil and "type         bool, 1 bit" in coil and "default      off" in coil
    demand = regmap("show", POWER_METER, "demand_period").stdout
    assert "default      900 (raw 900)" in demand and "firmware     firmware >= 1.20" in demand
    label = regmap("show", SWAPPED, "label").stdout
    assert "type         string, 4 word(s) = 8 bytes, ascii, nul padded" in label


def example_rows(map_path: str, example_id: str) -> tuple[list[str], list[str]]:
    """(the byte table's meanings, the decoded table's registers and values) of one example in the docs."""
    device = load_map(map_path)
    view = example_view(Context(device), device.example(example_id))
    meanings = [f"{row.field}: {row.meaning}" for frame in view.frames for row in frame.rows]
    return meanings, [f"{d.register} = {d.value} / {d.recorded}" for d in view.decoded]


def test_docs_annotate_the_iDM_RS_0x02_example_as_discrete_inputs() -> None:
    meanings, decoded = example_rows(IDM, "exception_fc_req")
    assert "Start address: `0x0001` (1): discrete input; the map has no discrete inputs" in meanings
    assert "Input count: 1 discrete input: `0x0001` … `0x0001`" in meanings
    assert decoded == [] and not any("pulses_per_revolution" in m for m in meanings)


def test_docs_annotate_the_specs_bit_examples() -> None:
    meanings, decoded = example_rows(REMOTE_IO, "read_coils_rsp")
    assert "Byte count: 3 bytes = up to 24 bits" in meanings
    assert any(m.startswith("Coils `0x0023` … `0x0025`: `00000101`") for m in meanings)
    assert all("differs" not in d for d in decoded) and sum("✓" in d for d in decoded) == 5
    meanings, decoded = example_rows(REMOTE_IO, "write_coil_req")
    assert "Value: 0xFF00: on" in meanings and decoded == ["[`alarm_output`](#alarm_output) = on / raw 1 ✓"]
    _, decoded = example_rows(REMOTE_IO, "read_discrete_inputs_rsp")
    assert sum("✓" in d for d in decoded) == 4 and all("differs" not in d for d in decoded)
    _, decoded = example_rows(POWER_METER, "read_voltage_current_rsp")
    assert decoded[0].startswith("[`voltage_l1`](#voltage_l1) = 230.5 V") and decoded[1].startswith("[`current_l1`](#current_l1) = 12.25 A")


# -- read, write, dump against the simulator ---------------------------------------------------


def test_live_commands_on_every_table(simulator: SimulatorFactory) -> None:
    sim = simulator(Path(REMOTE_IO))
    assert sim.port is not None
    tcp = ["--tcp", f"127.0.0.1:{sim.port}"]
    wrote = regmap("write", REMOTE_IO, *(f"relay_{20 + i}_on={v}" for i, v in enumerate(SPEC_ON_OFF)), "alarm_output=on", *tcp)
    assert wrote.returncode == 0, wrote.stderr
    assert wrote.stdout.count("(verified)") == 11 and "relay_20_on = on  (verified)" in wrote.stdout
    with ModbusTcpClient("127.0.0.1", port=sim.port, timeout=2) as modbus:
        assert [bool(b) for b in modbus.read_coils(0x13, count=10, device_id=1).bits[:10]] == [v == "on" for v in SPEC_ON_OFF]
        assert modbus.read_coils(0xAC, count=1, device_id=1).bits[0] is True
    bits = regmap("write", REMOTE_IO, "--words", "-t", "0", "0x13=0,0", *tcp)
    assert (bits.returncode, bits.stdout.strip()) == (0, "wrote 2 bit(s) in 1 request(s)"), bits.stderr
    read = regmap("read", REMOTE_IO, "0x13", "relay_22_on", "input_197_active", "analog_in_9", "--json", *tcp)
    assert read.returncode == 0, read.stderr
    rows = {r["register"]: r for r in json.loads(read.stdout)}
    assert rows["relay_20_on"]["value"] is False and rows["relay_22_on"]["value"] is True and rows["relay_20_on"]["space"] == "coil"
    assert rows["input_197_active"]["value"] is False and rows["analog_in_9"]["value"] == 0
    refused = regmap("write", REMOTE_IO, "input_197_active=on", *tcp)
    one_line_error(refused, "discrete inputs are read-only")
    dump = regmap("dump", REMOTE_IO, "--csv", *tcp)
    assert dump.returncode == 0, dump.stderr
    lines = dump.stdout.splitlines()
    assert lines[0] == "register,param,address,address_hex,raw,value,unit,in_range,text,space"
    assert (
        "relay_22_on,,21,0x0015,1,true,,true,on,coil" in lines and "input_218_active,,217,0x00D9,0,false,,true,off,discrete_input" in lines
    )
    assert len(lines) == 1 + 46


def test_live_floats_and_strings(simulator: SimulatorFactory) -> None:
    sim = simulator(Path(POWER_METER))
    assert sim.port is not None
    tcp = ["--tcp", f"127.0.0.1:{sim.port}"]
    wrote = regmap("write", POWER_METER, "demand_period=60.5", "voltage_alarm=0.1", "meter_label=Grüße", *tcp)
    assert wrote.returncode == 0, wrote.stderr
    assert "voltage_alarm = 0.1 V  (verified)" in wrote.stdout and 'meter_label = "Grüße"  (verified)' in wrote.stdout
    with ModbusTcpClient("127.0.0.1", port=sim.port, timeout=2) as modbus:
        registers = modbus.read_holding_registers(0x122, count=8, device_id=1).registers
    assert ModbusClientMixin.convert_from_registers(registers[0:2], DATATYPE.FLOAT32) == 60.5
    assert (
        ModbusClientMixin.convert_from_registers(registers[2:4], DATATYPE.FLOAT32, word_order="little")
        == struct.unpack(">f", struct.pack(">f", 0.1))[0]
    )
    assert words(registers[4:8]) == "Grüße".encode().ljust(8, b"\0")
    dump = regmap("dump", POWER_METER, "--json", *tcp)
    assert dump.returncode == 0, dump.stderr
    rows = {r["register"]: r for r in json.loads(dump.stdout)}
    assert rows["demand_period"]["value"] == 60.5 and isinstance(rows["voltage_l1"]["value"], float)
    assert rows["meter_label"]["value"] == "Grüße" and rows["model_name"]["value"] == ""
    assert rows["temperature"]["value"] == -40 and rows["voltage_l1"]["space"] == "input"


def test_live_commands_follow_the_firmware(simulator: SimulatorFactory) -> None:
    sim = simulator(Path(POWER_METER), "--firmware", "1.10")
    assert sim.port is not None
    tcp = ["--tcp", f"127.0.0.1:{sim.port}"]
    dump = regmap("dump", POWER_METER, "--json", *tcp)
    assert dump.returncode == 0, dump.stderr
    assert {r["register"] for r in json.loads(dump.stdout)} == {
        r.name for r in load_map(POWER_METER).registers if r.name not in ("demand_period", "thd_voltage_l1")
    }
    assert dump.stderr.strip() == "regmap dump: firmware 1.10 lacks 2 register(s) of the map, not read: thd_voltage_l1, demand_period"
    read = regmap("read", POWER_METER, "demand_period", "ct_ratio", *tcp)
    one_line_error(read, "demand_period exists only with firmware >= 1.20; the drive reports firmware 1.10: nothing was read")
    write = regmap("write", POWER_METER, "demand_period=60", *tcp)
    one_line_error(write, "nothing was written")
    assert regmap("read", POWER_METER, "firmware_version", *tcp).stdout.strip() == "firmware_version = 110"
