"""`regmap simulate` from the command line: start-up checks, listen, tell the caller, serve until told to stop."""

from __future__ import annotations

import asyncio
import contextlib
import os
import signal
import socket
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TextIO

from regmap.diagnostics import UsageError
from regmap.model import Device
from regmap.plant import Bus
from regmap.tools.link import Line, parse_endpoint
from regmap.tools.output import check_output

from .faults import FaultPlan
from .log import RequestLog
from .policy import TcpPolicy
from .quirks import Quirks
from .server import Simulator
from .store import DeviceStore, slave_refusal


def check_start(device: Device, slave: int, state: Path | None) -> None:
    """What would otherwise be found out later, as exception 0x04 or a lost save: refused now."""
    refused = slave_refusal(device, slave)
    if refused is not None:
        raise UsageError(f"--slave {refused}")
    if state is not None:
        check_output(state, "--state")


def _open_log(path: Path | None, echo: TextIO | None) -> tuple[list[TextIO], list[TextIO]]:
    """The streams the request log writes to, and those of them this function opened."""
    streams: list[TextIO] = [echo] if echo is not None else []
    opened: list[TextIO] = []
    if path is not None:
        try:
            handle = path.open("a", encoding="utf-8")
        except OSError as exc:
            raise UsageError(f"--log {path}: {exc.strerror or exc}") from None
        streams.append(handle)
        opened.append(handle)
    return streams, opened


def _listen_error(where: str, exc: OSError) -> UsageError:
    # a name that does not resolve is a gaierror, whose errno (-2 ...) os.strerror does not know
    reason = (exc.strerror or str(exc)) if isinstance(exc, socket.gaierror) else os.strerror(exc.errno) if exc.errno else str(exc)
    reason = reason.lower()
    return UsageError(f"cannot listen on {where}: {reason}")


def _quirks_text(quirks: Quirks | None) -> str:
    if quirks is None:
        return ""
    parts = [
        *([f"reads of at most {quirks.max_read} registers"] if quirks.max_read is not None else []),
        *(["answers reads over undocumented addresses"] if quirks.answer_gaps else []),
        *([f"32-bit values {quirks.word_order}"] if quirks.word_order else []),
    ]
    return f", playing a drive that departs from its map: {', '.join(parts)}" if parts else ""


def _firmware_text(simulator: Simulator) -> str:
    """What the banner says of the firmware played: its version, where the map reports it, and the registers it lacks."""
    store = simulator.store
    if store.firmware is None:
        return ""
    version = store.firmware_text
    fw = simulator.device.info.firmware_register
    where = f" (reported by {fw.register.label})" if fw is not None else " (the map names no firmware register)"
    absent = len(simulator.device.registers) - len(store.present)
    lacking = f", {absent} register(s) it lacks answer 0x02" if absent else ""
    return f", firmware {version}{where}{lacking}"


def _tcp_framing(policy: TcpPolicy, slave: int) -> str:
    if policy.gateway:
        return f"Modbus TCP, as a gateway with slave {slave} behind it"
    return f"Modbus TCP, units {slave}, 0xFF and 0"


@dataclass(frozen=True)
class Listening:
    """Where the simulator serves, for the line that says so."""

    model: str
    slave: int
    where: str
    framing: str  # RTU or Modbus TCP
    playing: str  # the firmware played and the quirks, as a clause (may be empty)


def run(
    device: Device,
    *,
    tcp: str | None,
    serial: str | None,
    slave: int,
    line: Line | None = None,
    state: Path | None,
    faults: FaultPlan,
    rtu_over_tcp: bool = False,
    log: Path | None = None,
    echo: TextIO | None = None,
    rtu_gap_s: float | None = None,
    quirks: Quirks | None = None,
    listening: Callable[[Listening], None] | None = None,
    tcp_policy: TcpPolicy | None = None,
) -> str:
    """Serve until Ctrl-C or SIGTERM; `listening` is told once the port is open, `echo` gets the request
    log as well as `log`. Returns what was served (the request counts)."""
    check_start(device, slave, state)
    streams, opened = _open_log(log, echo)
    request_log = RequestLog(device, streams) if streams else None
    simulator = Simulator(device, slave, state, faults, log=request_log, rtu_gap_s=rtu_gap_s, quirks=quirks, tcp_policy=tcp_policy)

    def banner(where: str) -> Listening:
        framing = "RTU" if serial or rtu_over_tcp else _tcp_framing(tcp_policy or TcpPolicy(), slave)
        return Listening(device.info.model, slave, where, framing, _firmware_text(simulator) + _quirks_text(quirks))

    return _serve(simulator, tcp, serial, line, rtu_over_tcp, opened, banner, listening)


def run_bus(
    bus: Bus,
    *,
    tcp: str | None,
    serial: str | None,
    line: Line | None = None,
    state_dir: Path | None,
    faults: FaultPlan,
    rtu_over_tcp: bool = False,
    log: Path | None = None,
    echo: TextIO | None = None,
    rtu_gap_s: float | None = None,
    listening: Callable[[Listening], None] | None = None,
    tcp_policy: TcpPolicy | None = None,
) -> str:
    """Serve every device of a plant's bus on one port, each at its slave id with its own map's store and
    rules (`state_dir/<device>.json` keeps each one's saved parameters). Returns what was served."""
    states = {dev.name: state_dir / f"{dev.name}.json" if state_dir is not None else None for dev in bus.devices}
    for dev in bus.devices:
        check_start(dev.device, dev.slave, states[dev.name])
    streams, opened = _open_log(log, echo)
    first = bus.devices[0].device
    request_log = RequestLog(first, streams, by_unit={dev.slave: dev.device for dev in bus.devices}) if streams else None
    units = {dev.slave: DeviceStore(dev.device, dev.slave, states[dev.name], Quirks(variant=dev.variant)) for dev in bus.devices}
    simulator = Simulator.serving(units, faults=faults, log=request_log, rtu_gap_s=rtu_gap_s, tcp_policy=tcp_policy)

    def banner(where: str) -> Listening:
        policy = tcp_policy or TcpPolicy()
        framing = "RTU" if serial or rtu_over_tcp else "Modbus TCP, as a gateway" if policy.gateway else "Modbus TCP, a unit id per device"
        served = ", ".join(
            f"{dev.name} ({dev.device.info.model}, slave {dev.slave}{', variant ' + dev.variant if dev.variant else ''})"
            for dev in bus.devices
        )
        return Listening(f"bus {bus.name}: {served}", 0, where, framing, "")

    return _serve(simulator, tcp, serial, line, rtu_over_tcp, opened, banner, listening)


def _serve(
    simulator: Simulator,
    tcp: str | None,
    serial: str | None,
    line: Line | None,
    rtu_over_tcp: bool,
    opened: list[TextIO],
    banner: Callable[[str], Listening],
    listening: Callable[[Listening], None] | None,
) -> str:
    host, port = parse_endpoint(tcp or "127.0.0.1:5020") if not serial else ("", 0)

    async def main() -> None:
        loop = asyncio.get_running_loop()
        for sig in (signal.SIGINT, signal.SIGTERM):
            loop.add_signal_handler(sig, simulator.stopped.set)
        if serial:
            await simulator.start_serial(serial, line)
            where = serial
        else:
            where = f"{host}:{port}"
            try:
                await simulator.start_tcp(host, port, rtu_over_tcp=rtu_over_tcp)
            except OSError as exc:
                raise _listen_error(where, exc) from None
        if listening is not None:
            listening(banner(where))
        await simulator.stopped.wait()
        await simulator.stop()
        if simulator.failure is not None:
            raise UsageError(f"stopped serving: {simulator.failure}")

    try:
        asyncio.run(main())
    finally:
        for handle in opened:
            with contextlib.suppress(OSError):
                handle.close()
    return simulator.stats.summary()
