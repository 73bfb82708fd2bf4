"""A device's page (commands, errata, overview, timing and the sections above), the index page."""

from __future__ import annotations

from collections.abc import Sequence

from regmap.backends.markdown import text as md
from regmap.backends.markdown.diagrams import bitfield_svg, diagram_path
from regmap.backends.markdown.frames import example_view
from regmap.backends.markdown.registers import enum_view, extra_headers, group_view
from regmap.backends.markdown.text import DocId, Md
from regmap.backends.markdown.views import (
    CommandView,
    Context,
    DevicePage,
    ErratumView,
    ExceptionView,
    Fact,
    FaultView,
    ReadingView,
    TimingView,
)
from regmap.backends.markdown.wire import Uses, firmware_register_text, order_name, read_alignment_text
from regmap.core.decoding import FUNCTION_NAMES
from regmap.core.text import number
from regmap.diagnostics import UsageError
from regmap.model import ByteOrder, Command, Device, Erratum, PollClass, WordOrder
from regmap.records import dataclass
from regmap.render import header_lines, hex2, md_text, templates
from regmap.runtime_bridge import read_plan
from regmap.target import Files
from regmap_runtime.codec import raw_to_words
from regmap_runtime.rtu import build_write_multiple, build_write_single, to_hex
from regmap_runtime.spaces import SPACES

INDEX_PAGE = "index.md"


def _command_frame(ctx: Context, cmd: Command) -> Md:
    """The frame a client sends for the command (to slave 1, with the smallest argument)."""
    reg = cmd.register
    argument = cmd.argument.min if cmd.argument is not None else None
    words = raw_to_words(ctx.registers.spec(reg), cmd.raw_value(argument))
    frame = build_write_single(1, reg.address, words[0]) if len(words) == 1 else build_write_multiple(1, reg.address, words)
    suffix = f" ({DocId(cmd.argument.name)} = {argument})" if cmd.argument is not None else ""
    return Md(f"`{to_hex(frame)}`{suffix}")


def _command_view(ctx: Context, cmd: Command) -> CommandView:
    reg = cmd.register
    writes = f"`{md.hex_value(cmd.value, reg.words)}`"
    label = md.enum_label(reg.enum, cmd.value) if reg.enum is not None else None
    if label:
        writes += f" = {label}"
    if cmd.argument is not None:
        arg = cmd.argument
        writes += f" + {md.code(arg.name)} ({arg.min} … {arg.max}{', ' + md_text(arg.title) if arg.title else ''})"
    return CommandView(
        anchor=md.anchor("command", cmd.name),
        name=md.code(cmd.name),
        title=cmd.title,
        title_zh=cmd.title_zh or md.DASH,
        register=Md(f"{md.reg_link(reg, param=False)} {md.address(reg.address)}"),
        writes=Md(writes),
        frame=_command_frame(ctx, cmd),
        description=cmd.description or md.DASH,
        source=md.sources(cmd.source),
        destructive=cmd.destructive,
    )


def _erratum_view(ctx: Context, erratum: Erratum) -> ErratumView:
    device = ctx.device
    links: list[Fact] = []
    if erratum.registers:
        links.append(Fact("Registers", md.join(md.reg_link(device.register(n)) for n in erratum.registers)))
    examples = [ex.id for ex in device.examples if ex.erratum == erratum.id]
    if examples:
        links.append(Fact("Examples", md.join(md.link(md.code(i), md.anchor("example", i)) for i in examples)))
    return ErratumView(
        anchor=md.anchor("erratum", erratum.id),
        heading=Md(f"{md_text(erratum.id)} — {md_text(erratum.title)}"),
        readings=tuple(ReadingView(source=md.sources(r.source), says=r.says) for r in erratum.readings),
        choice=md.paragraph(erratum.choice),
        reason=md.paragraph(erratum.reason),
        links=tuple(links),
    )


def _overview(device: Device, used: Uses) -> tuple[Fact, ...]:
    info, t = device.info, device.transport
    vendor = md_text(info.vendor) + (f" ({md_text(info.vendor_zh)})" if info.vendor_zh else "")
    manual = [md_text(info.manual_title)]
    if info.manual_version:
        manual.append(f"version {md_text(info.manual_version)}")
    manual.append(f"file {md_text(info.manual_file)}")
    if info.manual_language:
        manual.append(f"language {md_text(info.manual_language)}")
    parity = {"none": "no parity", "even": "even parity", "odd": "odd parity"}.get(t.parity, f"parity {t.parity}")
    serial = f"{t.baud} baud, {t.data_bits} data bits, {md_text(parity)}, {t.stop_bits} stop bit{'s' if t.stop_bits != 1 else ''}"
    if t.baud_rates:
        serial += "; baud rates " + ", ".join(str(b) for b in t.baud_rates)
    functions = ", ".join(f"`{hex2(c)}` {FUNCTION_NAMES.get(c, 'unknown function')}" for c in t.function_codes)
    limits = f"read {t.max_read_registers}, write {t.max_write_registers}"
    if t.max_message_bytes is not None:
        limits += f"; longest message {t.max_message_bytes} bytes"
    order = "high word first (at the lower address)" if t.word_order is WordOrder.HIGH_FIRST else "low word first (at the lower address)"
    facts = [
        Fact("Vendor", Md(vendor)),
        Fact("Model", md.escaped(info.model)),
        Fact("Manual", Md(", ".join(manual))),
        Fact("Firmware", md.escaped(info.firmware) if info.firmware else Md("not named by the manual")),
        *_firmware_facts(device, used),
        Fact(
            "Map",
            Md(f"{md_text(device.source_path)}, version {md_text(info.map_version)}, fingerprint {md_text(device.fingerprint)}"),
        ),
        Fact("Serial defaults", Md(serial)),
        Fact("Slave ids", Md(f"{t.slave_min} … {t.slave_max}")),
        Fact("Broadcast", Md(f"id {t.broadcast_id} (no reply)" if t.broadcast_id is not None else "not supported")),
        Fact("Function codes", Md(functions)),
        *_space_facts(device, used),
        Fact("Max registers per request", Md(limits)),
        Fact("32-bit word order", Md(order)),
    ]
    if used.byte_order:
        byte = "low byte first (bytes swapped)" if t.byte_order is ByteOrder.LOW_FIRST else "high byte first (Modbus order)"
        swapped = "; registers marked so below swap their bytes" if t.byte_order is ByteOrder.HIGH_FIRST else ""
        facts.append(
            Fact(
                "Byte order",
                Md(
                    f"{byte} in each word{swapped}; with the word order, 32-bit values travel as {order_name(2, t.word_order, t.byte_order)}"
                ),
            )
        )
    if t.word_order_register is not None:
        w = t.word_order_register
        if w.swap_value is not None:
            said = f"writing {w.swap_value} swaps the word order, whichever it is (a trigger: sent once; written in the current order)"
        else:
            said = f"{w.high_first} = high word first, {w.low_first} = low word first"
        facts.append(Fact("Word-order register", Md(f"{md.reg_link(w.register)}: {said}")))
    a = t.read_alignment
    if a is not None:
        facts.append(Fact("Read alignment", Md(read_alignment_text(a))))
    paired = [r for r in device.registers if r.paired]
    if paired:
        facts.append(
            Fact(
                "Paired registers",
                Md(
                    f"{len(paired)} registers: each listed address is the low word of a 32-bit pair whose unused high word sits at "
                    "address − 1; single writes (0x06) go to the listed address, block reads and writes start at the high word"
                ),
            )
        )
    crc = "low byte first (standard Modbus)" if t.crc_byte_order == "low_first" else md_text(t.crc_byte_order.replace("_", " "))
    facts.append(Fact("CRC byte order", Md(crc)))
    gaps = "tolerated: block reads may span gaps" if t.tolerates_gaps else "rejected: block reads never span gaps"
    facts.append(Fact("Undocumented addresses", Md(gaps)))
    if t.response_delay_ms is not None:
        facts.append(Fact("Response delay", Md(f"{number(t.response_delay_ms)} ms")))
    reading = f"{len(read_plan(device))} requests (the fewest the limits allow)"
    if used.poll:
        classes = [p for p in PollClass if any(r.poll is p and r.access.readable for r in device.registers)]
        reading += "; by poll class: " + ", ".join(f"{p._value_} {len(read_plan(device, poll=p))}" for p in classes)
    facts.append(Fact("Reading everything", Md(reading)))
    facts.append(Fact("Source", md.escaped(md.sources(t.source))))
    return tuple(facts)


def _firmware_facts(device: Device, used: Uses) -> list[Fact]:
    """The register that reports the firmware version, and how many registers only some versions have."""
    facts = []
    fw = device.info.firmware_register
    text = firmware_register_text(device)
    if fw is not None and text is not None:
        facts.append(Fact("Firmware register", Md(f"{md.reg_link(fw.register)} at {md.address(fw.register.address)}: {md_text(text)}")))
    if used.gates:
        gated = sum(1 for r in device.registers if r.firmware is not None)
        facts.append(
            Fact(
                "Firmware-gated registers",
                Md(f"{gated} register{'s' if gated != 1 else ''} exist only in some firmware versions (the Firmware column)"),
            )
        )
    return facts


def _space_facts(device: Device, used: Uses) -> list[Fact]:
    """Which Modbus tables the device's registers live in, and the bit limits of coil requests."""
    if not used.other_spaces:
        return []
    t = device.transport
    counts = []
    for name in used.spaces:
        space = SPACES[name]
        n = sum(1 for r in device.registers if r.space == name)
        codes = "/".join(hex2(c) for c in space.codes.values())
        counts.append(f"{space.title} ({codes}): {n}")
    facts = [Fact("Spaces", Md("; ".join(counts)))]
    if used.bit_spaces:
        limits = f"read {t.max_read_coils}" + (f", write {t.max_write_coils}" if "coil" in used.spaces else "")
        facts.append(Fact("Max bits per request", Md(limits + " (coils and discrete inputs)")))
    return facts


def _timing(device: Device) -> tuple[TimingView, ...]:
    def ms(value: float | None) -> str:
        return md.DASH if value is None else number(value)

    return tuple(
        TimingView(
            baud=str(row.baud),
            receive_to_send=ms(row.receive_to_send_ms),
            wait_after_receive=ms(row.wait_after_receive_ms),
            send_to_receive=ms(row.send_to_receive_ms),
            total=ms(row.total_ms),
        )
        for row in device.transport.timing
    )


def device_page(device: Device) -> DevicePage:
    """Every view of one device's page."""
    if device.id == INDEX_PAGE.removesuffix(".md"):
        raise UsageError(f"{device.source_path}: a device cannot be called {device.id!r}: its page would replace the docs index")
    ctx = Context(device)
    used = ctx.uses
    examples = tuple(example_view(ctx, ex) for ex in device.examples)  # first: registers link to them
    t = device.transport
    exceptions = tuple(
        ExceptionView(code=hex2(e.code), name=md.code(e.name), title=e.title, title_zh=e.title_zh or md.DASH, source=md.sources(e.source))
        for e in t.exceptions
    )
    note = (
        Md("")
        if exceptions
        else Md("The manual lists no exception codes; a device may still answer with the standard Modbus codes 0x01 … 0x04.")
    )
    return DevicePage(
        header=tuple(md.html_comment(line) for line in header_lines(device, "regmap generate")),
        title=Md(f"{md_text(device.info.vendor)} {md_text(device.info.model)}"),
        description=md.paragraph(device.info.description),
        overview=_overview(device, used),
        transport_notes=md.paragraph(t.notes),
        timing=_timing(device),
        quick_note=Md("raw × scale + offset" if used.offsets else "raw × scale"),
        extra_headers=extra_headers(used),
        groups=tuple(group_view(ctx, g) for g in device.groups),
        enums=tuple(enum_view(ctx, e) for e in device.enums),
        commands=tuple(_command_view(ctx, c) for c in device.commands),
        any_destructive=any(c.destructive for c in device.commands),
        faults=tuple(
            FaultView(
                anchor=md.anchor("fault", f.name),
                code=f.code,
                value=md.hex_value(f.value) if f.value is not None else md.DASH,
                name=md.code(f.name),
                title=f.title,
                title_zh=f.title_zh or md.DASH,
                kind=f.kind,
                resettable={True: "yes", False: "no", None: "not stated"}[f.resettable],
                description=f.description or md.DASH,
                source=md.sources(f.source),
            )
            for f in device.faults
        ),
        exceptions=exceptions,
        exceptions_note=note,
        examples=examples,
        errata=tuple(_erratum_view(ctx, e) for e in device.errata),
    )


def render_device(device: Device) -> Files:
    page = device_page(device)
    files: Files = {f"{DocId(device.id)}.md": templates(__name__).get_template("device.md.jinja").render(page=page)}
    for reg in device.registers:
        if reg.bitfields:
            path = diagram_path(device, reg)
            if path not in files:  # array elements share their member's diagram
                files[path] = bitfield_svg(device, reg)
    return files


@dataclass(frozen=True)
class IndexRow:
    page: str
    id: str  # the device id as the docs spell it in file names
    device: Md
    vendor: Md
    model: str
    manual: Md
    version: str
    fingerprint: str
    registers: int
    examples: int
    errata: int


def render_shared(devices: Sequence[Device]) -> Files:
    rows = []
    for d in sorted(devices, key=lambda d: d.id):
        info = d.info
        manual = md_text(info.manual_title) + (f", {md_text(info.manual_version)}" if info.manual_version else "")
        rows.append(
            IndexRow(
                page=f"{DocId(d.id)}.md",
                id=DocId(d.id),
                device=md.code(d.id),
                vendor=Md(md_text(info.vendor) + (f" ({md_text(info.vendor_zh)})" if info.vendor_zh else "")),
                model=info.model,
                manual=Md(manual),
                version=info.map_version,
                fingerprint=d.fingerprint,
                registers=len(d.registers),
                examples=len(d.examples),
                errata=len(d.errata),
            )
        )
    header = ["Generated by regmap from the maps listed below - do not edit.", "Regenerate with `regmap generate`."]
    text = templates(__name__).get_template("index.md.jinja").render(header=[md.html_comment(h) for h in header], devices=rows)
    return {INDEX_PAGE: text}
