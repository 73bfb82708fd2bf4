"""The plant's line schedule without a bus: the round-robin order, and the waits PacedLine keeps on a fake clock."""

from __future__ import annotations

import pytest

from regmap_runtime.line import PacedLine, frame_s, interleave
from regmap_runtime.rtu import build_read

from support.fake_clock import FakeClock


def test_interleave_takes_one_block_of_each_device_in_turn() -> None:
    plans = [["x1", "x2", "x3"], ["y1"], ["z1", "z2"]]
    assert interleave(plans) == [(0, "x1"), (1, "y1"), (2, "z1"), (0, "x2"), (2, "z2"), (0, "x3")]
    assert interleave([]) == []
    assert interleave([[], ["a"]]) == [(1, "a")]


def _line(fake: FakeClock) -> PacedLine:
    # 9600 baud, 11 bits a character: a 4.01 ms silence; slave 1 turns around in 25 ms, slave 2 in 1 ms.
    return PacedLine(3.5 * 11 / 9600, {1: 0.025, 2: 0.001}, character_bits=11, baud=9600, clock=fake.clock, sleep=fake.sleep)


def test_the_next_request_waits_for_the_silence_after_the_answer() -> None:
    fake = FakeClock()
    line = _line(fake)
    request = build_read(2, 0, 1)
    line(True, request)
    assert fake.slept == []  # the first frame goes at once
    fake.now += 0.050  # the answer comes 50 ms later: long after slave 2's turnaround
    line(False, b"\x02\x03\x02\x00\x00\x00\x00")
    answered = fake.now
    line(True, build_read(1, 0, 1))
    assert fake.now == pytest.approx(answered + 3.5 * 11 / 9600)
    assert line.waited_s == pytest.approx(3.5 * 11 / 9600)


def test_the_next_request_waits_for_the_turnaround_of_the_device_just_addressed() -> None:
    fake = FakeClock()
    line = _line(fake)
    sent = fake.now
    request = build_read(1, 0, 1)
    line(True, request)
    fake.now += 0.002  # a quick answer: slave 1 still needs its 25 ms
    line(False, b"\x01\x03\x02\x00\x00\x00\x00")
    line(True, build_read(2, 0, 1))
    assert fake.now == pytest.approx(sent + frame_s(len(request), 11, 9600) + 0.025)


def test_a_broadcast_holds_the_line_for_the_turnaround_without_an_answer() -> None:
    fake = FakeClock()
    line = PacedLine(0.002, {0: 0.1}, character_bits=10, baud=19200, clock=fake.clock, sleep=fake.sleep)
    sent = fake.now
    broadcast = bytes.fromhex("0006000100013A0B")  # slave 0: nobody answers
    line(True, broadcast)
    line(True, build_read(1, 0, 1))
    assert fake.now == pytest.approx(sent + frame_s(8, 10, 19200) + 0.1)


def test_the_hook_changes_no_byte() -> None:
    fake = FakeClock()
    line = _line(fake)
    request = build_read(1, 0x0191, 2)
    assert line(True, request) == request
    assert line(False, b"\x01\x03") == b"\x01\x03"
    assert line.packets_sent == 1 and line.received == b"\x01\x03"
