"""Frame annotation for the examples: a byte table per frame, and the values a frame carries.

Each frame is read in its function's data space (a 0x02 request names discrete inputs, never the
holding register at the same address) and through the decoder `regmap decode` uses; the bit
functions (0x01/0x02/0x05/0x0F) are annotated bit by bit, the first bit in the lowest bit of a byte.
"""

from __future__ import annotations

from regmap.backends.markdown import text as md
from regmap.backends.markdown.text import DocId, Md, md_text
from regmap.backends.markdown.views import ByteRow, Context, DecodedRow, ExampleView, Fact, FrameView
from regmap.core.decoding import FUNCTION_NAMES, carried, decode_words, trim_bits
from regmap.core.text import eng, number, number_text, space_label
from regmap.model import Device, Example, ExampleValue, Register, WordOrder
from regmap.render import hex2
from regmap_runtime.codec import words_to_raw
from regmap_runtime.rtu import STANDARD_EXCEPTIONS, Frame, crc_bytes, crc_ok, parse_frame, to_hex, unpack_bits
from regmap_runtime.spaces import COIL_OFF, COIL_ON, DEFAULT_SPACE, SPACES

# What a request's quantity counts, per space (the Modbus spec's "quantity of registers/coils/inputs").
_COUNTED = {"holding": "Register count", "input": "Register count", "coil": "Coil count", "discrete_input": "Input count"}


def _offsets(start: int, length: int) -> str:
    return str(start) if length == 1 else f"{start}–{start + length - 1}"


def _function_meaning(device: Device, function: int) -> Md:
    base = function & 0x7F
    name = FUNCTION_NAMES.get(base, "unknown function")
    supported = "" if base in device.transport.function_codes else " (not supported by this device)"
    if function & 0x80:
        return Md(f"`{hex2(function)}` = `{hex2(base)}` + `0x80`: exception response to {name}{supported}")
    return Md(f"`{hex2(function)}` {name}{supported}")


def _slave_meaning(device: Device, slave: int) -> Md:
    t = device.transport
    if t.broadcast_id is not None and slave == t.broadcast_id:
        return Md(f"{slave}: broadcast, no slave replies")
    if not t.slave_min <= slave <= t.slave_max:
        return Md(f"slave {slave} (outside the documented {t.slave_min} … {t.slave_max})")
    return Md(f"slave {slave}")


def _plural(count: int, space: str) -> str:
    noun = "register" if space in ("holding", "input") else space_label(space)
    return f"{count} {noun}{'s' if count != 1 else ''}"


def _word_owner(device: Device, address: int, space: str = DEFAULT_SPACE) -> Md:
    reg = device.covering(address, space)
    if reg is None:
        if space == DEFAULT_SPACE:
            return Md("no documented register")
        if not any(r.space == space for r in device.registers):
            return Md(f"{space_label(space)}; the map has no {SPACES[space].title}")
        return Md(f"no documented {space_label(space)}")
    link = md.reg_link(reg)
    if reg.paired and address < reg.address:
        return Md(f"unused high word of {link}")
    index = address - reg.address
    if reg.type.is_string and index:
        return Md(f"bytes {2 * index + 1}–{2 * index + 2} of {link}")
    if reg.wide and reg.words > 2:
        rank = index if reg.word_order is WordOrder.HIGH_FIRST else reg.words - 1 - index
        names = {0: "highest word", reg.words - 1: "lowest word"}
        return Md(f"{names.get(rank, f'word {rank + 1} of {reg.words} from the highest')} of {link}")
    if reg.wide:
        high = (address == reg.address) == (reg.word_order is WordOrder.HIGH_FIRST)
        return Md(f"{'high' if high else 'low'} word of {link}")
    return link


def _value_text(reg: Register, raw: int | float | str) -> Md:
    if isinstance(raw, str) or reg.type.is_bool or isinstance(raw, float):
        return Md(md_text(eng(reg, raw)) + md.unit_suffix(reg))
    if reg.bitfields:
        parts = []
        covered = 0
        for b in sorted(reg.bitfields, key=lambda b: b.lsb):
            covered |= b.mask
            field = (raw & b.mask) >> b.lsb
            label = md.enum_label(b.enum, field) if b.enum is not None else None
            parts.append(f"{DocId(b.name)} = {label or field}")
        rest = raw & ~covered & ((1 << reg.type.bits) - 1)
        if rest:
            parts.append(f"undefined bits {md.hex_value(rest, reg.words)}")
        return Md(", ".join(parts))
    text = eng(reg, raw) + md.unit_suffix(reg)
    label = md.enum_label(reg.enum, raw) if reg.enum is not None else None
    if reg.enum is not None:
        return Md(f"{text} = {label}" if label else f"{text} (not a listed value)")
    return Md(text)


def _word_meaning(ctx: Context, address: int | None, word: int, space: str = DEFAULT_SPACE) -> tuple[Md, Md]:
    if address is None:
        return Md("Data word"), Md(f"{word} ({md.hex_value(word)}); address unknown")
    owner = _word_owner(ctx.device, address, space)
    reg = ctx.device.covering(address, space)
    value = f"{word} ({md.hex_value(word)})"
    if reg is not None and reg.words == 1 and address == reg.address:
        value = f"{md.hex_value(word)} → {_value_text(reg, words_to_raw(ctx.registers.spec(reg), [word]))}"
    return Md(f"Register {md.address(address)}"), Md(f"{owner}: {value}")


def _bit_meaning(ctx: Context, first: int | None, byte: int, bits: int, space: str) -> tuple[Md, Md]:
    """One data byte of a bit frame: which addresses its bits are (the first in the lowest bit) and what each says."""
    values = unpack_bits(bytes([byte]), bits)
    pattern = f"`{byte:08b}`"
    if first is None:
        return Md("Data byte"), Md(f"`0x{byte:02X}` = {pattern}; addresses unknown")
    last = first + bits - 1
    field = Md(f"{SPACES[space].title.capitalize()} {md.address(first)}" + (f" … {md.address(last)}" if bits > 1 else ""))
    parts = []
    for i, bit in enumerate(values):
        reg = ctx.device.covering(first + i, space)
        parts.append(f"{md.reg_link(reg) if reg is not None else md.address(first + i)} = {bit}")
    return field, Md(f"{pattern} (lowest bit first): " + ", ".join(parts))


def _frame_view(
    ctx: Context, label: str, frame: bytes, direction: str, start: int | None, asked: Frame | None = None
) -> tuple[FrameView, Frame]:
    device = ctx.device
    parsed = parse_frame(frame, direction)
    if asked is not None and asked.count is not None:
        parsed = trim_bits(parsed, asked.count)  # a bit response's padding is no data
    space = parsed.space or DEFAULT_SPACE
    bits = SPACES[space].bits
    rows: list[ByteRow] = []
    pos = 0

    def take(length: int, field: str | Md, meaning: Md) -> bytes:
        nonlocal pos
        chunk = frame[pos : pos + length]
        rows.append(ByteRow(offset=_offsets(pos, len(chunk)), hex=to_hex(chunk), field=Md(field), meaning=meaning))
        pos += len(chunk)
        return chunk

    def data_words(first: int | None, data_end: int) -> None:
        i = 0
        while pos + 2 <= data_end:
            word = int.from_bytes(frame[pos : pos + 2], "big")
            field, meaning = _word_meaning(ctx, None if first is None else first + i, word, space)
            take(2, field, meaning)
            i += 1

    def data_bits(first: int | None, count: int | None, data_end: int) -> None:
        i = 0
        while pos < data_end:
            carried = 8 if count is None else max(0, min(8, count - 8 * i))
            byte = frame[pos]
            if carried == 0:
                take(1, "Padding", Md(f"`0x{byte:02X}`: no bits asked for" + ("" if byte == 0 else "; **not zero**")))
            else:
                field, meaning = _bit_meaning(ctx, None if first is None else first + 8 * i, byte, carried, space)
                take(1, field, meaning)
            i += 1

    end = len(frame) - 2
    take(1, "Slave id", _slave_meaning(device, parsed.slave))
    take(1, "Function", _function_meaning(device, parsed.function))
    address, count = parsed.address, parsed.count
    if parsed.kind in ("read_request", "write_multiple_response", "write_multiple_request") and address is not None and count is not None:
        take(2, "Start address", Md(f"{md.address(address)} ({address}): {_word_owner(device, address, space)}"))
        last = address + count - 1
        take(2, _COUNTED[space], Md(f"{_plural(count, space)}: {md.address(address)} … {md.address(last)}"))
        if parsed.kind == "write_multiple_request" and parsed.byte_count is not None:
            take(1, "Byte count", Md(f"{parsed.byte_count} bytes"))
            if bits:
                data_bits(address, count, end)
            else:
                data_words(address, end)
    elif parsed.kind == "read_response" and parsed.byte_count is not None:
        if bits:
            take(
                1, "Byte count", Md(f"{parsed.byte_count} byte{'s' if parsed.byte_count != 1 else ''} = up to {8 * parsed.byte_count} bits")
            )
            data_bits(start, asked.count if asked is not None else None, end)
        else:
            take(
                1, "Byte count", Md(f"{parsed.byte_count} bytes = {parsed.byte_count // 2} register{'s' if parsed.byte_count != 2 else ''}")
            )
            data_words(start, end)
    elif parsed.kind == "write_single" and address is not None:
        take(2, "Address", Md(f"{md.address(address)} ({address}): {_word_owner(device, address, space)}"))
        if pos + 2 <= end and bits:
            word = int.from_bytes(frame[pos : pos + 2], "big")
            state = {COIL_ON: "on", COIL_OFF: "off"}.get(word)
            meaning = (
                f"{md.hex_value(word)}: {state}"
                if state
                else f"{md.hex_value(word)}: **not a coil state** (0x05 takes 0xFF00 on or 0x0000 off)"
            )
            take(2, "Value", Md(meaning))
        elif pos + 2 <= end:
            take(2, "Value", _word_meaning(ctx, address, int.from_bytes(frame[pos : pos + 2], "big"))[1])
    elif parsed.kind == "exception" and parsed.exception_code is not None:
        code = parsed.exception_code
        known = device.transport.exception(code)
        meaning = (
            f"{md_text(known.title)}" + (f" ({md_text(known.title_zh)})" if known.title_zh else "")
            if known is not None
            else STANDARD_EXCEPTIONS.get(code, "unknown exception") + " (standard Modbus meaning; not listed by the manual)"
        )
        take(1, "Exception code", Md(f"`{hex2(code)}` {meaning}"))
    if pos < end:
        take(end - pos, "Data", Md("not decoded" if parsed.kind == "unknown" else "bytes the frame layout does not account for"))
    crc = int.from_bytes(frame[-2:], "little")
    if crc_ok(frame):
        crc_text = f"`{md.hex_value(crc)}`, sent low byte first: valid"
    else:
        crc_text = f"`{md.hex_value(crc)}`: **wrong**, the CRC of the preceding bytes is `{to_hex(crc_bytes(frame[:-2]))}`"
    take(2, "CRC", Md(crc_text))
    return FrameView(label=label, hex=to_hex(frame), rows=tuple(rows), problems=parsed.problems), parsed


def _span(parsed: Frame, start: int | None) -> range:
    """Addresses a frame touches: the request's range, or the response's data words from the request's start."""
    if parsed.kind == "read_response":
        return range(start, start + len(carried(parsed))) if start is not None else range(0)
    if parsed.address is not None and parsed.count is not None:
        return range(parsed.address, parsed.address + parsed.count)
    return range(0)


def _raw_shown(reg: Register, raw: int | float | str) -> str:
    """A raw value in the decoded table: text quoted, a float in its shortest form, an integer as `md.raw_literal` writes it."""
    if isinstance(raw, str):
        return f"“{md_text(raw)}”"
    if isinstance(raw, float):
        return number_text(raw, reg.type._value_)
    return md.raw_literal(reg, raw)


def _recorded(reg: Register, record: ExampleValue) -> Md:
    parts = []
    if record.raw is not None:
        parts.append("raw " + _raw_shown(reg, record.raw))
    if record.words is not None:
        parts.append("words " + ", ".join(md.hex_value(w) for w in record.words))
    value = record.value
    if isinstance(value, str):
        parts.append(f"“{md_text(value)}”")
    elif value is not None:
        parts.append(number(value) + md.unit_suffix(reg))
    return Md("; ".join(parts) if parts else md.DASH)


def _decoded_rows(ctx: Context, example: Example, parsed: Frame, start: int | None) -> list[DecodedRow]:
    device = ctx.device
    span = _span(parsed, start)
    space = parsed.space or DEFAULT_SPACE
    has_data = parsed.kind in ("read_response", "write_single", "write_multiple_request")
    # The words (bits) a frame carries, split into registers by the decoder `regmap decode` uses.
    found = decode_words(device, span.start, carried(parsed)[: len(span)], space=space, regs=ctx.registers) if has_data and span else []
    words = {v.address + i: w for v in found for i, w in enumerate(v.words)}
    raws = {v.register: v.raw for v in found if v.register is not None and v.raw is not None}
    # By name (unique in a device): comparing two registers compares every field.
    regs: dict[str, Register] = {}
    for address in span:
        reg = device.covering(address, space)
        if reg is not None:
            regs.setdefault(reg.name, reg)
    records: dict[str, ExampleValue] = {}
    for v in example.values:
        regs.setdefault(v.register.name, v.register)
        records.setdefault(v.register.name, v)
    rows = []
    for reg in regs.values():
        own = range(reg.address, reg.last_address + 1)
        decoded_raw = raws.get(reg.name)  # every word of the register is in the frame
        if decoded_raw is not None:
            raw_text, value = _raw_shown(reg, decoded_raw), _value_text(reg, decoded_raw)
        elif has_data and any(a in words for a in own):
            present = [a for a in own if a in words]
            raw_text = ", ".join(md.hex_value(words[a]) for a in present)
            value = Md(f"{len(present)} of {reg.words} words in this frame")
        else:
            raw_text, value = md.DASH, Md("read" if parsed.kind == "read_request" else md.DASH)
        record = records.get(reg.name)
        recorded = _recorded(reg, record) if record is not None else Md(md.DASH)
        if record is not None and record.raw is not None and decoded_raw is not None:
            recorded = Md(recorded + (" ✓" if record.raw == decoded_raw else " — **differs from the frame**"))
        where = Md(f"{md.address(reg.address)}–{md.address(reg.last_address)}") if reg.wide else md.address(reg.address)
        rows.append(DecodedRow(register=md.reg_link(reg), address=where, raw=raw_text, value=value, recorded=recorded))
        ctx.examples_by_register.setdefault(reg.name, [])
        if example.id not in ctx.examples_by_register[reg.name]:
            ctx.examples_by_register[reg.name].append(example.id)
    return rows


def example_view(ctx: Context, example: Example) -> ExampleView:
    device = ctx.device
    start: int | None = None
    request: Example | None = None
    asked: Frame | None = None
    if example.request is not None:
        request = device.example(example.request)
        asked = parse_frame(request.wire_frame, "request")
        start = asked.address
        if asked.kind != "read_request":
            asked = None  # only a read request's count cuts a response's bits
    printed, parsed = _frame_view(ctx, "Frame as printed in the manual", example.frame, example.direction, start, asked)
    frames = [printed]
    if example.corrected_frame is not None:
        corrected, parsed = _frame_view(ctx, "Frame regmap sends (corrected)", example.corrected_frame, example.direction, start, asked)
        frames.append(corrected)
    facts = [Fact("Direction", Md(example.direction)), Fact("Source", md.escaped(md.sources(example.source)))]
    if request is not None:
        facts.append(Fact("Answers", md.link(md.code(request.id), md.anchor("example", request.id))))
    answers = ctx.responses.get(example.id, [])
    if answers:
        facts.append(Fact("Answered by", md.join(md.link(md.code(a), md.anchor("example", a)) for a in answers)))
    if example.erratum is not None:
        facts.append(Fact("Erratum", md.errata_links([example.erratum])))
    direction = "request" if example.direction == "request" else "response"
    return ExampleView(
        anchor=md.anchor("example", example.id),
        heading=Md(f"{md.code(example.id)} — {direction}, {md_text(md.sources(example.source))}"),
        meaning=md.paragraph(example.meaning),
        meaning_zh=example.meaning_zh or "",
        facts=tuple(facts),
        frames=tuple(frames),
        decoded=tuple(_decoded_rows(ctx, example, parsed, start)),
        notes=md.paragraph(example.notes),
    )
