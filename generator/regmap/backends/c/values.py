"""The value-level helpers of one C header: per enum, whether a value is a member and whether a write may
send it; per register, `<name>_is_in_range`, `<name>_encode` and `<name>_decode` (as cantools generates
`_is_in_range/_encode/_decode` per signal). They refuse what the Python client and the Structured Text
encoders refuse: a value outside min/max, not a multiple of the resolution, not a member of the enum,
a member the device only reports (EnumMember.writable), NaN. Every line of C is computed here."""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from fractions import Fraction

from regmap.backends.c.names import (
    C_TYPES,
    FLOAT_GUARD,
    WIRE_FUNCTIONS,
    WORD_ORDER_MACRO,
    Context,
    c_double,
    c_float_literal,
    c_hex,
    c_raw,
    c_signed,
    c_unsigned,
    comment_text,
)
from regmap.core.text import eng, number, zone_text
from regmap.model import DataType, EnumType, Register
from regmap.records import NamedTuple

# The parameter a helper of a register whose word order follows the device's word-order register takes.
ORDER_PARAM = "word_order"


class EnumCheckView(NamedTuple):
    """`<enum>_is_member(value)` and `<enum>_is_writable(value)` (a member a write may send: not a state the device only reports)."""

    member_fn: str
    writable_fn: str
    param: str  # C type of the value: long long, or unsigned long long for a member beyond it
    member_cases: str  # `    case <label>:`, one a line (printed as one string, not a loop per member)
    writable_cases: str  # the same for the members a write may send; "" when there is none
    all_writable: bool


class ValueView(NamedTuple):
    """The value helpers of one register (or of every element of an array member)."""

    comment: str
    value_type: str
    words: str  # the words parameter's length (a C literal)
    order: str  # ", regmap_word_order word_order" where the device's word-order register sets it, else ""
    in_range: str  # "" for a register a write cannot reach
    in_range_body: tuple[str, ...]
    encode: str
    encode_body: tuple[str, ...]
    decode: str  # "" for a register a read cannot reach
    decode_body: tuple[str, ...]
    guard: str  # "" or REGMAP_HAS_F32 / REGMAP_HAS_F64
    available: str = ""  # `<name>_is_available(words)`: false for the device's "not available" marker (`na`)
    available_body: tuple[str, ...] = ()
    sf: str = ""  # ", int16_t sf": a `scale_from` register's helpers (`_decode_sf` ...) take its scale factor's raw value


def enum_checks(ctx: Context, e: EnumType, constants: Sequence[str]) -> EnumCheckView:
    """The tests of enum `e`, whose members' constants (as its view named them) are `constants`."""
    top = max((m.value for m in e.members), default=0)
    labels = [_member_label(name, m.value) for name, m in zip(constants, e.members, strict=True)]
    return EnumCheckView(
        member_fn=ctx.symbol(e.name, "is_member", what=f"the member test of enum {e.name}"),
        writable_fn=ctx.symbol(e.name, "is_writable", what=f"the write test of enum {e.name}"),
        param="unsigned long long" if top >= 1 << 63 else "long long",
        member_cases=_cases(labels),
        writable_cases=_cases(label for label, m in zip(labels, e.members, strict=True) if m.writable),
        all_writable=all(m.writable for m in e.members),
    )


def _cases(labels: Iterable[str]) -> str:
    return "\n".join([f"    case {label}:" for label in labels])


def _member_label(constant: str, value: int) -> str:
    # A table spelled as macros (a value beyond int) has no enum constants to compare with a long long.
    return constant if -(1 << 31) <= value < (1 << 31) else c_raw(value, value < 0)


def configurable(ctx: Context, reg: Register) -> bool:
    """A wide register whose word order follows the device's word-order register (C630S P0C-26), as the Python client's."""
    return reg.wide and ctx.device.transport.word_order_register is not None and not reg.word_order_fixed


def _word_order(ctx: Context, reg: Register) -> str:
    return ORDER_PARAM if configurable(ctx, reg) else WORD_ORDER_MACRO[reg.word_order._value_]


def _to_wire(ctx: Context, reg: Register, value: str) -> str:
    byte_order = WORD_ORDER_MACRO[reg.byte_order._value_]
    function = WIRE_FUNCTIONS[reg.type._value_][1]
    if reg.words == 1:
        return f"words[0] = {function}({value}, {byte_order});"
    return f"{function}({value}, {_word_order(ctx, reg)}, {byte_order}, words);"


def _from_wire(ctx: Context, reg: Register) -> str:
    byte_order = WORD_ORDER_MACRO[reg.byte_order._value_]
    function = WIRE_FUNCTIONS[reg.type._value_][0]
    if reg.words == 1:
        return f"{function}(words[0], {byte_order})"
    return f"{function}(words, {_word_order(ctx, reg)}, {byte_order})"


def _bits_to_wire(ctx: Context, reg: Register, value: str) -> str:
    """The words of a bitfield register's whole word (its unsigned bits) in its orders."""
    bits = C_TYPES[reg.type].bits.removeprefix("uint").removesuffix("_t")
    byte_order = WORD_ORDER_MACRO[reg.byte_order._value_]
    if reg.words == 1:
        return f"words[0] = regmap_u16_to_wire({value}, {byte_order});"
    return f"regmap_u{bits}_to_wire({value}, {_word_order(ctx, reg)}, {byte_order}, words);"


def _bits_from_wire(ctx: Context, reg: Register) -> str:
    bits = C_TYPES[reg.type].bits.removeprefix("uint").removesuffix("_t")
    byte_order = WORD_ORDER_MACRO[reg.byte_order._value_]
    if reg.words == 1:
        return f"regmap_u16_from_wire(words[0], {byte_order})"
    return f"regmap_u{bits}_from_wire(words, {_word_order(ctx, reg)}, {byte_order})"


def _inside(value: int | float, upward: bool) -> float:
    """The double nearest `value` on the inside of the range (a 64-bit bound is no exact double)."""
    bound = float(value)
    if upward and bound < value:
        return math.nextafter(bound, math.inf)
    if not upward and bound > value:
        return math.nextafter(bound, -math.inf)
    return bound


def _signed_bits(reg: Register, bits: str) -> str:
    """The signed value of a signed register's unsigned bits (`bits`), without implementation-defined conversions."""
    width = reg.type.bits
    if width == 16:
        return f"regmap_s16_from_word({bits})"
    half = c_hex(1 << (width - 1))
    signed = C_TYPES[reg.type].value
    return f"({bits} < {half} ? ({signed}){bits} : ({signed})({bits} - {half}) - {c_raw((1 << (width - 1)) - 1, True)} - 1)"


def _range_conditions(reg: Register, value: str, lo_type: int | float, hi_type: int | float) -> list[str]:
    """`value >= MIN` and `value <= MAX` where the map's range is narrower than what `value`'s type holds
    (a test the type already makes is left out: -Wtype-limits flags it)."""
    conditions = []
    if reg.raw_min > lo_type:
        conditions.append(f"{value} >= {c_raw(int(reg.raw_min), reg.signed)}")
    if reg.raw_max < hi_type:
        conditions.append(f"{value} <= {c_raw(int(reg.raw_max), reg.signed)}")
    return conditions


def _not_destructive(ctx: Context, reg: Register, value: str = "value") -> list[str]:
    """A plain write never sends what a destructive command writes: that command's helper, confirmed, does."""
    conditions = []
    for command in ctx.device.destructive_commands(reg):
        first, last = command.raw_values
        if first == last:
            conditions.append(f"(long long){value} != (long long){c_signed(first)}")
        else:
            conditions.append(f"((long long){value} < (long long){c_signed(first)} || (long long){value} > (long long){c_signed(last)})")
    return conditions


def _returns(conditions: list[str], value: str = "value") -> tuple[str, ...]:
    if not conditions:
        return (f"(void){value};", "return true;")
    return (f"return {' && '.join(conditions)};",)


def _refused_when_not(in_range: str, value: str = "value") -> tuple[str, ...]:
    return (f"if (!{in_range}({value})) {{", "    return false;", "}")


def _scaled(reg: Register) -> bool:
    return reg.scale != 1 or reg.offset_set


def _ratio(ctx: Context, reg: Register) -> tuple[str, ...]:
    """The offset, numerator and denominator as double literals (value = raw x num / den + offset); once per device for
    each scale and offset (registers share a handful)."""
    scale, offset = reg.scale, reg.offset
    key = ("double ratio", scale.numerator, scale.denominator, offset.numerator, offset.denominator)
    spelled = ctx.literals.get(key)
    if spelled is None:
        spelled = ctx.literals[key] = (c_double(offset), c_double(Fraction(scale.numerator)), c_double(Fraction(scale.denominator)))
    return spelled


def _scaled_value(ctx: Context, reg: Register, raw: str) -> str:
    """The engineering value of `raw` as the Python client computes it: raw x num / den (+ offset when there is one)."""
    offset, num, den = _ratio(ctx, reg)
    value = f"(double){raw} * {num} / {den}"
    return f"{value} + {offset}" if reg.offset_set else value


def _comment(reg: Register, label: str, order: str) -> str:
    """One line per register; the header's top comment says what the helpers refuse."""
    if reg.type.is_float and reg.enum is None:
        what = "any finite value of its type" if (reg.raw_min, reg.raw_max) == (reg.type.raw_min, reg.type.raw_max) else "its range"
    elif reg.bitfields:
        what = "its whole word, the fields set with the setters above"
    elif reg.enum is not None:
        what = f"the members of {reg.enum.name} a write may send"
    elif reg.zone is not None:
        what = f"{reg.raw_min}..{reg.raw_max} {zone_text(reg)}, {eng(reg, reg.raw_min)}..{eng(reg, reg.raw_max)}"
    else:
        what = f"{eng(reg, reg.raw_min)}..{eng(reg, reg.raw_max)}{f' {reg.unit}' if reg.unit else ''}"
        if _scaled(reg):
            what += f" in steps of {eng(reg, 1) if not reg.offset_set else number(reg.scale)}"
    parts = [f"Values of {label}: {what}" if reg.access.writable else f"Value of {label}" + (f": {zone_text(reg)}" if reg.zone else "")]
    if reg.paired:
        parts.append("a block write also sends the unused high word regmap_pair_high_word(words[0], _SIGNED) at _PAIR_ADDR")
    if order:
        parts.append("word_order as the device is set")
    return "; ".join(parts) + "."


def value_view(ctx: Context, reg: Register, label: str) -> ValueView | None:
    """The value helpers of `reg` under the name `label` (its owner: the register, or `<array>_<member>`).
    Coils, discrete inputs and strings have none: a bit is its value, and `_to_wire/_from_wire` take text."""
    if reg.type.is_bool or reg.type.is_string or not reg.type.numeric:
        return None
    readable, writable = reg.access.readable, reg.access.writable
    order = f", regmap_word_order {ORDER_PARAM}" if configurable(ctx, reg) else ""
    if reg.scale_from is not None:
        return _scale_from_view(ctx, reg, label, order)
    value_type, in_range, encode, decode = _bodies(ctx, reg, label)
    available = ""
    available_body: tuple[str, ...] = ()
    if reg.has_na and readable:
        available = ctx.symbol(label, "is_available", what=f"the availability test of {label}")
        available_body = (
            f"{C_TYPES[reg.type].value} raw = {_from_wire(ctx, reg)};",
            f"return {' && '.join(_na_conditions(reg, 'raw'))};",
        )
        call = f"{available}(words{', ' + ORDER_PARAM if order else ''})"
        decode = (f"if (!{call}) {{", "    return false; /* the device's 'not available' marker: no value */", "}", *decode)
    if reg.has_na and writable:
        in_range = _refusing_na(reg, in_range)
    return ValueView(
        available=available,
        available_body=available_body,
        comment=_comment(reg, label, order),
        value_type=value_type,
        words=str(reg.words),
        order=order,
        in_range=ctx.symbol(label, "is_in_range", what=f"the range test of {label}") if writable else "",
        in_range_body=in_range,
        encode=ctx.symbol(label, "encode", what=f"the encoder of {label}") if writable else "",
        encode_body=encode,
        decode=ctx.symbol(label, "decode", what=f"the decoder of {label}") if readable else "",
        decode_body=decode,
        guard=FLOAT_GUARD.get(reg.type._value_, ""),
    )


def _scale_from_view(ctx: Context, reg: Register, label: str, order: str) -> ValueView:
    """`_decode_sf`, `_is_in_range_sf`, `_encode_sf`: value = raw x 10^sf, `sf` the scale factor's raw value the caller
    read (false for its "not available" marker, SunSpec's 0x8000, and for the point's own); a value to write must be a
    whole multiple of 10^sf (within regmap_value_to_raw's 0.001 of a raw integer) inside the raw range."""
    sf_reg = ctx.device.register(reg.scale_from or "")
    sf_ok = " && ".join([f"sf != {c_raw(int(mark), True)}" for mark in sf_reg.na] or ["true"])
    power = (
        "double scale = 1.0;",
        "int n;",
        f"if (!({sf_ok})) {{",
        f"    return false; /* {sf_reg.name} reads its 'not available' marker: no value */",
        "}",
        "for (n = sf < 0 ? -(int)sf : (int)sf; n > 0; n--) {",
        "    scale *= 10.0;",
        "}",
    )
    lo, hi = c_double(_inside(reg.raw_min, True)), c_double(_inside(reg.raw_max, False))
    convert = f"regmap_value_to_raw(value, 0.0, sf < 0 ? 1.0 : scale, sf < 0 ? scale : 1.0, {lo}, {hi}, &raw)"
    marks = _na_conditions(reg, "raw")
    fits = " && ".join([convert, *marks])
    raw_type = C_TYPES[reg.type].value
    decode = (
        *power,
        f"{raw_type} raw = {_from_wire(ctx, reg)};",
        *((f"if (!({' && '.join(marks)})) {{", "    return false; /* the point's 'not available' marker */", "}") if marks else ()),
        "*out = sf < 0 ? (double)raw / scale : (double)raw * scale; /* raw / 10^-sf: correctly rounded, as the Python client */",
        "return true;",
    )
    writable, readable = reg.access.writable, reg.access.readable
    return ValueView(
        comment=f"Value of {label} = raw x 10^{sf_reg.name} (sf: its raw value, read with it)"
        + (f"; a write: {eng(reg, reg.raw_min)}..{eng(reg, reg.raw_max)} raw" if writable else "")
        + ("; word_order as the device is set" if order else "")
        + ".",
        value_type="double",
        words=str(reg.words),
        order=order,
        in_range=ctx.symbol(label, "is_in_range_sf", what=f"the range test of {label}") if writable else "",
        in_range_body=("double raw;", *power, f"return {fits};"),
        encode=ctx.symbol(label, "encode_sf", what=f"the encoder of {label}") if writable else "",
        encode_body=(
            "double raw;",
            *power,
            f"if (!({fits})) {{",
            "    return false;",
            "}",
            _to_wire(ctx, reg, f"({raw_type})raw"),
            "return true;",
        ),
        decode=ctx.symbol(label, "decode_sf", what=f"the decoder of {label}") if readable else "",
        decode_body=decode,
        guard="",
        sf=", int16_t sf",
    )


def _bodies(ctx: Context, reg: Register, label: str) -> tuple[str, tuple[str, ...], tuple[str, ...], tuple[str, ...]]:
    """(value type, is_in_range body, encode body, decode body) of a numeric register."""
    in_range = ctx.symbol_ref(label, "is_in_range")
    raw_type = C_TYPES[reg.type].value
    if reg.bitfields:
        return _bitfield_bodies(ctx, reg, label, in_range)
    if reg.enum is not None:
        return _enum_bodies(ctx, reg, in_range)
    if reg.type.is_float:
        return _float_bodies(ctx, reg, in_range)
    if _scaled(reg):
        offset, num, den = _ratio(ctx, reg)
        lo, hi = c_double(_inside(reg.raw_min, True)), c_double(_inside(reg.raw_max, False))
        convert = f"regmap_value_to_raw(value, {offset}, {num}, {den}, {lo}, {hi}, &raw)"
        return (
            "double",
            ("double raw;", f"return {convert};"),
            ("double raw;", f"if (!{convert}) {{", "    return false;", "}", _to_wire(ctx, reg, f"({raw_type})raw"), "return true;"),
            (f"*out = {_scaled_value(ctx, reg, _from_wire(ctx, reg))};", "return true;"),
        )
    conditions = _range_conditions(reg, "value", reg.type.raw_min, reg.type.raw_max) + _not_destructive(ctx, reg)
    return (
        raw_type,
        _returns(conditions),
        (*_refused_when_not(in_range), _to_wire(ctx, reg, "value"), "return true;"),
        (f"*out = {_from_wire(ctx, reg)};", "return true;"),
    )


def _enum_span(ctx: Context, e: EnumType) -> tuple[bool, int | None, int | None]:
    """Whether every member of `e` fits an int (the enum's C type holds them), and its lowest and highest member a
    write may send (None when none may be): once per device for each enum, which several registers may use."""
    span = ctx.enum_spans.get(e.name)
    if span is None:
        writable = [m.value for m in e.members if m.writable]
        typed = all(-(1 << 31) <= m.value < (1 << 31) for m in e.members)
        span = ctx.enum_spans[e.name] = (typed, min(writable, default=None), max(writable, default=None))
    return span


def _enum_bodies(ctx: Context, reg: Register, in_range: str) -> tuple[str, tuple[str, ...], tuple[str, ...], tuple[str, ...]]:
    e = reg.enum
    assert e is not None
    raw_type = C_TYPES[reg.type].value
    typed, lowest_writable, highest_writable = _enum_span(ctx, e)
    value_type = ctx.symbol_ref(e.name) if typed else raw_type
    writable, member = ctx.symbol_ref(e.name, "is_writable"), ctx.symbol_ref(e.name, "is_member")
    conditions = [f"{writable}(value)"]
    # The range where a member a write may send lies outside it (else membership says it all, and a bound
    # the enum's type already keeps would be flagged by -Wtype-limits).
    if lowest_writable is not None and lowest_writable < reg.raw_min:
        conditions.append(f"(long long)value >= (long long){c_signed(int(reg.raw_min))}")
    if highest_writable is not None and highest_writable > reg.raw_max:
        conditions.append(f"(long long)value <= (long long){c_signed(int(reg.raw_max))}")
    conditions += _not_destructive(ctx, reg)
    cast = f"({value_type})raw" if typed else "raw"
    encode = (*_refused_when_not(in_range), _to_wire(ctx, reg, f"({raw_type})value"), "return true;")
    if reg.type.is_float:
        # A setting coded as a float (a baud code 0-4 as an f32): a member only when the float is that integer exactly
        # (the range test first, so the conversion is defined; NaN fails it).
        lowest, highest = (c_float_literal(float(v), reg.type) for v in (min(m.value for m in e.members), max(m.value for m in e.members)))
        return (
            value_type,
            (f"return {' && '.join(conditions)};",),
            encode,
            (
                f"{raw_type} coded = {_from_wire(ctx, reg)};",
                "long long raw;",
                f"if (!(coded >= {lowest} && coded <= {highest})) {{",
                "    return false;",
                "}",
                "raw = (long long)coded;",
                f"if (coded != ({raw_type})raw || !{member}(raw)) {{",
                "    return false;",
                "}",
                f"*out = {cast};",
                "return true;",
            ),
        )
    return (
        value_type,
        (f"return {' && '.join(conditions)};",),
        encode,
        (
            f"{raw_type} raw = {_from_wire(ctx, reg)};",
            f"if (!{member}(raw)) {{",
            "    return false;",
            "}",
            f"*out = {cast};",
            "return true;",
        ),
    )


def _bitfield_bodies(
    ctx: Context, reg: Register, label: str, in_range: str
) -> tuple[str, tuple[str, ...], tuple[str, ...], tuple[str, ...]]:
    """A bitfield register's value is its whole word (built with the field setters); a write refuses a
    field whose enum does not have the value, or has it as a state the device only reports."""
    bits_type = C_TYPES[reg.type].bits
    if reg.signed:
        signed = _signed_bits(reg, "value")
        conditions = _range_conditions(reg, signed, reg.type.raw_min, reg.type.raw_max)
    else:
        conditions = _range_conditions(reg, "value", reg.type.raw_min, reg.type.raw_max)
    for b in reg.bitfields:
        if b.enum is not None:
            conditions.append(f"{ctx.symbol_ref(b.enum.name, 'is_writable')}({ctx.symbol_ref(label, 'get', b.name)}(value))")
    conditions += _not_destructive(ctx, reg)
    return (
        bits_type,
        _returns(conditions),
        (*_refused_when_not(in_range), _bits_to_wire(ctx, reg, "value"), "return true;"),
        (f"*out = {_bits_from_wire(ctx, reg)};", "return true;"),
    )


def _float_bodies(ctx: Context, reg: Register, in_range: str) -> tuple[str, tuple[str, ...], tuple[str, ...], tuple[str, ...]]:
    raw_type = C_TYPES[reg.type].value
    lo, hi = c_float_literal(float(reg.raw_min), reg.type), c_float_literal(float(reg.raw_max), reg.type)
    half = reg.type is DataType.F16
    held: tuple[str, ...]
    if _scaled(reg):
        offset, num, den = _ratio(ctx, reg)
        raw = f"(value - {offset}) * {den} / {num}"
        if half:  # rounded once from the double, as the Python client rounds it; the half it becomes is checked too
            held = ("float held = regmap_f16_from_bits(regmap_f16_to_bits_from_double(raw));",)
            sent = f"words[0] = regmap_u16_to_wire(regmap_f16_to_bits_from_double({raw}), {WORD_ORDER_MACRO[reg.byte_order._value_]});"
        else:
            held, sent = (), _to_wire(ctx, reg, f"({raw_type})({raw})")
        return (
            "double",
            (f"double raw = {raw};", *held, f"return raw >= {lo} && raw <= {hi}{_held_inside(half, lo, hi)}; /* NaN fails */"),
            (*_refused_when_not(in_range), sent, "return true;"),
            (f"*out = {_scaled_value(ctx, reg, _from_wire(ctx, reg))};", "return true;"),
        )
    held = ("float held = regmap_f16_from_bits(regmap_f16_to_bits(value));",) if half else ()
    return (
        raw_type,
        (*held, f"return value >= {lo} && value <= {hi}{_held_inside(half, lo, hi)}; /* NaN fails */"),
        (*_refused_when_not(in_range), _to_wire(ctx, reg, "value"), "return true;"),
        (f"*out = {_from_wire(ctx, reg)};", "return true;"),
    )


def _held_inside(half: bool, lo: str, hi: str) -> str:
    """An f16 is rounded to 11 bits on the way out: the half it becomes must be inside the range too (never infinity)."""
    return f" && held >= {lo} && held <= {hi}" if half else ""


def _na_conditions(reg: Register, raw: str) -> list[str]:
    """`raw` is none of the register's "not available" markers (a NaN marker: `raw == raw`, false only for NaN)."""
    conditions = [
        f"{raw} != {c_float_literal(float(mark), reg.type) if reg.type.is_float else c_raw(int(mark), reg.signed)}" for mark in reg.na
    ]
    if reg.na_nan:
        conditions.append(f"{raw} == {raw} /* not NaN */")
    return conditions


def _refusing_na(reg: Register, in_range: tuple[str, ...]) -> tuple[str, ...]:
    """The range test, refusing a "not available" marker as a value to write (the raw value for a scaled register)."""
    *head, last = in_range
    raw = "raw" if any(line.startswith("double raw") for line in head) else "value"
    expression = last.split(" /*")[0].removeprefix("return ").removesuffix(";")
    conditions = [expression] if expression != "true" else []
    conditions += _na_conditions(reg, raw)
    if any(line.startswith("float held") for line in head):  # an f16 that rounds onto a marker is refused too
        conditions += [c for c in _na_conditions(reg, "held") if "NaN" not in c]
    return (*head, f"return {' && '.join(conditions)};")


def _function(head: str, body: tuple[str, ...]) -> list[str]:
    return [head, "{", *["    " + line for line in body], "}"]


def value_lines(view: ValueView) -> list[str]:
    """The C of one register's value helpers, one line an item: printed by the header as one block (a register has
    a dozen small fields; a template would spend more steps on them than the lines take to join)."""
    v = view
    lines = [f"#if {v.guard}"] if v.guard else []
    lines.append(f"/* {comment_text(v.comment)} */")
    if v.in_range:
        lines += _function(f"static inline bool {v.in_range}({v.value_type} value{v.sf})", v.in_range_body)
        lines += _function(f"static inline bool {v.encode}({v.value_type} value{v.sf}{v.order}, uint16_t words[{v.words}])", v.encode_body)
    if v.available:
        lines += _function(f"static inline bool {v.available}(const uint16_t words[{v.words}]{v.order})", v.available_body)
    if v.decode:
        lines += _function(
            f"static inline bool {v.decode}(const uint16_t words[{v.words}]{v.order}{v.sf}, {v.value_type} *out)", v.decode_body
        )
    if v.guard:
        lines.append("#endif")
    return lines


def values_text(views: Iterable[ValueView]) -> str:
    """The value helpers of a register or array member as the header prints them ("" when it has none)."""
    return "\n".join([line for v in views for line in value_lines(v)])


def register_values(ctx: Context, reg: Register, label: str = "") -> tuple[ValueView, ...]:
    view = value_view(ctx, reg, label or reg.name)
    return (view,) if view is not None else ()


def member_values(ctx: Context, elements: Sequence[Register], owner: str) -> tuple[ValueView, ...]:
    """One set of value helpers for an array member whose elements share their range, else one per element (named as the element)."""
    if len({(r.raw_min, r.raw_max) for r in elements}) == 1:
        return register_values(ctx, elements[0], owner)
    return tuple(v for r in elements for v in register_values(ctx, r))


def ratio_literal(reg: Register, part: int, ratio: Fraction) -> str:
    """A numerator or denominator of a scale or offset, of the essential type of the raw value it multiplies
    (MISRA C:2012 10.4): unsigned (`u`) beside an unsigned raw value, signed beside a signed one or when
    the ratio is negative, so `raw * NUM / DEN` never turns a negative raw value into a huge unsigned one."""
    return c_signed(part) if reg.signed or ratio < 0 else c_unsigned(part)
