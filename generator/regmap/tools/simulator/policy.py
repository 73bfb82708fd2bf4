"""How the simulator's TCP server treats unit ids and connections (light: the CLI reads its defaults)."""

from __future__ import annotations

import resource
from dataclasses import dataclass

DIRECT_UNITS = (0xFF, 0x00)  # Modbus TCP implementation guide §4.4.2: a server addressed by its IP address takes these
DEFAULT_IDLE_TIMEOUT_S = 120.0
DEFAULT_MAX_CONNECTIONS = 64
DESCRIPTOR_RESERVE = 16  # descriptors kept free for the listening sockets, the log, the state file


@dataclass(frozen=True)
class TcpPolicy:
    """How the TCP server treats unit ids and connections.

    `gateway`: play a Modbus TCP to serial gateway with this one device behind it (unit 0 is a serial
    broadcast, other units answer exception 0x0B); otherwise the device is addressed directly by its IP
    address and also answers units 0xFF and 0 (RTU over TCP keeps the serial line's rules either way).
    `idle_timeout_s`: a connection that sends nothing for this long is closed (None: never).
    `max_connections`: at most this many at once (clipped to the descriptors the process may open);
    a new one past the cap closes the connection idle the longest.
    """

    gateway: bool = False
    idle_timeout_s: float | None = DEFAULT_IDLE_TIMEOUT_S
    max_connections: int = DEFAULT_MAX_CONNECTIONS

    def connection_cap(self) -> int:
        soft, _hard = resource.getrlimit(resource.RLIMIT_NOFILE)
        if soft == resource.RLIM_INFINITY:
            return self.max_connections
        return max(1, min(self.max_connections, soft - DESCRIPTOR_RESERVE))
