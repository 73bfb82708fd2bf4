"""`regmap show`: the map for humans, as `cantools dump` prints a database."""

from __future__ import annotations

from fractions import Fraction

from regmap.backends.text import titled
from regmap.diagnostics import UsageError
from regmap.model import Command, Device, EnumType, Register
from regmap.tools.selectors import Registers, suggest


def _eng(reg: Register, raw: int | None) -> str:
    if raw is None:
        return "?"
    value = Fraction(raw) * reg.scale
    return str(value.numerator) if value.denominator == 1 else f"{float(value):g}"


def _register_line(reg: Register) -> str:
    unit = f" {reg.unit}" if reg.unit else ""
    kind = reg.enum.name if reg.enum else "bitfield" if reg.bitfields else reg.type.value
    param = f"{reg.param:<8} " if reg.param else " " * 9
    return (
        f"  0x{reg.address:04X} {param}{reg.name:<32} {reg.type.value:<4} {reg.access.value:<2} "
        f"{_eng(reg, reg.raw_min)}..{_eng(reg, reg.raw_max)}{unit}  default {_eng(reg, reg.default)}  [{kind}]"
    )


def _enum_lines(e: EnumType) -> list[str]:
    return [f"enum {e.name}: {titled(e.title, e.title_zh)}"] + [
        f"  {m.value:>6} {m.name:<28} {titled(m.title, m.title_zh)}" for m in e.members
    ]


def _command_line(c: Command) -> str:
    argument = f" {c.argument.name} ({c.argument.min}..{c.argument.max})" if c.argument else ""
    return f"  {c.name}{argument}: 0x{c.value:04X} to {c.register.label}  {titled(c.title, c.title_zh)}"


def register_detail(reg: Register) -> list[str]:
    lines = [f"{reg.label}: {titled(reg.title, reg.title_zh)}"]
    facts = [
        ("address", f"0x{reg.address:04X} ({reg.address})" + (f", high word at 0x{reg.first_address:04X} (paired)" if reg.paired else "")),
        ("type", f"{reg.type.value}, {reg.words} word(s)" + (f", {reg.word_order.value}" if reg.wide else "")),
        ("access", {"r": "read only", "rw": "read/write", "w": "write only"}[reg.access.value]),
        ("unit", reg.unit or "-"),
        ("scale", str(reg.scale)),
        ("range", f"{_eng(reg, reg.raw_min)}..{_eng(reg, reg.raw_max)} (raw {reg.raw_min}..{reg.raw_max})"),
        ("default", f"{_eng(reg, reg.default)} (raw {reg.default})" if reg.default is not None else "unknown"),
        ("takes effect", reg.takes_effect or "-"),
        ("source", ", ".join(reg.source) or "-"),
    ]
    lines += [f"  {key:<13}{value}" for key, value in facts]
    if reg.enum:
        lines += ["  " + line for line in _enum_lines(reg.enum)]
    for b in reg.bitfields:
        values = f" ({', '.join(f'{m.value}={m.name}' for m in b.enum.members)})" if b.enum else ""
        lines.append(f"  bit {b.bits_text:<6}{b.name}: {titled(b.title, b.title_zh)}{values}")
    if reg.errata:
        lines.append(f"  errata       {', '.join(reg.errata)}")
    if reg.notes:
        lines.append(f"  notes        {' '.join(reg.notes.split())}")
    return lines


def show(device: Device, selector: str | None = None) -> str:
    if selector is not None:
        return "\n".join(_one(device, selector))
    t = device.transport
    lines = [
        f"{device.info.vendor} {device.info.model} — map {device.info.map_version} ({device.source_path})",
        f"  serial {t.baud} {t.data_bits}{t.parity[0].upper()}{t.stop_bits}, slave {t.slave_min}..{t.slave_max}"
        + (f", broadcast {t.broadcast_id}" if t.broadcast_id is not None else "")
        + f", functions {' '.join(f'0x{c:02X}' for c in t.function_codes)}, word order {t.word_order.value}"
        + f", at most {t.max_read_registers} registers per read, {t.max_write_registers} per write",
        "",
        f"registers ({len(device.registers)}):",
    ]
    for group in device.groups:
        lines.append(f" {group.id}: {titled(group.title, group.title_zh)}")
        lines += [_register_line(r) for r in group.registers]
    lines += ["", f"enums ({len(device.enums)}):"]
    for e in device.enums:
        lines += ["  " + line for line in _enum_lines(e)]
    lines += ["", f"commands ({len(device.commands)}):"] + [_command_line(c) for c in device.commands]
    return "\n".join(lines)


def _one(device: Device, selector: str) -> list[str]:
    reg = Registers(device).find(selector)
    if reg is not None:
        return register_detail(reg)
    wanted = selector.strip().lower()
    for e in device.enums:
        if e.name == wanted:
            return _enum_lines(e)
    for c in device.commands:
        if c.name == wanted:
            return [_command_line(c).strip()]
    names = [r.name for r in device.registers] + [r.param for r in device.registers if r.param] + [e.name for e in device.enums]
    raise UsageError(
        f"{selector!r} is no register, enum or command of {device.info.model}{suggest(selector, names + [c.name for c in device.commands])}"
    )
