"""What the probe found: notes (each a disagreement with the map, or information), the stages'
details, a human summary and a JSON document."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from regmap.model import Device


@dataclass(frozen=True)
class Note:
    stage: str  # registers, word_order, limits, gaps, scan, firmware, variants, identity, write_test, sunspec
    subject: str  # a register's label, or "transport"
    kind: str
    text: str
    disagrees: bool

    def as_json(self) -> dict[str, Any]:
        return {"stage": self.stage, "subject": self.subject, "kind": self.kind, "text": self.text, "disagrees": self.disagrees}


@dataclass
class Findings:
    device: Device
    where: str
    notes: list[Note] = field(default_factory=list)
    details: dict[str, Any] = field(default_factory=dict)  # stage -> its JSON
    stages_done: list[str] = field(default_factory=list)
    stopped: str | None = None  # why the probe ended early
    interrupted: bool = False
    requests: int = 0
    elapsed_s: float = 0.0
    answered_registers: int = 0

    @property
    def disagreements(self) -> list[Note]:
        return [n for n in self.notes if n.disagrees]

    @property
    def probed(self) -> bool:
        """Enough was read to say anything: the registers stage ran and some register answered."""
        return "registers" in self.stages_done and self.answered_registers > 0

    @property
    def verdict(self) -> str:
        if self.disagreements and self.probed:
            return "disagrees"
        return "agrees" if self.stopped is None and self.probed and not self.interrupted else "could not probe"

    def as_json(self) -> dict[str, Any]:
        return {
            "device": self.device.id,
            "model": self.device.info.model,
            "map_version": self.device.info.map_version,
            "map_fingerprint": self.device.fingerprint,
            "where": self.where,
            "verdict": self.verdict,
            "stopped": self.stopped,
            "interrupted": self.interrupted,
            "requests": self.requests,
            "seconds": round(self.elapsed_s, 3),
            "stages": self.stages_done,
            "disagreements": [n.as_json() for n in self.disagreements],
            "information": [n.as_json() for n in self.notes if not n.disagrees],
            **self.details,
        }


STAGE_TITLES = {
    "registers": "registers",
    "word_order": "word order",
    "limits": "read limit",
    "gaps": "gap reads",
    "scan": "undocumented addresses",
    "firmware": "firmware",
    "variants": "variants",
    "write_test": "write test",
    "sunspec": "SunSpec",
}
MAX_SHOWN = 40


def render_text(f: Findings) -> str:
    d = f.device
    lines = [f"regmap probe: {d.info.model} (map {d.info.map_version}, fingerprint {d.fingerprint}) on {f.where}"]
    registers = f.details.get("registers", [])
    if registers:
        answered = sum(1 for r in registers if r["status"] == "answered")
        lines.append(f"  {answered} of {len(registers)} documented readable registers answered")
    for stage, title in STAGE_TITLES.items():
        notes = [n for n in f.notes if n.stage == stage]
        shown = [n for n in notes if n.disagrees] + [n for n in notes if not n.disagrees]
        for note in shown[:MAX_SHOWN]:
            mark = "DISAGREES" if note.disagrees else "ok"
            subject = "" if note.subject == "transport" else f"{note.subject}: "
            lines.append(f"  {mark:>9}  {title}: {subject}{note.text}")
        if len(shown) > MAX_SHOWN:
            lines.append(f"             {title}: ... {len(shown) - MAX_SHOWN} more (--json lists all)")
    if f.interrupted:
        lines.append("  stopped by Ctrl-C: the above is what was learned")
    elif f.stopped:
        lines.append(f"  stopped early: {f.stopped}; the above is what was learned")
    count = len(f.disagreements)
    lines.append(f"{f.verdict}: {count} disagreement(s) with the map; {f.requests} request(s) in {f.elapsed_s:.1f} s")
    return "\n".join(lines)
