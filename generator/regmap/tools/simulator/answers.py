"""Answers to repeated reads, kept while the device's memory stays as it was.

A polling client asks the same few reads over and over: each is worked out once per change of the
device's memory (`DeviceStore.generation`), not once per poll. Only reads are kept, only when nothing
else shapes the answer (no request log, no injected fault, no value that changes on being read), and
an answer is used only while its device's generation is the one it was worked out at.
"""

from __future__ import annotations

from regmap_runtime.rtu import EXCEPTION_FLAG, READS

from .store import DeviceStore

READ_FUNCTIONS = frozenset(READS)  # 0x01-0x04: they change nothing on the device
ANSWERS_KEPT = 4096  # a client sweeping addresses keeps memory bounded
KEPT_FUNCTION = 5  # the function code's place in a frame after its transaction id


class AnswerCache:
    """Request frame after its transaction id -> the answer frame after its transaction id, and whether that
    answer is an exception (1 or 0), with the store and the generation it holds at."""

    def __init__(self) -> None:
        self._answers: dict[bytes, tuple[DeviceStore, int, tuple[bytes, int]]] = {}

    def get(self, request: bytes) -> tuple[bytes, int] | None:
        hit = self._answers.get(request)
        if hit is None:
            return None
        store, generation, answer = hit
        if store.generation != generation:  # the memory changed since: work it out again
            del self._answers[request]
            return None
        return answer

    def keep(self, request: bytes, store: DeviceStore, generation: int, answer: bytes) -> None:
        if len(self._answers) >= ANSWERS_KEPT:
            self._answers.clear()
        self._answers[request] = (store, generation, (answer, 1 if answer[KEPT_FUNCTION] & EXCEPTION_FLAG else 0))

    def __len__(self) -> int:
        return len(self._answers)
