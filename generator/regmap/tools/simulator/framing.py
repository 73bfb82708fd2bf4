"""Cutting a byte stream into requests: RTU frames (serial line, or RTU over TCP) and MBAP ADUs.

Both receivers hold at most a few hundred bytes, whatever arrives. RTU: a request whose function
fixes its length is taken as soon as its bytes and CRC are in, so back-to-back requests need no
gap; anything else (a bad CRC, a truncated frame, a function of unknown length) ends when the line
has been silent for `gap_s` — 3.5 characters on a serial port, as the Modbus serial line spec
says, longer on a pty or a socket where bytes do not arrive at the line's pace. A good frame for
this slave found after rubbish in the buffer is taken at once (resynchronisation). MBAP: a header
with a protocol id other than 0, or a length out of range, cannot be resynchronised reliably, so
the connection is closed; so is one that leaves a request incomplete for `partial_timeout_s`.
"""

from __future__ import annotations

import asyncio
import struct
from collections.abc import Callable
from typing import NamedTuple

from regmap_runtime.rtu import crc_ok

from .pdu import NEED_MORE, rtu_request_length

RTU_MAX_FRAME = 256  # Modbus serial line spec §2.5.1
RTU_BUFFER = 2 * RTU_MAX_FRAME
MBAP_HEADER = 7
MBAP_MAX_LENGTH = 254  # unit id + a PDU of at most 253 bytes
TCP_PARTIAL_TIMEOUT_S = 1.0


def rtu_gap_s(baud: int, bits_per_char: int) -> float:
    """3.5 character times; above 19200 baud the spec fixes the gap at 1.75 ms."""
    return 1.75e-3 if baud > 19200 else 3.5 * bits_per_char / baud


class RtuReceiver:
    """Feeds whole RTU frames to `on_frame`; frames with a bad CRC to `on_bad_frame`; the bytes it
    has to throw away (too short to be a frame, rubbish before a good frame) to `on_dropped`."""

    def __init__(
        self,
        loop: asyncio.AbstractEventLoop,
        gap_s: float,
        ours: Callable[[int, int], bool],
        on_frame: Callable[[bytes], None],
        on_bad_frame: Callable[[bytes], None],
        on_dropped: Callable[[bytes], None],
    ) -> None:
        self.loop = loop
        self.gap_s = gap_s
        self.ours = ours  # (slave id, function) -> a request this device would take
        self.on_frame = on_frame
        self.on_bad_frame = on_bad_frame
        self.on_dropped = on_dropped
        self.buffer = bytearray()
        self.timer: asyncio.TimerHandle | None = None

    def feed(self, data: bytes) -> None:
        self.buffer += data
        self._take_whole_frames()
        if len(self.buffer) > RTU_BUFFER:  # no frame is this long: keep only what could still start one
            cut = len(self.buffer) - RTU_MAX_FRAME
            self.on_dropped(bytes(self.buffer[:cut]))
            del self.buffer[:cut]
        if self.timer is not None:
            self.timer.cancel()
            self.timer = None
        if self.buffer:
            self.timer = self.loop.call_later(self.gap_s, self._silence)

    def close(self) -> None:
        if self.timer is not None:
            self.timer.cancel()
            self.timer = None

    def _take_whole_frames(self) -> None:
        buf = self.buffer
        while buf:
            need = rtu_request_length(buf)
            if need is not None and need != NEED_MORE and len(buf) >= need and crc_ok(bytes(buf[:need])):
                frame = bytes(buf[:need])
                del buf[:need]
                self.on_frame(frame)
                continue
            if need is not None and (need == NEED_MORE or len(buf) < need):
                return  # wait for the rest, or for the silence that says it is not coming
            start = self._resync()
            if not start:
                return
            self.on_dropped(bytes(buf[:start]))
            del buf[:start]

    def _resync(self) -> int:
        """Where a whole request for this device starts after the head of the buffer, or 0."""
        buf = self.buffer
        for i in range(1, len(buf) - 3):
            if not self.ours(buf[i], buf[i + 1]):
                continue
            need = rtu_request_length(buf[i:])
            if need and i + need <= len(buf) and crc_ok(bytes(buf[i : i + need])):
                return i
        return 0

    def _silence(self) -> None:
        """The line went quiet: what is buffered is one frame, however it ends."""
        self.timer = None
        frame = bytes(self.buffer)
        self.buffer.clear()
        if len(frame) < 4 or len(frame) > RTU_MAX_FRAME:  # no RTU frame is that short, or that long
            self.on_dropped(frame)
        elif crc_ok(frame):
            self.on_frame(frame)
        else:
            self.on_bad_frame(frame)


class Adu(NamedTuple):
    transaction: int
    protocol: int
    unit: int
    pdu: bytes
    raw: bytes  # the whole ADU as it came (header and PDU)


class MbapError(ValueError):
    """A header no Modbus TCP client sends: the connection cannot be trusted to be in step."""


MBAP_HEADER_STRUCT = _HEADER = struct.Struct(">HHHB")  # transaction, protocol, length, unit


class MbapReceiver:
    """Cuts a TCP stream into MBAP ADUs."""

    def __init__(self) -> None:
        self.buffer = bytearray()

    def feed(self, data: bytes) -> list[Adu]:
        """The whole ADUs now buffered; raises MbapError on a header that cannot be one.
        The common case, whole ADUs in one segment with nothing buffered, is cut without a copy."""
        if self.buffer:
            self.buffer += data
            data = bytes(self.buffer)
            self.buffer.clear()
        out = []
        at, size = 0, len(data)
        while size - at >= MBAP_HEADER:
            transaction, protocol, length, unit = _HEADER.unpack_from(data, at)
            if protocol != 0:
                self.buffer += data[at:]
                raise MbapError(f"MBAP protocol id {protocol} (Modbus is 0)")
            if not 2 <= length <= MBAP_MAX_LENGTH:
                self.buffer += data[at:]
                raise MbapError(f"MBAP length {length} is outside 2..{MBAP_MAX_LENGTH}")
            end = at + 6 + length
            if size < end:
                break
            raw = data[at:end] if at or end != size else data
            out.append(Adu(transaction, protocol, unit, raw[MBAP_HEADER:], raw))
            at = end
        if at < size:
            self.buffer += data[at:]
        return out

    @property
    def partial(self) -> bool:
        return bool(self.buffer)


def mbap(transaction: int, unit: int, pdu: bytes) -> bytes:
    return _HEADER.pack(transaction, 0, len(pdu) + 1, unit) + pdu
