"""The transport part of the model: line settings, function codes, limits, exceptions and identification."""

from __future__ import annotations

from typing import TYPE_CHECKING

from regmap.kinds import ByteOrder, WordOrder
from regmap.records import dataclass

if TYPE_CHECKING:
    from regmap.model import Register


@dataclass(frozen=True)
class ModbusException:
    code: int
    name: str
    title: str
    title_zh: str | None = None
    source: tuple[str, ...] = ()


@dataclass(frozen=True)
class TimingRow:
    baud: int
    receive_to_send_ms: float | None = None
    wait_after_receive_ms: float | None = None
    send_to_receive_ms: float | None = None
    total_ms: float | None = None


@dataclass(frozen=True)
class BadCrc:
    """What the device does with a request whose CRC is wrong: `silent` (the Modbus serial line
    spec) or `exception` with `code` (as maps/idm_rs.yaml records for its manual)."""

    reply: str = "silent"
    code: int | None = None
    source: tuple[str, ...] = ()
    notes: str = ""


@dataclass(frozen=True)
class WordOrderRegister:
    """The register that sets the word order: either a value per order (`high_first`, `low_first`), or
    one magic value (`swap_value`) whose write swaps the order, whichever it is (a trigger: sent once)."""

    register: Register
    high_first: int | float | None = None
    low_first: int | float | None = None
    swap_value: int | float | None = None

    @property
    def swaps(self) -> bool:
        return self.swap_value is not None

    def value_for(self, current: WordOrder, wanted: WordOrder) -> int | float | None:
        """What to write so that a device using `current` uses `wanted`; None: nothing (a swap already there)."""
        if self.swap_value is not None:
            return None if current is wanted else self.swap_value
        return self.high_first if wanted is WordOrder.HIGH_FIRST else self.low_first

    def order_after(self, current: WordOrder, written: int | float) -> WordOrder:
        """The word order once `written` reached the register of a device that used `current`."""
        if self.swap_value is not None:
            if written != self.swap_value:
                return current
            return WordOrder.LOW_FIRST if current is WordOrder.HIGH_FIRST else WordOrder.HIGH_FIRST
        if written == self.high_first:
            return WordOrder.HIGH_FIRST
        return WordOrder.LOW_FIRST if written == self.low_first else current


@dataclass(frozen=True)
class ReadAlignment:
    """Reads of `spaces` start on a multiple of `words` and cover a multiple of `words` (a float meter
    answers `exception` otherwise); the `exempt` registers may be read alone as the manual allows."""

    words: int
    spaces: tuple[str, ...] = ("holding", "input")
    exception: int | None = None
    exempt: tuple[Register, ...] = ()
    source: tuple[str, ...] = ()
    notes: str = ""

    def exempt_reads(self) -> tuple[tuple[str, int, int], ...]:
        """(space, first address, count) of each exempt register read alone."""
        return tuple((r.space, r.address, r.words) for r in self.exempt)


@dataclass(frozen=True)
class DeviceIdentification:
    """The objects of read device identification (0x2B/0x0E), by object id: 0x00-0x02 basic, 0x03-0x06 regular."""

    objects: tuple[tuple[int, str], ...]
    source: tuple[str, ...] = ()

    @property
    def conformity_level(self) -> int:
        """0x81 basic or 0x82 regular, both with individual access (0x04)."""
        return 0x82 if any(object_id > 0x02 for object_id, _ in self.objects) else 0x81


@dataclass(frozen=True)
class ServerId:
    """What report server id (0x11) answers: the id bytes, the run indicator, additional data."""

    id: bytes
    running: bool = True
    additional_data: str = ""
    source: tuple[str, ...] = ()


@dataclass(frozen=True)
class Transport:
    baud: int
    parity: str
    data_bits: int
    stop_bits: int
    slave_min: int
    slave_max: int
    function_codes: tuple[int, ...]
    max_read_registers: int
    max_write_registers: int
    word_order: WordOrder
    byte_order: ByteOrder = ByteOrder.HIGH_FIRST
    max_read_coils: int = 2000
    max_write_coils: int = 1968
    baud_rates: tuple[int, ...] = ()
    parities: tuple[str, ...] = ()
    broadcast_id: int | None = None
    max_message_bytes: int | None = None
    word_order_register: WordOrderRegister | None = None
    read_alignment: ReadAlignment | None = None
    crc_byte_order: str = "low_first"
    undocumented_addresses: str = "reject"
    bad_crc: BadCrc = BadCrc()
    response_delay_ms: float | None = None
    timing: tuple[TimingRow, ...] = ()
    exceptions: tuple[ModbusException, ...] = ()
    identification: DeviceIdentification | None = None
    server_id: ServerId | None = None
    source: tuple[str, ...] = ()
    notes: str = ""

    @property
    def tolerates_gaps(self) -> bool:
        return self.undocumented_addresses == "tolerate"

    def exception(self, code: int) -> ModbusException | None:
        return next((e for e in self.exceptions if e.code == code), None)
