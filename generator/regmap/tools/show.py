"""`regmap show`: the map for humans, as `cantools dump` prints a database."""

from __future__ import annotations

from regmap.core.text import eng, number_text, titled
from regmap.diagnostics import UsageError
from regmap.model import Access, ByteOrder, Command, Device, EnumType, PollClass, Register
from regmap.tools.selectors import Registers, suggest
from regmap_runtime.spaces import DEFAULT_SPACE


def _eng(reg: Register, raw: int | float | str | None) -> str:
    """A raw value as the engineering value people read, every digit it has; `?` when the map gives none."""
    if reg.scale_from is not None and raw is not None:
        return f"raw {raw}"  # the value is raw x 10^sf, sf read from the device: no value is known here
    return "?" if raw is None else eng(reg, raw, every_digit=True)


def _range(reg: Register, unit: str) -> str:
    if reg.type.is_string:
        return f"text of up to {2 * reg.words} bytes"
    if reg.type.is_bool:
        return "off/on"
    if reg.scale_from is not None:
        return f"raw {reg.raw_min}..{reg.raw_max}"
    return f"{_eng(reg, reg.raw_min)}..{_eng(reg, reg.raw_max)}{unit}"


def _register_line(reg: Register) -> str:
    unit = f" {reg.unit}" if reg.unit else ""
    kind = reg.enum.name if reg.enum else "bitfield" if reg.bitfields else reg.type.value
    if reg.space != DEFAULT_SPACE:
        kind += f", {reg.space_info.title}"
    if reg.firmware is not None:
        kind += f", {reg.firmware.text}"
    param = f"{reg.param:<8} " if reg.param else " " * 9
    return (
        f"  0x{reg.address:04X} {param}{reg.name:<32} {reg.type.value:<4} {reg.access.value:<2} "
        f"{_range(reg, unit)}  default {_eng(reg, reg.default)}  [{kind}]"
    )


_DIRECTION = {Access.READ: " [read only: never written]", Access.WRITE: " [write only]", Access.READ_WRITE: ""}


def _enum_lines(e: EnumType) -> list[str]:
    return [f"enum {e.name}: {titled(e.title, e.title_zh)}"] + [
        f"  {m.value:>6} {m.name:<28} {titled(m.title, m.title_zh)}{_DIRECTION[m.access]}" for m in e.members
    ]


def _command_line(c: Command) -> str:
    argument = f" {c.argument.name} ({c.argument.min}..{c.argument.max})" if c.argument else ""
    return f"  {c.name}{argument}: 0x{c.value:04X} to {c.register.label}  {titled(c.title, c.title_zh)}"


def _type_text(reg: Register) -> str:
    if reg.type.is_bool:
        return "bool, 1 bit"
    if reg.type.is_string:
        return f"string, {reg.words} word(s) = {2 * reg.words} bytes, {reg.encoding}, {reg.padding} padded"
    text = f"{reg.type.value}, {reg.words} word(s)" + (f", {reg.word_order.value}" if reg.wide else "")
    if reg.byte_order is not ByteOrder.HIGH_FIRST:
        text += f", bytes {reg.byte_order.value}"
    return text


def _raw_text(reg: Register, raw: int | float | str) -> str:
    return repr(raw) if isinstance(raw, str) else number_text(raw, reg.type.value)


def register_detail(reg: Register) -> list[str]:
    lines = [f"{reg.label}: {titled(reg.title, reg.title_zh)}"]
    unit = f" {reg.unit}" if reg.unit else ""
    space = reg.space_info
    codes = "/".join(f"0x{c:02X}" for c in space.codes.values())
    facts = [
        ("address", f"0x{reg.address:04X} ({reg.address})" + (f", high word at 0x{reg.first_address:04X} (paired)" if reg.paired else "")),
        *([("space", f"{space.title} ({codes})")] if reg.space != DEFAULT_SPACE else []),
        ("type", _type_text(reg)),
        ("access", {"r": "read only", "rw": "read/write", "w": "write only"}[reg.access.value]),
        ("unit", reg.unit or "-"),
        ("scale", f"10^{reg.scale_from} (read from the device)" if reg.scale_from else str(reg.scale) if reg.type.numeric else "-"),
        *([("offset", str(reg.offset))] if reg.offset_set else []),
        (
            "range",
            _range(reg, unit)
            + (f" (raw {_raw_text(reg, reg.raw_min)}..{_raw_text(reg, reg.raw_max)})" if reg.type.numeric and not reg.scale_from else ""),
        ),
        (
            "default",
            "unknown"
            if reg.default is None
            else _eng(reg, reg.default) + ("" if reg.scale_from else f" (raw {_raw_text(reg, reg.default)})"),
        ),
        *([("firmware", reg.firmware.text)] if reg.firmware is not None else []),
        *([("poll", reg.poll.value)] if reg.poll is not PollClass.NORMAL else []),
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
        + f", at most {t.max_read_registers} registers per read, {t.max_write_registers} per write"
        + (
            f"; {t.max_read_coils} bits per read, {t.max_write_coils} coils per write"
            if any(r.space_info.bits for r in device.registers)
            else ""
        )
        + (f", bytes {t.byte_order.value}" if t.byte_order is not ByteOrder.HIGH_FIRST else ""),
        *(
            [f"  firmware version in {fw.register.label} ({fw.format}" + (f", {fw.decimals} decimals)" if fw.decimals else ")")]
            if (fw := device.info.firmware_register) is not None
            else []
        ),
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
