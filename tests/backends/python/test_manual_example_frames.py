"""Golden frames: every example frame printed in the manuals, reproduced and decoded.

For each request example the generated Python client makes the call the example describes (from
its recorded `values`, not from its bytes) against a fake device on loopback that speaks RTU over
TCP; the bytes pymodbus puts on the wire must equal the manual's frame. The fake device answers
with the manual's response frame, and what the client returns must equal the recorded meaning.
Independently, `regmap decode` must read every frame back to the recorded registers and values.

Issue #19's fixture maps (tests/maps/fixtures) are cases too: their frames are built by hand from the
Modbus specification (the remote IO module's are the spec's own §6.1-§6.12 examples), and the runtime's
frame builders must build every one of their requests byte for byte.
"""

from __future__ import annotations

import importlib
import socket
import threading
from collections.abc import Iterator
from dataclasses import dataclass, field
from datetime import datetime
from pathlib import Path
from typing import Any

import pytest

from regmap.frontend import load_map
from regmap.model import Device, Example, ExampleValue
from regmap.tools.decode import decode_frame
from regmap_runtime.codec import value_to_raw
from regmap_runtime.rtu import (
    build_read,
    build_read_response,
    build_write_multiple,
    build_write_multiple_response,
    build_write_single,
    crc_ok,
    parse_frame,
    to_hex,
)
from regmap_runtime.spaces import SPACES

from conftest import FIXTURE_MAPS, MAPS, SMALL_MAPS, generated_runtime, small_maps_python

_errors = generated_runtime("errors")
BitfieldValue = generated_runtime("bits").BitfieldValue
DeviceException = _errors.DeviceException
RegmapError = _errors.RegmapError

DEVICES = {path.stem: load_map(path) for path in (*MAPS, *SMALL_MAPS, *FIXTURE_MAPS)}
FIXTURES = {path.stem for path in FIXTURE_MAPS}
_FIXTURE_PY: list[Path] = []


def fixture_maps_python() -> Path:
    """Python clients of the fixture maps (only the python target, not committed), made once per run."""
    if not _FIXTURE_PY:
        import sys
        import tempfile

        from regmap.generate import generate

        out = Path(tempfile.mkdtemp(prefix="regmap-fixtures-py-")) / "generated"
        generate([DEVICES[name] for name in sorted(FIXTURES)], out, ["python"], complete=True)
        _FIXTURE_PY.append(out / "python")
        sys.path.append(str(out / "python"))
    return _FIXTURE_PY[0]


def _cases() -> list[tuple[str, str | None, str | None]]:
    """(device, request example id, response example id or None) for every request example."""
    cases: list[tuple[str, str | None, str | None]] = []
    for name, device in DEVICES.items():
        responses: dict[str, list[Example]] = {}
        for ex in device.examples:
            if ex.direction == "response" and ex.request:
                responses.setdefault(ex.request, []).append(ex)
        for ex in device.examples:
            if ex.direction == "request":
                answers: list[Example | None] = [*responses.get(ex.id, [])] or [None]
                cases.extend((name, ex.id, answer.id if answer else None) for answer in answers)
            elif ex.request is None:
                cases.append((name, None, ex.id))  # a response the manual prints without its request
    return cases


CASES = _cases()


def test_every_example_is_covered() -> None:
    covered = {(d, x) for d, q, r in CASES for x in (q, r) if x}
    for name, device in DEVICES.items():
        for ex in device.examples:
            assert (name, ex.id) in covered, f"{name}: example {ex.id} is neither a request nor answers one"


@dataclass
class FakeDevice:
    """A device on loopback that records RTU requests and answers from a script."""

    answers: list[bytes | None]
    received: list[bytes] = field(default_factory=list)
    port: int = 0

    def __post_init__(self) -> None:
        self.server = socket.socket()
        self.server.bind(("127.0.0.1", 0))
        self.server.listen(1)
        self.port = self.server.getsockname()[1]
        self.thread = threading.Thread(target=self._serve, daemon=True)
        self.thread.start()

    def _serve(self) -> None:
        conn, _ = self.server.accept()
        with conn:
            conn.settimeout(5)
            buffer = b""
            while True:
                try:
                    chunk = conn.recv(512)
                except OSError:
                    return
                if not chunk:
                    return
                buffer += chunk
                length = _request_length(buffer)
                if length is None or len(buffer) < length:
                    continue
                request, buffer = buffer[:length], buffer[length:]
                self.received.append(request)
                answer = self.answers.pop(0) if self.answers else None
                conn.sendall(answer if answer is not None else _default_answer(request))

    def close(self) -> None:
        self.server.close()


def _request_length(buffer: bytes) -> int | None:
    if len(buffer) < 2:
        return None
    function = buffer[1]
    if function in (0x0F, 0x10):
        return 9 + buffer[6] if len(buffer) >= 7 else None
    return 8  # 0x01-0x06 requests are 8 bytes


def _default_answer(request: bytes) -> bytes:
    frame = parse_frame(request, "request")
    space = frame.space or "holding"
    if frame.kind == "read_request" and frame.count:
        return build_read_response(frame.slave, [0] * frame.count, space=space)
    if frame.kind == "write_multiple_request" and frame.address is not None and frame.count is not None:
        return build_write_multiple_response(frame.slave, frame.address, frame.count, space=space)
    return request  # 0x05 and 0x06 echo


@pytest.fixture
def fake_device() -> Iterator[list[FakeDevice]]:
    made: list[FakeDevice] = []
    yield made
    for dev in made:
        dev.close()


def _client(device: Device, port: int, slave: int) -> Any:
    if device.source_path in {str(p) for p in SMALL_MAPS}:
        small_maps_python()
    if device.source_path in {str(p) for p in FIXTURE_MAPS}:
        fixture_maps_python()
    module = importlib.import_module(device.id)
    client_class = getattr(module, module.__all__[0])  # the sync client class comes first
    return client_class.tcp("127.0.0.1", port, slave=slave, timeout=1.0, retries=0, rtu_over_tcp=True), module


def _spec(module: Any, name: str) -> Any:
    return getattr(module, name.upper())


def _call(client: Any, module: Any, request: Example, device: Device) -> Any:
    """Make the call the example describes, from its recorded values where it has them."""
    frame = parse_frame(request.wire_frame, "request")
    space = frame.space or "holding"
    reads = {s.read for s in SPACES.values()}
    if frame.function in reads and request.values:
        return client.read_many(*(_spec(module, v.register.name) for v in request.values))
    if frame.function in reads and frame.address is not None and frame.count is not None:
        # A request that names no register: the registers it covers, when the client's plan for them is this very request.
        covered = [
            _spec(module, r.name)
            for r in device.registers
            if r.space == space
            and r.access.readable
            and frame.address <= r.first_address
            and r.address + r.words <= frame.address + frame.count
        ]
        plan = client.plan_reads(covered) if covered else []
        if [(b.address, b.count) for b in plan] == [(frame.address, frame.count)]:
            return client.read_many(*covered)
    writes = {code for s in SPACES.values() for code in (s.write_single, s.write_multiple) if code is not None}
    whole = all(_whole_raw(v) is not None for v in request.values)
    if frame.function in writes and request.values and whole:
        values = {_spec(module, v.register.name): _whole_raw(v) for v in request.values}
        blocks = client.plan_writes(values, raw=True)
        if len(blocks) == 1 and blocks[0].address == frame.address and len(blocks[0].words) == frame.count:
            return client.write_many(values, raw=True)
    # Frames addressing what the map does not document, one word of a 32-bit value (7.4 writes a PR
    # position as two 0x06 frames), or some of the coils one 0x0F sets, go out through the raw calls.
    if frame.function not in device.transport.function_codes and frame.function == 0x02:
        # An unsupported function, sent to show the device's answer.
        response = client.modbus.read_discrete_inputs(frame.address, count=frame.count, device_id=frame.slave)
        return client.check_response(response, 0x02)
    if frame.function in reads:
        return client.read_raw(frame.address, frame.count, space=space)
    if frame.function in (0x05, 0x06):
        return client.write_raw(frame.address, list(frame.bits or frame.words), space=space)
    if frame.function in (0x0F, 0x10):
        return client.write_raw(frame.address, list(frame.bits or frame.words), multiple=True, space=space)
    raise AssertionError(f"no client call for function 0x{frame.function:02X}")


def _whole_raw(v: ExampleValue) -> int | float | str | None:
    """The raw value an example records for a whole register (None when it has only some words)."""
    if v.raw is not None:
        return v.raw
    if v.words is not None and len(v.words) == v.register.words:
        return v.words[0] if len(v.words) == 1 else _join(v.register, v.words)
    return None


def _join(register: Any, words: tuple[int, ...]) -> int:
    high, low = (words[0], words[1]) if register.word_order.value == "high_first" else (words[1], words[0])
    raw = (high << 16) | low
    return raw - (1 << 32) if register.signed and raw >> 31 else raw


def _raw_of(module: Any, name: str, value: Any) -> int | float | str:
    if isinstance(value, BitfieldValue):
        return int(value.to_raw())
    spec = _spec(module, name)
    if spec.type_info.kind == "float" and spec.scale_num == spec.scale_den and spec.offset_num == 0:
        return float(value)  # a float register's raw value is the float itself
    return value_to_raw(spec, value) if not isinstance(value, int) else int(value)


@pytest.mark.parametrize(("device_name", "request_id", "response_id"), CASES, ids=[f"{d}-{q or ''}-{r or ''}" for d, q, r in CASES])
def test_client_reproduces_example(
    device_name: str, request_id: str | None, response_id: str | None, fake_device: list[FakeDevice]
) -> None:
    device = DEVICES[device_name]
    response = device.example(response_id) if response_id else None
    if request_id is None:
        # No request printed: any read provokes the printed answer; only the answer is checked.
        assert response is not None
        # The register the answer is about, read alone; an answer about none (an exception): the first readable register.
        first = response.values[0].register if response.values else next(r for r in device.registers if r.access.readable)
        frame = build_read(response.frame[0], first.address, first.words, space=first.space)
        request = Example(id="synthetic", source=(), direction="request", frame=frame, meaning="", values=tuple(response.values[:1]))
    else:
        request = device.example(request_id)
    fake = FakeDevice([response.wire_frame if response else None])
    fake_device.append(fake)
    client, module = _client(device, fake.port, request.wire_frame[0])
    with client:
        expected_exception = response is not None and response.wire_frame[1] & 0x80
        if expected_exception:
            with pytest.raises(DeviceException) as info:
                _call(client, module, request, device)
            assert response is not None
            assert info.value.code == response.wire_frame[2]
            result = None
        else:
            info = None
            result = _call(client, module, request, device)
    assert [to_hex(f) for f in fake.received] == [to_hex(request.wire_frame)], f"manual: {to_hex(request.frame)}"
    if expected_exception:
        assert response is not None
        meaning = device.transport.exception(response.wire_frame[2])
        assert info is not None
        assert meaning is None or info.value.meaning == meaning.title
    if response is not None and isinstance(result, dict):
        for v in response.values:
            if v.not_available:  # the device's "not available" marker: no value, never a number
                assert result[v.register.name] is None, f"{v.register.name}: client read {result[v.register.name]!r}, not None"
                continue
            expected = _whole_raw(v)
            if expected is None:
                continue
            got = _raw_of(module, v.register.name, result[v.register.name])
            assert got == expected, f"{v.register.name}: client read {got}, the manual says {expected}"
            _check_value(v, result[v.register.name])


def _check_value(v: ExampleValue, got: Any) -> None:
    """The typed value the client returned against the example's recorded engineering value, where it records one."""
    if v.value is None or isinstance(got, BitfieldValue):
        return
    kind = v.register.type.kind
    if v.register.type.is_timestamp:  # ISO 8601 text in the map; an aware (utc) or naive (local) datetime from the client
        assert isinstance(v.value, str) and got == datetime.fromisoformat(v.value), (
            f"{v.register.name}: client returned {got!r}, the example says {v.value!r}"
        )
        assert (got.tzinfo is not None) == (v.register.zone == "utc"), f"{v.register.name}: {got!r} on a {v.register.zone} clock"
    elif kind == "string" or kind == "bool":
        assert got == v.value and type(got) is type(v.value), f"{v.register.name}: client returned {got!r}, the example says {v.value!r}"
    elif isinstance(v.value, (int, float)) and not isinstance(v.value, bool):
        assert got == pytest.approx(v.value), f"{v.register.name}: client returned {got!r}, the example says {v.value!r}"
        if kind == "float" or v.register.scaled or v.register.offset_set:
            assert type(got) is float, f"{v.register.name}: {got!r} is not a float"


def _build_request(frame_bytes: bytes) -> bytes:
    """The request rebuilt by the runtime's frame builders (regmap_runtime.rtu) from what it parses to."""
    frame = parse_frame(frame_bytes, "request")
    space = frame.space or "holding"
    assert frame.address is not None
    if frame.kind == "read_request":
        assert frame.count is not None
        return build_read(frame.slave, frame.address, frame.count, space=space)
    if frame.kind == "write_single":
        return build_write_single(frame.slave, frame.address, frame.bits[0] if frame.bits else frame.words[0], space=space)
    assert frame.kind == "write_multiple_request", frame.kind
    return build_write_multiple(frame.slave, frame.address, list(frame.bits or frame.words), space=space)


@pytest.mark.parametrize("device_name", sorted(FIXTURES))
def test_the_runtime_builds_the_fixture_requests(device_name: str) -> None:
    """Every request of the fixture maps, hand-built from the Modbus spec, is what regmap_runtime.rtu builds."""
    requests = [ex for ex in DEVICES[device_name].examples if ex.direction == "request"]
    assert requests
    for ex in requests:
        assert to_hex(_build_request(ex.wire_frame)) == to_hex(ex.wire_frame), ex.id


@pytest.mark.parametrize("device_name", sorted(DEVICES))
def test_printed_erratum_frames_are_what_the_manual_printed(device_name: str) -> None:
    """A declared erratum frame is kept as printed; the corrected frame is valid and differs from it."""
    for ex in DEVICES[device_name].examples:
        if ex.corrected_frame is None:
            assert crc_ok(ex.frame) or ex.erratum, f"{ex.id}: CRC mismatch without an erratum"
            continue
        assert ex.erratum is not None
        assert crc_ok(ex.corrected_frame)
        assert ex.corrected_frame != ex.frame


def test_client_rejects_a_printed_response_with_a_wrong_crc(fake_device: list[FakeDevice]) -> None:
    bad = [(d, ex) for d in DEVICES.values() for ex in d.examples if ex.direction == "response" and ex.request and not crc_ok(ex.frame)]
    assert bad, "the manuals print at least one response with a wrong CRC"
    device, response = bad[0]
    assert response.request is not None
    request = device.example(response.request)
    fake = FakeDevice([response.frame])
    fake_device.append(fake)
    client, module = _client(device, fake.port, request.wire_frame[0])
    with client, pytest.raises(RegmapError):
        _call(client, module, request, device)


@pytest.mark.parametrize("device_name", sorted(DEVICES))
def test_examples_decode_to_their_recorded_meaning(device_name: str) -> None:
    device = DEVICES[device_name]
    for ex in device.examples:
        request = None
        if ex.direction == "response" and ex.request:
            request = parse_frame(device.example(ex.request).wire_frame, "request")
        elif ex.direction == "response" and ex.values and not ex.wire_frame[1] & 0x80:
            # A response printed without its request: the read of the register it is about (as the client test sends).
            first = ex.values[0].register
            request = parse_frame(build_read(ex.wire_frame[0], first.address, first.words, space=first.space), "request")
        decoded = decode_frame(device, ex.wire_frame, direction=ex.direction, request=request)
        assert decoded.frame.crc_valid, f"{ex.id}: {decoded.frame.problems}"
        by_register = {v.register: v for v in decoded.values if v.register}
        for v in ex.values:
            assert v.register.name in by_register or decoded.frame.kind == "exception", f"{ex.id}: {v.register.name} not decoded"
            if v.register.name not in by_register:
                continue
            got = by_register[v.register.name]
            if v.not_available:
                assert got.value is None and got.text.startswith("not available"), f"{ex.id}: {v.register.name} = {got.text}"
                continue
            expected = _whole_raw(v)
            if expected is None:
                if v.words is not None:  # one word of a 32-bit value
                    assert got.words == list(v.words), f"{ex.id}: {v.register.name} words {got.words}, the map records {list(v.words)}"
                continue
            assert got.raw == expected, f"{ex.id}: {v.register.name} decodes to {got.raw}, the map records {expected}"
            if isinstance(v.value, (int, float)) and not isinstance(v.value, bool) and isinstance(got.value, (int, float)):
                assert got.value == pytest.approx(v.value), f"{ex.id}: {v.register.name} = {got.value}, the map says {v.value}"
