"""One device's Structured Text context per dialect, from the views and the statements."""

from __future__ import annotations

from typing import Any

from regmap.backends.st import codec, half, scaling
from regmap.backends.st.codec import Dialect
from regmap.backends.st.encoders import _encoder_input, command_functions, encoder_targets, encoders
from regmap.backends.st.functions import Values, bitfield_functions, blocks, owners
from regmap.backends.st.names import StIdentifier, st_int
from regmap.backends.st.views import (
    Const,
    EnumValue,
    EnumView,
    FunctionView,
    Member,
    Names,
    Section,
    StructView,
    array_consts,
    bitfield_consts,
    command_consts,
    device_consts,
    enum_functions,
    enum_views,
    needs_order_input,
    register_consts,
    variant_consts,
)
from regmap.backends.st.writes import queue_function, write_functions, write_struct
from regmap.diagnostics import Diagnostic
from regmap.model import Device, PollClass
from regmap.render import header_lines


def device_views(device: Device, dialect: Dialect, problems: list[Diagnostic]) -> dict[str, Any]:
    names = Names(device, dialect, problems)
    enums = enum_views(names, dialect)
    helpers = codec.helper_names(device.id)
    values = Values(names, dialect, helpers)
    plan = blocks(names, values)
    writers = encoders(names, helpers, values.used)
    targets = encoder_targets(device)
    request = write_struct(names, targets)
    queue = queue_function(names, request)
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
    functions += helper_functions(names, dialect, helpers, values.used)
    scaled = [r for r in device.registers if r.scale_from is not None]
    if scaled:
        functions += [scaling.power_function(names), *(scaling.scaled_function(names, r) for r in scaled if r.access.readable)]
    functions += [b.decode for b in plan]
    functions += writers
    functions += command_functions(names)
    writable = next(
        (r for r in device.registers if r.access.writable and r.array is None and not r.bitfields and r.scale_from is None), None
    )
    example = None
    if writable is not None:
        example = {
            "register": writable,
            "encoder": StIdentifier("F", device.id, "ENCODE", writable.name),
            "addr": StIdentifier(device.id, writable.name, "FIRST_ADDR" if writable.paired else "ADDR"),
            "words": writable.span if writable.paired else writable.words,
            "input": _encoder_input(writable),
            "single": writable.words == 1 and not writable.paired,
        }
    dev = device_consts(names)
    plan_len = Const(
        names.const("READ_PLAN_LEN", what="the read plan"), "UINT", st_int(len(plan)), "requests that read every readable register"
    )
    return {
        "header": header_lines(device, "regmap generate"),
        "device": device,
        "names": names,
        "dialect": dialect,
        "enums": [access, *enums],
        "device_consts": Section(dev.comment, dev.consts + tuple(poll_consts(names)) + tuple(variant_consts(names))),
        "registers": registers,
        "arrays": array_consts(names),
        "bitfields": bitfields,
        "commands": command_consts(names),
        "plan": plan,
        "plan_len": plan_len,
        "values": values.struct(),
        "write": request.struct,
        "write_functions": [queue, *write_functions(names, targets, writers, request, queue)],
        "functions": functions,
        "unions": unions(names, dialect, helpers, values.used),
        "spaces": sorted({r.space for r in device.registers}),
        "has_bits": any(b.bits for b in plan),
        "has_floats": bool(values.used & {"f16", "f32", "f64"}),
        "has_text": any(r.type.is_string for r in device.registers),
        "poll_consts_used": any(
            r.type.words == 4 or r.firmware is not None or codec.swapped(r) or r.poll is not PollClass.NORMAL for r in device.registers
        ),
        "order_input": needs_order_input(device, device.registers),
        "scaled": scaled,
        "example": example,
    }


def helper_functions(names: Names, dialect: Dialect, h: codec.Helpers, used: set[str]) -> list[FunctionView]:
    """The float and text helpers the decoders and encoders call (none for a map without floats or text)."""
    union = dialect.unions  # CODESYS / TwinCAT: reinterpret through a UNION; otherwise exact arithmetic
    how = "through a UNION" if union else "rebuilt from sign, exponent and mantissa with exact LREAL arithmetic"
    out: list[FunctionView] = []

    def add(
        name: StIdentifier, comment: str, inputs: list[Member], in_outs: list[Member], made: tuple[list[tuple[str, str]], list[str]]
    ) -> None:
        names.globals.add(name, f"the helper {name}")
        out.append(
            FunctionView(name, "BOOL", comment, tuple(inputs), tuple(in_outs), tuple(Member(n, t) for n, t in made[0]), tuple(made[1]))
        )

    no_value = "" if union else "; FALSE for infinity and NaN, which plain IEC 61131-3 cannot hold"
    if "f16" in used:  # no 16-bit float to reinterpret through a UNION: exact arithmetic in both dialects
        add(
            h.f16_from_bits,
            "The IEEE 754 half of 16 bits, rebuilt from sign, exponent and mantissa with exact LREAL arithmetic; FALSE for infinity and NaN.",
            [Member("nBits", "WORD")],
            [Member("fValue", "LREAL")],
            half.f16_from_bits_body(h),
        )
        add(
            h.f16_to_bits,
            "The 16 bits of the nearest IEEE 754 half (ties to even), with exact LREAL arithmetic; FALSE for infinity, NaN and 65520 on.",
            [Member("fValue", "LREAL")],
            [Member("nBits", "WORD")],
            half.f16_to_bits_body(h),
        )
    if "f32" in used:
        add(
            h.f32_from_bits,
            f"The IEEE 754 single of 32 bits, {how}{no_value}.",
            [Member("nBits", "DWORD")],
            [Member("fValue", "LREAL")],
            codec.f32_from_bits_body(h, union),
        )
        add(
            h.f32_to_bits,
            f"The 32 bits of an IEEE 754 single, {how}; FALSE for infinity and NaN.",
            [Member("fValue", "REAL")],
            [Member("nBits", "DWORD")],
            codec.f32_to_bits_body(h, union),
        )
    if "f64" in used:
        add(
            h.f64_from_bits,
            f"The IEEE 754 double of 64 bits (nHigh: the upper 32), {how}{no_value}.",
            [Member("nHigh", "DWORD"), Member("nLow", "DWORD")],
            [Member("fValue", "LREAL")],
            codec.f64_from_bits_body(h, union),
        )
        add(
            h.f64_to_bits,
            f"The 64 bits of an IEEE 754 double (nHigh: the upper 32), {how}; FALSE for infinity and NaN.",
            [Member("fValue", "LREAL")],
            [Member("nHigh", "DWORD"), Member("nLow", "DWORD")],
            codec.f64_to_bits_body(h, union),
        )
    if "char" in used or "code" in used:
        names.globals.add(h.char, "the text helper")
        out.append(
            FunctionView(
                h.char,
                "STRING",
                "The one-character string of a byte (1..255): MID of tables of every byte in order.",
                (Member("nByte", "BYTE"),),
                (),
                (),
                tuple(codec.char_body(h.char)),
            )
        )
    if "code" in used:
        names.globals.add(h.code, "the text helper")
        out.append(
            FunctionView(
                h.code,
                "BYTE",
                "The byte of a one-character string: its position in the same tables (0 for the empty string).",
                (Member("sChar", dialect.string(1)),),
                (),
                (Member("nAt", "INT"),),
                tuple(codec.char_code_body(h.code)),
            )
        )
    return out


def unions(names: Names, dialect: Dialect, h: codec.Helpers, used: set[str]) -> list[StructView]:
    """CODESYS / TwinCAT: the UNIONs the float helpers reinterpret bits through."""
    if not dialect.unions:
        return []
    out = []
    if "f32" in used:
        names.globals.add(h.union32, "the float union")
        out.append(
            StructView(
                h.union32, "The bits of an IEEE 754 single (CODESYS / TwinCAT UNION).", (Member("nBits", "DWORD"), Member("fValue", "REAL"))
            )
        )
    if "f64" in used:
        names.globals.add(h.union64, "the float union")
        out.append(
            StructView(
                h.union64,
                "The bits of an IEEE 754 double (CODESYS / TwinCAT UNION).",
                (Member("nBits", "LWORD"), Member("fValue", "LREAL")),
            )
        )
    return out


def poll_consts(names: Names) -> list[Const]:
    """<DEV>_POLL_STATIC .. _SLOW, the values of the POLL constants (only for a map that uses poll classes)."""
    if all(r.poll is PollClass.NORMAL for r in names.device.registers):
        return []
    return [
        Const(names.const("POLL", poll.value, what="the poll classes"), "USINT", st_int(value), comment)
        for poll, value, comment in (
            (PollClass.STATIC, 0, "read once (nameplate, limits)"),
            (PollClass.FAST, 1, "read fast"),
            (PollClass.NORMAL, 2, "read at the normal rate"),
            (PollClass.SLOW, 3, "read slowly"),
        )
    ]
