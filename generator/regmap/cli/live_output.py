"""How `read`, `write` and `dump` show what the live tools return, and the exit status each outcome gets."""

from __future__ import annotations

import csv
import io
import json
import sys
from collections.abc import Sequence
from typing import Any

from regmap.core.decoding import DecodedValue
from regmap.core.text import space_label
from regmap.diagnostics import ExitCode, LinkError
from regmap.tools.live import Checked, ReadResult, Word, Written
from regmap_runtime.spaces import SPACES

CSV_COLUMNS = ["register", "param", "address", "address_hex", "raw", "value", "unit", "in_range", "text", "space"]


def show_value(value: DecodedValue) -> str:
    label = " ".join(x for x in (value.param, value.register) if x)
    return f"{label} = {value.text}"


def _csv_cell(value: Any) -> Any:
    """A CSV cell as JSON writes the value: true/false for a bit (and in_range), numbers as numbers, text as text."""
    if isinstance(value, bool):
        return "true" if value else "false"
    return "" if value is None else value


def print_values(values: Sequence[DecodedValue], output: str) -> None:
    if output == "json":
        json.dump([v.as_json() for v in values], sys.stdout, ensure_ascii=False, indent=2)
        sys.stdout.write("\n")
    elif output == "csv":
        fields = list(dict.fromkeys(name for v in values if v.fields for name in v.fields))
        buffer = io.StringIO()
        writer = csv.DictWriter(buffer, fieldnames=CSV_COLUMNS + fields, lineterminator="\n")
        writer.writeheader()
        for v in values:
            row: dict[str, Any] = {k: _csv_cell(val) for k, val in v.as_json().items() if k in CSV_COLUMNS}
            row.update({k: _csv_cell(val) for k, val in (v.fields or {}).items()})
            writer.writerow(row)
        sys.stdout.write(buffer.getvalue())
    else:
        for v in values:
            print(show_value(v))


def print_words(words: Sequence[Word], output: str) -> None:
    """`read --words`: every word as it came (hex, unsigned, signed; bits 0/1)."""
    if output == "json":
        out = [{"address": w.address, "address_hex": f"0x{w.address:04X}", "space": w.space, "word": w.word} for w in words]
        json.dump(out, sys.stdout, indent=2)
        sys.stdout.write("\n")
    elif output == "csv":
        buffer = io.StringIO()
        writer = csv.DictWriter(buffer, fieldnames=["space", "address", "address_hex", "word"], lineterminator="\n")
        writer.writeheader()
        writer.writerows({"space": w.space, "address": w.address, "address_hex": f"0x{w.address:04X}", "word": w.word} for w in words)
        sys.stdout.write(buffer.getvalue())
    else:
        for w in words:
            word = w.word
            shown = (
                str(word) if SPACES[w.space].bits else f"0x{word:04X} = {word} unsigned, {word - 0x10000 if word & 0x8000 else word} signed"
            )
            print(f"{space_label(w.space)} 0x{w.address:04X} = {shown}")


def read_status(result: ReadResult, command: str) -> int:
    """The exit status of a read or dump; one cut short names, on stderr, what was not read and why."""
    if result.error is None:
        return ExitCode.OK
    names = ", ".join(r.name for r in result.unread[:10]) + (f" and {len(result.unread) - 10} more" if len(result.unread) > 10 else "")
    cause = "stopped" if result.interrupted else "the bus failed"
    print(f"regmap {command}: {cause} after {len(result.values)} register(s) were read: {result.error}; not read: {names}", file=sys.stderr)
    return ExitCode.INTERRUPTED if result.interrupted else ExitCode.BUS


def _checked_line(checked: Checked) -> str:
    shown = show_value(checked.value)
    if checked.outcome == "write-only":
        return f"{shown}  (written; write-only, not read back)"
    return f"{shown}  (verified)" if checked.outcome == "verified" else f"{shown}  (MISMATCH: wrote raw {checked.wrote!r})"


def write_status(written: Written) -> int:
    """Print what a write sent or read back; the exit status says whether the drive holds what was written."""
    if written.unknown is not None:
        print(f"regmap write: outcome unknown: {written.unknown}", file=sys.stderr)
        return ExitCode.OUTCOME_UNKNOWN
    if written.checked is None:
        print(f"wrote {written.count} {written.unit}(s) in {written.requests} request(s)")
        return ExitCode.OK
    for checked in written.checked:
        print(_checked_line(checked))
    if written.read_back_error:
        raise LinkError(f"written, but the read-back failed: {written.read_back_error}")
    if written.mismatches:
        print(f"regmap write: {written.mismatches} register(s) read back different values", file=sys.stderr)
        return ExitCode.VERIFY_MISMATCH
    return ExitCode.OK


class ProgressBar:
    """`dump`'s progress on a terminal's stderr: one line, redrawn after each request."""

    WIDTH = 30

    def __init__(self) -> None:
        self.drawn = False

    def __call__(self, done: int, total: int) -> None:
        filled = self.WIDTH * done // total
        sys.stderr.write(f"\r[{'#' * filled}{'.' * (self.WIDTH - filled)}] {done}/{total} requests")
        sys.stderr.flush()
        self.drawn = True

    def end(self) -> None:
        if self.drawn:
            sys.stderr.write("\n")
