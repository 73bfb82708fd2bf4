"""What the device says it is, against the map: read device identification (0x2B/0x0E, the map's
`transport.identification`) and report server id (0x11, `transport.server_id`), each asked only where
the map lists it. An object or byte that differs is a disagreement; an object the map does not list,
or a run indicator saying OFF, is information (the device's state, not a fault of the map)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from regmap.model import Device

from .bus import ProbeBus
from .report import Note

STAGE = "identity"
OBJECT_NAMES = {
    0: "vendor name",
    1: "product code",
    2: "revision",
    3: "vendor url",
    4: "product name",
    5: "model name",
    6: "application name",
}


@dataclass(frozen=True)
class IdentityCheck:
    identification: dict[int, str] | None = None  # what the device answered (None: not asked, or no answer)
    server_id: bytes | None = None
    texts: tuple[str, ...] = field(default=())

    def as_json(self) -> dict[str, Any]:
        return {
            "identification": None if self.identification is None else {f"0x{k:02X}": v for k, v in self.identification.items()},
            "server_id": None if self.server_id is None else self.server_id.hex(" ").upper(),
        }


def _object(object_id: int) -> str:
    return f"object 0x{object_id:02X} ({OBJECT_NAMES.get(object_id, 'vendor specific')})"


def check(bus: ProbeBus, device: Device) -> tuple[IdentityCheck, list[Note]]:
    t = device.transport
    notes: list[Note] = []
    found: dict[int, str] | None = None
    report: bytes | None = None
    if t.identification is not None:
        expected = dict(t.identification.objects)
        level = "regular" if any(i > 0x02 for i in expected) else "basic"
        got, answer = bus.call(lambda: bus.client.read_identification(level))
        if not answer.ok or got is None:
            notes.append(Note(STAGE, "transport", "identification", f"read device identification ({level}): {answer.text}", True))
        else:
            found = got
            for object_id, text in sorted(expected.items()):
                if found.get(object_id) != text:
                    said = repr(found[object_id]) if object_id in found else "nothing"
                    notes.append(
                        Note(STAGE, "transport", "identification", f"{_object(object_id)}: the device says {said}, the map {text!r}", True)
                    )
            extra = sorted(set(found) - set(expected))
            if extra:
                listed = ", ".join(f"{_object(i)} = {found[i]!r}" for i in extra)
                notes.append(Note(STAGE, "transport", "identification", f"the device also reports {listed}", False))
            if not any(n.disagrees for n in notes):
                notes.append(Note(STAGE, "transport", "identification", f"identification agrees ({len(expected)} objects)", False))
    if t.server_id is not None:
        s = t.server_id
        reported, answered = bus.call(lambda: bus.client.report_server_id())
        if not answered.ok or reported is None:
            notes.append(Note(STAGE, "transport", "server_id", f"report server id: {answered.text}", True))
        else:
            report = reported.data
            server, running, additional = reported.split(len(s.id))
            if server != s.id:
                notes.append(
                    Note(STAGE, "transport", "server_id", f"server id {server.hex(' ').upper()}, the map {s.id.hex(' ').upper()}", True)
                )
            if additional != s.additional_data.encode("ascii"):
                notes.append(Note(STAGE, "transport", "server_id", f"additional data {additional!r}, the map {s.additional_data!r}", True))
            if running is None:
                notes.append(
                    Note(STAGE, "transport", "server_id", f"the run indicator is neither 00 nor FF: {report.hex(' ').upper()}", True)
                )
            elif running != s.running:
                notes.append(Note(STAGE, "transport", "server_id", f"the run indicator says {'ON' if running else 'OFF'}", False))
            if not any(n.disagrees and n.kind == "server_id" for n in notes):
                notes.append(Note(STAGE, "transport", "server_id", f"server id agrees ({report.hex(' ').upper()})", False))
    return IdentityCheck(found, report), notes
