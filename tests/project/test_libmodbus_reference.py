"""The libmodbus reference harness (tests/support/libmodbus_ref.py) against Python's struct, the Modbus spec's own
example and pymodbus: before other tests trust it to judge regmap, it is judged itself."""

from __future__ import annotations

import math
import signal
import struct
import subprocess
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path

import pytest
from pymodbus.client import ModbusTcpClient

from support.libmodbus_ref import (
    ORDERS,
    LibmodbusRef,
    LibmodbusRefError,
    LibmodbusServerFactory,
    libmodbus_programs,
    libmodbus_ref_fixture,  # noqa: F401
    libmodbus_server_fixture,  # noqa: F401
    parse_dump,
)

FLOATS = [0.0, -0.0, 1.5, 230.1, -1e-38, 3.4e38, math.inf, -math.inf, math.nan]
# Bit patterns for the getters: a signalling NaN, a NaN with payload and sign, the smallest subnormal.
FLOAT_BITS = [0x7F800001, 0xFFC00123, 0x00000001, 0x40490FDB, 0xC2F60000]

# Modbus Application Protocol v1.1b3 §6.1 Read Coils: coils 20..38 are CD 6B 05.
SPEC_COILS_20_TO_38 = [1, 0, 1, 1, 0, 0, 1, 1, 1, 1, 0, 1, 0, 1, 1, 0, 1, 0, 1]
SPEC_STATUS = bytes([0xCD, 0x6B, 0x05])


def bits_of(value: float) -> int:
    return int.from_bytes(struct.pack(">f", value), "big")


def expected_words(order: str, big_endian: bytes) -> tuple[int, int]:
    """Registers 0 and 1 of the four big-endian bytes a b c d, in byte order `order`."""
    a, b, c, d = big_endian
    layout = {"abcd": (a, b, c, d), "badc": (b, a, d, c), "cdab": (c, d, a, b), "dcba": (d, c, b, a)}[order]
    return layout[0] << 8 | layout[1], layout[2] << 8 | layout[3]


@pytest.mark.parametrize("order", ORDERS)
@pytest.mark.parametrize("value", FLOATS, ids=repr)
def test_set_float_writes_the_struct_layout(libmodbus_ref: LibmodbusRef, order: str, value: float) -> None:
    assert libmodbus_ref.set_float(order, value) == expected_words(order, struct.pack(">f", value))


@pytest.mark.parametrize("order", ORDERS)
@pytest.mark.parametrize("bits", [*(bits_of(v) for v in FLOATS), *FLOAT_BITS], ids=lambda b: f"{b:#010x}")
def test_get_float_reads_the_struct_layout(libmodbus_ref: LibmodbusRef, order: str, bits: int) -> None:
    words = expected_words(order, bits.to_bytes(4, "big"))
    assert libmodbus_ref.get_float_bits(order, *words) == bits
    value = libmodbus_ref.get_float(order, *words)
    expected = struct.unpack(">f", bits.to_bytes(4, "big"))[0]
    assert (math.isnan(value) and math.isnan(expected)) or struct.pack(">d", value) == struct.pack(">d", expected)


@pytest.mark.parametrize("order", ORDERS)
@pytest.mark.parametrize("value", FLOATS, ids=repr)
def test_float_round_trip(libmodbus_ref: LibmodbusRef, order: str, value: float) -> None:
    assert libmodbus_ref.get_float_bits(order, *libmodbus_ref.set_float(order, value)) == bits_of(value)


def test_libmodbus_getters_follow_their_names_and_setters_are_mapped(libmodbus_ref: LibmodbusRef) -> None:
    """The getters are called by name (the parametrised tests above prove them); every order has one
    libmodbus setter, and that setter's raw output is the order's layout."""
    assert sorted(libmodbus_ref.setter_for) == sorted(ORDERS)
    assert sorted(libmodbus_ref.setter_for.values()) == sorted(ORDERS)
    for order, function in libmodbus_ref.setter_for.items():
        assert libmodbus_ref.libmodbus_set_float(function, 230.1) == expected_words(order, struct.pack(">f", 230.1))


def test_float32_rounding_and_overflow(libmodbus_ref: LibmodbusRef) -> None:
    # A double is rounded to the nearest float32, as struct does; beyond the float32 range it is inf.
    assert libmodbus_ref.set_float("abcd", 0.1) == expected_words("abcd", struct.pack(">f", 0.1))
    assert libmodbus_ref.set_float("abcd", 1e39) == (0x7F80, 0x0000)
    assert libmodbus_ref.set_float("abcd", 1e-50) == (0x0000, 0x0000)


def test_bits_against_the_spec_example(libmodbus_ref: LibmodbusRef) -> None:
    assert libmodbus_ref.pack_bits(SPEC_COILS_20_TO_38) == SPEC_STATUS
    assert libmodbus_ref.unpack_bits(19, SPEC_STATUS) == SPEC_COILS_20_TO_38


@pytest.mark.parametrize("n", [0, 1, 7, 8, 9, 16, 17, 1968, 2000])
def test_bits_round_trip(libmodbus_ref: LibmodbusRef, n: int) -> None:
    bits = [(i * i + i // 3) % 2 for i in range(n)]
    packed = sum(bit << i for i, bit in enumerate(bits)).to_bytes((n + 7) // 8, "little")
    assert libmodbus_ref.pack_bits(bits) == packed
    assert libmodbus_ref.unpack_bits(n, packed) == bits


def test_bits_past_n_are_ignored(libmodbus_ref: LibmodbusRef) -> None:
    assert libmodbus_ref.unpack_bits(3, b"\xfd") == [1, 0, 1]
    assert libmodbus_ref.pack_bits([1, 1, 1, 1, 1, 1, 1, 1, 1]) == b"\xff\x01"


def test_errors_are_lines_and_the_process_goes_on(libmodbus_ref: LibmodbusRef) -> None:
    assert libmodbus_ref.command("u64 abcd 1").startswith("error unknown command")
    assert libmodbus_ref.command("set_float abdc 1").startswith("error usage")
    assert libmodbus_ref.command("get_float abcd 0x10000 0").startswith("error usage")
    assert libmodbus_ref.command("get_bits 9 0xff").startswith("error byte 1")
    assert libmodbus_ref.command("set_float abcd 1.5x").startswith("error not a float")
    with pytest.raises(LibmodbusRefError):
        libmodbus_ref.pack_bits([0, 2])
    with pytest.raises(LibmodbusRefError):
        libmodbus_ref.unpack_bits(8, b"\x00\x00")
    assert libmodbus_ref.set_float("abcd", 1.5) == (0x3FC0, 0x0000)


# -- the tables server -------------------------------------------------------------------------------

TABLES = {
    "coil": {20: 1, 21: 0, 22: 1, 25: 1},
    "discrete_input": {0x100: 1, 0x102: 1},
    "holding": {0x1000: 0xBEEF, 0x1001: 7, 0x1003: 65535},
    "input": {5: 230, 6: 0x8000},
}


@contextmanager
def client(port: int) -> Iterator[ModbusTcpClient]:
    modbus = ModbusTcpClient("127.0.0.1", port=port, timeout=5, retries=0)
    connect: Callable[[], bool] = modbus.connect  # pymodbus leaves the sync client's connect and close unannotated
    close: Callable[[], None] = modbus.close
    assert connect()
    try:
        yield modbus
    finally:
        close()


def test_server_serves_the_tables_and_keeps_the_writes(libmodbus_server: LibmodbusServerFactory) -> None:
    port, finish = libmodbus_server(TABLES)
    with client(port) as modbus:
        assert modbus.read_coils(20, count=6, device_id=1).bits[:6] == [True, False, True, False, False, True]
        assert modbus.read_discrete_inputs(0x100, count=3, device_id=1).bits[:3] == [True, False, True]
        assert modbus.read_holding_registers(0x1000, count=4, device_id=1).registers == [0xBEEF, 7, 0, 65535]
        assert modbus.read_input_registers(5, count=2, device_id=1).registers == [230, 0x8000]
        assert not modbus.write_coil(21, True, device_id=1).isError()
        assert not modbus.write_register(0x1002, 0x1234, device_id=1).isError()
        assert not modbus.write_registers(0x1000, [1, 2], device_id=1).isError()
    # A second client, after the first one left, sees what the first wrote.
    with client(port) as modbus:
        assert modbus.read_holding_registers(0x1000, count=4, device_id=1).registers == [1, 2, 0x1234, 65535]
        assert not modbus.write_coils(24, [True, False], device_id=1).isError()
    assert finish() == {
        "coil": {20: 1, 21: 1, 22: 1, 23: 0, 24: 1, 25: 0},
        "discrete_input": {0x100: 1, 0x101: 0, 0x102: 1},
        "holding": {0x1000: 1, 0x1001: 2, 0x1002: 0x1234, 0x1003: 65535},
        "input": {5: 230, 6: 0x8000},
    }
    assert finish()["holding"][0x1002] == 0x1234  # a second call returns the same


def test_server_tables_span_what_the_file_names(libmodbus_server: LibmodbusServerFactory) -> None:
    port, finish = libmodbus_server({"holding": {10: 1, 12: 3}})
    with client(port) as modbus:
        assert modbus.read_holding_registers(10, count=3, device_id=1).registers == [1, 0, 3]
        for address, count in ((9, 1), (12, 2), (13, 1)):
            refused = modbus.read_holding_registers(address, count=count, device_id=1)
            assert refused.isError() and refused.exception_code == 2, (address, count)
        assert modbus.read_coils(0, count=16, device_id=1).bits == [False] * 16  # a table not named: 0..15
        assert modbus.read_coils(16, count=1, device_id=1).exception_code == 2
    tables = finish()
    assert tables["holding"] == {10: 1, 11: 0, 12: 3}
    assert tables["coil"] == dict.fromkeys(range(16), 0)
    assert tables["input"] == dict.fromkeys(range(16), 0)


def test_server_dumps_on_sigterm(tmp_path_factory: pytest.TempPathFactory, tmp_path: Path) -> None:
    binary = libmodbus_programs(tmp_path_factory).tables_server
    table_file = tmp_path / "tables.txt"
    table_file.write_text("# a comment\nholding 0x10 0xffff  # hex\n\ninput 3 12\n", encoding="utf-8")
    process = subprocess.Popen(
        [str(binary), "0", str(table_file)], stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
    )
    assert process.stdout is not None
    assert process.stdout.readline().startswith("listening ")
    process.send_signal(signal.SIGTERM)
    out, err = process.communicate(timeout=10)
    assert process.returncode == 0, err
    tables = parse_dump(out)
    assert tables["holding"] == {0x10: 0xFFFF}
    assert tables["input"] == {3: 12}


@pytest.mark.parametrize(
    ("text", "complaint"),
    [
        ("holding 1 65536\n", ":1: expected"),
        ("coil 1 2\n", ":1: expected"),
        ("coils 1 1\n", ":1: expected"),
        ("# ok\ninput 1 010x\n", ":2: expected"),
        ("input 1 1\ninput 1 2\n", ":2: input 1 is named twice"),
    ],
)
def test_server_refuses_a_bad_table_file(tmp_path_factory: pytest.TempPathFactory, tmp_path: Path, text: str, complaint: str) -> None:
    binary = libmodbus_programs(tmp_path_factory).tables_server
    table_file = tmp_path / "tables.txt"
    table_file.write_text(text, encoding="utf-8")
    result = subprocess.run([str(binary), "0", str(table_file)], stdin=subprocess.DEVNULL, capture_output=True, text=True, timeout=10)
    assert result.returncode == 2
    assert complaint in result.stderr
    assert result.stdout == ""
