"""The opt-in request log (`--log FILE`, `-v`): every request and its answer, decoded with the map's names."""

from __future__ import annotations

import time
from collections.abc import Callable, Mapping
from typing import TextIO

from regmap.diagnostics import UsageError
from regmap.model import Device
from regmap.tools.decode import decode_frame, render_text
from regmap_runtime.rtu import Frame, FrameError, parse_frame, to_hex, with_crc

MAX_LINES = 40  # per frame: a refused read of 0xFFFF registers is one line of bytes, not 65535 register names


def _stamp() -> str:
    now = time.time()
    return time.strftime("%H:%M:%S", time.localtime(now)) + f".{int(now * 1000) % 1000:03d}"


class RequestLog:
    """Writes one block per exchange; nothing is kept in memory."""

    def __init__(self, device: Device, streams: list[TextIO], by_unit: Mapping[int, Device] | None = None) -> None:
        self.device = device
        self.streams = streams
        self.by_unit = dict(by_unit or {})  # several devices on one port: each frame decoded with its slave's map

    def _decoded(self, frame: bytes, direction: str, request: bytes | None = None) -> list[str]:
        try:
            asked: Frame | None = parse_frame(request, "request") if request is not None else None
        except FrameError:
            asked = None
        device = self.by_unit.get(frame[0], self.device) if frame else self.device
        try:
            lines = render_text(decode_frame(device, frame, direction=direction, request=asked)).splitlines()
        except UsageError as exc:  # too short to decode: the bytes say it all
            return [to_hex(frame), f"  problem: {exc}"]
        if len(lines) > MAX_LINES:
            lines = [*lines[: MAX_LINES - 1], f"  ... {len(lines) - MAX_LINES + 1} more lines"]
        return lines

    def rtu(self, peer: str, request: bytes, answer: bytes | None, note: str = "") -> None:
        lines = [f"{_stamp()} {peer} > {line}" if i == 0 else line for i, line in enumerate(self._decoded(request, "request"))]
        lines += self._answer(answer, note, lambda a: self._decoded(a, "response", request))
        self._write(lines)

    def tcp(self, peer: str, transaction: int, unit: int, pdu: bytes, answer: bytes | None, note: str = "") -> None:
        request = with_crc(bytes([unit]) + pdu)

        def pdu_lines(body: bytes, direction: str) -> list[str]:
            # Decoded as the RTU frame with the same slave id and PDU; TCP carries no CRC, so that part goes.
            frame = with_crc(bytes([unit]) + body)
            decoded = self._decoded(frame, direction, request if direction == "response" else None)
            head = f"MBAP transaction {transaction}, unit {unit}, PDU {to_hex(body)}"
            return [head, *(line.split(", CRC ")[0] for line in decoded[1:])]

        lines = pdu_lines(pdu, "request")
        lines[0] = f"{_stamp()} {peer} > {lines[0]}"
        lines += self._answer(answer, note, lambda a: pdu_lines(a, "response"))
        self._write(lines)

    def event(self, peer: str, text: str) -> None:
        self._write([f"{_stamp()} {peer} ! {text}"])

    @staticmethod
    def _answer(answer: bytes | None, note: str, render: Callable[[bytes], list[str]]) -> list[str]:
        out = []
        if answer is None:
            out.append(f"  < no answer{f' ({note})' if note else ''}")
        else:
            rendered = render(answer)
            out.append(f"  < {rendered[0]}" + (f"  ({note})" if note else ""))
            out += ["  " + line for line in rendered[1:]]
        return out

    def _write(self, lines: list[str]) -> None:
        text = "\n".join(lines) + "\n"
        for stream in self.streams:
            stream.write(text)
            stream.flush()
