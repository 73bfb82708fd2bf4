"""`regmap simulate`: a Modbus server that behaves like the device as its map describes it.

regmap's own server on asyncio (the generated clients still use pymodbus): Modbus TCP, RTU over
TCP, RTU on a serial port or pty. It answers exactly where the device would: the exception a
conformant slave gives (0x01 for a function the map does not list, 0x03 for a quantity beyond the
map's limits or a byte count that disagrees, 0x02 for an undocumented address), the map's
`bad_crc` behaviour, no answer to other slave ids or to broadcasts. Commands with a declared
`effect` act; faults can be injected for client tests. Memory stays bounded under any load.

`store` (registers and rules), `quirks` (where the drive departs from its map), `pdu` (dispatch per function code), `framing` (RTU and MBAP
streams), `server` (asyncio transports, faults, statistics), `log` (the request log), `run` (CLI).
"""

from __future__ import annotations

from .faults import FAULT_KINDS, FaultPlan
from .log import RequestLog
from .pdu import Dispatcher, rtu_request_length
from .quirks import Quirks
from .run import check_start, parse_endpoint, run
from .server import Simulator, Stats
from .store import DeviceStore

__all__ = [
    "FAULT_KINDS",
    "DeviceStore",
    "Dispatcher",
    "FaultPlan",
    "Quirks",
    "RequestLog",
    "Simulator",
    "Stats",
    "check_start",
    "parse_endpoint",
    "rtu_request_length",
    "run",
]
