"""The map's read-alignment rule (`transport.read_alignment`) and its word-order switch given as a magic
value (`word_order_register.swap_value`), checked against the registers for the cross-reference stage."""

from __future__ import annotations

from typing import Any, Protocol

from regmap.frontend.stages import Problems
from regmap.frontend.values import _source
from regmap.frontend.yamlsource import Path
from regmap.model import ReadAlignment, Register

REGISTER_SPACES = ("holding", "input")


class AlignmentHost(Protocol):
    """What the cross-reference stage lends: its problems, the registers and where each is declared."""

    problems: Problems
    registers: list[Register]
    register_paths: tuple[Path, ...]

    def _ref(self, selector: str, by_selector: dict[str, Register], path: Path, what: str) -> Register | None: ...


def read_alignment(host: AlignmentHost, t: dict[str, Any], by_selector: dict[str, Register]) -> ReadAlignment | None:
    """The rule, or None; every readable register of an aligned space must be readable by an aligned
    read (its words within whole aligned units, the padding words readable), or be listed in `exempt`."""
    a = t.get("read_alignment")
    if a is None:
        return None
    path: Path = ("transport", "read_alignment")
    codes = [e["code"] for e in t.get("exceptions", [])]
    if "exception" in a and a["exception"] not in codes:
        listed = ", ".join(f"0x{c:02X}" for c in codes) or "none"
        host.problems.add(
            (*path, "exception"),
            f"read_alignment answers exception 0x{a['exception']:02X}, which transport.exceptions does not list (listed: {listed})",
        )
    exempt: list[Register] = []
    for i, selector in enumerate(a.get("exempt", [])):
        reg = host._ref(selector, by_selector, (*path, "exempt", i), "read_alignment.exempt")
        if reg is not None:
            exempt.append(reg)
    rule = ReadAlignment(
        words=a["words"],
        spaces=tuple(a.get("spaces", REGISTER_SPACES)),
        exception=a.get("exception"),
        exempt=tuple(exempt),
        source=_source(a.get("source")),
        notes=a.get("notes", ""),
    )
    for i, reg in enumerate(exempt):
        if reg.space not in rule.spaces:
            host.problems.add((*path, "exempt", i), f"read_alignment.exempt: {reg.name} is in {reg.space}, which the rule does not cover")
        elif not _own_read_breaks(rule, reg):
            host.problems.add((*path, "exempt", i), f"read_alignment.exempt: {reg.name} is aligned already; nothing to exempt")
    _check_registers(host, rule, t.get("undocumented_addresses", "reject") == "tolerate")
    return rule


def _own_read_breaks(rule: ReadAlignment, reg: Register) -> bool:
    first, end = reg.first_address, reg.last_address + 1
    return first % rule.words != 0 or end % rule.words != 0


def _check_registers(host: AlignmentHost, rule: ReadAlignment, tolerates_gaps: bool) -> None:
    w = rule.words
    exempt = {r.name for r in rule.exempt}
    always = [r for r in host.registers if r.access.readable and not r.variants and r.firmware is None]
    readable = {(r.space, a) for r in always for a in range(r.first_address, r.last_address + 1)}
    for reg, path in zip(host.registers, host.register_paths, strict=True):
        if not reg.access.readable or reg.space not in rule.spaces or reg.name in exempt:
            continue
        first, last = reg.first_address, reg.last_address
        if first % w != 0 and first // w != last // w:
            host.problems.add(
                path,
                f"{reg.name}: its {last + 1 - first} words at 0x{first:04X} cross a {w}-word boundary, and transport.read_alignment"
                f" lets reads start only on multiples of {w} (list it in read_alignment.exempt if the manual allows it)",
            )
            continue
        start, end = first - first % w, last + 1 + (-(last + 1)) % w
        pads = [a for a in (*range(start, first), *range(last + 1, end)) if (reg.space, a) not in readable]
        if pads and not tolerates_gaps:
            host.problems.add(
                path,
                f"{reg.name}: an aligned read of it ({end - start} words at 0x{start:04X}) covers 0x{pads[0]:04X}, which the map does"
                f" not document and the device does not tolerate (list it in read_alignment.exempt if the manual allows reading it alone)",
            )


def swap_value_problems(t: dict[str, Any], reg: Register) -> list[tuple[Path, str]]:
    """A magic value whose write swaps the word order: a trigger (never repeated), writable, and a value the register admits."""
    w = t["word_order_register"]
    path: Path = ("transport", "word_order_register")
    value = w["swap_value"]
    out: list[tuple[Path, str]] = []
    if not reg.access.writable:
        out.append(((*path, "register"), f"word_order_register: {reg.name} is read-only; a swap_value must be written to it"))
    if not reg.trigger:
        out.append(
            (
                (*path, "register"),
                f"word_order_register: a write of swap_value {value} to {reg.name} swaps the order each time it arrives, so {reg.name}"
                " must be marked trigger: true (never sent twice)",
            )
        )
    if not reg.type.is_float and (not float(value).is_integer() or not reg.raw_min <= value <= reg.raw_max):
        out.append(((*path, "swap_value"), f"word_order_register: swap_value {value} is not a value of {reg.name} ({reg.type.value})"))
    return out
