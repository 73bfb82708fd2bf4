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

Several devices on one port (a plant's RS-485 bus, or a gateway with several drives behind it)::

    units = {1: DeviceStore(load_map("maps/idm_rs.yaml"), 1), 7: DeviceStore(meter, 7, state_file=path)}
    await serve(units, tcp=("127.0.0.1", 5020))                       # Modbus TCP: unit id -> device
    await serve(units, serial="/dev/ttyUSB0")                         # RTU on a serial port or pty
    await serve(units, tcp=("0.0.0.0", 502), tcp_policy=TcpPolicy(gateway=True))

or `Simulator.serving(units, ...)` and its `start_tcp` / `start_serial` / `stop` inside a running loop.
Each slave id answers with its own map's store and strictness (exceptions, firmware, quirks, state
file); `faults`, the request log (`RequestLog(device, streams, by_unit={id: device})` decodes each
frame with its slave's map), the statistics and the TCP policy are the server's. Ids no device has
stay silent (a gateway answers them 0x0B). A broadcast write (the maps' broadcast id, 0 on RTU; unit
0 over TCP only under `TcpPolicy(gateway=True)`) reaches every device whose map has that broadcast
id and gets no reply; a broadcast read is ignored. Units 0xFF and 0 address a lone device directly
over TCP; with several devices only their own unit ids reach them. `serve` checks each slave id
against its map (`slave_refusal`) and that each store was made for its id.
"""

from __future__ import annotations

from regmap.tools.link import parse_endpoint

from .faults import FAULT_KINDS, FaultPlan
from .log import RequestLog
from .pdu import Dispatcher, rtu_request_length
from .policy import TcpPolicy
from .quirks import Quirks
from .run import check_start, run
from .server import Simulator, Stats, Unit, serve
from .store import DeviceStore, slave_refusal

__all__ = [
    "FAULT_KINDS",
    "DeviceStore",
    "Dispatcher",
    "FaultPlan",
    "Quirks",
    "RequestLog",
    "Simulator",
    "Stats",
    "TcpPolicy",
    "Unit",
    "check_start",
    "parse_endpoint",
    "rtu_request_length",
    "run",
    "serve",
    "slave_refusal",
]
