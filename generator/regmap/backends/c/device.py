"""The context of one device header (`<device>.h`) and of the shared RTU helpers (`regmap_rtu.h`)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from regmap.backends.c.names import (
    BUILDERS,
    FIRMWARE_FORMAT_MACRO,
    FUNCTION_MACROS,
    PADDING_MACRO,
    PARITY_CHAR,
    POLL_MACRO,
    SPACE_MACRO,
    TYPE_MACRO,
    WORD_ORDER_MACRO,
    CIdentifier,
    Context,
    Macro,
    c_float,
    c_hex,
    c_raw,
    c_unsigned,
    file_header,
)
from regmap.backends.c.values import configurable
from regmap.backends.c.variants import variant_macros
from regmap.backends.c.views import (
    ArrayView,
    GroupView,
    command_view,
    enum_view,
    group_views,
    modern,
)
from regmap.core.text import manual_sections, sentences, titled
from regmap.diagnostics import UsageError
from regmap.model import ByteOrder, Device, PollClass, Register
from regmap.records import NamedTuple
from regmap.render import c_comment, templates
from regmap.runtime_bridge import read_plan
from regmap.target import Files
from regmap_runtime.spaces import (
    BY_FUNCTION,
    COIL_OFF,
    COIL_ON,
    HOLDING,
    MAX_READ_BITS,
    MAX_READ_REGISTERS,
    MAX_WRITE_BITS,
    MAX_WRITE_REGISTERS,
    SPACES,
    Space,
)

SHARED_HEADER = "regmap_rtu.h"


class PlanBlock(NamedTuple):
    address: str
    quantity: str  # of registers (or bits) it reads
    comment: str
    function: str  # the macro of the read function of its space


class Plan(NamedTuple):
    """A read plan table; `functions` names the table of each request's function code ("" when every request reads holding registers)."""

    comment: str
    length: str
    table: str
    functions: str
    blocks: tuple[PlanBlock, ...]


class TableView(NamedTuple):
    """A constant table: declared `extern` in the header, defined once where <DEVICE>_IMPLEMENTATION is defined."""

    comment: str
    c_type: str
    name: str
    length: str
    body: str  # the initialiser's rows, one a line (_table_body)
    declared: bool = True  # False: declared beside its array member


def _table_body(rows: Sequence[tuple[str, str]]) -> str:
    """A table's rows (value, comment), one a line, a comma after each but the last: one string for the template,
    not a loop that asks at every row whether it is the last."""
    last = len(rows) - 1
    return "\n".join(
        [
            f"    {value}{',' if i < last else ''}{f' /* {c_comment(comment)} */' if comment else ''}"
            for i, (value, comment) in enumerate(rows)
        ]
    )


def _tables(plans: list[Plan], groups: list[GroupView]) -> list[TableView]:
    """The read plans and their function-code tables, then the per-element tables of array members."""
    tables = []
    for plan in plans:
        if not plan.blocks:
            continue
        rows = _table_body([(f"{{ {b.address}, {b.quantity} }}", b.comment) for b in plan.blocks])
        tables.append(TableView(f"Read plan of {plan.comment}" if plan.comment else "", "regmap_read_block", plan.table, plan.length, rows))
        if plan.functions:
            functions = _table_body([(b.function, "") for b in plan.blocks])
            comment = f"The function code of each request of {plan.table} (the Modbus table it reads)"
            tables.append(TableView(comment, "uint8_t", plan.functions, plan.length, functions))
    for group in groups:
        for item in group.items:
            for member in item.members if isinstance(item, ArrayView) else ():
                for t in member.tables:
                    tables.append(TableView("", t.c_type, t.name, t.length, _table_body([(v, "") for v in t.values]), declared=False))
    return tables


class BuilderView(NamedTuple):
    function: str
    params: str
    body: str  # the returned C expression


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
    if _bit_spaces(ctx.device):
        macros += [
            Macro(ctx.const("MAX_READ_COILS"), c_unsigned(t.max_read_coils), "coils or discrete inputs one read may cover"),
            Macro(ctx.const("MAX_WRITE_COILS"), c_unsigned(t.max_write_coils), "coils one write multiple coils may cover"),
        ]
    if t.max_message_bytes is not None:
        macros.append(Macro(ctx.const("MAX_MESSAGE_BYTES"), c_unsigned(t.max_message_bytes)))
    macros.append(Macro(ctx.const("WORD_ORDER"), WORD_ORDER_MACRO[t.word_order._value_], "order of the words of 32-bit values"))
    if t.byte_order is not ByteOrder.HIGH_FIRST:
        macros.append(Macro(ctx.const("BYTE_ORDER"), WORD_ORDER_MACRO[t.byte_order._value_], "order of the bytes in each word"))
    firmware = ctx.device.info.firmware_register
    if firmware is not None:
        macros += [
            Macro(
                ctx.const("FIRMWARE_REGISTER_ADDR"), ctx.addr(firmware.register), f"{firmware.register.label} reports the firmware version"
            ),
            Macro(
                ctx.const("FIRMWARE_FORMAT"),
                FIRMWARE_FORMAT_MACRO[firmware.format],
                "see regmap_firmware_version / regmap_version_from_text",
            ),
        ]
        if firmware.format == "decimal":
            macros.append(Macro(ctx.const("FIRMWARE_DECIMALS"), c_unsigned(firmware.decimals)))
    if t.word_order_register is not None:
        w = t.word_order_register
        macros.append(Macro(ctx.const("WORD_ORDER_REGISTER_ADDR"), ctx.addr(w.register), f"{w.register.label} selects the word order"))
        if w.swap_value is not None:
            macros.append(
                Macro(
                    ctx.const("WORD_ORDER_REGISTER_SWAP"),
                    _order_value(w.register, w.swap_value),
                    "written (in the current word order) to swap the word order; a trigger: send it once",
                )
            )
        else:
            assert w.high_first is not None and w.low_first is not None
            macros += [
                Macro(ctx.const("WORD_ORDER_REGISTER_HIGH_FIRST"), _order_value(w.register, w.high_first)),
                Macro(ctx.const("WORD_ORDER_REGISTER_LOW_FIRST"), _order_value(w.register, w.low_first)),
            ]
    if t.response_delay_ms is not None:
        macros.append(Macro(ctx.const("RESPONSE_DELAY_US"), f"{round(t.response_delay_ms * 1000)}ul", "response delay"))
    return macros


def _order_value(reg: Register, value: int | float) -> str:
    """A word-order register's value as its C type writes it: a float literal for a float register."""
    return c_float(value) if reg.type.is_float else c_raw(int(value), reg.signed)


def _bit_spaces(device: Device) -> bool:
    return any(r.space_info.bits for r in device.registers)


def _plan_blocks(ctx: Context, poll: PollClass | None = None, variant: str | None = None) -> list[PlanBlock]:
    blocks = []
    for block in read_plan(ctx.device, poll=poll, variants=(variant,) if variant else ()):
        first, last = block.registers[0], block.registers[-1]
        names = [r.param or r.name for r in (first, last)]
        unit = f"{SPACES[block.space].unit}s" if SPACES[block.space].bits else "registers"
        comment = names[0] if first is last else f"{names[0]} .. {names[1]} ({len(block.registers)} {unit})"
        function = FUNCTION_MACROS[block.space]["read"]
        blocks.append(PlanBlock(address=c_hex(block.address), quantity=c_unsigned(block.count), comment=comment, function=function))
    return blocks


def _plans(ctx: Context) -> tuple[Plan, list[Plan], list[Plan]]:
    """The read plan of every readable register; where the map uses more than one poll class, one per class;
    and per declared variant the same again, leaving out (and never bridging over) what that variant lacks."""
    blocks = _plan_blocks(ctx)
    spaces = any(b.function != FUNCTION_MACROS[HOLDING.name]["read"] for b in blocks)
    main = Plan(
        comment="",
        length=ctx.const("READ_PLAN_LEN"),
        table=ctx.symbol("read_plan"),
        functions=ctx.symbol("read_plan_function") if spaces and blocks else "",
        blocks=tuple(blocks),
    )
    classes = [p for p in PollClass if any(r.poll is p for r in ctx.device.registers)]
    per_variant = []
    for v in ctx.device.info.variants:
        per_variant.append(
            Plan(
                comment=f"variant {v.name} ({titled(v.title, None)})",
                length=ctx.const("READ_PLAN", v.name, "LEN"),
                table=ctx.symbol("read_plan", v.name),
                functions=ctx.symbol("read_plan", v.name, "function") if spaces else "",
                blocks=tuple(_plan_blocks(ctx, variant=v.name)),
            )
        )
        per_variant += _class_plans(ctx, classes, spaces, v.name)
    return main, _class_plans(ctx, classes, spaces), per_variant


def _class_plans(ctx: Context, classes: list[PollClass], spaces: bool, variant: str | None = None) -> list[Plan]:
    """Where the map uses more than one poll class, a plan per class (of `variant`'s registers, when given)."""
    plans = []
    for poll in classes if len(classes) > 1 else ():
        blocks = _plan_blocks(ctx, poll, variant)
        if blocks:
            parts = (poll._value_, variant) if variant else (poll._value_,)
            plans.append(
                Plan(
                    comment=f"poll class {poll._value_} ({POLL_MACRO[poll._value_]})" + (f" of variant {variant}" if variant else ""),
                    length=ctx.const("READ_PLAN", *parts, "LEN"),
                    table=ctx.symbol("read_plan", *parts),
                    functions=ctx.symbol("read_plan", *parts, "function") if spaces else "",
                    blocks=tuple(blocks),
                )
            )
    return plans


def has_device_builder(device: Device, space: str, operation: str) -> bool:
    """Whether the device header wraps the shared builder of `operation` on `space`: holding's always
    (the first maps' own), another space's where the map has registers in it and lists the function code."""
    if space == HOLDING.name:
        return True
    code = SPACES[space].codes.get(operation)
    return (
        operation in BUILDERS.get(space, {}) and code in device.transport.function_codes and any(r.space == space for r in device.registers)
    )


def _builders(ctx: Context) -> list[BuilderView]:
    """A device wrapper within the device's limits for each shared builder of the other spaces the map uses."""
    views = []
    for space in SPACES.values():
        for operation in space.codes:
            if space.name == HOLDING.name or not has_device_builder(ctx.device, space.name, operation):
                continue
            builder = BUILDERS[space.name][operation]
            call = f"{builder.shared}(buf, cap, slave, address, {builder.args})"
            limit = ""
            if builder.limited_by:
                bits = "COILS" if space.bits else "REGISTERS"
                limit = CIdentifier(ctx.prefix, f"MAX_{builder.limited_by.upper()}_{bits}")
            views.append(
                BuilderView(
                    function=ctx.symbol(builder.suffix, what=f"the {space.title} builder"),
                    params=builder.params,
                    body=f"count > {limit} ? 0u : {call}" if limit else call,
                )
            )
    return views


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
    builders = _builders(ctx)
    main, per_class, per_variant = _plans(ctx)
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
        "plan": main.blocks,
        "plan_len": main.length,
        "class_plans": per_class,
        "variant_plans": per_variant,
        "variants": variant_macros(ctx),
        "variant_bits": CIdentifier(ctx.prefix, "VARIANT"),
        "tables": _tables([main, *per_class, *per_variant], groups),
        "implementation": ctx.const("IMPLEMENTATION", what="the macro that defines the tables"),
        "implemented": CIdentifier("REGMAP", device.id, "IMPLEMENTED"),
        "word_order_param": any(configurable(ctx, r) for r in device.registers),
        "builders": builders,
        "modern": any(modern(r) for r in device.registers),
    }


def render_device(device: Device) -> Files:
    env = templates(__name__)
    return {f"{device.id}.h": env.get_template("device.h.jinja").render(**device_context(device))}


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
    template = templates(__name__).get_template("regmap_rtu.h.jinja")
    return {SHARED_HEADER: template.render(**_shared_context(header))}


def _shared_context(header: list[str]) -> dict[str, Any]:
    """The shared header's tables, all from the runtime's: function codes, limits, spaces, types, poll classes."""
    return {
        "header": header,
        "functions": _function_macros(),
        "all_codes": ", ".join(f"0x{code:02X}" for code in sorted(BY_FUNCTION)),
        **{s.name: _codes(s) for s in SPACES.values()},
        "limits": [
            Macro("REGMAP_RTU_MAX_READ_REGISTERS", c_unsigned(MAX_READ_REGISTERS)),
            Macro("REGMAP_RTU_MAX_WRITE_REGISTERS", c_unsigned(MAX_WRITE_REGISTERS)),
            Macro("REGMAP_RTU_MAX_READ_BITS", c_unsigned(MAX_READ_BITS)),
            Macro("REGMAP_RTU_MAX_WRITE_BITS", c_unsigned(MAX_WRITE_BITS)),
        ],
        "coil_values": [Macro("REGMAP_COIL_ON", c_hex(COIL_ON)), Macro("REGMAP_COIL_OFF", c_hex(COIL_OFF))],
        "spaces": [Macro(SPACE_MACRO[s.name], str(i), f"{s.title}: {_codes(s)['all']}") for i, s in enumerate(SPACES.values())],
        "types": [Macro(TYPE_MACRO[t], str(i)) for i, t in enumerate(TYPE_MACRO)],
        "paddings": [Macro(name, str(i)) for i, name in enumerate(PADDING_MACRO.values())],
        "polls": [Macro(name, str(i)) for i, name in enumerate(POLL_MACRO.values())],
        "firmware_formats": [Macro(name, str(i)) for i, name in enumerate(FIRMWARE_FORMAT_MACRO.values())],
    }


def _function_macros() -> list[Macro]:
    """A macro per function code of every space, from the runtime's table."""
    return [Macro(FUNCTION_MACROS[s.name][operation], f"0x{code:02X}u") for s in SPACES.values() for operation, code in s.codes.items()]


def _codes(space: Space) -> dict[str, str]:
    """How the helpers' comments name a space's function codes: by operation, and `all` of them."""
    texts = {operation: f"0x{code:02X}" for operation, code in space.codes.items()}
    return {**texts, "all": ", ".join(texts.values())}
