"""A decoded frame as text, the way `regmap decode` prints it."""

from __future__ import annotations

from regmap.tools.decode.frame import Decoded
from regmap_runtime.rtu import to_hex
from regmap_runtime.spaces import SPACES


def render_text(decoded: Decoded) -> str:
    f = decoded.frame
    crc = "ok" if f.crc_valid else "MISMATCH"
    where = f"line {decoded.source_line}: " if decoded.source_line is not None else ""
    head = f"function 0x{f.function:02X} {decoded.function_name} ({decoded.direction})"
    if decoded.mbap is None:
        lines = [where + to_hex(f.raw), f"  slave {f.slave}, {head}, CRC {to_hex(f.raw[-2:])} {crc}"]
    else:
        adu, transaction, unit = decoded.mbap
        lines = [where + to_hex(adu), f"  MBAP transaction {transaction}, unit {unit}, {head}"]
    bits = f.space is not None and SPACES[f.space].bits
    if f.address is not None:
        lines.append(
            f"  address 0x{f.address:04X}"
            + (f", count {f.count}" if f.count is not None else "")
            + (f", byte count {f.byte_count}" if f.byte_count is not None else "")
        )
    elif f.byte_count is not None and f.kind == "server_id_response":
        lines.append(f"  byte count {f.byte_count}")
    elif f.byte_count is not None:
        lines.append(f"  byte count {f.byte_count}, " + (f"{8 * (len(f.raw) - 5)} bits" if bits else f"{len(f.words)} words"))
    if decoded.exception:
        lines.append(f"  exception {decoded.exception}")
    lines.extend(f"  {row}" for row in decoded.data_words)
    for v in decoded.values:
        label = " ".join(x for x in (v.param, v.register) if x) or "-"
        value = f" = {v.text}" if v.raw is not None else f": {v.text}"
        lines.append(f"  0x{v.address:04X} {label}{value}")
    for problem in [*f.problems, *decoded.problems]:
        lines.append(f"  problem: {problem}")
    for note in decoded.notes:
        lines.append(f"  note: {note}")
    return "\n".join(lines)
