"""How the docs spell what a register is on the wire: its space and function codes, its type, its word
and byte order (ABCD ...), its firmware gate and poll class; and what a device uses of these.

A device that uses none of these features (every register a holding register, no byte order, no
gates, no poll classes, as the seed maps) gets none of the new columns or facts. One spelling is
new on every page: a wide value whose order is not Modbus's ABCD names it in its type cell
(`u32, 2 words, low first (CDAB)`), because that name is what users compare against other tools.
"""

from __future__ import annotations

from regmap.backends.markdown.text import reg_link
from regmap.core.text import number, zone_text
from regmap.model import ByteOrder, Device, FirmwareGate, PollClass, ReadAlignment, Register, WordOrder
from regmap.records import dataclass
from regmap.render import hex2
from regmap_runtime.spaces import DEFAULT_SPACE, SPACES, Space

# Keyed by the type's value string, as POLL_MEANING by the poll class's: as the map writes them.
TYPE_LONG = {
    "u16": "unsigned 16-bit",
    "s16": "signed 16-bit",
    "u32": "unsigned 32-bit",
    "s32": "signed 32-bit",
    "u64": "unsigned 64-bit",
    "s64": "signed 64-bit",
    "f16": "16-bit IEEE 754 half-precision float",
    "f32": "32-bit IEEE 754 float",
    "f64": "64-bit IEEE 754 float",
    "string": "text",
    "bool": "one bit: on or off",
    "timestamp": "seconds since 1970, unsigned 32-bit",
}

SPACE_SHORT = {"holding": "holding", "input": "input", "coil": "coil", "discrete_input": "discrete input"}

ENCODING_NAMES = {"ascii": "ASCII", "latin-1": "Latin-1", "utf-8": "UTF-8", "gbk": "GBK"}

POLL_MEANING = {
    "static": "static: read once (nameplate, limits), not polled",
    "fast": "fast: polled at the fast rate",
    "normal": "normal: polled with everything else",
    "slow": "slow: polled at the slow rate",
}

FIRMWARE_FORMATS = {
    "decimal": "a decimal number",
    "major_minor": "major version in the high byte, minor in the low byte",
    "string": "text; the version is its first dotted number",
}


# ---------------------------------------------------------------------------------------------- space


def codes(space: Space, reg: Register | None = None) -> str:
    """`0x03/0x06/0x10`: the space's function codes (only those the register's access uses)."""
    readable = reg is None or reg.access.readable
    writable = reg is None or reg.access.writable
    picked = [space.read] if readable else []
    if writable:
        picked += [c for c in (space.write_single, space.write_multiple) if c is not None]
    return "/".join(hex2(c) for c in picked)


def space_cell(reg: Register) -> str:
    """The quick reference's cell: `input 0x04`, `coil 0x01/0x05/0x0F`."""
    return f"{SPACE_SHORT[reg.space]} {codes(reg.space_info, reg)}"


def space_fact(reg: Register) -> str:
    """`input registers: read with 0x04`; `holding registers: read with 0x03, written with 0x06/0x10`."""
    space = reg.space_info
    parts = []
    if reg.access.readable:
        parts.append(f"read with {hex2(space.read)}")
    writes = [c for c in (space.write_single, space.write_multiple) if c is not None]
    if reg.access.writable and writes:
        parts.append("written with " + "/".join(hex2(c) for c in writes))
    return f"{space.title}: " + ", ".join(parts)


# ---------------------------------------------------------------------------------------------- order


def order_name(words: int, word_order: WordOrder, byte_order: ByteOrder) -> str:
    """The bytes of a value as they travel, A the most significant: ABCD, CDAB, BADC, DCBA (and the
    eight-letter names of 64-bit values, AB/BA of one word)."""
    letters = [chr(ord("A") + i) for i in range(2 * words)]
    pairs = [letters[2 * i : 2 * i + 2] for i in range(words)]
    if word_order is WordOrder.LOW_FIRST:
        pairs.reverse()
    if byte_order is ByteOrder.LOW_FIRST:
        pairs = [[low, high] for high, low in pairs]
    return "".join(b for pair in pairs for b in pair)


def bytes_swapped(reg: Register) -> bool:
    return reg.byte_order is ByteOrder.LOW_FIRST and reg.type.info.has_byte_order  # the cheap test first: most keep the order


def order_suffix(reg: Register) -> str:
    """What the type cell adds: the word order as before; the four-letter name when the bytes are
    swapped too (word order alone says CDAB already); `bytes swapped` for a one-word value or a string."""
    if reg.wide:
        order = "high" if reg.word_order is WordOrder.HIGH_FIRST else "low"
        text = (f" {reg.zone.upper() if reg.zone == 'utc' else reg.zone}" if reg.zone else "") + f", {reg.words} words, {order} first"
        if bytes_swapped(reg):
            text += f" ({order_name(reg.words, reg.word_order, reg.byte_order)})"
        return text
    if reg.type.is_string:
        return f", {reg.words} words" + (", bytes swapped" if bytes_swapped(reg) else "")
    return ", bytes swapped (BA)" if bytes_swapped(reg) else ""


def order_fact(reg: Register) -> str:
    """The register's word and byte order in words, with the four-letter name of wide values."""
    if reg.type.is_string:
        if bytes_swapped(reg):
            return "bytes swapped in each word: the first character of each pair is in the low byte"
        return "first character in the high byte of the first word (Modbus order)"
    byte = "low byte first in each word (bytes swapped)" if bytes_swapped(reg) else "high byte first in each word"
    if not reg.wide:
        return f"{byte}: {order_name(1, WordOrder.HIGH_FIRST, reg.byte_order)}"
    word = "high word first" if reg.word_order is WordOrder.HIGH_FIRST else "low word first"
    return f"{word}, {byte}: {order_name(reg.words, reg.word_order, reg.byte_order)}"


# ---------------------------------------------------------------------------------------------- type


def type_fact(reg: Register) -> str:
    """`f32 (32-bit IEEE 754 float)`; a string says its length, encoding and padding."""
    if reg.type.is_string:
        padding = "NUL padded" if reg.padding == "nul" else "space padded (a read strips the trailing spaces)"
        return (
            f"string ({reg.words} words = {2 * reg.words} bytes of {ENCODING_NAMES[reg.encoding]} text, "
            f"{padding}; a read stops at the first NUL)"
        )
    if reg.zone is not None:  # the clock the seconds count, read as a date and time
        return f"{reg.type._value_} ({zone_text(reg)}, unsigned 32-bit; read as a {'UTC' if reg.zone == 'utc' else 'local, zone-less'} date and time)"
    return f"{reg.type._value_} ({TYPE_LONG[reg.type._value_]})"  # _value_: the member's value, without Enum.value's Python descriptor


def scale_fact(reg: Register, unit: str) -> str:
    """`raw × 0.1 = value in A`; with an offset `raw × 0.1 − 40 = value in °C` (value = raw × scale + offset)."""
    text = "raw" if reg.scale == 1 and reg.offset_set else f"raw × {number(reg.scale)}"
    if reg.offset_set:
        sign = "−" if reg.offset < 0 else "+"
        text += f" {sign} {number(abs(reg.offset))}"
    return f"{text} = value{' in ' + unit if unit else ''}"


def has_conversion(reg: Register) -> bool:
    return reg.scaled or reg.offset_set


# ---------------------------------------------------------------------------------------------- firmware and poll


def gate_text(gate: FirmwareGate) -> str:
    """`firmware ≥ 2.0`, `firmware < 2.0`, `2.1 ≤ firmware < 3.0` (`from` inclusive, `until` exclusive)."""
    if gate.first is not None and gate.until is not None:
        return f"{gate.first} ≤ firmware < {gate.until}"
    if gate.first is not None:
        return f"firmware ≥ {gate.first}"
    return f"firmware < {gate.until}"


def gate_fact(gate: FirmwareGate) -> str:
    """The gate, and what it means for older and newer firmware."""
    if gate.first is not None and gate.until is not None:
        meaning = f"added in {gate.first}, removed in {gate.until}"
    elif gate.first is not None:
        meaning = f"added in {gate.first}: older firmware does not have it"
    else:
        meaning = f"removed in {gate.until}: that and later firmware do not have it"
    return f"{gate_text(gate)} ({meaning})"


def firmware_register_text(device: Device) -> str | None:
    """How the device reports its firmware version: the register, its format and a worked reading."""
    fw = device.info.firmware_register
    if fw is None:
        return None
    text = FIRMWARE_FORMATS[fw.format]
    if fw.format == "decimal" and fw.decimals:
        scale = 10**fw.decimals
        example = 2 * scale + scale // 10  # 210 = 2.10: the digits after the point are the minor version
        version = f"{example // scale}.{example % scale:0{fw.decimals}d}"
        text += f" with {fw.decimals} decimal{'s' if fw.decimals != 1 else ''} ({example} = version {version})"
    elif fw.format == "decimal":
        text += " (the major version)"
    elif fw.format == "major_minor":
        text += " (0x0203 = version 2.3)"
    else:
        text += " (V2.10 = version 2.10)"
    return text


# ---------------------------------------------------------------------------------------------- what a device uses


@dataclass(frozen=True)
class Uses:
    """Which of the features a device's map uses: the docs show a column or a fact only when it does."""

    spaces: tuple[str, ...]  # in table order, each that has a register
    byte_order: bool  # the device or a register swaps bytes
    gates: bool
    poll: bool
    offsets: bool

    @property
    def other_spaces(self) -> bool:
        return self.spaces != (DEFAULT_SPACE,)

    @property
    def bit_spaces(self) -> bool:
        return any(SPACES[s].bits for s in self.spaces)


def uses(device: Device) -> Uses:
    regs = device.registers
    present = {r.space for r in regs}
    return Uses(
        spaces=tuple(s for s in SPACES if s in present) or (DEFAULT_SPACE,),
        byte_order=device.transport.byte_order is ByteOrder.LOW_FIRST or any(bytes_swapped(r) for r in regs),
        gates=any(r.firmware is not None for r in regs),
        poll=any(r.poll is not PollClass.NORMAL for r in regs),
        offsets=any(r.offset_set for r in regs),
    )


def shared(regs: tuple[Register, ...] | list[Register], key: str) -> object:
    """The value of `key` every register has (a group's inherited `space`, `firmware`, `poll`), or None."""
    if not regs:
        return None
    values = [getattr(r, key) for r in regs]
    first = values[0]
    return first if values.count(first) == len(values) else None  # equal values (list.count tries identity first)


def read_alignment_text(a: ReadAlignment) -> str:
    """The read-alignment rule in one sentence: the unit, the spaces, the device's answer otherwise, the exempt registers."""
    spaces = " and ".join(SPACES[s].title for s in a.spaces)
    answer = f"exception {hex2(a.exception)}" if a.exception is not None else "an exception"
    text = (
        f"reads of {spaces} start on an address that is a multiple of {a.words} and cover a multiple of {a.words} registers;"
        f" the device answers {answer} otherwise (regmap's read plans, client and simulator keep the rule)"
    )
    if a.exempt:
        text += "; may be read alone: " + ", ".join(reg_link(r) for r in a.exempt)
    return text
