"""The client base that generated device modules subclass: sync and async, one surface.

Validation, encoding and planning happen before anything is sent; pymodbus does the transport.
Every space is served: holding and input registers, coils and discrete inputs (a bit's "words" are
its 0/1, one per address, as in the codec). A client asked to `check_firmware` reads the device's
firmware register in `connect()` (or, used without `connect()`, before its first other request) and
from then on refuses registers that firmware lacks.

Beyond reads and writes, where the map lists the function: `echo` (0x08 sub-function 0x00, return
query data), `report_server_id` (0x11), `write_and_read` (0x17: one write and one read of holding
registers in one request, the write checked as `write_many` checks it and sent once: a lost answer
is `OutcomeUnknown`), `read_identification` (0x2B/0x0E, basic or regular objects, following "more
follows" to the end of the stream). A function the map does not list is refused before anything is sent.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterable, Mapping
from typing import Any, TypeVar, cast

from pymodbus.client import AsyncModbusSerialClient, AsyncModbusTcpClient, ModbusSerialClient, ModbusTcpClient
from pymodbus.exceptions import ModbusException as PymodbusError

from .base import ECHO_WORD, ClientCore, WriteTarget
from .bits import BitfieldValue
from .codec import check_command, raw_to_words
from .errors import ConnectionLost
from .plan import ReadBlock
from .rtu import (
    DIAGNOSTICS,
    ENCAPSULATED_INTERFACE,
    READ_WRITE_MULTIPLE,
    REPORT_SERVER_ID,
)
from .spaces import DEFAULT_SPACE, MASK_WRITE_REGISTER
from .spec import LOW_FIRST, Readable, ReadWrite, Writable, poll_class
from .wire import (
    ServerIdReport,
    identification_objects,
    next_identification_object,
    server_id_report,
)

T = TypeVar("T")
B = TypeVar("B", bound=BitfieldValue)


class SyncClient(ClientCore):
    """Blocking client. Use as a context manager, or call close()."""

    modbus: ModbusSerialClient | ModbusTcpClient
    SERIAL_TRANSPORT = ModbusSerialClient
    TCP_TRANSPORT = ModbusTcpClient

    def __enter__(self: C) -> C:
        self.connect()
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def connect(self) -> None:
        """Open the port or socket; with check_firmware, read the firmware version too."""
        if not self.modbus.connect():
            raise ConnectionLost(f"cannot connect to {self.where}")
        if self.firmware_pending:
            self.detect_firmware()

    def close(self) -> None:
        self.modbus.close()  # type: ignore[no-untyped-call]

    def detect_firmware(self) -> tuple[int, ...]:
        """Read the firmware register now and keep its version (`firmware`, `firmware_text`); with
        check_firmware, connect() does this, or the first request when connect() was not called."""
        block = self.firmware_block()
        response = self._send(*self.reader(block.space), block.address, count=block.count)
        return self.learn_firmware(self.read_words(response, block))

    def _send(self, function: int, method: Any, *args: Any, write: WriteTarget | None = None, once: bool = False, **kwargs: Any) -> Any:
        tries = self._tries(write, once)
        for attempt in range(1, tries + 1):
            self.requests_sent += 1
            sent_before = getattr(self.line, "packets_sent", 0)
            try:
                response = method(*args, device_id=self.slave, no_response_expected=self.broadcast, **kwargs)
                break
            except PymodbusError as exc:
                error = self._failure(exc, write, attempt < tries, sent_before, once)
                if error is not None:
                    raise error from exc
        if self.broadcast:
            return None
        return self.check_response(response, function)

    def _call(self, function: int, method: Any, *args: Any, **kwargs: Any) -> Any:
        if self.firmware_pending:
            self.detect_firmware()
        return self._send(function, method, *args, **kwargs)

    def read_raw(self, address: int, count: int, *, space: str = DEFAULT_SPACE) -> list[int]:
        """Read `count` words from `address` of `space` (holding registers: 0x03; coils and discrete inputs: one 0/1 per bit)."""
        if self.broadcast:
            raise ValueError("a broadcast cannot read")
        self.check_aligned(space, address, count)
        response = self._call(*self.reader(space), address, count=count)
        return self.read_words(response, ReadBlock(address, count, (), space))

    def write_raw(
        self, address: int, words: list[int] | tuple[int, ...], *, multiple: bool | None = None, space: str = DEFAULT_SPACE
    ) -> None:
        """Write words from `address`: write single (0x06; a coil 0x05) for one word unless `multiple`, else
        write multiple (0x10; coils 0x0F). A coil's word is its bit, 0 or 1 (0x05 sends it as FF 00 / 00 00)."""
        function, method, single = self.writer(space, len(words) == 1 and not multiple)
        self._call(function, method, *self.write_args(space, address, words, single), write=(space, address, words))

    def send_command(self, spec: Writable[Any], raw: int, *, confirmed: bool = False) -> None:
        """Write a command's fixed raw value (already checked against the map at generation time); a
        destructive command's only when `confirmed` (DestructiveWriteError, nothing sent)."""
        check_command(spec, raw, confirmed)
        if self.firmware_pending:
            self.detect_firmware()
        self.check_exists(spec)
        target = self.effective(spec)
        words = raw_to_words(target, raw)
        self.write_raw(target.address, words, multiple=len(words) > 1, space=target.space)

    def read(self, spec: Readable[T]) -> T:
        return cast(T, self.read_many(spec)[spec.name])

    def read_many(self, *specs: Readable[Any]) -> Mapping[str, Any]:
        """Read several registers with the fewest requests the device allows (a generated client types the result)."""
        if self.firmware_pending:
            self.detect_firmware()
        read = [
            (block, self.read_raw(block.address, block.count, space=block.space))
            for block in self.plan_reads(self.with_scale_factors(specs))
        ]
        return self.values_read(read, specs)

    def read_all(self, poll: object = None) -> Mapping[str, Any]:
        """Every readable register, by the device's read plan; `poll` ("static", "fast", "normal",
        "slow"): only that class's. With check_firmware, the registers the firmware lacks are left out."""
        if poll is not None:
            poll_class(poll)  # an unknown class fails before anything is sent
        if self.firmware_pending:
            self.detect_firmware()
        return self.read_many(*cast(list[Readable[Any]], self.readable(poll)))

    def write(self, spec: Writable[T], value: T | int | float | str, *, raw: bool = False) -> None:
        self.write_many({spec: value}, raw=raw)

    def set_word_order(self, order: str) -> None:
        """Make the device use `order` for its 32-bit values: write its word-order register (the map's value for
        `order`, or the swap value when the device uses the other order now), then read and write with `order`.
        A swap is a trigger: sent once, and a lost answer is OutcomeUnknown (the order is then not known)."""
        write = self.word_order_write(order)
        if write is not None:
            self.write_many({cast(Writable[Any], write[0]): write[1]}, raw=True)
        self.word_order = order

    def update(self, spec: ReadWrite[B], **fields: Any) -> B:
        """Change only the named fields of a bitfield register (every other bit, described or not, stays):
        one mask write (0x16) where the device lists it, then the register read back; else read-modify-write."""
        masks = self.masked(spec, fields)
        if masks is None:
            new = dataclasses.replace(self.read(spec), **fields)
            self.write(spec, new)
            return new
        if self.firmware_pending:
            self.detect_firmware()
        self.check_exists(spec)
        write = (spec.space, spec.address, [masks[1]])
        self._call(
            MASK_WRITE_REGISTER, self.modbus.mask_write_register, address=spec.address, and_mask=masks[0], or_mask=masks[1], write=write
        )
        return self.read(spec)

    def echo(self, word: int = ECHO_WORD) -> int:
        """Diagnostics 0x08 sub-function 0x00 (return query data): the device echoes `word`; ProtocolError if not."""
        self.check_listed(DIAGNOSTICS, "diagnostics")
        return self.echoed(word, self._call(DIAGNOSTICS, self.modbus.diag_query_data, word.to_bytes(2, "big")))

    def report_server_id(self) -> ServerIdReport:
        """Report server id (0x11): the id, run indicator and additional data as the device sends them."""
        self.check_listed(REPORT_SERVER_ID, "report server id")
        return server_id_report(self.line, self._call(REPORT_SERVER_ID, self.modbus.report_device_id))

    def read_identification(self, level: str = "regular") -> dict[int, str]:
        """Read device identification (0x2B/0x0E): the basic (0x00-0x02) or regular (to 0x7F) objects by id,
        every answer of the stream followed ("more follows")."""
        self.check_listed(ENCAPSULATED_INTERFACE, "read device identification")
        code = self.identification_code(level)
        start: int | None = 0
        answers: list[Any] = []
        while start is not None:  # each answer moves forward (next_identification_object), so this ends
            answer = self._call(ENCAPSULATED_INTERFACE, self.modbus.read_device_information, read_code=code, object_id=start)
            answers.append(answer)
            start = next_identification_object(answer, start)
        return identification_objects(answers)

    def write_and_read(
        self, writes: Mapping[Writable[Any], Any], reads: Iterable[Readable[Any]], *, raw: bool = False
    ) -> Mapping[str, Any]:
        """Read/write multiple registers (0x17): write `writes` (checked and encoded as write_many does; one run
        of adjacent holding registers), then read `reads` (one block), in one request sent once: a lost
        answer is OutcomeUnknown. Returns the values read, by register name."""
        if self.firmware_pending:
            self.detect_firmware()
        written, read = self.read_write_plan(writes, reads, raw)
        response = self._send(READ_WRITE_MULTIPLE, self.modbus.readwrite_registers, **self.read_write_arguments(written, read))
        return self.values_of(read, self.read_words(response, read))

    def write_many(self, values: Mapping[Writable[Any], Any], *, raw: bool = False) -> None:
        """Validate every value, then write contiguous registers together (0x10; coils 0x0F)."""
        for spec in values:
            self.check_writable(spec)  # refused before even the firmware is read
        if self.firmware_pending:
            self.detect_firmware()
        needed = [] if raw else self.scale_factors(values)
        factors = self.read_many(*cast(list[Readable[Any]], needed)) if needed else None  # read fresh for this write, never a guess
        for block in self.plan_writes(values, raw, factors=factors):
            self.write_raw(block.address, block.words, multiple=not block.single, space=block.space)


class AsyncClient(ClientCore):
    """asyncio client with the same surface as SyncClient (every I/O method is a coroutine)."""

    modbus: AsyncModbusSerialClient | AsyncModbusTcpClient
    SERIAL_TRANSPORT = AsyncModbusSerialClient
    TCP_TRANSPORT = AsyncModbusTcpClient

    async def __aenter__(self: A) -> A:
        await self.connect()
        return self

    async def __aexit__(self, *exc: object) -> None:
        self.close()

    async def connect(self) -> None:
        if not await self.modbus.connect():
            raise ConnectionLost(f"cannot connect to {self.where}")
        if self.firmware_pending:
            await self.detect_firmware()

    def close(self) -> None:
        self.modbus.close()

    async def detect_firmware(self) -> tuple[int, ...]:
        block = self.firmware_block()
        response = await self._send(*self.reader(block.space), block.address, count=block.count)
        return self.learn_firmware(self.read_words(response, block))

    async def _send(
        self, function: int, method: Any, *args: Any, write: WriteTarget | None = None, once: bool = False, **kwargs: Any
    ) -> Any:
        tries = self._tries(write, once)
        for attempt in range(1, tries + 1):
            self.requests_sent += 1
            sent_before = getattr(self.line, "packets_sent", 0)
            try:
                response = await method(*args, device_id=self.slave, no_response_expected=self.broadcast, **kwargs)
                break
            except PymodbusError as exc:
                error = self._failure(exc, write, attempt < tries, sent_before, once)
                if error is not None:
                    raise error from exc
        if self.broadcast:
            return None
        return self.check_response(response, function)

    async def _call(self, function: int, method: Any, *args: Any, **kwargs: Any) -> Any:
        if self.firmware_pending:
            await self.detect_firmware()
        return await self._send(function, method, *args, **kwargs)

    async def read_raw(self, address: int, count: int, *, space: str = DEFAULT_SPACE) -> list[int]:
        if self.broadcast:
            raise ValueError("a broadcast cannot read")
        self.check_aligned(space, address, count)
        response = await self._call(*self.reader(space), address, count=count)
        return self.read_words(response, ReadBlock(address, count, (), space))

    async def write_raw(
        self, address: int, words: list[int] | tuple[int, ...], *, multiple: bool | None = None, space: str = DEFAULT_SPACE
    ) -> None:
        function, method, single = self.writer(space, len(words) == 1 and not multiple)
        await self._call(function, method, *self.write_args(space, address, words, single), write=(space, address, words))

    async def send_command(self, spec: Writable[Any], raw: int, *, confirmed: bool = False) -> None:
        check_command(spec, raw, confirmed)
        if self.firmware_pending:
            await self.detect_firmware()
        self.check_exists(spec)
        target = self.effective(spec)
        words = raw_to_words(target, raw)
        await self.write_raw(target.address, words, multiple=len(words) > 1, space=target.space)

    async def read(self, spec: Readable[T]) -> T:
        return cast(T, (await self.read_many(spec))[spec.name])

    async def read_many(self, *specs: Readable[Any]) -> Mapping[str, Any]:
        if self.firmware_pending:
            await self.detect_firmware()
        read = [
            (block, await self.read_raw(block.address, block.count, space=block.space))
            for block in self.plan_reads(self.with_scale_factors(specs))
        ]
        return self.values_read(read, specs)

    async def read_all(self, poll: object = None) -> Mapping[str, Any]:
        if poll is not None:
            poll_class(poll)
        if self.firmware_pending:
            await self.detect_firmware()
        return await self.read_many(*cast(list[Readable[Any]], self.readable(poll)))

    async def write(self, spec: Writable[T], value: T | int | float | str, *, raw: bool = False) -> None:
        await self.write_many({spec: value}, raw=raw)

    async def set_word_order(self, order: str) -> None:
        """As SyncClient.set_word_order: the word-order register written (a swap sent once), then `order` used."""
        write = self.word_order_write(order)
        if write is not None:
            await self.write_many({cast(Writable[Any], write[0]): write[1]}, raw=True)
        self.word_order = order

    async def update(self, spec: ReadWrite[B], **fields: Any) -> B:
        """Change only the named fields of a bitfield register (see SyncClient.update)."""
        masks = self.masked(spec, fields)
        if masks is None:
            new = dataclasses.replace(await self.read(spec), **fields)
            await self.write(spec, new)
            return new
        if self.firmware_pending:
            await self.detect_firmware()
        self.check_exists(spec)
        write = (spec.space, spec.address, [masks[1]])
        method = self.modbus.mask_write_register
        await self._call(MASK_WRITE_REGISTER, method, address=spec.address, and_mask=masks[0], or_mask=masks[1], write=write)
        return await self.read(spec)

    async def echo(self, word: int = ECHO_WORD) -> int:
        """Diagnostics 0x08 sub-function 0x00 (return query data): the device echoes `word`; ProtocolError if not."""
        self.check_listed(DIAGNOSTICS, "diagnostics")
        return self.echoed(word, await self._call(DIAGNOSTICS, self.modbus.diag_query_data, word.to_bytes(2, "big")))

    async def report_server_id(self) -> ServerIdReport:
        """Report server id (0x11): the id, run indicator and additional data as the device sends them."""
        self.check_listed(REPORT_SERVER_ID, "report server id")
        return server_id_report(self.line, await self._call(REPORT_SERVER_ID, self.modbus.report_device_id))

    async def read_identification(self, level: str = "regular") -> dict[int, str]:
        """Read device identification (0x2B/0x0E): the basic (0x00-0x02) or regular (to 0x7F) objects by id,
        every answer of the stream followed ("more follows")."""
        self.check_listed(ENCAPSULATED_INTERFACE, "read device identification")
        code = self.identification_code(level)
        start: int | None = 0
        answers: list[Any] = []
        while start is not None:  # each answer moves forward (next_identification_object), so this ends
            answer = await self._call(ENCAPSULATED_INTERFACE, self.modbus.read_device_information, read_code=code, object_id=start)
            answers.append(answer)
            start = next_identification_object(answer, start)
        return identification_objects(answers)

    async def write_and_read(
        self, writes: Mapping[Writable[Any], Any], reads: Iterable[Readable[Any]], *, raw: bool = False
    ) -> Mapping[str, Any]:
        """Read/write multiple registers (0x17): write `writes` (checked and encoded as write_many does; one run
        of adjacent holding registers), then read `reads` (one block), in one request sent once: a lost
        answer is OutcomeUnknown. Returns the values read, by register name."""
        if self.firmware_pending:
            await self.detect_firmware()
        written, read = self.read_write_plan(writes, reads, raw)
        response = await self._send(READ_WRITE_MULTIPLE, self.modbus.readwrite_registers, **self.read_write_arguments(written, read))
        return self.values_of(read, self.read_words(response, read))

    async def write_many(self, values: Mapping[Writable[Any], Any], *, raw: bool = False) -> None:
        for spec in values:
            self.check_writable(spec)
        if self.firmware_pending:
            await self.detect_firmware()
        needed = [] if raw else self.scale_factors(values)
        factors = await self.read_many(*cast(list[Readable[Any]], needed)) if needed else None  # read fresh for this write, never a guess
        for block in self.plan_writes(values, raw, factors=factors):
            await self.write_raw(block.address, block.words, multiple=not block.single, space=block.space)


C = TypeVar("C", bound=SyncClient)
A = TypeVar("A", bound=AsyncClient)

__all__ = ["LOW_FIRST", "AsyncClient", "SyncClient"]
