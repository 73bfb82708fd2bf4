"""The context of one device header (`<device>.h`) and of the shared RTU helpers (`regmap_rtu.h`)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from regmap.backends.c.names import (
    FUNCTION_MACROS,
    PARITY_CHAR,
    WORD_ORDER_MACRO,
    CIdentifier,
    Context,
    c_hex,
    c_raw,
    c_unsigned,
    file_header,
)
from regmap.backends.c.views import Macro, command_view, enum_view, group_views, manual_sections, sentences
from regmap.backends.text import titled
from regmap.diagnostics import UsageError
from regmap.generate import Files
from regmap.model import Device
from regmap.render import environment
from regmap.runtime_bridge import read_plan
from regmap_runtime.spaces import HOLDING, SPACES, Space

SHARED_HEADER = "regmap_rtu.h"


@dataclass(frozen=True)
class PlanBlock:
    address: str
    count: str
    comment: str


def _transport_macros(ctx: Context) -> list[Macro]:
    t = ctx.device.transport
    macros = [
        Macro(ctx.const("DEFAULT_BAUD"), f"{t.baud}ul", "baud rates: " + ", ".join(str(b) for b in t.baud_rates) if t.baud_rates else ""),
        Macro(ctx.const("PARITY"), PARITY_CHAR[t.parity], f"parity {t.parity} (as libmodbus spells it)"),
        Macro(ctx.const("DATA_BITS"), c_unsigned(t.data_bits)),
        Macro(ctx.const("STOP_BITS"), c_unsigned(t.stop_bits)),
        Macro(ctx.const("SLAVE_MIN"), c_unsigned(t.slave_min)),
        Macro(ctx.const("SLAVE_MAX"), c_unsigned(t.slave_max)),
    ]
    if t.broadcast_id is not None:
        macros.append(Macro(ctx.const("HAS_BROADCAST"), "1"))
        macros.append(Macro(ctx.const("BROADCAST_ID"), c_unsigned(t.broadcast_id), "a request to it is not answered"))
    else:
        macros.append(Macro(ctx.const("HAS_BROADCAST"), "0", "the manual says the device does not support broadcast"))
    macros += [
        Macro(ctx.const("MAX_READ_REGISTERS"), c_unsigned(t.max_read_registers)),
        Macro(ctx.const("MAX_WRITE_REGISTERS"), c_unsigned(t.max_write_registers)),
    ]
    if t.max_message_bytes is not None:
        macros.append(Macro(ctx.const("MAX_MESSAGE_BYTES"), c_unsigned(t.max_message_bytes)))
    macros.append(Macro(ctx.const("WORD_ORDER"), WORD_ORDER_MACRO[t.word_order], "order of the words of 32-bit values"))
    if t.word_order_register is not None:
        w = t.word_order_register
        macros += [
            Macro(ctx.const("WORD_ORDER_REGISTER_ADDR"), ctx.addr(w.register), f"{w.register.label} selects the word order"),
            Macro(ctx.const("WORD_ORDER_REGISTER_HIGH_FIRST"), c_raw(w.high_first, w.register.signed)),
            Macro(ctx.const("WORD_ORDER_REGISTER_LOW_FIRST"), c_raw(w.low_first, w.register.signed)),
        ]
    if t.response_delay_ms is not None:
        macros.append(Macro(ctx.const("RESPONSE_DELAY_US"), f"{round(t.response_delay_ms * 1000)}ul", "response delay"))
    return macros


def _plan_blocks(ctx: Context) -> list[PlanBlock]:
    blocks = []
    for block in read_plan(ctx.device):
        first, last = block.registers[0], block.registers[-1]
        names = [r.param or r.name for r in (first, last)]
        comment = names[0] if first is last else f"{names[0]} .. {names[1]} ({len(block.registers)} registers)"
        blocks.append(PlanBlock(address=c_hex(block.address), count=c_unsigned(block.count), comment=comment))
    return blocks


def device_context(device: Device) -> dict[str, Any]:
    ctx = Context(device)
    info = device.info
    about = [
        f"{info.vendor}{f' ({info.vendor_zh})' if info.vendor_zh else ''} {info.model}"
        + (f": {info.description}" if info.description else ""),
        f"Manual: {info.manual_title}" + (f", version {info.manual_version}" if info.manual_version else "") + f" ({info.manual_file}).",
    ]
    if info.firmware:
        about.append(f"Firmware: {info.firmware}")
    transport = _transport_macros(ctx)
    exceptions = tuple(
        Macro(
            ctx.const("EXCEPTION", e.name, what=f"exception {e.name}"),
            f"0x{e.code:02X}",
            sentences(titled(e.title, e.title_zh), manual_sections(e.source)),
        )
        for e in device.transport.exceptions
    )
    enums = [enum_view(ctx, e) for e in device.enums]
    groups = group_views(ctx)
    commands = [command_view(ctx, c) for c in device.commands]
    faults = [
        Macro(ctx.const("FAULT", f.name, what=f"fault {f.name}"), c_hex(f.value), f"{f.code} {titled(f.title, f.title_zh)} ({f.kind})")
        for f in device.faults
        if f.value is not None
    ]
    return {
        "header": file_header(device),
        "about": about,
        "device": device,
        "guard": CIdentifier("REGMAP", device.id, "H"),
        "shared_header": SHARED_HEADER,
        "max_read": CIdentifier(ctx.prefix, "MAX_READ_REGISTERS"),
        "max_write": CIdentifier(ctx.prefix, "MAX_WRITE_REGISTERS"),
        "map_version": ctx.const("MAP_VERSION"),
        "map_fingerprint": ctx.const("MAP_FINGERPRINT"),
        "transport": transport,
        "exception_type": ctx.symbol("exception") if exceptions else "",
        "exceptions": exceptions,
        "build_read": ctx.symbol("build_read"),
        "build_write_single": ctx.symbol("build_write_single"),
        "build_write_multiple": ctx.symbol("build_write_multiple"),
        "enums": enums,
        "groups": groups,
        "commands": commands,
        "faults": faults,
        "plan": _plan_blocks(ctx),
        "plan_len": ctx.const("READ_PLAN_LEN"),
        "plan_table": ctx.symbol("read_plan"),
    }


def render_device(device: Device) -> Files:
    env = environment()
    return {f"{device.id}.h": env.get_template("c/device.h.jinja").render(**device_context(device))}


def render_shared(devices: Sequence[Device]) -> Files:
    ids: dict[str, str] = {}
    for device in devices:
        if device.id in ids:
            raise UsageError(f"{device.source_path} and {ids[device.id]} both have device id {device.id!r}: their C headers would collide")
        ids[device.id] = device.source_path
    header = [
        "Generated by regmap - do not edit; regenerate with `regmap generate`.",
        "The same file for every map: device headers include it.",
    ]
    template = environment().get_template("c/regmap_rtu.h.jinja")
    return {SHARED_HEADER: template.render(header=header, functions=_function_macros(), holding=_codes(HOLDING))}


def _function_macros() -> list[Macro]:
    """A macro per function code of every space, from the runtime's table."""
    return [Macro(FUNCTION_MACROS[s.name][operation], f"0x{code:02X}u") for s in SPACES.values() for operation, code in s.codes.items()]


def _codes(space: Space) -> dict[str, str]:
    """How the helpers' comments name a space's function codes: by operation, and `all` of them."""
    texts = {operation: f"0x{code:02X}" for operation, code in space.codes.items()}
    return {**texts, "all": ", ".join(texts.values())}
