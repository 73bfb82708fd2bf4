"""Runtime overhead of the generated client over raw pymodbus doing the same work.

"The same work" is the same requests (the addresses and counts of the read plan, worked out before
timing starts) and the same typed values at the end: the raw side decodes each register with
pymodbus's `convert_from_registers`, scales it, and makes enum members and bitfield values itself,
in the plain table-driven loop someone would write by hand. Both sides must return equal values.
Timings are interleaved (ABBA) in one run; the overhead is the ratio of the medians.
"""

from __future__ import annotations

import contextlib
import random
import subprocess
import sys
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any, Literal

from pymodbus.client import ModbusTcpClient
from pymodbus.client.mixin import ModbusClientMixin
from pymodbus.pdu.register_message import ReadHoldingRegistersResponse

from bench.common import (
    MAPS,
    ROOT,
    Pair,
    calibrate,
    client_class,
    client_module,
    free_port,
    median,
    side_by_side,
    time_call,
    wait_for_port,
)
from regmap_runtime.codec import raw_to_words
from regmap_runtime.plan import ReadBlock, plan_reads
from regmap_runtime.spec import HIGH_FIRST, DeviceSpec, RegisterSpec

DATATYPES = {
    "u16": ModbusClientMixin.DATATYPE.UINT16,
    "s16": ModbusClientMixin.DATATYPE.INT16,
    "u32": ModbusClientMixin.DATATYPE.UINT32,
    "s32": ModbusClientMixin.DATATYPE.INT32,
}
convert_from_registers = ModbusClientMixin.convert_from_registers

Row = tuple[str, int, int, Any, Literal["big", "little"], int, int, Any, Any]  # name, offset, words, datatype, order, num, den, enum, bits


@dataclass(frozen=True)
class Comparison:
    case: str
    detail: str
    generated_s: float  # median wall seconds per call
    raw_s: float
    generated_cpu_s: float  # median CPU seconds of this process per call
    raw_cpu_s: float
    samples: int

    @property
    def overhead(self) -> float:
        return self.generated_s / self.raw_s - 1

    @property
    def cpu_overhead(self) -> float:
        return self.generated_cpu_s / self.raw_cpu_s - 1


def _comparison(case: str, detail: str, pair: Pair) -> Comparison:
    return Comparison(
        case,
        detail,
        median(list(pair.wall_a)),
        median(list(pair.wall_b)),
        median(list(pair.cpu_a)),
        median(list(pair.cpu_b)),
        len(pair.wall_a),
    )


def documented_of(device: DeviceSpec) -> frozenset[tuple[str, int]] | None:
    """The (space, address) pairs the device answers (a method of DeviceSpec once, a cached property now)."""
    documented: Any = device.documented
    return documented() if callable(documented) else documented  # type: ignore[no-any-return]


def raw_table(specs: Sequence[RegisterSpec[Any]], start: int) -> list[Row]:
    """What a hand-written decoder keeps per register: where its words are and how to read them."""
    return [
        (
            s.name,
            s.address - start,
            s.words,
            DATATYPES[s.data_type],
            "big" if s.word_order == HIGH_FIRST else "little",
            s.scale_num,
            s.scale_den,
            s.enum if not s.bitfields else None,
            s.bitfield_type,
        )
        for s in specs
    ]


def raw_decode(table: list[Row], registers: Sequence[int], out: dict[str, Any]) -> None:
    for name, offset, words, datatype, order, num, den, enum_cls, bits_cls in table:
        value: Any = convert_from_registers(registers[offset : offset + words], datatype, word_order=order)
        if bits_cls is not None:
            value = bits_cls.from_raw(value)
        elif enum_cls is not None:
            with contextlib.suppress(ValueError):  # a value the enum does not list stays a number
                value = enum_cls(value)
        elif num != den:
            value = value * num / den
        out[name] = value


def sample_raw(spec: RegisterSpec[Any], rng: random.Random) -> int | float:
    """A raw value the register can hold: an enum member, or anything in its range (signs included)."""
    if spec.enum is not None and not spec.bitfields:
        return int(rng.choice(list(spec.enum)))
    if spec.type_info.is_float:
        return rng.uniform(spec.raw_min, spec.raw_max)
    return rng.randint(int(spec.raw_min), int(spec.raw_max))


def response_words(block: ReadBlock, rng: random.Random) -> list[int]:
    words = [0] * block.count
    for spec in block.registers:
        for i, word in enumerate(raw_to_words(spec, sample_raw(spec, rng))):
            words[spec.address - block.address + i] = word
    return words


def window(specs: Sequence[RegisterSpec[Any]], start: int, count: int) -> ReadBlock:
    """The readable registers that lie wholly inside `count` words from `start`, as one block."""
    inside = tuple(s for s in specs if s.readable and start <= s.first_address and s.address + s.words <= start + count)
    covered = sum(s.span for s in inside)
    if covered != count:
        raise ValueError(f"the registers from 0x{start:04X} cover {covered} of {count} words")
    return ReadBlock(start, count, inside)


def decode_case(client: Any, blocks: list[ReadBlock], rng: random.Random, repeats: int, case: str, detail: str) -> Comparison:
    responses = [ReadHoldingRegistersResponse(dev_id=1, registers=response_words(b, rng)) for b in blocks]
    tables = [raw_table(b.registers, b.address) for b in blocks]

    def generated() -> dict[str, Any]:  # the loop of SyncClient.read_many, after pymodbus answered
        values: dict[str, Any] = {}
        for block, response in zip(blocks, responses, strict=True):
            words = client.read_words(response, block)
            for spec in block.registers:
                values[spec.name] = client.decode(spec, block.words_of(spec, words))
        return values

    def raw() -> dict[str, Any]:
        values: dict[str, Any] = {}
        for table, response in zip(tables, responses, strict=True):
            raw_decode(table, response.registers, values)
        return values

    if generated() != raw():
        raise AssertionError(f"{case}: the generated client and the raw decoder disagree")
    number = calibrate(raw)
    return _comparison(case, detail, side_by_side(generated, raw, repeats, number))


def round_trip_case(
    client: Any, modbus: ModbusTcpClient, specs: Sequence[RegisterSpec[Any]], limit: int, documented: Any, repeats: int, case: str
) -> Comparison:
    blocks = plan_reads(specs, limit, documented)  # worked out once: the raw side is told the requests
    requests = [(b.address, b.count, raw_table(b.registers, b.address)) for b in blocks]

    def generated() -> dict[str, Any]:
        return dict(client.read_many(*specs))

    def raw() -> dict[str, Any]:
        values: dict[str, Any] = {}
        for address, count, table in requests:
            response = modbus.read_holding_registers(address, count=count, device_id=1)
            if response.isError() or len(response.registers) != count:
                raise RuntimeError(f"read of {count} at 0x{address:04X} failed: {response}")
            raw_decode(table, response.registers, values)
        return values

    if generated() != raw():
        raise AssertionError(f"{case}: the generated client and raw pymodbus read different values")
    number = calibrate(raw, 0.05)
    pair = side_by_side(generated, raw, repeats, number)
    detail = f"{len(specs)} registers, {len(blocks)} request(s) of {', '.join(str(b.count) for b in blocks[:6])}{' ...' if len(blocks) > 6 else ''} words"
    return _comparison(case, detail, pair)


@dataclass(frozen=True)
class ClientCost:
    """Where the generated client's own time goes in read_many(), with a transport that answers at once."""

    case: str
    read_many_s: float  # the whole call, without I/O
    plan_s: float  # planning the requests (ClientCore.plan_reads; the client keeps plans it made before)
    decode_s: float  # decoding the responses into typed values


class _AnswerAtOnce:
    """Stands in for a pymodbus client: answers every read from prepared responses."""

    def __init__(self, responses: dict[tuple[int, int], ReadHoldingRegistersResponse]) -> None:
        self.responses = responses

    def read_holding_registers(self, address: int, *, count: int, device_id: int, no_response_expected: bool = False) -> Any:
        return self.responses[(address, count)]

    def close(self) -> None:
        pass


def client_cost(cls: Any, specs: Sequence[RegisterSpec[Any]], case: str, repeats: int) -> ClientCost:
    rng = random.Random(7)
    device = cls.DEVICE
    blocks = plan_reads(specs, device.max_read_registers, documented_of(device))
    responses = {(b.address, b.count): ReadHoldingRegistersResponse(dev_id=1, registers=response_words(b, rng)) for b in blocks}
    client = cls(_AnswerAtOnce(responses))

    def decode() -> None:
        for block in blocks:
            words = client.read_words(responses[(block.address, block.count)], block)
            for spec in block.registers:
                client.decode(spec, block.words_of(spec, words))

    cases: list[Callable[[], object]] = [lambda: client.read_many(*specs), lambda: client.plan_reads(specs), decode]
    medians = [median(time_call(fn, repeats, calibrate(fn))) for fn in cases]
    return ClientCost(case, *medians)


def _simulator(port: int) -> subprocess.Popen[bytes]:
    idm = next(m for m in MAPS if m.stem == "idm_rs")
    cmd = [sys.executable, "-m", "regmap", "simulate", str(idm), "--tcp", f"127.0.0.1:{port}"]
    return subprocess.Popen(cmd, cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


def measure_costs(repeats: int = 11) -> list[ClientCost]:
    module = client_module("idm_rs")
    cls = client_class(module)
    specs = [s for s in module.DEVICE.registers if s.readable]
    pr_window = window(specs, 0x6200, 100)
    return [
        client_cost(cls, list(pr_window.registers), "the 100-register PR table window", repeats),
        client_cost(cls, specs, "read_all()", repeats),
    ]


def measure(repeats: int = 31) -> list[Comparison]:
    module = client_module("idm_rs")
    cls = client_class(module)
    device = module.DEVICE
    specs = [s for s in device.registers if s.readable]
    rng = random.Random(13)
    pr_window = window(specs, 0x6200, 100)
    full = plan_reads(specs, device.max_read_registers, documented_of(device))
    offline = cls(ModbusTcpClient("127.0.0.1", port=1))  # never connected: decoding needs no bus
    results = [
        decode_case(
            offline,
            [pr_window],
            rng,
            repeats,
            "decode one 100-register response",
            f"iDM-RS PR table 0x6200..0x6263: {len(pr_window.registers)} registers (u16, s16, s32, bitfields)",
        ),
        decode_case(
            offline, full, rng, repeats, "decode the read_all() responses", f"iDM-RS: {len(specs)} registers in {len(full)} responses"
        ),
    ]
    port = free_port()
    server = _simulator(port)
    try:
        wait_for_port(port)
        with cls.tcp("127.0.0.1", port, slave=1, timeout=5) as client:
            modbus = ModbusTcpClient("127.0.0.1", port=port, timeout=5)
            if not modbus.connect():  # type: ignore[no-untyped-call]
                raise RuntimeError("raw pymodbus client cannot connect to the simulator")
            try:
                cases: list[tuple[str, list[RegisterSpec[Any]]]] = [
                    ("round trip: the 100-register PR table window", list(pr_window.registers)),
                    ("round trip: read_all()", specs),
                ]
                for case, subset in cases:
                    results.append(round_trip_case(client, modbus, subset, device.max_read_registers, documented_of(device), repeats, case))
            finally:
                modbus.close()  # type: ignore[no-untyped-call]
    finally:
        server.terminate()
        server.wait(timeout=10)
    return results


def functions() -> dict[str, Callable[..., Any]]:
    """The pieces the smoke test drives on tiny inputs."""
    return {"raw_table": raw_table, "raw_decode": raw_decode, "window": window, "response_words": response_words}
