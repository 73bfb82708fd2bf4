"""`regmap simulate`: a Modbus server that behaves like the device as its map describes it.

Built on pymodbus's server side: `DeviceStore` answers pymodbus's datastore calls, returning
Modbus exception codes where the real device would (undocumented address, read-only register,
value out of range, unsupported function). Commands with a declared `effect` act (save to the
state file, restore defaults, clear a register). Faults can be injected for client tests.
"""

from __future__ import annotations

import asyncio
import contextlib
import dataclasses
import json
import os
import signal
import tempfile
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from pymodbus import FramerType
from pymodbus.constants import ExcCodes
from pymodbus.datastore import ModbusServerContext
from pymodbus.exceptions import NoSuchIdException
from pymodbus.server import ModbusSerialServer, ModbusTcpServer

from regmap.backends.common import runtime_specs
from regmap.diagnostics import UsageError
from regmap.model import Device, Register
from regmap_runtime.codec import raw_to_words, words_to_raw
from regmap_runtime.rtu import crc_bytes

FAULT_KINDS = ("none", "no_answer", "bad_crc", "truncated", "exception", "wrong_slave", "wrong_function", "delay")

READ_FUNCTIONS = {0x03}
WRITE_FUNCTIONS = {0x06, 0x10}


@dataclass
class FaultPlan:
    """Faults injected into answers: `kind` applies to every answer, or to the next `count` ones."""

    kind: str = "none"
    count: int | None = None  # None: every answer
    after: int = 0  # answers that go out unharmed before the faults start
    delay_s: float = 2.0
    exception_code: int = 0x04

    def take(self, kinds: tuple[str, ...]) -> str:
        """The fault to apply now if it is one of `kinds` (consuming one of `count`)."""
        if self.kind == "none" or self.kind not in kinds:
            return "none"
        if self.after > 0:
            self.after -= 1
            return "none"
        if self.count is None:
            return self.kind
        if self.count <= 0:
            return "none"
        self.count -= 1
        return self.kind


@dataclass
class Stats:
    frames_received: int = 0
    bytes_received: int = 0
    frames_sent: int = 0
    bytes_sent: int = 0
    requests: list[bytes] = field(default_factory=list)


class DeviceStore(ModbusServerContext):
    """The device's register memory and rules, in the shape pymodbus's server calls.

    Not initialised through ModbusServerContext.__init__ (deprecated datastores); pymodbus serves
    any context whose `old_simulator` is set by calling async_getValues/async_setValues directly.
    """

    def __init__(self, device: Device, slave: int, state_file: Path | None = None) -> None:
        self.device = device
        self.slave = slave
        self.state_file = state_file
        self.old_simulator = True
        self.simdevices = []
        self.specs = {s.name: s for s in runtime_specs(device)}
        self.registers = {r.name: r for r in device.registers}
        self.owner: dict[int, Register] = {}
        for reg in device.registers:
            for address in range(reg.first_address, reg.last_address + 1):
                self.owner[address] = reg
        self.words: dict[int, int] = {}
        self.word_order = device.transport.word_order.value
        self.pending_after_read: dict[int, int] = {}
        self.faults = FaultPlan()
        self.load_defaults()
        if state_file is not None and state_file.exists():
            self.load_state(state_file)

    # -- memory ------------------------------------------------------------------------------

    def spec(self, reg: Register) -> Any:
        """The register's codec in the word order the device uses right now (C630S P0C-26 can change it)."""
        spec = self.specs[reg.name]
        if spec.words == 2 and spec.follows_device_order and spec.word_order != self.word_order:
            return dataclasses.replace(spec, word_order=self.word_order)
        return spec

    def follow_word_order_register(self) -> None:
        """Re-lay every 32-bit value when the word-order parameter changes: values stay, words swap."""
        control = self.device.transport.word_order_register
        if control is None:
            return
        setting = self.raw_of(control.register)
        wanted = "high_first" if setting == control.high_first else "low_first" if setting == control.low_first else self.word_order
        if wanted == self.word_order:
            return
        moving = [r for r in self.device.registers if r.words == 2 and not r.word_order_fixed]
        values = {r.name: self.raw_of(r) for r in moving}
        self.word_order = wanted
        for reg in moving:
            self.store_raw(reg, values[reg.name])

    def store_raw(self, reg: Register, raw: int) -> None:
        words = raw_to_words(self.spec(reg), raw, with_pair=True)
        for offset, word in enumerate(words):
            self.words[reg.first_address + offset] = word

    def raw_of(self, reg: Register) -> int:
        spec = self.spec(reg)
        return words_to_raw(spec, [self.words.get(reg.address + i, 0) for i in range(reg.words)])

    def load_defaults(self) -> None:
        self.words.clear()
        self.word_order = self.device.transport.word_order.value
        for reg in self.device.registers:
            self.store_raw(reg, reg.default if reg.default is not None else 0)
        self.follow_word_order_register()

    def persistent(self) -> list[Register]:
        return [r for r in self.device.registers if r.access.readable and r.access.writable]

    def save_state(self) -> None:
        if self.state_file is None:
            return
        data = {r.name: self.raw_of(r) for r in self.persistent()}
        text = json.dumps(
            {"device": self.device.id, "map_version": self.device.info.map_version, "registers": data}, indent=1, sort_keys=True
        )
        # Write beside the target and rename: the state file is never left half-written.
        fd, tmp = tempfile.mkstemp(prefix=".state-", dir=self.state_file.parent)
        try:
            with os.fdopen(fd, "w", encoding="utf-8") as handle:
                handle.write(text)
                handle.flush()
                os.fsync(handle.fileno())
            os.replace(tmp, self.state_file)
        except BaseException:
            with contextlib.suppress(OSError):
                os.unlink(tmp)
            raise

    def load_state(self, path: Path) -> None:
        try:
            data = json.loads(path.read_text(encoding="utf-8"))
            saved = data["registers"]
        except (OSError, ValueError, KeyError, TypeError) as exc:
            raise UsageError(f"{path}: not a regmap simulator state file ({exc})") from None
        control = self.device.transport.word_order_register
        if control is not None and isinstance(saved.get(control.register.name), int):
            self.store_raw(control.register, saved[control.register.name])
            self.follow_word_order_register()
        for name, raw in saved.items():
            reg = self.registers.get(name)
            if reg is not None and isinstance(raw, int) and reg.type.raw_min <= raw <= reg.type.raw_max:
                self.store_raw(reg, raw)

    # -- the rules ---------------------------------------------------------------------------

    def device_ids(self) -> list[int]:
        return [self.slave]

    def _check_id(self, device_id: int) -> None:
        broadcast = self.device.transport.broadcast_id
        if device_id != self.slave and not (broadcast is not None and device_id == broadcast):
            raise NoSuchIdException(f"no device {device_id}")

    def documented(self, address: int) -> bool:
        reg = self.owner.get(address)
        return reg is not None or self.device.transport.tolerates_gaps

    async def async_getValues(self, device_id: int, func_code: int, address: int, count: int = 1) -> list[int] | list[bool] | ExcCodes:
        self._check_id(device_id)
        if func_code in WRITE_FUNCTIONS:  # pymodbus reads back what it wrote to build the echo
            return [self.words.get(a, 0) for a in range(address, address + count)]
        if func_code not in READ_FUNCTIONS or func_code not in self.device.transport.function_codes:
            return ExcCodes.ILLEGAL_FUNCTION
        if self.faults.take(("exception",)) == "exception":
            return ExcCodes(self.faults.exception_code)
        values = []
        for a in range(address, address + count):
            reg = self.owner.get(a)
            if reg is None and not self.device.transport.tolerates_gaps:
                return ExcCodes.ILLEGAL_ADDRESS
            if reg is not None and not reg.access.readable:
                return ExcCodes.ILLEGAL_ADDRESS
            values.append(self.words.get(a, 0))
        for a in range(address, address + count):
            if a in self.pending_after_read:
                self.words[a] = self.pending_after_read.pop(a)
        return values

    async def async_setValues(
        self, device_id: int, func_code: int, address: int, values: Sequence[int] | Sequence[bool]
    ) -> ExcCodes | None:
        self._check_id(device_id)
        if func_code not in WRITE_FUNCTIONS or func_code not in self.device.transport.function_codes:
            return ExcCodes.ILLEGAL_FUNCTION
        if self.faults.take(("exception",)) == "exception":
            return ExcCodes(self.faults.exception_code)
        words = [int(v) for v in values]
        end = address + len(words)
        touched: list[Register] = []
        for a in range(address, end):
            reg = self.owner.get(a)
            if reg is None:
                if self.device.transport.tolerates_gaps:
                    continue
                return ExcCodes.ILLEGAL_ADDRESS
            if reg not in touched:
                touched.append(reg)
        updates: list[tuple[Register, int]] = []
        for reg in touched:
            own = range(reg.address, reg.last_address + 1)
            covered = [a for a in own if address <= a < end]
            if not covered:
                continue  # only the unused high word of a pair was written
            if len(covered) != len(own):
                return ExcCodes.ILLEGAL_ADDRESS  # half of a 32-bit value
            if not reg.access.writable:
                return ExcCodes.ILLEGAL_VALUE
            spec = self.spec(reg)
            raw = words_to_raw(spec, [words[a - address] for a in own])
            out_of_range = (reg.min is not None and raw < reg.min) or (reg.max is not None and raw > reg.max)
            if out_of_range and not self._is_command(reg, raw):
                return ExcCodes.ILLEGAL_VALUE
            if reg.enum is not None and not reg.bitfields and reg.enum.by_value(raw) is None and not self._is_command(reg, raw):
                return ExcCodes.ILLEGAL_VALUE
            updates.append((reg, raw))
        for reg, raw in updates:
            self.store_raw(reg, raw)
            self._act(reg, raw)
        self.follow_word_order_register()
        return None

    def _is_command(self, reg: Register, raw: int) -> bool:
        return any(
            c.register.name == reg.name and (c.value == raw or (c.argument and c.value + c.argument.min <= raw <= c.value + c.argument.max))
            for c in self.device.commands
        )

    def _act(self, reg: Register, raw: int) -> None:
        for command in self.device.commands:
            if command.register.name != reg.name or command.value != raw or command.effect is None:
                continue
            effect = command.effect
            if effect.kind == "save":
                self.save_state()
                if effect.register is not None:
                    self.store_raw(effect.register, effect.value)
                    if effect.after_read is not None:
                        self.pending_after_read[effect.register.address] = effect.after_read
            elif effect.kind == "restore_defaults":
                self.load_defaults()
            elif effect.kind == "clear" and effect.register is not None:
                self.store_raw(effect.register, effect.value)


class Simulator:
    """One simulated device on TCP or serial, with fault injection and frame statistics."""

    def __init__(self, device: Device, slave: int = 1, state_file: Path | None = None, faults: FaultPlan | None = None) -> None:
        self.device = device
        self.store = DeviceStore(device, slave, state_file)
        self.faults = faults or FaultPlan()
        self.store.faults = self.faults
        self.stats = Stats()
        self.server: ModbusTcpServer | ModbusSerialServer | None = None

    def trace_packet(self, sending: bool, data: bytes) -> bytes:
        if not sending:
            self.stats.frames_received += 1
            self.stats.bytes_received += len(data)
            self.stats.requests.append(bytes(data))
            return data
        fault = self.faults.take(("no_answer", "delay", "bad_crc", "truncated", "wrong_slave", "wrong_function"))
        if fault == "no_answer":
            return b""
        if fault == "delay":
            time.sleep(self.faults.delay_s)  # blocks this server only: the reply is late, as on a slow device
        elif fault == "bad_crc" and len(data) >= 4:
            data = data[:-2] + bytes([data[-2] ^ 0xFF, data[-1]])
        elif fault == "truncated" and len(data) > 3:
            data = data[: len(data) // 2]
        elif fault == "wrong_slave" and len(data) >= 4:
            data = self._rebuild(bytes([(data[0] + 1) & 0xFF]) + data[1:-2])
        elif fault == "wrong_function" and len(data) >= 4:
            data = self._rebuild(data[:1] + bytes([data[1] ^ 0x04]) + data[2:-2])
        self.stats.frames_sent += 1
        self.stats.bytes_sent += len(data)
        return data

    def _rebuild(self, body: bytes) -> bytes:
        return body + crc_bytes(body) if self.framer == FramerType.RTU else body

    framer: FramerType = FramerType.RTU

    async def serve_tcp(self, host: str, port: int, *, rtu_over_tcp: bool = False) -> None:
        self.framer = FramerType.RTU if rtu_over_tcp else FramerType.SOCKET
        self.server = ModbusTcpServer(
            self.store,
            address=(host, port),
            framer=self.framer,
            ignore_missing_devices=True,
            broadcast_enable=self.device.transport.broadcast_id == 0,
            trace_packet=self.trace_packet,
        )
        await self.server.serve_forever()

    async def serve_serial(self, port: str, baud: int | None = None) -> None:
        t = self.device.transport
        self.framer = FramerType.RTU
        self.server = ModbusSerialServer(
            self.store,
            port=port,
            framer=FramerType.RTU,
            baudrate=baud or t.baud,
            bytesize=t.data_bits,
            parity={"none": "N", "even": "E", "odd": "O"}[t.parity],
            stopbits=t.stop_bits,
            ignore_missing_devices=True,
            broadcast_enable=t.broadcast_id == 0,
            trace_packet=self.trace_packet,
        )
        await self.server.serve_forever()

    async def stop(self) -> None:
        if self.server is not None:
            await self.server.shutdown()  # type: ignore[no-untyped-call]


def parse_endpoint(text: str) -> tuple[str, int]:
    host, sep, port = text.rpartition(":")
    if not sep or not port.isdigit() or not 0 < int(port) < 65536:
        raise UsageError(f"--tcp wants HOST:PORT, got {text!r}")
    return host or "127.0.0.1", int(port)


def run(
    device: Device, *, tcp: str | None, serial: str | None, slave: int, state: Path | None, faults: FaultPlan, rtu_over_tcp: bool = False
) -> int:
    """Serve until Ctrl-C or SIGTERM; returns the exit status."""
    simulator = Simulator(device, slave, state, faults)

    async def main() -> None:
        loop = asyncio.get_running_loop()
        stop = asyncio.Event()
        for sig in (signal.SIGINT, signal.SIGTERM):
            loop.add_signal_handler(sig, stop.set)
        if serial:
            task = asyncio.create_task(simulator.serve_serial(serial))
            where = serial
        else:
            host, port = parse_endpoint(tcp or "127.0.0.1:5020")
            task = asyncio.create_task(simulator.serve_tcp(host, port, rtu_over_tcp=rtu_over_tcp))
            where = f"{host}:{port}"
        print(f"regmap simulate: {device.info.model} (slave {slave}) on {where}; Ctrl-C stops", flush=True)
        waiter = asyncio.create_task(stop.wait())
        done, _ = await asyncio.wait({task, waiter}, return_when=asyncio.FIRST_COMPLETED)
        if task in done and task.exception() is not None:
            raise UsageError(f"cannot serve on {where}: {task.exception()}")
        await simulator.stop()
        task.cancel()
        with contextlib.suppress(asyncio.CancelledError, Exception):
            await task
        print(f"regmap simulate: stopped after {simulator.stats.frames_received} requests", flush=True)

    asyncio.run(main())
    return 0
