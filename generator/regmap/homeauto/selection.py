"""Which registers and commands the home-automation back ends (ESPHome, Home Assistant) turn into entities.

A full map is not what anyone flashes (the C630S has 463 registers), so these back ends generate a
*selection*: `regmap generate --select 'status,Pr5.*,!pr5_reserved*'` or `--select @FILE`.

Format: patterns separated by commas or newlines; `#` starts a comment. Each pattern is a glob
(`*`, `?`, `[...]`, case-sensitive) matched against a register's name, its parameter id (`Pr5.22`,
`P0B-00`) and its group id, and against a command's name. Patterns apply in order and the last one
that matches decides: a plain pattern selects, `!pattern` deselects. A pattern that matches nothing
is an error (a typo must not silently drop entities).

Default (no `--select`): every read-only register (status and monitor values), every command that
is not destructive, and the readable registers the commands write (so their state shows beside the
buttons). A destructive command (restore defaults, initialise parameters, force-enable) is one
deliberate step away: it is generated only when a pattern names it.
"""

from __future__ import annotations

from fnmatch import fnmatchcase
from pathlib import Path

from regmap.diagnostics import UsageError
from regmap.model import Command, Device, Register
from regmap.records import dataclass

DEFAULT_RULE = "the default: every read-only register, every command that is not destructive and the readable registers the commands write"


@dataclass(frozen=True)
class Selection:
    """The chosen part of one map, in map order, and how it was chosen (printed in the generated file)."""

    registers: tuple[Register, ...]
    commands: tuple[Command, ...]
    rule: str
    left_out: tuple[str, ...] = ()  # what `for_variant` took out: the registers and commands the variant lacks


def parse_patterns(spec: str) -> tuple[str, ...]:
    """The patterns of a `--select` value: inline, or read from the file named after `@`."""
    if spec.startswith("@"):
        path = Path(spec[1:])
        try:
            spec = path.read_text(encoding="utf-8")
        except OSError as exc:
            raise UsageError(f"--select {spec}: cannot read the selection file: {exc.strerror}") from None
    patterns: list[str] = []
    for line in spec.splitlines():
        for item in line.split("#", 1)[0].split(","):
            if item.strip():
                patterns.append(item.strip())
    if not patterns:
        raise UsageError("--select: no patterns given")
    return tuple(patterns)


def _keys(reg: Register) -> tuple[str, ...]:
    return tuple(k for k in (reg.name, reg.param, reg.group) if k)


def select(device: Device, patterns: tuple[str, ...] | None) -> Selection:
    """The registers and commands `patterns` choose (the default rule when None)."""
    if patterns is None:
        commands = tuple(c for c in device.commands if not c.destructive)
        targets = {c.register.name for c in commands}
        registers = tuple(r for r in device.registers if r.access.readable and (not r.access.writable or r.name in targets))
        return Selection(registers, commands, DEFAULT_RULE)
    chosen_regs = dict.fromkeys(r.name for r in device.registers if _decide(_keys(r), patterns))
    chosen_cmds = dict.fromkeys(c.name for c in device.commands if _decide((c.name,), patterns))
    unused = [
        p
        for p in patterns
        if not any(fnmatchcase(k, p.removeprefix("!")) for r in device.registers for k in _keys(r))
        and not any(fnmatchcase(c.name, p.removeprefix("!")) for c in device.commands)
    ]
    if unused:
        raise UsageError(f"{device.source_path}: --select pattern(s) {', '.join(unused)} match no register, parameter, group or command")
    return Selection(
        tuple(r for r in device.registers if r.name in chosen_regs),
        tuple(c for c in device.commands if c.name in chosen_cmds),
        "patterns " + ", ".join(patterns),
    )


def for_variant(selection: Selection, variant: str | None) -> Selection:
    """The selection for a device that is one variant (a plant's device, `variant:`): the registers that variant
    lacks, and the commands that write them, left out (they would only ever answer an exception); None: as it is."""
    if variant is None:
        return selection
    commands = tuple(c for c in selection.commands if c.register.on_variant(variant))
    return Selection(
        tuple(r for r in selection.registers if r.on_variant(variant)),
        commands,
        selection.rule,
        tuple(r.name for r in selection.registers if not r.on_variant(variant))
        + tuple(c.name for c in selection.commands if c not in commands),
    )


def _decide(keys: tuple[str, ...], patterns: tuple[str, ...]) -> bool:
    chosen = False
    for pattern in patterns:
        negate = pattern.startswith("!")
        if any(fnmatchcase(k, pattern.removeprefix("!")) for k in keys):
            chosen = not negate
    return chosen
