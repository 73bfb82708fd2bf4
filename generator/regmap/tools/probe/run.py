"""The probe from start to end: each stage in turn on one bounded bus; a stop (budget, a confused
device, Ctrl-C) ends the stages but never the report of what was learned."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Protocol

from regmap.model import Device, Register
from regmap_runtime.client import SyncClient
from regmap_runtime.profile import DeviceProfile

from . import firmware, gaps, identity, limits, profile, registers, sunspec, variants, wordorder, writetest
from .bus import ProbeBus, Stop
from .report import Findings, Note

DEFAULT_BUDGET_S = 300.0


class Reported(Protocol):
    def as_json(self) -> Any: ...


Step = Callable[[], tuple[Reported, list[Note]]]


@dataclass(frozen=True)
class Options:
    budget_s: float = DEFAULT_BUDGET_S
    rate: float | None = None  # requests per second; None: as fast as the drive answers
    scan_undocumented: bool = False
    write_test: tuple[Register, ...] = ()
    sunspec: bool = False
    progress: Callable[[str], None] | None = None


def probe(device: Device, client: SyncClient, where: str, options: Options) -> tuple[Findings, DeviceProfile]:
    bus = ProbeBus(client, budget_s=options.budget_s, rate=options.rate)
    found = Findings(device, where)
    reads: dict[str, registers.RegisterRead] = {}

    def guarded(stage: Callable[[], None]) -> bool:
        """Run a stage; False when the probe has to stop (and why is recorded)."""
        try:
            stage()
        except Stop as exc:
            found.stopped = str(exc)
            return False
        except KeyboardInterrupt:
            found.interrupted = True
            return False
        return True

    def read_all() -> None:
        registers.read_registers(bus, device, reads, options.progress)
        found.stages_done.append("registers")

    going = guarded(read_all)
    order, notes = wordorder.infer(device, reads)
    found.notes += registers.judge(device, reads, order.effective) + notes
    found.details["registers"] = [r.as_json() for r in reads.values()]
    found.details["word_order"] = order.as_json()
    found.answered_registers = sum(1 for r in reads.values() if r.answer is not None and r.answer.ok)
    limit: list[limits.Limit] = []
    steps: list[tuple[str, Step]] = [
        ("limits", lambda: limits.search(bus, device, gaps.holding_addresses(device) | bus.observed)),
        ("gaps", lambda: gaps.try_gaps(bus, device, _gap_limit(device, limit), options.progress)),
    ]
    if variants.gated(device):
        steps.insert(0, ("variants", lambda: variants.check(bus, device)))  # a few requests: before the long stages
    if options.scan_undocumented:
        steps.append(("scan", lambda: gaps.scan(bus, device, options.progress)))
    if options.sunspec:
        steps.insert(0, ("sunspec", lambda: sunspec.walk(bus, device)))
    if device.transport.identification is not None or device.transport.server_id is not None:
        steps.append((identity.STAGE, lambda: identity.check(bus, device)))
    if options.write_test:
        steps.append(("write_test", lambda: writetest.write_test(bus, device, options.write_test, order.effective)))
    for name, step in steps if going and found.answered_registers else []:

        def run_step(name: str = name, step: Step = step) -> None:
            result, notes = step()
            if isinstance(result, limits.Limit):
                limit.append(result)
            found.notes.extend(notes)
            found.details[name] = result.as_json()
            found.stages_done.append(name)

        if not guarded(run_step):
            break
    found.notes.append(_firmware(device, reads))
    found.requests, found.elapsed_s = bus.requests, bus.elapsed_s
    return found, profile.learned(device, bus.observed, limit[0] if limit else None, order)


def _gap_limit(device: Device, limit: list[limits.Limit]) -> int:
    """Gap reads as long as the plan would make them, but no longer than the drive proved it takes."""
    taken = limit[0].accepted if limit else None
    return min(device.transport.max_read_registers, taken or device.transport.max_read_registers)


def _firmware(device: Device, reads: dict[str, registers.RegisterRead]) -> Note:
    reg = firmware.firmware_register(device)
    read = reads.get(reg.name) if reg is not None else None
    check = firmware.check_firmware(device, reg, read.raw if read is not None else None, reads)
    return Note("firmware", "transport", "firmware", check.text, not check.agrees)
