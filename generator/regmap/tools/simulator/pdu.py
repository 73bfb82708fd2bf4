"""Modbus PDU dispatch: one request PDU in, the answer PDU out, with the exception a conformant slave gives.

The checks follow the Modbus Application Protocol v1.1b3 §6 in its order: function code supported
(else 0x01), quantity and byte count (else 0x03; for 0x05 a value other than FF 00/00 00), address
range (else 0x02), then the device's own rules (`DeviceStore`: an address the map does not document
in that space, or a register the simulated firmware lacks, 0x02; read-only or out-of-range value
0x03). An injected `exception` fault (device failure, 0x04) comes after the address checks, as the
spec's processing does, for every function. The map's limits narrow the spec's: `max_read_registers` (0x03/0x04), `max_write_registers`,
`max_read_coils` (0x01/0x02), `max_write_coils` (0x0F) and `max_message_bytes` are quantity limits,
refused with 0x03 like the spec's 125/123/2000/1968. Input registers and discrete inputs have no
write function, so a write to them is a function the space lacks. The exception codes are the spec's;
every map that lists exceptions gives these codes the same meaning (the maps' `transport.exceptions` say where their manuals agree).
"""

from __future__ import annotations

import functools
import struct
from collections.abc import Callable

from regmap.model import Device
from regmap_runtime.rtu import (
    DIAGNOSTICS,
    ENCAPSULATED_INTERFACE,
    EXCEPTION_FLAG,
    MAX_READ_WRITE_REGISTERS,
    READ_DEVICE_ID,
    READ_WRITE_MULTIPLE,
    READS,
    REPORT_SERVER_ID,
    RETURN_QUERY_DATA,
    WRITES_MULTIPLE,
    WRITES_SINGLE,
    pack_bits,
    unpack_bits,
)
from regmap_runtime.spaces import COIL_OFF, COIL_ON, HOLDING, MASK_WRITE_REGISTER, MAX_READ_BITS, MAX_WRITE_BITS, Space

from .quirks import Quirks
from .store import ILLEGAL_ADDRESS, ILLEGAL_FUNCTION, ILLEGAL_VALUE, DeviceStore

IMPLEMENTED = (
    *READS,
    *WRITES_SINGLE,
    *WRITES_MULTIPLE,
    MASK_WRITE_REGISTER,
    DIAGNOSTICS,
    REPORT_SERVER_ID,
    READ_WRITE_MULTIPLE,
    ENCAPSULATED_INTERFACE,
)
SPEC_MAX_READ = 125  # §6.3
SPEC_MAX_WRITE = 123  # §6.12
MAX_PDU = 253
RTU_OVERHEAD = 3  # slave id + CRC around a PDU; a map's max_message_bytes counts the RTU frame

# Request length of an RTU frame by function code, for the public functions of §5.1 whose request
# has a fixed size (slave id, function, data, CRC). Functions that carry a byte count are in
# `_BYTE_COUNTED`: (offset of the byte count, bytes around the counted data).
_FIXED = {0x01: 8, 0x02: 8, 0x03: 8, 0x04: 8, 0x05: 8, 0x06: 8, 0x07: 4, 0x08: 8, 0x0B: 4, 0x0C: 4, 0x11: 4, 0x16: 10, 0x18: 6}
_BYTE_COUNTED = {0x0F: (6, 9), 0x10: (6, 9), 0x14: (2, 5), 0x15: (2, 5), 0x17: (10, 13)}
NEED_MORE = 0


def rtu_request_length(buf: bytes | bytearray) -> int | None:
    """Length of the RTU request frame at the start of `buf`: NEED_MORE until enough bytes tell,
    None for a function whose request length is not fixed by the spec (only the line's silence ends it)."""
    if len(buf) < 2:
        return NEED_MORE
    function = buf[1]
    if function in _FIXED:
        return _FIXED[function]
    if function in _BYTE_COUNTED:
        at, around = _BYTE_COUNTED[function]
        return around + buf[at] if len(buf) > at else NEED_MORE
    if function == 0x2B:  # encapsulated interface: read device identification is 7 bytes
        if len(buf) < 3:
            return NEED_MORE
        return 7 if buf[2] == 0x0E else None
    return None


_TWO_WORDS = struct.Struct(">HH")


@functools.cache
def _words_answer(count: int) -> struct.Struct:
    """A read answer of `count` registers: function, byte count, the words."""
    return struct.Struct(f">BB{count}H")


def exception_pdu(function: int, code: int) -> bytes:
    return bytes([(function | EXCEPTION_FLAG) & 0xFF, code])


class Dispatcher:
    """Answers request PDUs for one device."""

    def __init__(self, device: Device, store: DeviceStore, quirks: Quirks | None = None) -> None:
        t = device.transport
        self.store = store
        self.functions = frozenset(t.function_codes) & frozenset(IMPLEMENTED)
        wanted = quirks.max_read if quirks is not None and quirks.max_read is not None else t.max_read_registers
        self.max_read = min(SPEC_MAX_READ, wanted)
        self.max_write = min(SPEC_MAX_WRITE, t.max_write_registers)
        self.max_read_bits = min(MAX_READ_BITS, t.max_read_coils)
        self.max_write_bits = min(MAX_WRITE_BITS, t.max_write_coils)
        self.max_bytes = t.max_message_bytes
        self.identification = t.identification
        self.server_id = t.server_id
        handlers: dict[int, Callable[[bytes], bytes]] = {
            MASK_WRITE_REGISTER: self._mask_write,
            DIAGNOSTICS: self._diagnostics,
            REPORT_SERVER_ID: self._report_server_id,
            READ_WRITE_MULTIPLE: self._read_write_multiple,
            ENCAPSULATED_INTERFACE: self._encapsulated,
        }
        for code, space in READS.items():
            handlers[code] = functools.partial(self._read_bits if space.bits else self._read, space=space)
        for code, space in WRITES_SINGLE.items():
            handlers[code] = functools.partial(self._write_coil if space.bits else self._write_single, space=space)
        for code, space in WRITES_MULTIPLE.items():
            handlers[code] = functools.partial(self._write_coils if space.bits else self._write_multiple, space=space)
        # Only the functions the map lists: any other is 0x01. One look-up per request, the hot path of a polling client.
        self._handlers = {code: handler for code, handler in handlers.items() if code in self.functions}

    def answer(self, pdu: bytes) -> bytes:
        """The answer PDU (a normal response or `function | 0x80, code`)."""
        function = pdu[0]
        handler = self._handlers.get(function)
        if handler is None:
            return exception_pdu(function, ILLEGAL_FUNCTION)
        if self.max_bytes is not None and len(pdu) + RTU_OVERHEAD > self.max_bytes:
            # Longer than the device takes in one message. The spec has no code for a frame too long;
            # every such request of these functions asks for more registers than the map allows, so
            # it is the quantity error (0x03), as a request of that quantity is.
            return exception_pdu(function, ILLEGAL_VALUE)
        return handler(pdu)

    # -- registers: 0x03, 0x04 (§6.3, §6.4), 0x06 (§6.6), 0x10 (§6.12) ---------------------

    def _read(self, pdu: bytes, space: Space) -> bytes:
        function = pdu[0]
        if len(pdu) != 5:
            return exception_pdu(function, ILLEGAL_VALUE)
        address, count = _TWO_WORDS.unpack_from(pdu, 1)
        if not 1 <= count <= self.max_read:
            return exception_pdu(function, ILLEGAL_VALUE)
        if address + count > 0x10000:
            return exception_pdu(function, ILLEGAL_ADDRESS)
        words = self.store.read(address, count, space.name)
        if isinstance(words, int):
            return exception_pdu(function, words)
        return _words_answer(count).pack(function, 2 * count, *words)

    def _write_single(self, pdu: bytes, space: Space) -> bytes:
        function = pdu[0]
        if len(pdu) != 5:
            return exception_pdu(function, ILLEGAL_VALUE)
        address, word = struct.unpack(">HH", pdu[1:5])
        refused = self.store.write(address, [word], space.name)
        return pdu if refused is None else exception_pdu(function, refused)

    def _write_multiple(self, pdu: bytes, space: Space) -> bytes:
        function = pdu[0]
        if len(pdu) < 6:
            return exception_pdu(function, ILLEGAL_VALUE)
        address, count, byte_count = struct.unpack(">HHB", pdu[1:6])
        if not 1 <= count <= self.max_write or byte_count != 2 * count or len(pdu) != 6 + byte_count:
            return exception_pdu(function, ILLEGAL_VALUE)
        if address + count > 0x10000:
            return exception_pdu(function, ILLEGAL_ADDRESS)
        words = list(struct.unpack(f">{count}H", pdu[6:]))
        refused = self.store.write(address, words, space.name)
        return pdu[:5] if refused is None else exception_pdu(function, refused)

    def _mask_write(self, pdu: bytes) -> bytes:
        """0x16 (§6.16): the register becomes (current AND and_mask) OR (or_mask AND NOT and_mask); the answer echoes the request."""
        function = pdu[0]
        if len(pdu) != 7:
            return exception_pdu(function, ILLEGAL_VALUE)
        address, and_mask, or_mask = struct.unpack(">HHH", pdu[1:7])
        current = self.store.words.get((HOLDING.name, address), 0)  # the device's own word, write-only or not
        refused = self.store.write(address, [(current & and_mask) | (or_mask & ~and_mask & 0xFFFF)], HOLDING.name)
        return pdu if refused is None else exception_pdu(function, refused)

    # -- bits: 0x01, 0x02 (§6.1, §6.2), 0x05 (§6.5), 0x0F (§6.11) ---------------------------

    def _read_bits(self, pdu: bytes, space: Space) -> bytes:
        function = pdu[0]
        if len(pdu) != 5:
            return exception_pdu(function, ILLEGAL_VALUE)
        address, count = struct.unpack(">HH", pdu[1:5])
        if not 1 <= count <= self.max_read_bits:
            return exception_pdu(function, ILLEGAL_VALUE)
        if address + count > 0x10000:
            return exception_pdu(function, ILLEGAL_ADDRESS)
        bits = self.store.read(address, count, space.name)
        if isinstance(bits, int):
            return exception_pdu(function, bits)
        data = pack_bits(bits)  # LSB first, the last byte's unused bits zero
        return bytes([function, len(data)]) + data

    def _write_coil(self, pdu: bytes, space: Space) -> bytes:
        function = pdu[0]
        if len(pdu) != 5:
            return exception_pdu(function, ILLEGAL_VALUE)
        address, value = struct.unpack(">HH", pdu[1:5])
        if value not in (COIL_ON, COIL_OFF):  # §6.5: FF 00 or 00 00, any other value is illegal
            return exception_pdu(function, ILLEGAL_VALUE)
        refused = self.store.write(address, [1 if value == COIL_ON else 0], space.name)
        return pdu if refused is None else exception_pdu(function, refused)

    def _write_coils(self, pdu: bytes, space: Space) -> bytes:
        function = pdu[0]
        if len(pdu) < 6:
            return exception_pdu(function, ILLEGAL_VALUE)
        address, count, count_byte = struct.unpack(">HHB", pdu[1:6])
        if not 1 <= count <= self.max_write_bits or count_byte != (count + 7) // 8 or len(pdu) != 6 + count_byte:
            return exception_pdu(function, ILLEGAL_VALUE)
        if address + count > 0x10000:
            return exception_pdu(function, ILLEGAL_ADDRESS)
        refused = self.store.write(address, list(unpack_bits(pdu[6:], count)), space.name)
        return pdu[:5] if refused is None else exception_pdu(function, refused)

    # -- 0x08 diagnostics (§6.8), 0x11 report server id (§6.13) ---------------------------

    def _diagnostics(self, pdu: bytes) -> bytes:
        if len(pdu) < 3:
            return exception_pdu(pdu[0], ILLEGAL_VALUE)
        if struct.unpack(">H", pdu[1:3])[0] != RETURN_QUERY_DATA:
            return exception_pdu(pdu[0], ILLEGAL_FUNCTION)  # a sub-function the device does not have
        if self.store.failing():
            return exception_pdu(pdu[0], self.store.faults.exception_code)
        return pdu  # the query data echoed

    def _report_server_id(self, pdu: bytes) -> bytes:
        if len(pdu) != 1 or self.server_id is None:
            return exception_pdu(pdu[0], ILLEGAL_VALUE)
        if self.store.failing():
            return exception_pdu(pdu[0], self.store.faults.exception_code)
        s = self.server_id
        data = s.id + bytes([0xFF if s.running else 0x00]) + s.additional_data.encode("ascii")
        return bytes([pdu[0], len(data)]) + data

    # -- 0x17 read/write multiple registers (§6.17): the write is done before the read -------

    def _read_write_multiple(self, pdu: bytes) -> bytes:
        function = pdu[0]
        if len(pdu) < 10:
            return exception_pdu(function, ILLEGAL_VALUE)
        read_at, read_count, write_at, write_count, byte_count = struct.unpack(">HHHHB", pdu[1:10])
        if (
            not 1 <= read_count <= self.max_read
            or not 1 <= write_count <= min(MAX_READ_WRITE_REGISTERS, self.max_write)
            or byte_count != 2 * write_count
            or len(pdu) != 10 + byte_count
        ):
            return exception_pdu(function, ILLEGAL_VALUE)
        if read_at + read_count > 0x10000 or write_at + write_count > 0x10000:
            return exception_pdu(function, ILLEGAL_ADDRESS)
        refused = self.store.unreadable(read_at, read_count, "holding")  # checked first: nothing written for a read refused
        if refused is None:
            refused = self.store.write(write_at, list(struct.unpack(f">{write_count}H", pdu[10:])), "holding")
        if refused is not None:
            return exception_pdu(function, refused)
        words = self.store.read(read_at, read_count, "holding")
        if isinstance(words, int):
            return exception_pdu(function, words)
        return bytes([function, 2 * read_count]) + struct.pack(f">{read_count}H", *words)

    # -- 0x2B / 0x0E read device identification (§6.21) ------------------------------------

    def _encapsulated(self, pdu: bytes) -> bytes:
        function = pdu[0]
        if len(pdu) < 2 or pdu[1] != READ_DEVICE_ID or self.identification is None:
            return exception_pdu(function, ILLEGAL_FUNCTION)  # an MEI type the device does not implement
        if len(pdu) != 4 or not 1 <= pdu[2] <= 4:
            return exception_pdu(function, ILLEGAL_VALUE)
        access, wanted = pdu[2], pdu[3]
        objects = dict(self.identification.objects)
        level = self.identification.conformity_level
        if access == 4 and wanted not in objects:  # one object, individually
            return exception_pdu(function, ILLEGAL_ADDRESS)
        if self.store.failing():
            return exception_pdu(function, self.store.faults.exception_code)
        if access == 4:
            chosen = [wanted]
        else:  # a stream: basic (1), regular (2), extended (3); an unknown start restarts at object 0
            last = {1: 0x02, 2: 0x7F, 3: 0xFF}[access]
            ids = [i for i in sorted(objects) if i <= last]
            chosen = [i for i in ids if i >= wanted] if wanted in objects else ids
        header = bytes([function, READ_DEVICE_ID, access, level])
        body, more, next_id, count = b"", 0x00, 0x00, 0
        for object_id in chosen:
            value = objects[object_id].encode("ascii", "replace")
            item = bytes([object_id, len(value)]) + value
            if len(header) + 3 + len(body) + len(item) > MAX_PDU and count:  # the rest in the next answer
                more, next_id = 0xFF, object_id
                break
            body += item
            count += 1
        return header + bytes([more, next_id, count]) + body

    @staticmethod
    def writes(pdu: bytes) -> bool:
        """A request a broadcast may carry (§4.1: broadcast requests are writes)."""
        return pdu[0] in WRITES_SINGLE or pdu[0] in WRITES_MULTIPLE or pdu[0] == MASK_WRITE_REGISTER
