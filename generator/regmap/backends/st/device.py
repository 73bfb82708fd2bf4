"""One device's Structured Text context per dialect, from the views and the statements.

The names are the same in every dialect, so one `DeviceViews` per device checks them once and makes each
view once: what no dialect changes once, what the notation changes (an enum value, a text type) once per
`Notation` (CODESYS and the PLCopen XML share one), and only the float helpers, their UNIONs and the
decoders' comments per dialect."""

from __future__ import annotations

import weakref
from typing import Any

from regmap.backends.st import codec, half, scaling
from regmap.backends.st.codec import Dialect, Notation
from regmap.backends.st.encoders import _encoder_input, command_functions, encoder_targets, encoders
from regmap.backends.st.functions import Block, Values, bitfield_functions, blocks, owners
from regmap.backends.st.names import StIdentifier, st_int
from regmap.backends.st.view_types import (
    Const,
    EnumValue,
    EnumView,
    FunctionView,
    Member,
    Section,
    SectionToSpell,
    SpelledText,
    StructView,
)
from regmap.backends.st.views import (
    Names,
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
from regmap.backends.st.writes import WriteStruct, queue_function, write_function, write_functions, write_struct
from regmap.diagnostics import Diagnostic
from regmap.model import Device, PollClass, Register
from regmap.records import cached_property
from regmap.render import header_lines


def device_views(device: Device, dialect: Dialect, problems: list[Diagnostic]) -> dict[str, Any]:
    """The template context of one dialect alone."""
    return DeviceViews(device, problems).context(dialect)


class DeviceViews:
    """One device's views in every dialect. Each is made when `context` first asks for it, in the order it
    asks: the first dialect checks the names in that order, and the others reuse what they share."""

    def __init__(self, device: Device, problems: list[Diagnostic]) -> None:
        self.device = device
        self.names = Names(device, problems)
        self.helpers = codec.helper_names(device.id)
        self._notations: dict[Notation, SpelledViews] = {}

    def spelled(self, notation: Notation) -> SpelledViews:
        if notation not in self._notations:
            first = next(iter(self._notations.values()), None)
            # Weakly: a cycle would leave the device's views (tens of thousands of objects) to the cyclic collector,
            # which a generate run calls rarely (cli/generate.py), instead of freeing them when the device is done.
            self._notations[notation] = SpelledViews(weakref.proxy(self), notation, first)
        return self._notations[notation]

    @cached_property
    def enums(self) -> list[EnumView]:
        """The enums with their base types, made and their names checked once for every notation."""
        return enum_views(self.names)

    @cached_property
    def values(self) -> Values:
        return Values(self.names, self.helpers)

    @cached_property
    def plan(self) -> list[Block]:
        return blocks(self.names, self.values)

    @cached_property
    def targets(self) -> list[tuple[str, list[Register]]]:
        return encoder_targets(self.device)

    @cached_property
    def request(self) -> WriteStruct:
        return write_struct(self.names, self.targets)

    @cached_property
    def queue(self) -> FunctionView:
        return queue_function(self.names, self.request)

    @cached_property
    def registers(self) -> list[SectionToSpell]:
        return [register_consts(self.names, reg) for reg in self.device.registers]

    @cached_property
    def bitfields(self) -> list[Section]:
        sections = (bitfield_consts(self.names, regs[0]) for regs in owners(self.device))
        return [s for s in sections if s is not None]

    @cached_property
    def bitfield_functions(self) -> list[FunctionView]:
        return bitfield_functions(self.names)

    @cached_property
    def scaled(self) -> list[Register]:
        return [r for r in self.device.registers if r.scale_from is not None]

    @cached_property
    def scaled_functions(self) -> list[FunctionView]:
        if not self.scaled:
            return []
        return [scaling.power_function(self.names), *(scaling.scaled_function(self.names, r) for r in self.scaled if r.access.readable)]

    @cached_property
    def command_functions(self) -> list[FunctionView]:
        return command_functions(self.names)

    @cached_property
    def device_consts(self) -> Section:
        return device_consts(self.names)

    @cached_property
    def plan_len(self) -> Const:
        what = "requests that read every readable register"
        return Const(self.names.const("READ_PLAN_LEN", what="the read plan"), "UINT", st_int(len(self.plan)), what)

    @cached_property
    def poll_and_variant_consts(self) -> tuple[Const, ...]:
        return (*poll_consts(self.names), *variant_consts(self.names))

    @cached_property
    def arrays(self) -> list[Section]:
        return array_consts(self.names)

    @cached_property
    def commands(self) -> list[SectionToSpell]:
        return command_consts(self.names)

    @cached_property
    def const_sections(self) -> list[Section | SectionToSpell]:
        """The sections of the registers, arrays, bitfields and commands, in the order the constants files print them;
        the constants a notation spells its own way are spelled as they are printed (`const_text`, the PLCopen XML)."""
        return [*self.registers, *self.arrays, *self.bitfields, *self.commands]

    @cached_property
    def const_text(self) -> SpelledText:
        """`const_sections` as an ST file prints them, made once for every notation but the few constants it spells."""
        return SpelledText(self.const_sections)

    @cached_property
    def plan_const_lines(self) -> str:
        """The read blocks' constants, as the constants file prints them (the same in every dialect)."""
        return "".join([b.const_lines for b in self.plan])

    def context(self, dialect: Dialect) -> dict[str, Any]:
        device, names = self.device, self.names
        spelled = self.spelled(dialect.notation)
        enums = spelled.enums
        values = self.values
        plan = self.plan
        writers = spelled.encoders
        # The registers' and bitfields' constants are made here, though printed later: the first dialect checks the names
        # in this order, which decides the item a collision names first.
        _ = self.registers, self.bitfields
        access = spelled.access
        functions = [*spelled.enum_functions, *self.bitfield_functions]
        functions += helper_functions(names, dialect, self.helpers, values.used)
        functions += self.scaled_functions
        functions += [b.decoder(dialect) for b in plan]
        functions += writers
        functions += self.command_functions
        dev = self.device_consts
        plan_len = self.plan_len
        return {
            "header": header_lines(device, "regmap generate"),
            "device": device,
            "names": names,
            "dialect": dialect,
            "enums": [access, *enums],
            "device_consts": Section(dev.comment, dev.consts + self.poll_and_variant_consts),
            "plan_const_lines": self.plan_const_lines,
            "const_sections": self.const_sections,
            "const_text": spelled.const_text,
            "plan": plan,
            "plan_len": plan_len,
            "values": spelled.values,
            "write": self.request.struct,
            "write_functions": spelled.write_functions,
            "functions": functions,
            "unions": unions(names, dialect, self.helpers, values.used),
            **self.facts,
            "has_floats": bool(values.used & {"f16", "f32", "f64"}),
            "scaled": self.scaled,
            "example": self.example,
        }

    @cached_property
    def facts(self) -> dict[str, Any]:
        """What the templates ask of the device as a whole, the same in every dialect."""
        device = self.device
        return {
            "spaces": sorted({r.space for r in device.registers}),
            "has_bits": any(b.bits for b in self.plan),
            "has_text": any(r.type.is_string for r in device.registers),
            "poll_consts_used": any(
                r.type.words == 4 or r.firmware is not None or codec.swapped(r) or r.poll is not PollClass.NORMAL for r in device.registers
            ),
            "order_input": needs_order_input(device, device.registers),
        }

    @cached_property
    def example(self) -> dict[str, Any] | None:
        """A writable plain register, for the README's write example."""
        writable = next(
            (r for r in self.device.registers if r.access.writable and r.array is None and not r.bitfields and r.scale_from is None),
            None,
        )
        if writable is None:
            return None
        device = self.device
        return {
            "register": writable,
            "encoder": StIdentifier("F", device.id, "ENCODE", writable.name),
            "addr": StIdentifier(device.id, writable.name, "FIRST_ADDR" if writable.paired else "ADDR"),
            "words": writable.span if writable.paired else writable.words,
            "input": _encoder_input(writable),
            "single": writable.words == 1 and not writable.paired,
        }


class SpelledViews:
    """The views of one device whose text a dialect's notation changes (an enum value, a text type). `other`:
    another notation's, whose encoders and write functions this one takes where the notation changes nothing."""

    def __init__(self, views: DeviceViews, notation: Notation, other: SpelledViews | None) -> None:
        self.views = views
        self.notation = notation
        self.other = other

    @cached_property
    def enums(self) -> list[EnumView]:
        made = self.views.enums
        if self.notation.enum_base:
            return made
        return [EnumView(e.type_name, "", e.comment, e.members) for e in made]

    @cached_property
    def encoders(self) -> list[FunctionView]:
        v = self.views
        return encoders(v.names, v.targets, self.notation, v.helpers, v.values.used, self.other.encoders if self.other else ())

    @cached_property
    def access(self) -> EnumView:
        return EnumView(
            self.views.names.access_type,
            "UINT" if self.notation.enum_base else "",
            "Access of a register.",
            (EnumValue("R", "1", "read only"), EnumValue("W", "2", "write only"), EnumValue("RW", "3", "read and write")),
        )

    @cached_property
    def enum_functions(self) -> list[FunctionView]:
        return enum_functions(self.views.names, self.notation, self.enums)

    @cached_property
    def const_text(self) -> str:
        return self.views.const_text.text(self.notation)

    @cached_property
    def values(self) -> StructView:
        return self.views.values.struct(self.notation)

    @cached_property
    def write_functions(self) -> list[FunctionView]:
        v = self.views
        if self.other is None:
            return [v.queue, *write_functions(v.names, v.targets, self.encoders, v.request, v.queue)]
        theirs = zip(self.other.encoders, self.other.write_functions[1:], strict=True)
        return [
            v.queue,
            *(
                same if encoder is their_encoder else write_function(v.names, label, regs, encoder, v.request, v.queue)
                for (label, regs), encoder, (their_encoder, same) in zip(v.targets, self.encoders, theirs, strict=True)
            ),
        ]


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
