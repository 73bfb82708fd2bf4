"""`regmap probe`: check a live drive against its map, and learn what it tolerates.

Read only (writes only for `--write-test`, and then only the value the drive already holds, plus
one out-of-range value the drive must refuse). The stages, one module each, in the order run:
`registers` (every documented register, by read-plan blocks, per register where a block fails),
`wordorder` (32-bit word order from the values, and the word-order register), `limits` (the
largest read), `gaps` (reads across undocumented addresses; the opt-in scan), `firmware` (the seam
for firmware gates), `writetest`; `bus` bounds every request (budget, rate, confused device),
`profile` keeps what was observed, `report` says it. `run.probe` puts them together.
"""

from __future__ import annotations

from .report import Findings, Note
from .run import Options, probe

__all__ = ["Findings", "Note", "Options", "probe"]
