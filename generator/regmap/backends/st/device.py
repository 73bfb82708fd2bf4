"""One device's Structured Text context per dialect, from the views and the statements."""

from __future__ import annotations

from typing import Any

from regmap.backends.st.functions import Values, _encoder_input, bitfield_functions, blocks, command_functions, encoders, owners
from regmap.backends.st.names import StIdentifier, st_int
from regmap.backends.st.views import (
    Const,
    Dialect,
    EnumValue,
    EnumView,
    Names,
    array_consts,
    bitfield_consts,
    command_consts,
    device_consts,
    enum_functions,
    enum_views,
    needs_order_input,
    register_consts,
)
from regmap.diagnostics import Diagnostic
from regmap.model import Device
from regmap.render import header_lines


def device_views(device: Device, dialect: Dialect, problems: list[Diagnostic]) -> dict[str, Any]:
    names = Names(device, dialect, problems)
    enums = enum_views(names, dialect)
    values = Values(names, dialect)
    plan = blocks(names, values)
    registers = []
    for reg in device.registers:
        registers.append(register_consts(names, reg))
    bitfields = []
    for regs in owners(device):
        section = bitfield_consts(names, regs[0])
        if section is not None:
            bitfields.append(section)
    access = EnumView(
        names.access_type,
        "UINT" if dialect.enum_base else "",
        "Access of a register.",
        (EnumValue("R", "1", "read only"), EnumValue("W", "2", "write only"), EnumValue("RW", "3", "read and write")),
    )
    functions = [*enum_functions(names, dialect, enums), *bitfield_functions(names)]
    functions += [b.decode for b in plan]
    functions += encoders(names)
    functions += command_functions(names)
    writable = next((r for r in device.registers if r.access.writable and r.array is None and not r.bitfields), None)
    example = None
    if writable is not None:
        example = {
            "register": writable,
            "encoder": StIdentifier("F", device.id, "ENCODE", writable.name),
            "addr": StIdentifier(device.id, writable.name, "FIRST_ADDR" if writable.paired else "ADDR"),
            "words": writable.span if writable.paired else writable.words,
            "input": _encoder_input(writable),
        }
    plan_len = Const(
        names.const("READ_PLAN_LEN", what="the read plan"), "UINT", st_int(len(plan)), "requests that read every readable register"
    )
    return {
        "header": header_lines(device, "regmap generate"),
        "device": device,
        "dialect": dialect,
        "enums": [access, *enums],
        "device_consts": device_consts(names),
        "registers": registers,
        "arrays": array_consts(names),
        "bitfields": bitfields,
        "commands": command_consts(names),
        "plan": plan,
        "plan_len": plan_len,
        "values": values.struct(),
        "functions": functions,
        "order_input": needs_order_input(device, device.registers),
        "example": example,
    }
