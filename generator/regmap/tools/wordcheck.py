"""`write --words` on a live bus: words at addresses the map does not list go out as given (that is what
--words is for), but words that land on a register the map lists pass that register's own checks first,
as a named write would: it is writable, all of its words are written (no torn 32-bit value), and their raw
value is in its range, a member of its enum, no state it only reports and no destructive command's value
(that goes through `regmap command NAME --confirm NAME`), read in the drive's word order (a 32-bit value of a
drive whose order can be switched is checked once `write` has read it, as a named write reads it, and before
anything is sent). `frame --words` only prints bytes and stays raw,
so the manuals' frames can be reproduced as printed."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from regmap.diagnostics import UsageError
from regmap.model import Device
from regmap.runtime_bridge import runtime_specs
from regmap_runtime.codec import RangeError, check_raw, raw_to_words, words_to_raw
from regmap_runtime.spec import RegisterSpec

NOTHING_SENT = "nothing was sent; --words writes only what the map allows at a register it lists"


def check_word_runs(
    device: Device, space: str, runs: Sequence[tuple[int, Sequence[int]]], order: str | None = None, *, order_read: bool = False
) -> bool:
    """Refuse (UsageError) a run of words that writes a listed register in a way a named write could not. Before
    the drive's word order is read (`order_read` False), the values of the 32-bit registers that follow it wait for
    a second call with `order` (None: the map's); the answer says whether any did."""
    written = {address + i: word for address, run in runs for i, word in enumerate(run)}
    touched = dict.fromkeys(reg for reg in (device.covering(address, space) for address in sorted(written)) if reg is not None)
    specs = {spec.name: spec for spec in runtime_specs(device)} if touched else {}
    pending = False
    for reg in touched:  # each register once, in the order its first word is written
        at = f"--words 0x{next(a for a in sorted(written) if reg.first_address <= a <= reg.last_address):04X}"
        if not reg.access.writable:
            raise UsageError(f"{at}: {reg.label} is read-only (access {reg.access.value}); {NOTHING_SENT}")
        own = range(reg.address, reg.last_address + 1)  # without a pair's unused high word
        missing = [address for address in own if address not in written]
        if reg.paired and len(missing) == reg.words:
            raise UsageError(
                f"{at}: 0x{reg.first_address:04X} is the unused high word of {reg.label}; write it together with the "
                f"low word 0x{reg.address:04X}, or 0x{reg.address:04X} alone; {NOTHING_SENT}"
            )
        if missing:
            raise UsageError(
                f"{at}: writes {reg.words - len(missing)} of the {reg.words} word(s) of {reg.label} ({reg.type.value} at "
                f"0x{reg.address:04X}), which would leave it half old, half new; write all of them or name the register; {NOTHING_SENT}"
            )
        spec = specs[reg.name]
        if spec.wide and spec.follows_device_order and not order_read:
            pending = True
            continue
        _check_value(spec.in_word_order(order), [written[a] for a in own], at)
        if reg.paired and reg.first_address in written:
            # The pair is one 32-bit parameter of which only the low word is used: its high word is the sign extension.
            extension = raw_to_words(spec, words_to_raw(spec, [written[reg.address]]), with_pair=True)[0]
            if written[reg.first_address] != extension:
                raise UsageError(
                    f"{at}: 0x{reg.first_address:04X} is the unused high word of {reg.label}, which holds the sign "
                    f"extension of its low word: 0x{extension:04X}, not 0x{written[reg.first_address]:04X}; {NOTHING_SENT}"
                )
    return pending


def _check_value(spec: RegisterSpec[Any], words: list[int], at: str) -> None:
    """check_raw on the words as the drive reads them (`spec` in the drive's word order)."""
    try:
        check_raw(spec, words_to_raw(spec, words))
    except (RangeError, ValueError) as exc:
        read_as = f" (read {spec.word_order.replace('_', ' ')}, the drive's word order)" if spec.wide else ""
        raise UsageError(f"{at}: {exc}{read_as}; {NOTHING_SENT}") from None
