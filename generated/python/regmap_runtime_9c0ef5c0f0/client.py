"""The client base that generated device modules subclass: sync and async, one surface.

Validation, encoding and planning happen before anything is sent; pymodbus does the transport.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterable, Mapping
from typing import Any, TypeVar, cast

from pymodbus import FramerType
from pymodbus.client import AsyncModbusSerialClient, AsyncModbusTcpClient, ModbusSerialClient, ModbusTcpClient
from pymodbus.exceptions import ConnectionException, ModbusIOException
from pymodbus.exceptions import ModbusException as PymodbusError
from pymodbus.pdu import ExceptionResponse

from .bits import BitfieldValue
from .codec import check_raw, decode_value, raw_to_words, value_to_raw, words_to_raw
from .errors import ConnectionLost, CrcError, DeviceException, DeviceTimeout, ProtocolError, WrongSlave
from .plan import ReadBlock, WriteBlock, plan_reads, plan_writes
from .profile import DeviceProfile
from .rtu import STANDARD_EXCEPTIONS, crc_ok, to_hex
from .spaces import DEFAULT_SPACE, HOLDING, SPACES
from .spec import LOW_FIRST, DeviceSpec, Raw, Readable, ReadWrite, RegisterSpec, Writable

T = TypeVar("T")
B = TypeVar("B", bound=BitfieldValue)
PARITY = {"none": "N", "even": "E", "odd": "O"}
# pymodbus's spelling of each space's reads and writes: (read, write single, write multiple).
PYMODBUS_METHODS = {HOLDING.name: ("read_holding_registers", "write_register", "write_registers")}


class LineWatch:
    """pymodbus's packet hook: keeps the bytes of the latest answer (bounded) so an unusable answer
    can be named (bad CRC, another slave, garbage) rather than reported as silence. Changes nothing."""

    def __init__(self, rtu_framing: bool) -> None:
        self.rtu_framing = rtu_framing
        self.received = b""

    def __call__(self, sending: bool, data: bytes) -> bytes:
        self.received = b"" if sending else bytes(data[-260:])
        return data


class _Core:
    """Everything that does not touch the bus: value checks, encoding, request planning."""

    DEVICE: DeviceSpec
    modbus: Any  # the pymodbus client of the subclass

    def __init__(self, slave: int, word_order: str | None = None, profile: DeviceProfile | None = None) -> None:
        if not 0 <= slave <= 255:
            raise ValueError(f"slave id {slave} is outside 0..255")
        if profile is not None:
            # What `regmap probe` observed: the read limit, the gaps proven readable, the word order (ProfileError for another map).
            self.DEVICE = profile.apply(type(self).DEVICE)
        self.profile = profile
        self.slave = slave
        self.word_order = word_order or (profile.word_order if profile is not None else None) or self.DEVICE.word_order
        self.requests_sent = 0
        self._plans: dict[tuple[str, ...], list[ReadBlock]] = {}
        self.line = LineWatch(rtu_framing=False)

    def transport_error(self, exc: Exception) -> Exception:
        """A typed error saying what happened on the line: silence, a bad CRC, another slave, or garbage."""
        if isinstance(exc, ConnectionException):
            return ConnectionLost(str(exc))
        if not isinstance(exc, ModbusIOException):
            return ProtocolError(str(exc))
        seen = self.line.received
        if "device id" in str(exc) and "received" in str(exc):
            return WrongSlave(f"asked slave {self.slave}, {str(exc).split('but ')[-1].rstrip('.')}")
        if not seen:
            return DeviceTimeout(f"no answer from slave {self.slave} (after all retries)")
        if self.line.rtu_framing:
            if len(seen) >= 4 and seen[0] != self.slave:
                return WrongSlave(f"asked slave {self.slave}, the answer came from slave {seen[0]}: {to_hex(seen)}")
            if len(seen) >= 4 and not crc_ok(seen):
                return CrcError(f"the answer's CRC does not match: {to_hex(seen)}")
        return ProtocolError(f"unusable answer: {to_hex(seen)}")

    @property
    def broadcast(self) -> bool:
        return self.DEVICE.broadcast_id is not None and self.slave == self.DEVICE.broadcast_id

    def effective(self, spec: RegisterSpec[T]) -> RegisterSpec[T]:
        """The spec with the word order this client was told the device uses (a device with a word-order register, `transport.word_order_register` in its map)."""
        return spec.in_word_order(self.word_order)

    def encode(self, spec: RegisterSpec[Any], value: Any) -> Raw:
        if not spec.writable:
            raise TypeError(f"{spec.label} is read-only")
        if spec.bitfield_type is not None and isinstance(value, spec.bitfield_type):
            raw = int(value.to_raw())
            check_raw(spec, raw)
            return raw
        return value_to_raw(spec, value)

    def encode_raw(self, spec: RegisterSpec[Any], raw: Raw) -> Raw:
        if not spec.writable:
            raise TypeError(f"{spec.label} is read-only")
        raw = raw if isinstance(raw, str | float) else int(raw)
        check_raw(spec, raw)
        return raw

    def decode(self, spec: RegisterSpec[T], words: list[int]) -> T:
        spec = self.effective(spec)
        raw = words_to_raw(spec, words)
        if spec.bitfield_type is not None:
            return cast(T, spec.bitfield_type.from_raw(raw))
        return cast(T, decode_value(spec, raw))

    def plan_reads(self, specs: Iterable[RegisterSpec[Any]]) -> list[ReadBlock]:
        """The requests for these registers; plans are kept, so a polling loop plans once."""
        chosen = tuple(specs)
        key = tuple(spec.name for spec in chosen)
        plan = self._plans.get(key)
        if plan is None:
            for spec in chosen:
                if not spec.readable:
                    raise TypeError(f"{spec.label} is write-only")
            plan = plan_reads(chosen, self.DEVICE.max_read_registers, self.DEVICE.documented)
            self._plans[key] = plan
        return plan

    def plan_writes(self, values: Mapping[Writable[Any], Any], raw: bool = False) -> list[WriteBlock]:
        """Check and encode every value, then group them into requests. `raw`: values are register integers."""
        raws = [(self.effective(spec), self.encode_raw(spec, value) if raw else self.encode(spec, value)) for spec, value in values.items()]
        return plan_writes(raws, self.DEVICE.max_write_registers, HOLDING.write_multiple in self.DEVICE.function_codes)

    def readable(self) -> list[RegisterSpec[Any]]:
        return [r for r in self.DEVICE.registers if r.readable]

    def check_response(self, response: Any, function: int) -> Any:
        if isinstance(response, ExceptionResponse) or (hasattr(response, "isError") and response.isError()):
            code = int(getattr(response, "exception_code", 0))
            for known, name, meaning in self.DEVICE.exceptions:
                if known == code:
                    raise DeviceException(function, code, meaning, name)
            raise DeviceException(function, code, STANDARD_EXCEPTIONS.get(code, "unknown exception code"))
        return response

    def reader(self, space: str) -> tuple[int, Any]:
        """The function code and the pymodbus method that read `space`."""
        return SPACES[space].read, getattr(self.modbus, PYMODBUS_METHODS[space][0])

    def writer(self, space: str, single: bool) -> tuple[int, Any]:
        """The function code and the pymodbus method of a write to `space`: single or multiple."""
        facts = SPACES[space]
        function = facts.write_single if single else facts.write_multiple
        if function is None:
            raise TypeError(f"{facts.title} cannot be written")
        return function, getattr(self.modbus, PYMODBUS_METHODS[space][1 if single else 2])

    def read_words(self, response: Any, block: ReadBlock) -> list[int]:
        words = list(getattr(response, "registers", []))
        if len(words) != block.count:
            raise ProtocolError(f"asked for {block.count} registers at 0x{block.address:04X}, got {len(words)}")
        return words


class SyncClient(_Core):
    """Blocking client. Use as a context manager, or call close()."""

    modbus: ModbusSerialClient | ModbusTcpClient

    def __init__(
        self,
        modbus: ModbusSerialClient | ModbusTcpClient,
        slave: int = 1,
        word_order: str | None = None,
        line: LineWatch | None = None,
        profile: DeviceProfile | None = None,
    ) -> None:
        super().__init__(slave, word_order, profile)
        self.modbus = modbus
        if line is not None:
            self.line = line

    @classmethod
    def rtu(
        cls: type[C],
        port: str,
        slave: int = 1,
        *,
        baud: int | None = None,
        parity: str | None = None,
        stop_bits: int | None = None,
        timeout: float = 1.0,
        retries: int = 2,
        word_order: str | None = None,
        profile: DeviceProfile | None = None,
    ) -> C:
        """Serial RTU; port settings default to the map's transport settings."""
        device = cls.DEVICE
        line = LineWatch(rtu_framing=True)
        modbus = ModbusSerialClient(
            port,
            baudrate=baud or device.baud,
            parity=PARITY[parity or device.parity],
            bytesize=device.data_bits,
            stopbits=stop_bits or device.stop_bits,
            timeout=timeout,
            retries=retries,
            trace_packet=line,
        )
        return cls(modbus, slave, word_order, line, profile)

    @classmethod
    def tcp(
        cls: type[C],
        host: str,
        port: int = 502,
        slave: int = 1,
        *,
        timeout: float = 1.0,
        retries: int = 2,
        word_order: str | None = None,
        rtu_over_tcp: bool = False,
        profile: DeviceProfile | None = None,
    ) -> C:
        """Modbus TCP (gateways, simulators); `rtu_over_tcp` for transparent serial-to-Ethernet converters."""
        framer = FramerType.RTU if rtu_over_tcp else FramerType.SOCKET
        line = LineWatch(rtu_framing=rtu_over_tcp)
        modbus = ModbusTcpClient(host, port=port, framer=framer, timeout=timeout, retries=retries, trace_packet=line)
        return cls(modbus, slave, word_order, line, profile)

    def __enter__(self: C) -> C:
        self.connect()
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def connect(self) -> None:
        if not self.modbus.connect():
            raise ConnectionLost(f"cannot connect to {self.modbus}")

    def close(self) -> None:
        self.modbus.close()  # type: ignore[no-untyped-call]

    def _call(self, function: int, method: Any, *args: Any, **kwargs: Any) -> Any:
        self.requests_sent += 1
        try:
            response = method(*args, device_id=self.slave, no_response_expected=self.broadcast, **kwargs)
        except PymodbusError as exc:
            raise self.transport_error(exc) from exc
        if self.broadcast:
            return None
        return self.check_response(response, function)

    def read_raw(self, address: int, count: int, *, space: str = DEFAULT_SPACE) -> list[int]:
        """Read `count` register words from `address` of `space` (holding registers: function 0x03)."""
        if self.broadcast:
            raise ValueError("a broadcast cannot read")
        response = self._call(*self.reader(space), address, count=count)
        return self.read_words(response, ReadBlock(address, count, (), space))

    def write_raw(
        self, address: int, words: list[int] | tuple[int, ...], *, multiple: bool | None = None, space: str = DEFAULT_SPACE
    ) -> None:
        """Write words from `address`: write single (0x06) for one word unless `multiple`, else write multiple (0x10)."""
        single = len(words) == 1 and not multiple
        self._call(*self.writer(space, single), address, words[0] if single else list(words))

    def send_command(self, spec: Writable[Any], raw: int) -> None:
        """Write a command's fixed raw value (already checked against the map at generation time)."""
        target = self.effective(spec)
        words = raw_to_words(target, raw)
        self.write_raw(target.address, words, multiple=len(words) > 1, space=target.space)

    def read(self, spec: Readable[T]) -> T:
        return cast(T, self.read_many(spec)[spec.name])

    def read_many(self, *specs: Readable[Any]) -> dict[str, Any]:
        """Read several registers with the fewest requests the device allows."""
        values: dict[str, Any] = {}
        for block in self.plan_reads(specs):
            words = self.read_raw(block.address, block.count, space=block.space)
            for spec in block.registers:
                values[spec.name] = self.decode(spec, block.words_of(spec, words))
        return values

    def read_all(self) -> dict[str, Any]:
        """Every readable register, by the device's read plan."""
        return self.read_many(*cast(list[Readable[Any]], self.readable()))

    def write(self, spec: Writable[T], value: T | int | float | str, *, raw: bool = False) -> None:
        self.write_many({spec: value}, raw=raw)

    def update(self, spec: ReadWrite[B], **fields: Any) -> B:
        """Read-modify-write of a bitfield register: one read, then one write that changes only
        the named fields (every other bit, described or not, is written back as read)."""
        new = dataclasses.replace(self.read(spec), **fields)
        self.write(spec, new)
        return new

    def write_many(self, values: Mapping[Writable[Any], Any], *, raw: bool = False) -> None:
        """Validate every value, then write contiguous registers together with 0x10."""
        for block in self.plan_writes(values, raw):
            self.write_raw(block.address, block.words, multiple=not block.single, space=block.space)


class AsyncClient(_Core):
    """asyncio client with the same surface as SyncClient (every I/O method is a coroutine)."""

    modbus: AsyncModbusSerialClient | AsyncModbusTcpClient

    def __init__(
        self,
        modbus: AsyncModbusSerialClient | AsyncModbusTcpClient,
        slave: int = 1,
        word_order: str | None = None,
        line: LineWatch | None = None,
        profile: DeviceProfile | None = None,
    ) -> None:
        super().__init__(slave, word_order, profile)
        self.modbus = modbus
        if line is not None:
            self.line = line

    @classmethod
    def rtu(
        cls: type[A],
        port: str,
        slave: int = 1,
        *,
        baud: int | None = None,
        parity: str | None = None,
        stop_bits: int | None = None,
        timeout: float = 1.0,
        retries: int = 2,
        word_order: str | None = None,
        profile: DeviceProfile | None = None,
    ) -> A:
        device = cls.DEVICE
        line = LineWatch(rtu_framing=True)
        modbus = AsyncModbusSerialClient(
            port,
            baudrate=baud or device.baud,
            parity=PARITY[parity or device.parity],
            bytesize=device.data_bits,
            stopbits=stop_bits or device.stop_bits,
            timeout=timeout,
            retries=retries,
            trace_packet=line,
        )
        return cls(modbus, slave, word_order, line, profile)

    @classmethod
    def tcp(
        cls: type[A],
        host: str,
        port: int = 502,
        slave: int = 1,
        *,
        timeout: float = 1.0,
        retries: int = 2,
        word_order: str | None = None,
        rtu_over_tcp: bool = False,
        profile: DeviceProfile | None = None,
    ) -> A:
        framer = FramerType.RTU if rtu_over_tcp else FramerType.SOCKET
        line = LineWatch(rtu_framing=rtu_over_tcp)
        return cls(
            AsyncModbusTcpClient(host, port=port, framer=framer, timeout=timeout, retries=retries, trace_packet=line),
            slave,
            word_order,
            line,
            profile,
        )

    async def __aenter__(self: A) -> A:
        await self.connect()
        return self

    async def __aexit__(self, *exc: object) -> None:
        self.close()

    async def connect(self) -> None:
        if not await self.modbus.connect():
            raise ConnectionLost(f"cannot connect to {self.modbus}")

    def close(self) -> None:
        self.modbus.close()

    async def _call(self, function: int, method: Any, *args: Any, **kwargs: Any) -> Any:
        self.requests_sent += 1
        try:
            response = await method(*args, device_id=self.slave, no_response_expected=self.broadcast, **kwargs)
        except PymodbusError as exc:
            raise self.transport_error(exc) from exc
        if self.broadcast:
            return None
        return self.check_response(response, function)

    async def read_raw(self, address: int, count: int, *, space: str = DEFAULT_SPACE) -> list[int]:
        if self.broadcast:
            raise ValueError("a broadcast cannot read")
        response = await self._call(*self.reader(space), address, count=count)
        return self.read_words(response, ReadBlock(address, count, (), space))

    async def write_raw(
        self, address: int, words: list[int] | tuple[int, ...], *, multiple: bool | None = None, space: str = DEFAULT_SPACE
    ) -> None:
        single = len(words) == 1 and not multiple
        await self._call(*self.writer(space, single), address, words[0] if single else list(words))

    async def send_command(self, spec: Writable[Any], raw: int) -> None:
        target = self.effective(spec)
        words = raw_to_words(target, raw)
        await self.write_raw(target.address, words, multiple=len(words) > 1, space=target.space)

    async def read(self, spec: Readable[T]) -> T:
        return cast(T, (await self.read_many(spec))[spec.name])

    async def read_many(self, *specs: Readable[Any]) -> dict[str, Any]:
        values: dict[str, Any] = {}
        for block in self.plan_reads(specs):
            words = await self.read_raw(block.address, block.count, space=block.space)
            for spec in block.registers:
                values[spec.name] = self.decode(spec, block.words_of(spec, words))
        return values

    async def read_all(self) -> dict[str, Any]:
        return await self.read_many(*cast(list[Readable[Any]], self.readable()))

    async def write(self, spec: Writable[T], value: T | int | float | str, *, raw: bool = False) -> None:
        await self.write_many({spec: value}, raw=raw)

    async def update(self, spec: ReadWrite[B], **fields: Any) -> B:
        """Read-modify-write of a bitfield register (see SyncClient.update)."""
        new = dataclasses.replace(await self.read(spec), **fields)
        await self.write(spec, new)
        return new

    async def write_many(self, values: Mapping[Writable[Any], Any], *, raw: bool = False) -> None:
        for block in self.plan_writes(values, raw):
            await self.write_raw(block.address, block.words, multiple=not block.single, space=block.space)


C = TypeVar("C", bound=SyncClient)
A = TypeVar("A", bound=AsyncClient)

__all__ = ["LOW_FIRST", "AsyncClient", "SyncClient"]
