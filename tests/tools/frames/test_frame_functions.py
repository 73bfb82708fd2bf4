"""`regmap frame` and `regmap decode` for 0x08, 0x11, 0x16, 0x17 and 0x2B/0x0E, RTU and MBAP: each frame
byte-exact against struct (MBAP §6) and against the requests libmodbus's own client calls send."""

from __future__ import annotations

import contextlib
import io
import json
import socket
import struct
import subprocess
import threading
from pathlib import Path

import pytest

from regmap.cli import main
from regmap.diagnostics import ExitCode
from regmap.frontend import load_map
from regmap_runtime.rtu import to_hex, with_crc

from conftest import ROOT
from support.libmodbus_ref import build_libmodbus_program

METER = str(ROOT / "tests" / "maps" / "fixtures" / "power_meter.yaml")
MASK = str(ROOT / "tests" / "maps" / "protocol" / "mask_write.yaml")
METER_MAP = load_map(METER)
CT_RATIO = METER_MAP.register("ct_ratio").address
FIRMWARE = METER_MAP.register("firmware_version").address
OUTPUT_WORD = load_map(MASK).register("output_word").address


def regmap(*args: str) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(list(args))
    return code, out.getvalue(), err.getvalue()


def rtu(*fields: tuple[str, int]) -> str:
    """An RTU frame from struct fields: slave 1, then (format, value) pairs, the CRC."""
    return to_hex(with_crc(b"".join(struct.pack(">" + f, v) for f, v in (("B", 1), *fields))))


FRAMES = [
    ((METER, "echo"), rtu(("B", 0x08), ("H", 0x0000), ("H", 0xA537))),
    ((METER, "echo", "0x1234"), rtu(("B", 0x08), ("H", 0x0000), ("H", 0x1234))),
    ((METER, "server-id"), rtu(("B", 0x11))),
    ((METER, "identification"), rtu(("B", 0x2B), ("B", 0x0E), ("B", 1), ("B", 0))),
    ((METER, "identification", "regular"), rtu(("B", 0x2B), ("B", 0x0E), ("B", 2), ("B", 0))),
    ((METER, "identification", "5"), rtu(("B", 0x2B), ("B", 0x0E), ("B", 4), ("B", 5))),
    (
        (METER, "write-read", "firmware_version", "ct_ratio=7"),
        rtu(("B", 0x17), ("H", FIRMWARE), ("H", 1), ("H", CT_RATIO), ("H", 1), ("B", 2), ("H", 7)),
    ),
    (
        (METER, "write-read", "--words", hex(FIRMWARE), "1", f"{CT_RATIO:#x}=7"),
        rtu(("B", 0x17), ("H", FIRMWARE), ("H", 1), ("H", CT_RATIO), ("H", 1), ("B", 2), ("H", 7)),
    ),
    ((MASK, "mask", "--words", f"{OUTPUT_WORD:#x}=0x00F2,0x0025"), rtu(("B", 0x16), ("H", OUTPUT_WORD), ("H", 0x00F2), ("H", 0x0025))),
    # Bits 0 and 1 named: AND clears exactly them, OR sets the new ones; every other bit is the device's.
    ((MASK, "mask", "output_word=enable:1,reverse:0"), rtu(("B", 0x16), ("H", OUTPUT_WORD), ("H", 0xFFFC), ("H", 0x0001))),
    ((METER, "server-id", "--mbap"), to_hex(struct.pack(">HHHBB", 1, 0, 2, 1, 0x11))),
    ((METER, "echo", "--mbap", "--transaction", "7", "--slave", "3"), to_hex(struct.pack(">HHHBBHH", 7, 0, 6, 3, 0x08, 0, 0xA537))),
]


@pytest.mark.parametrize(("args", "expected"), FRAMES)
def test_frames_byte_exact(args: tuple[str, ...], expected: str) -> None:
    code, out, err = regmap("frame", *args)
    assert code == ExitCode.OK, err
    assert out.strip() == expected


@pytest.mark.parametrize(
    ("args", "message"),
    [
        ((METER, "write-read", "firmware_version", "ct_ratio=0"), "ct_ratio: 0 is outside 1..10000"),
        ((METER, "write-read", "ct_ratio", "ct_ratio=2", "voltage_alarm=5"), "one run of adjacent holding registers"),
        ((METER, "write-read", "ct_ratio=2"), "wants what to read"),
        ((METER, "mask", "ct_ratio=3"), "has no function 0x16"),
        ((MASK, "mask", "setpoint=3"), "one-word holding register with bitfields"),
        ((MASK, "server-id"), "has no function 0x11"),
        ((METER, "identification", "7", "8"), "at most one argument"),
        ((METER, "echo", "--transaction", "2"), "give --mbap too"),
    ],
)
def test_frames_refused_with_a_reason(args: tuple[str, ...], message: str) -> None:
    code, out, err = regmap("frame", *args)
    assert code != ExitCode.OK and not out
    assert message in err and "Traceback" not in err


LIBMODBUS_REQUESTS = r"""
#include <stdlib.h>
#include <modbus.h>
int main(int argc, char **argv) {
    uint8_t id[64];
    uint16_t write[1] = {7}, read[1];
    modbus_t *ctx;
    if (argc != 6) return 2;
    ctx = modbus_new_tcp("127.0.0.1", atoi(argv[1]));
    if (ctx == NULL || modbus_set_slave(ctx, 1) != 0 || modbus_connect(ctx) != 0) return 2;
    modbus_report_slave_id(ctx, sizeof id, id);
    modbus_mask_write_register(ctx, (int)strtol(argv[2], NULL, 0), 0x00F2, 0x0025);
    modbus_write_and_read_registers(ctx, (int)strtol(argv[4], NULL, 0), 1, write, (int)strtol(argv[3], NULL, 0), 1, read);
    (void)argv[5];
    modbus_close(ctx);
    modbus_free(ctx);
    return 0;
}
"""
ANSWERS = {0x11: bytes([0x11, 0x03, 0x50, 0x4D, 0xFF]), 0x17: bytes([0x17, 0x02, 0x00, 0x7D])}  # 0x16: the echo


def test_the_frames_are_what_libmodbus_sends(tmp_path: Path) -> None:
    (tmp_path / "requests.c").write_text(LIBMODBUS_REQUESTS)
    program = build_libmodbus_program(tmp_path / "requests.c", tmp_path / "requests")
    listener = socket.create_server(("127.0.0.1", 0))
    port = listener.getsockname()[1]
    seen: list[bytes] = []

    def serve() -> None:
        connection, _ = listener.accept()
        with connection:
            for _ in range(3):
                head = connection.recv(7, socket.MSG_WAITALL)
                body = connection.recv(struct.unpack(">H", head[4:6])[0] - 1, socket.MSG_WAITALL)
                seen.append(head + body)
                answer = ANSWERS.get(body[0], body)
                connection.sendall(head[:4] + struct.pack(">HB", len(answer) + 1, head[6]) + answer)

    thread = threading.Thread(target=serve, daemon=True)
    thread.start()
    result = subprocess.run(
        [str(program), str(port), hex(OUTPUT_WORD), hex(FIRMWARE), hex(CT_RATIO), "x"],
        capture_output=True,
        text=True,
        timeout=30,
        check=False,
    )
    thread.join(10)
    listener.close()
    assert result.returncode == 0, result.stderr
    assert len(seen) == 3
    ours = [
        ("server-id",),
        ("mask", "--words", f"{OUTPUT_WORD:#x}=0x00F2,0x0025"),
        ("write-read", "--words", hex(FIRMWARE), "1", f"{CT_RATIO:#x}=7"),
    ]
    for adu, args in zip(seen, ours, strict=True):
        transaction = struct.unpack(">H", adu[:2])[0]
        map_path = MASK if args[0] == "mask" else METER
        # The mask fixture does not list 0x11/0x17 nor the meter 0x16: each frame is built with the map that lists it.
        code, out, err = regmap("frame", map_path, *args, "--mbap", "--transaction", str(transaction))
        assert code == ExitCode.OK, err
        assert out.strip() == to_hex(adu), args


def decoded(*args: str) -> dict[str, object]:
    code, out, err = regmap("decode", METER, "--json", *args)
    assert code == ExitCode.OK, err
    (one,) = json.loads(out)
    assert isinstance(one, dict)
    return one


def test_decode_names_what_the_frames_carry() -> None:
    request = rtu(("B", 0x17), ("H", FIRMWARE), ("H", 1), ("H", CT_RATIO), ("H", 1), ("B", 2), ("H", 7))
    one = decoded(request)
    assert (one["kind"], one["address"], one["count"]) == ("read_write_request", FIRMWARE, 1)
    assert [v["register"] for v in one["values"]] == ["ct_ratio"]  # type: ignore[attr-defined]
    answer = decoded(rtu(("B", 0x17), ("B", 2), ("H", 125)), "--request", request)
    assert [(v["register"], v["raw"]) for v in answer["values"]] == [("firmware_version", 125)]  # type: ignore[attr-defined]
    exception = decoded("--mbap", to_hex(struct.pack(">HHHBBB", 9, 0, 3, 1, 0x97, 0x02)))
    assert (exception["kind"], exception["exception_code"], exception["mbap"]) == ("exception", 2, {"transaction": 9, "unit": 1})
    objects = decoded(to_hex(with_crc(bytes([1, 0x2B, 0x0E, 0x01, 0x82, 0xFF, 0x02, 0x01, 0x02, 0x04]) + b"1.30")))
    assert objects["kind"] == "device_id_response"
    assert "object 0x02 = '1.30' (the map says '1.25')" in objects["notes"]  # type: ignore[operator]
    assert "conformity level 0x82; more follows from object 0x02" in objects["notes"]  # type: ignore[operator]
    server = decoded(rtu(("B", 0x11), ("B", 3), ("H", 0x504D), ("B", 0xFF)))
    assert server["kind"] == "server_id_response" and server["ok"]
    mask = decoded(rtu(("B", 0x16), ("H", CT_RATIO), ("H", 0xFF00), ("H", 0x0010)))
    assert "ct_ratio: keeps bits 0xFF00, sets 0x0010, clears 0x00EF (AND 0xFF00, OR 0x0010)" in mask["notes"]  # type: ignore[operator]
    bad = regmap("decode", METER, "--mbap", "00 01 00 00 00 09 01 11")
    assert bad[0] != ExitCode.OK and "the MBAP length says 9 bytes follow, 2 do" in bad[2]
