"""A bus capture read line by line: serial monitors' hex, mbpoll -v's and pymodbus's frame lines,
timestamps and direction tags, each response paired with the request before it."""

from __future__ import annotations

import codecs
import re
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from regmap.diagnostics import UsageError
from regmap.model import Device
from regmap.tools.decode.frame import Decoded, decode_frame
from regmap_runtime.rtu import Frame, FrameError, parse_hex

_DIRECTION_TAGS = {"tx": "request", ">": "request", "->": "request", "rx": "response", "<": "response", "<-": "response"}
# A timestamp before the tag: `12:00:00.001`, `[2024-05-01 12:00:00.001]`, `2024-05-01T12:00:00Z`, `1714557600.123`.
_TIMESTAMP = re.compile(
    r"^\s*(?:\[[^\]]*\]|\d{4}-\d{2}-\d{2}[T ]\d{1,2}:\d{2}(?::\d{2}(?:[.,]\d+)?)?(?:Z|[+-]\d{2}:?\d{2})?|\d{1,2}:\d{2}:\d{2}(?:[.,]\d+)?|\d{9,}\.\d+)\s*"
)
_LIBMODBUS = re.compile(r"^(?:(?:\[[0-9A-Fa-f]{2}\])+|(?:<[0-9A-Fa-f]{2}>)+)$")
_TAG = re.compile(r"^(tx|rx|->|<-|>|<)\s*[:>]?\s*", re.I)
# pymodbus's frame logging, after its log prefix: `send: 0x1 0x3 0x1 0x91 ...`, `recv: 0x1 0x3 ... extra data: `
# (2.x: SEND:/RECV:), and `Processing: 0x1 0x3 ...` for the bytes it received (a response on a client).
_PYMODBUS = re.compile(r"\b(send|recv|processing):\s*((?:0x[0-9a-f]{1,2}\b\s*)+)", re.I)
_PYMODBUS_DIRECTIONS = {"send": "request", "recv": "response", "processing": None}


@dataclass(frozen=True)
class CaptureLine:
    number: int
    text: str
    not_utf8: tuple[int, int] | None = None  # (file offset, byte) of the first byte that is not UTF-8 text


@dataclass(frozen=True)
class CaptureError:
    line: int | None  # None: the capture as a whole (no frames at all)
    text: str
    message: str
    source: str

    def __str__(self) -> str:
        return f"{self.source}:{self.line}: {self.message}" if self.line is not None else f"{self.source}: {self.message}"

    def as_json(self) -> dict[str, Any]:
        return {"line": self.line, "text": self.text, "error": self.message, "ok": False}


@dataclass
class CaptureResult:
    frames: list[Decoded]
    errors: list[CaptureError]

    def entries(self) -> list[Decoded | CaptureError]:
        """Every frame and every line that is none, in the capture's order."""
        found: list[Decoded | CaptureError] = [*self.frames, *self.errors]
        return sorted(found, key=lambda entry: (entry.source_line if isinstance(entry, Decoded) else entry.line) or 0)


# A capture with a NUL byte is not text (UTF-16 without a BOM, a pcap, a logic analyser's own format).
BINARY_HINT = "decode wants text, one frame a line in hex, as serial monitors and `mbpoll -v` print them"


def capture_lines(data: bytes, source: str) -> list[CaptureLine]:
    """The lines of a capture file as serial monitors, mbpoll and Windows tools write them: UTF-8 (a BOM
    allowed), UTF-16 with its BOM (PowerShell's `>`), CRLF or LF. A line that is not UTF-8 (a comment in
    a Windows code page) is read byte for byte, so its hex is still decoded; a binary file is refused."""
    if data.startswith((codecs.BOM_UTF16_LE, codecs.BOM_UTF16_BE)):
        try:
            text = data.decode("utf-16")
        except UnicodeDecodeError as exc:
            raise UsageError(f"{source}: not UTF-16 text at byte offset {exc.start}, although it starts with a UTF-16 BOM") from None
        return [CaptureLine(n, line) for n, line in enumerate(text.splitlines(), 1)]
    nul = data.find(b"\0")
    if nul >= 0:
        raise UsageError(f"{source}: a binary file, not a text capture (byte offset {nul} is 0x00); {BINARY_HINT}")
    offset = len(codecs.BOM_UTF8) if data.startswith(codecs.BOM_UTF8) else 0
    out = []
    for number, raw_line in enumerate(data[offset:].split(b"\n"), 1):
        try:
            out.append(CaptureLine(number, raw_line.decode("utf-8").rstrip("\r")))
        except UnicodeDecodeError as exc:
            where = (offset + exc.start, raw_line[exc.start])
            out.append(CaptureLine(number, raw_line.decode("latin-1").rstrip("\r"), where))
        offset += len(raw_line) + 1
    return out


def split_capture_line(line: str) -> tuple[str | None, str]:
    """(direction or None, the hex text) of one capture line, without timestamp and comment."""
    text = line.split("#", 1)[0].strip()
    if _LIBMODBUS.match(text):  # libmodbus's debug output (mbpoll -v): [01][03]... sent, <01><03>... received
        direction = "request" if text.startswith("[") else "response"
        return direction, " ".join(re.findall(r"[0-9A-Fa-f]{2}", text))
    pymodbus = _PYMODBUS.search(text)
    if pymodbus is not None:
        return _PYMODBUS_DIRECTIONS[pymodbus.group(1).lower()], " ".join(f"{int(t, 16):02X}" for t in pymodbus.group(2).split())
    text = _TIMESTAMP.sub("", text, count=1)
    match = _TAG.match(text)
    if match is None:
        return None, text
    return _DIRECTION_TAGS[match.group(1).lower()], text[match.end() :]


def decode_capture(device: Device, lines: Sequence[CaptureLine], source: str, *, word_order: str | None = None) -> CaptureResult:
    """Decode a log of frames, one per line, pairing each response with the request before it.

    A line may start with a timestamp and a direction tag (TX/RX, TX>, > or <), or be a frame line of
    mbpoll -v or of pymodbus's log; `#` starts a comment.
    A line that is not a frame is reported with its number and the rest is still decoded; a capture
    without a single frame is reported too.
    """
    out: list[Decoded] = []
    errors: list[CaptureError] = []
    pending: Frame | None = None
    for line in lines:
        direction, text = split_capture_line(line.text)
        if not text:
            continue
        try:
            frame_bytes = parse_hex(text)
            if direction is None:
                direction = "response" if pending is not None else None
            decoded = decode_frame(
                device, frame_bytes, direction=direction, request=pending if direction == "response" else None, word_order=word_order
            )
        except (FrameError, UsageError) as exc:
            message = str(exc)
            if line.not_utf8 is not None:
                at, byte = line.not_utf8
                message = f"not UTF-8 text: byte 0x{byte:02X} at byte offset {at}"
            errors.append(CaptureError(line.number, line.text.strip(), message, source))
            pending = None
            continue
        decoded.source_line = line.number
        out.append(decoded)
        pending = decoded.frame if decoded.direction == "request" else None
    if not out and not errors:
        errors.append(CaptureError(None, "", "no frames", source))
    return CaptureResult(out, errors)
