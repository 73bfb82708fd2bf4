"""Faults injected into the simulator's answers, for testing clients against a misbehaving bus."""

from __future__ import annotations

from dataclasses import dataclass

from regmap_runtime.rtu import with_crc

FAULT_KINDS = ("none", "no_answer", "bad_crc", "truncated", "exception", "wrong_slave", "wrong_function", "delay")
ANSWER_FAULTS = ("no_answer", "delay", "bad_crc", "truncated", "wrong_slave", "wrong_function")


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


def damage_rtu(fault: str, frame: bytes) -> bytes:
    """An RTU answer as `fault` spoils it (`no_answer` and `delay` are the sender's business)."""
    if fault == "bad_crc" and len(frame) >= 4:
        return frame[:-2] + bytes([frame[-2] ^ 0xFF, frame[-1]])
    if fault == "truncated" and len(frame) > 3:
        return frame[: len(frame) // 2]
    if fault == "wrong_slave" and len(frame) >= 4:
        return with_crc(bytes([(frame[0] + 1) & 0xFF]) + frame[1:-2])
    if fault == "wrong_function" and len(frame) >= 4:
        return with_crc(frame[:1] + bytes([frame[1] ^ 0x04]) + frame[2:-2])
    return frame


def damage_tcp(fault: str, adu: bytes) -> bytes:
    """A Modbus TCP answer (MBAP header + PDU) as `fault` spoils it. TCP has no CRC: `bad_crc`
    corrupts the last data byte, which is what a checksum would have caught."""
    if fault == "bad_crc" and len(adu) > 8:
        return adu[:-1] + bytes([adu[-1] ^ 0xFF])
    if fault == "truncated" and len(adu) > 7:
        return adu[: len(adu) // 2]
    if fault == "wrong_slave" and len(adu) > 7:
        return adu[:6] + bytes([(adu[6] + 1) & 0xFF]) + adu[7:]
    if fault == "wrong_function" and len(adu) > 7:
        return adu[:7] + bytes([adu[7] ^ 0x04]) + adu[8:]
    return adu
