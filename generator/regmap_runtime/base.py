"""The clients' core: everything that does not touch the bus (value checks, encoding, request planning,
firmware gates, the arguments of each function), shared by `client.SyncClient` and `client.AsyncClient`."""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from typing import Any, TypeVar, cast

from pymodbus import FramerType
from pymodbus.client import AsyncModbusSerialClient, ModbusSerialClient
from pymodbus.exceptions import ConnectionException, ModbusIOException
from pymodbus.exceptions import ModbusException as PymodbusError
from pymodbus.pdu import ExceptionResponse

from .bits import BitfieldValue
from .codec import RangeError, check_raw, decode_value, value_to_raw, words_to_raw
from .errors import AccessError, DeviceException, FirmwareError, ProtocolError, RegmapError
from .plan import ReadBlock, WriteBlock, plan_reads, plan_writes
from .profile import DeviceProfile
from .rtu import (
    DEVICE_ID_CODES,
    MAX_READ_WRITE_REGISTERS,
    READ_WRITE_MULTIPLE,
    STANDARD_EXCEPTIONS,
)
from .scaling import scaled, unscaled
from .spaces import HOLDING, MASK_WRITE_REGISTER, SPACES
from .spec import DeviceSpec, Raw, Readable, RegisterSpec, Writable, poll_class, refuse_absent
from .wire import (
    PYMODBUS_METHODS,
    LineWatch,
    mask_write_masks,
    may_repeat,
    outcome_unknown,
    serial_settings,
    transport_error,
)

T = TypeVar("T")
B = TypeVar("B", bound=BitfieldValue)
K = TypeVar("K", bound="ClientCore")
WriteTarget = tuple[str, int, list[int] | tuple[int, ...]]  # a write's space, first address and words
ECHO_WORD = 0xA537  # the query data echo() sends unless told (the spec's example carries A5 37)


class ClientCore:
    """Everything that does not touch the bus: value checks, encoding, request planning, firmware gates."""

    DEVICE: DeviceSpec
    modbus: Any  # the pymodbus client of the subclass
    # pymodbus's client classes the subclass drives: one pair of constructors serves sync and async.
    SERIAL_TRANSPORT: Any
    TCP_TRANSPORT: Any

    def __init__(
        self,
        modbus: Any,
        slave: int = 1,
        word_order: str | None = None,
        line: LineWatch | None = None,
        profile: DeviceProfile | None = None,
        *,
        check_firmware: bool = False,
        retries: int = 0,
        variant: str | None = None,
    ) -> None:
        if not 0 <= slave <= 255:
            raise ValueError(f"slave id {slave} is outside 0..255")
        self.variant = type(self).DEVICE.check_variant(variant)  # registers it lacks: refused, left out of read_all()
        if profile is not None:
            # What `regmap probe` observed: the read limit, the gaps proven readable, the word order (ProfileError for another map).
            self.DEVICE = profile.apply(type(self).DEVICE)
        self.profile = profile
        self.slave = slave
        self.word_order = word_order or (profile.word_order if profile is not None else None) or self.DEVICE.word_order
        self.requests_sent = 0
        self.retries = retries
        """How often a read, or a write of settings, is sent again after a lost answer; commands and triggers never are."""
        self._plans: dict[tuple[str, ...], list[ReadBlock]] = {}
        self.modbus = modbus
        self.line = line or LineWatch(rtu_framing=False)
        self.check_firmware = check_firmware
        self.firmware: tuple[int, ...] | None = None
        """The firmware version the device reported (check_firmware=True, once read), e.g. (2, 3)."""
        self.firmware_text: str | None = None
        """The same version as the device's documents write it, e.g. "1.25"."""
        self._documented = self.DEVICE.documented if variant is None else self.DEVICE.documented_in(None, variant)
        self._firmware_spec: RegisterSpec[Any] | None = None
        if check_firmware:
            name = self.DEVICE.firmware_register
            if name is None:
                raise FirmwareError(
                    f"{self.DEVICE.id}: check_firmware=True, but the map names no firmware register (device.firmware_register)"
                )
            if self.broadcast:
                raise FirmwareError(f"check_firmware=True: a broadcast (slave {slave}) cannot read the firmware register {name}")
            self._firmware_spec = next(r for r in self.DEVICE.registers if r.name == name)

    @classmethod
    def rtu(
        cls: type[K],
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
        check_firmware: bool = False,
        variant: str | None = None,
    ) -> K:
        """Serial RTU; port settings default to the map's transport settings. `check_firmware`: read the
        firmware register on connect and refuse the registers that firmware lacks. `retries`: a read or a
        setting is sent again after a lost answer; a command or trigger write goes out once (OutcomeUnknown)."""
        line = LineWatch(rtu_framing=True)
        settings = serial_settings(cls.DEVICE, baud, parity, stop_bits)
        modbus = cls.SERIAL_TRANSPORT(port, **settings, timeout=timeout, retries=0, trace_packet=line)
        return cls(modbus, slave, word_order, line, profile, check_firmware=check_firmware, retries=retries, variant=variant)

    @classmethod
    def tcp(
        cls: type[K],
        host: str,
        port: int = 502,
        slave: int = 1,
        *,
        timeout: float = 1.0,
        retries: int = 2,
        word_order: str | None = None,
        rtu_over_tcp: bool = False,
        profile: DeviceProfile | None = None,
        check_firmware: bool = False,
        variant: str | None = None,
    ) -> K:
        """Modbus TCP (gateways, simulators); `rtu_over_tcp` for transparent serial-to-Ethernet converters.
        `check_firmware`: read the firmware register on connect and refuse the registers that firmware lacks.
        `retries`: as for rtu(); commands and trigger writes are never sent again."""
        framer = FramerType.RTU if rtu_over_tcp else FramerType.SOCKET
        line = LineWatch(rtu_framing=rtu_over_tcp)
        modbus = cls.TCP_TRANSPORT(host, port=port, framer=framer, timeout=timeout, retries=0, trace_packet=line)
        return cls(modbus, slave, word_order, line, profile, check_firmware=check_firmware, retries=retries, variant=variant)

    def transport_error(self, exc: Exception) -> RegmapError:
        """A typed error saying what happened on the line (`wire.transport_error`)."""
        return transport_error(self.line, self.slave, exc)

    def _tries(self, write: WriteTarget | None, once: bool = False) -> int:
        """How often a request may go out: a read, or a write of settings, 1 + `retries`; a write that
        must not be repeated (a command, a trigger register, an address the map does not describe,
        any read/write multiple: `once`) once."""
        if write is not None and (once or self.broadcast or not may_repeat(self.DEVICE.registers, *write)):
            return 1
        return 1 + self.retries

    def _failure(
        self, exc: PymodbusError, write: WriteTarget | None, again: bool, sent_before: int, once: bool = False
    ) -> RegmapError | None:
        """None: send the request again; else the error to raise. A write sent once whose answer is lost
        is OutcomeUnknown (a connection that never opened sent nothing)."""
        if again and isinstance(exc, ModbusIOException):
            return None
        error = self.transport_error(exc)
        went_out = not isinstance(exc, ConnectionException) or getattr(self.line, "packets_sent", sent_before) > sent_before
        if write is not None and went_out and (once or not may_repeat(self.DEVICE.registers, *write)):
            return outcome_unknown(self.DEVICE.registers, *write, error)
        return error

    @property
    def where(self) -> str:
        """The port or HOST:PORT, as the user gave it (pymodbus's str() starts with its class name)."""
        params = getattr(self.modbus, "comm_params", None)
        if params is None:  # a stand-in for pymodbus's client (a test double)
            return str(self.modbus)
        return str(params.host) if isinstance(self.modbus, ModbusSerialClient | AsyncModbusSerialClient) else f"{params.host}:{params.port}"

    @property
    def broadcast(self) -> bool:
        return self.DEVICE.broadcast_id is not None and self.slave == self.DEVICE.broadcast_id

    def effective(self, spec: RegisterSpec[T]) -> RegisterSpec[T]:
        """The spec with the word order this client was told the device uses (a device with a word-order register, `transport.word_order_register` in its map)."""
        return spec.in_word_order(self.word_order)

    def check_aligned(self, space: str, address: int, count: int) -> None:
        """Refuse a read the device's read alignment forbids (`transport.read_alignment`): nothing is sent."""
        alignment = self.DEVICE.alignment
        why = None if alignment is None else alignment.refusal(space, address, count)
        if why is not None:
            raise AccessError(f"{self.DEVICE.id}: {why}: nothing was sent")

    def word_order_write(self, order: str) -> tuple[RegisterSpec[Any], Raw] | None:
        """What `set_word_order(order)` writes to the word-order register: the map's value for `order`, or its
        swap value when the device uses the other order now (as this client knows it); None: nothing to write."""
        name = self.DEVICE.word_order_register
        if name is None:
            raise AccessError(f"{self.DEVICE.id} has no word-order register: its map fixes the word order ({self.DEVICE.word_order})")
        if order not in ("high_first", "low_first"):
            raise ValueError(f"word order {order!r}: high_first or low_first")
        high, low, swap = self.DEVICE.word_order_values
        spec = next(r for r in self.DEVICE.registers if r.name == name)
        if swap is not None:
            return None if order == self.word_order else (spec, swap)
        value = high if order == "high_first" else low
        assert value is not None  # a map without swap_value gives both values
        return spec, value

    # -- firmware gates ------------------------------------------------------------------------

    @property
    def firmware_pending(self) -> bool:
        """check_firmware=True and the version not read yet: the next request reads it first."""
        return self.check_firmware and self.firmware is None

    def firmware_block(self) -> ReadBlock:
        """The read of the firmware register."""
        spec = self._firmware_spec
        if spec is None:
            raise FirmwareError(f"{self.DEVICE.id}: this client was not asked to check the firmware (check_firmware=True)")
        return ReadBlock(spec.address, spec.words, (spec,), spec.space)

    def learn_firmware(self, words: list[int]) -> tuple[int, ...]:
        """Keep the version the firmware register's words report; from now on plans and checks follow it."""
        spec = self.effective(self.firmware_block().registers[0])
        raw = words_to_raw(spec, words)
        try:
            version = self.DEVICE.firmware_version(raw)
            text = self.DEVICE.firmware_text(raw)
        except ValueError as exc:
            raise FirmwareError(
                f"the firmware register {spec.label} holds {raw!r}, which is not a version ({exc})", found=str(raw)
            ) from None
        self.firmware, self.firmware_text = version, text
        self._documented = self.DEVICE.documented_in(version, self.variant)
        self._plans.clear()
        return version

    def check_exists(self, spec: RegisterSpec[Any]) -> None:
        """Refuse a register the connected firmware or variant lacks (nothing is sent)."""
        refuse_absent(spec, self.firmware, self.firmware_text, self.variant)

    # -- values --------------------------------------------------------------------------------

    def check_writable(self, spec: RegisterSpec[Any]) -> None:
        if not spec.space_info.writable:
            raise AccessError(f"{spec.label} is read-only ({spec.space_info.title} cannot be written): nothing was sent")
        if not spec.writable:
            raise AccessError(f"{spec.label} is read-only: nothing was sent")

    def encode(self, spec: RegisterSpec[Any], value: Any, factors: Mapping[str, Any] | None = None) -> Raw:
        """`factors`: scale factors read fresh for this write, by name (a `scale_from` register needs its own)."""
        self.check_writable(spec)
        if spec.scale_from is not None:
            if factors is None or spec.scale_from not in factors:
                raise RangeError(f"{spec.label}: its scale factor {spec.scale_from} must be read for this write: nothing was sent")
            raw: Raw = unscaled(spec, value, factors[spec.scale_from])
            check_raw(spec, raw)
            return raw
        if spec.bitfield_type is not None and isinstance(value, spec.bitfield_type):
            raw = int(value.to_raw())
            check_raw(spec, raw)
            return raw
        return value_to_raw(spec, value)

    def encode_raw(self, spec: RegisterSpec[Any], raw: Raw) -> Raw:
        self.check_writable(spec)
        raw = raw if isinstance(raw, str | float) else int(raw)
        check_raw(spec, raw)
        return raw

    def decode(self, spec: RegisterSpec[T], words: list[int]) -> T:
        spec = self.effective(spec)
        raw = words_to_raw(spec, words)
        if spec.bitfield_type is not None:
            return cast(T, spec.bitfield_type.from_raw(raw))
        return cast(T, decode_value(spec, raw))

    # -- planning ------------------------------------------------------------------------------

    def plan_reads(self, specs: Iterable[RegisterSpec[Any]]) -> list[ReadBlock]:
        """The requests for these registers, per space within its limit; plans are kept, so a polling loop plans once."""
        chosen = tuple(specs)
        key = tuple(spec.name for spec in chosen)
        plan = self._plans.get(key)
        if plan is None:
            for spec in chosen:
                if not spec.readable:
                    raise AccessError(f"{spec.label} is write-only: nothing was sent")
                self.check_exists(spec)
            device = self.DEVICE
            plan = plan_reads(
                chosen, device.max_read_registers, self._documented, max_bits=device.max_read_coils, alignment=device.alignment
            )
            self._plans[key] = plan
        return plan

    def plan_writes(
        self,
        values: Mapping[Writable[Any], Any],
        raw: bool = False,
        *,
        grouped: bool | None = None,
        factors: Mapping[str, Any] | None = None,
    ) -> list[WriteBlock]:
        """Check and encode every value, then group them into requests, space by space. `raw`: values are register integers;
        `grouped`: contiguous registers in one block (default: where the device lists the space's write multiple);
        `factors`: the scale factors the values of `scale_from` registers were read with just now."""
        by_space: dict[str, list[tuple[RegisterSpec[Any], Raw]]] = {}
        for spec, value in values.items():
            self.check_writable(spec)
            self.check_exists(spec)
            encoded = self.encode_raw(spec, value) if raw else self.encode(spec, value, factors)
            by_space.setdefault(spec.space, []).append((self.effective(spec), encoded))
        device = self.DEVICE
        blocks: list[WriteBlock] = []
        for space in SPACES:
            if space in by_space:
                together = SPACES[space].write_multiple in device.function_codes if grouped is None else grouped
                blocks += plan_writes(by_space[space], device.max_write_registers, together, max_bits=device.max_write_coils)
        return blocks

    def masked(self, spec: RegisterSpec[Any], fields: Mapping[str, Any]) -> tuple[int, int] | None:
        """(AND mask, OR mask) of the one mask write (0x16) that sets only the named fields, where the device
        lists 0x16 and the register is one holding word with no range of its own; None: read-modify-write."""
        if MASK_WRITE_REGISTER not in self.DEVICE.function_codes or self.broadcast:
            return None
        if spec.space != HOLDING.name or spec.words != 1 or spec.paired or spec.min is not None or spec.max is not None:
            return None
        self.check_writable(spec)
        return mask_write_masks(spec, fields)

    def check_listed(self, function: int, what: str) -> None:
        """Refuse a function the map does not list, or one whose answer a broadcast would never bring (nothing is sent)."""
        if function not in self.DEVICE.function_codes:
            raise AccessError(f"{self.DEVICE.id} does not list function 0x{function:02X} ({what}): nothing was sent")
        if self.broadcast:
            raise ValueError(f"a broadcast cannot {what}: no answer comes back")

    def read_write_plan(
        self, writes: Mapping[Writable[Any], Any], reads: Iterable[Readable[Any]], raw: bool = False
    ) -> tuple[WriteBlock, ReadBlock]:
        """The one write and the one read of a read/write multiple (0x17): each value checked and encoded
        as `write_many` does, each a contiguous run of holding registers within the limits; else nothing is sent."""
        self.check_listed(READ_WRITE_MULTIPLE, "read/write multiple registers")
        written = self.plan_writes(writes, raw, grouped=True)
        read = self.plan_reads(reads)
        if len(written) != 1 or written[0].space != HOLDING.name or len(written[0].words) > MAX_READ_WRITE_REGISTERS:
            raise ValueError(
                f"read/write multiple writes one run of at most {MAX_READ_WRITE_REGISTERS} adjacent holding registers"
                f" ({', '.join(spec.label for spec in writes)} are not): nothing was sent"
            )
        if len(read) != 1 or read[0].space != HOLDING.name:
            raise ValueError("read/write multiple reads one block of adjacent holding registers within the read limit: nothing was sent")
        return written[0], read[0]

    @staticmethod
    def read_write_arguments(written: WriteBlock, read: ReadBlock) -> dict[str, Any]:
        """pymodbus's arguments for the 0x17 of `read_write_plan`, and the write sent once (OutcomeUnknown if its answer is lost)."""
        return {
            "read_address": read.address,
            "read_count": read.count,
            "write_address": written.address,
            "values": list(written.words),
            "write": (HOLDING.name, written.address, written.words),
            "once": True,
        }

    def values_of(self, block: ReadBlock, words: list[int], factors: Mapping[str, Any] | None = None) -> dict[str, Any]:
        """Each register of a read block decoded from the block's words; a `scale_from` register scaled by its
        scale factor from `factors` (read in another block) or from this block, else refused, never shown raw."""
        values = {spec.name: self.decode(spec, block.words_of(spec, words)) for spec in block.registers}
        for spec in block.registers:
            if spec.scale_from is not None:
                known = {**(factors or {}), **values}
                if spec.scale_from not in known:
                    raise ValueError(f"{spec.label}: its scale factor {spec.scale_from} was not read with it")
                values[spec.name] = scaled(values[spec.name], known[spec.scale_from])
        return values

    def scale_factors(self, specs: Iterable[RegisterSpec[Any]]) -> list[RegisterSpec[Any]]:
        """The scale-factor registers of the `scale_from` registers among `specs`, each once."""
        wanted = {spec.scale_from for spec in specs if spec.scale_from is not None}
        return [r for r in self.DEVICE.registers if r.name in wanted] if wanted else []  # most maps have none: no scan

    def with_scale_factors(self, specs: Iterable[Readable[Any]]) -> list[Readable[Any]]:
        """`specs` and the scale factors they need, so that one plan reads a point with its sf (one request where it can)."""
        chosen = list(specs)
        names = {spec.name for spec in chosen}
        return chosen + cast(list[Readable[Any]], [sf for sf in self.scale_factors(chosen) if sf.name not in names])

    def values_read(self, read: list[tuple[ReadBlock, list[int]]], specs: Iterable[RegisterSpec[Any]]) -> dict[str, Any]:
        """The values of `specs` from the blocks read (`with_scale_factors`'s plan): scale factors first, then the rest."""
        factor_names = {sf.name for sf in self.scale_factors([spec for block, _ in read for spec in block.registers])}
        factors = {
            spec.name: self.decode(spec, block.words_of(spec, words))
            for block, words in read
            for spec in block.registers
            if spec.name in factor_names
        }
        values: dict[str, Any] = {}
        for block, words in read:
            values.update(self.values_of(block, words, factors))
        names = {spec.name for spec in specs}
        return {name: value for name, value in values.items() if name in names}

    def echoed(self, word: int, response: Any) -> int:
        """The word return query data sent back; a device that echoes something else is a ProtocolError."""
        sent = word.to_bytes(2, "big")
        got = bytes(getattr(response, "message", b"") or b"")
        if got != sent:
            raise ProtocolError(f"return query data sent {sent.hex(' ').upper()}, the device echoed {got.hex(' ').upper() or 'nothing'}")
        return word

    @staticmethod
    def identification_code(level: str) -> int:
        code = DEVICE_ID_CODES.get(level)
        if code is None or level not in ("basic", "regular"):
            raise ValueError(f"identification level {level!r}: basic or regular")
        return code

    def readable(self, poll: object = None) -> list[RegisterSpec[Any]]:
        """The registers read_all() reads: every readable one (of one poll class, if given) the firmware has."""
        cls = None if poll is None else poll_class(poll)
        return [
            r for r in self.DEVICE.registers if r.readable and (cls is None or r.poll == cls) and r.present(self.firmware, self.variant)
        ]

    # -- the wire ------------------------------------------------------------------------------

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

    def writer(self, space: str, single: bool) -> tuple[int, Any, bool]:
        """The function code and the pymodbus method of a write to `space`, and whether it is the
        single write (0x06/0x05): one word goes single unless the device lists only the multiple write."""
        facts = SPACES[space]
        if not facts.writable:
            raise AccessError(f"{facts.title} cannot be written: nothing was sent")
        codes = self.DEVICE.function_codes
        if single and facts.write_single not in codes and facts.write_multiple in codes:
            single = False
        function = facts.write_single if single else facts.write_multiple
        method = PYMODBUS_METHODS[space][1 if single else 2]
        assert function is not None and method is not None  # a writable space has both writes
        return function, getattr(self.modbus, method), single

    def write_args(self, space: str, address: int, words: list[int] | tuple[int, ...], single: bool) -> tuple[Any, ...]:
        """pymodbus's arguments for a write: register words, or coils as booleans (0/1 in, so that a
        stray 0xFF00 is not taken for "on" silently)."""
        if not SPACES[space].bits:
            return (address, words[0] if single else list(words))
        if any(w not in (0, 1) for w in words):
            raise ValueError(f"a coil is written as 0 or 1, got {list(words)}")
        return (address, bool(words[0]) if single else [bool(w) for w in words])

    def read_words(self, response: Any, block: ReadBlock) -> list[int]:
        """The block's words from a read response: registers, or (coils, discrete inputs) one 0/1 per
        address, the answer's padding bits cut off."""
        if SPACES[block.space].bits:
            bits = list(getattr(response, "bits", []))
            if len(bits) < block.count:
                raise ProtocolError(f"asked for {block.count} bits at 0x{block.address:04X}, got {len(bits)}")
            return [1 if bit else 0 for bit in bits[: block.count]]
        words = list(getattr(response, "registers", []))
        if len(words) != block.count:
            raise ProtocolError(f"asked for {block.count} registers at 0x{block.address:04X}, got {len(words)}")
        return words
