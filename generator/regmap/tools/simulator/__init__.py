"""`regmap simulate`: a Modbus server that behaves like the device as its map describes it.

regmap's own server on asyncio (the generated clients still use pymodbus): Modbus TCP, RTU over
TCP, RTU on a serial port or pty. All four tables (holding and input registers, coils, discrete
inputs) with their functions 0x01-0x06, 0x0F, 0x10 as the Modbus Application Protocol v1.1b3
§6.1-§6.12 lays them out (bits packed LSB first, padding zero). It answers exactly where the device
would: the exception a conformant slave gives (0x01 for a function the map does not list, 0x03 for
a quantity beyond the map's limits, a byte count that disagrees or a coil value other than
FF 00/00 00, 0x02 for an address the map does not document in that space or a register the played
firmware lacks), the map's `bad_crc` behaviour, no answer to other slave ids or to broadcasts.
Commands with a declared `effect` act; faults can be injected for client tests. Memory stays
bounded under any load.

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
