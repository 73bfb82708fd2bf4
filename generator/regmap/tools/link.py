"""Where a drive is and how to talk to it: what the live subcommands' bus options say."""

from __future__ import annotations

import os
from typing import TYPE_CHECKING

from regmap.diagnostics import UsageError
from regmap.records import dataclass

if TYPE_CHECKING:
    from regmap.model import Device


@dataclass(frozen=True)
class Link:
    tcp: str | None = None
    serial: str | None = None
    slave: int = 1
    baud: int | None = None  # None: the map's (never 0)
    parity: str | None = None
    stop_bits: int | None = None
    timeout: float = 1.0
    retries: int = 2
    rtu_over_tcp: bool = False
    word_order: str | None = None  # auto, high_first, low_first; None: auto where the map has a word-order register
    variant: str | None = None  # the device's model or option (device.variants); None: not known, every register may be there

    @property
    def where(self) -> str:
        return self.serial or self.tcp or "?"


@dataclass(frozen=True)
class Line:
    """A serial line's settings: the map's, where an option does not override them."""

    baud: int
    parity: str
    stop_bits: int

    def refused(self, reason: str) -> str:
        """Why a port refused these settings (termios says only "Invalid argument"), for the one-line error."""
        hint = " (a pseudo-terminal may refuse parity: try --parity none)" if self.parity != "none" else ""
        return f"the port refuses {self.baud} baud, {self.parity} parity, {self.stop_bits} stop bit(s): {reason}{hint}"


def serial_line(
    device: Device, serial: str | None, baud: int | None = None, parity: str | None = None, stop_bits: int | None = None
) -> Line:
    """The line settings --baud/--parity/--stop-bits ask for, checked: only with a serial port (a TCP
    gateway's line is set on the gateway), and only a baud rate the map lists (the drive talks at no other)."""
    given = [option for option, value in (("--baud", baud), ("--parity", parity), ("--stop-bits", stop_bits)) if value is not None]
    if given and serial is None:
        raise UsageError(f"{', '.join(given)}: a serial line's settings, given without --serial (a TCP gateway's line is set on it)")
    rates = device.transport.baud_rates
    if baud is not None and rates and baud not in rates:
        listed = ", ".join(str(rate) for rate in rates)
        raise UsageError(f"--baud {baud} is not a baud rate of {device.info.model}: it talks at {listed}")
    t = device.transport
    return Line(t.baud if baud is None else baud, t.parity if parity is None else parity, t.stop_bits if stop_bits is None else stop_bits)


def port_reason(exc: Exception) -> str:
    """The operating system's words for why a port cannot be opened ("No such file or directory"),
    not pyserial's "[Errno 2] could not open port X: [Errno 2] ..."."""
    errno = getattr(exc, "errno", None)
    return os.strerror(errno) if isinstance(errno, int) else str(exc)


def parse_endpoint(text: str) -> tuple[str, int]:
    """`--tcp HOST:PORT` (an IPv6 address in brackets, `[::1]:502`; no host: 127.0.0.1) as (host, port)."""
    host, sep, port = text.rpartition(":")
    if not sep or not port.isdigit() or not 0 < int(port) < 65536:
        raise UsageError(f"--tcp wants HOST:PORT, got {text!r}")
    if host.startswith("[") and host.endswith("]"):
        host = host[1:-1]
    return host or "127.0.0.1", int(port)
