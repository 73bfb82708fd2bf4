"""Where a drive is and how to talk to it: what the live subcommands' bus options say."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Link:
    tcp: str | None = None
    serial: str | None = None
    slave: int = 1
    baud: int | None = None
    parity: str | None = None
    stop_bits: int | None = None
    timeout: float = 1.0
    retries: int = 2
    rtu_over_tcp: bool = False
    word_order: str | None = None  # auto, high_first, low_first; None: auto where the map has a word-order register

    @property
    def where(self) -> str:
        return self.serial or self.tcp or "?"
