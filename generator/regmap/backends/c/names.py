"""C identifiers and literals: the validated names (`CIdentifier`, `CSymbol`), the per-device name
table that refuses two map items generating one name, and the C spelling of numbers."""

from __future__ import annotations

import re
from collections.abc import Iterable
from fractions import Fraction

from regmap.diagnostics import UsageError
from regmap.keywords import C_KEYWORDS, CPP_KEYWORDS
from regmap.model import Access, DataType, Device, PollClass, Register, WordOrder
from regmap.records import NamedTuple
from regmap.render import c_comment, header_lines
from regmap_runtime.spaces import COIL, DISCRETE_INPUT, HOLDING, INPUT, SPACES
from regmap_runtime.types import TYPES

# -- identifiers -----------------------------------------------------------------------------

# Names the headers this code includes (stdbool.h, stddef.h, stdint.h) define, and common macros.
STANDARD_NAMES = frozenset(
    [
        "NULL",
        "offsetof",
        "size_t",
        "ptrdiff_t",
        "max_align_t",
        "EOF",
        "errno",
        "assert",
        "main",
        "int8_t",
        "int16_t",
        "int32_t",
        "int64_t",
        "uint8_t",
        "uint16_t",
        "uint32_t",
        "uint64_t",
        "intptr_t",
        "uintptr_t",
        "intmax_t",
        "uintmax_t",
        "INT8_MAX",
        "INT16_MAX",
        "INT32_MAX",
        "INT64_MAX",
        "INT8_MIN",
        "INT16_MIN",
        "INT32_MIN",
        "INT64_MIN",
        "UINT8_MAX",
        "UINT16_MAX",
        "UINT32_MAX",
        "UINT64_MAX",
        "SIZE_MAX",
        "PTRDIFF_MAX",
        "PTRDIFF_MIN",
        "INTPTR_MAX",
        "UINTPTR_MAX",
    ]
)
# Patterns only a name that is not plain (below) is checked against, rarely: compiled on first use (re's cache), not
# at import, where compiling them cost every cold run about 1.5M instructions.
_RESERVED = r"^_|__|_t$"
_UPPER = r"^[A-Z_][A-Z0-9_]*$"
_LOWER = r"^[a-z_][a-z0-9_]*$"
# Names that pass every check above at once (no leading, doubled or trailing underscore): nearly all of them. The
# others take the checks one by one, which say what is wrong.
_PLAIN_UPPER = re.compile(r"[A-Z][A-Z0-9]*(?:_[A-Z0-9]+)*")
_PLAIN_LOWER = re.compile(r"[a-z][a-z0-9]*(?:_[a-z0-9]+)*")


def _check_reserved(name: str) -> None:
    # Leading underscores and `__` anywhere are reserved to the implementation (C 7.1.3, C++
    # [lex.name]); `_t` names to POSIX.
    if re.search(_RESERVED, name):
        raise UsageError(f"{name!r} is a reserved C identifier (leading underscore, '__' or a '_t' suffix); rename it in the map")


class CIdentifier(str):
    """An upper-case C identifier for macros and enum constants, joined from parts: `[A-Z_][A-Z0-9_]*`,
    never reserved. Upper-case names cannot be C or C++ keywords; they can be standard macros."""

    def __new__(cls, *parts: str) -> CIdentifier:
        name = "_".join(filter(None, parts)).upper()
        if not _PLAIN_UPPER.fullmatch(name):
            if not re.match(_UPPER, name):
                raise UsageError(f"{name!r} is not a valid C identifier")
            _check_reserved(name)
        if name in STANDARD_NAMES:
            raise UsageError(f"{name!r} is a name of the C standard library; rename it in the map")
        return str.__new__(cls, name)


class CSymbol(str):
    """A lower-case C identifier for functions, types, tables and parameters. A C or C++ keyword
    gets a trailing underscore (`register` -> `register_`); reserved names are refused."""

    def __new__(cls, *parts: str) -> CSymbol:
        name = "_".join(filter(None, parts)).lower()
        plain = _PLAIN_LOWER.fullmatch(name) and not name.endswith("_t")
        if not plain and not re.match(_LOWER, name):
            raise UsageError(f"{name!r} is not a valid C identifier")
        if name in C_KEYWORDS or name in CPP_KEYWORDS or name in STANDARD_NAMES:
            name += "_"
        if not plain:
            _check_reserved(name)
        return str.__new__(cls, name)


# The names CSymbol gives a trailing underscore (keywords, standard names): a name among them takes CSymbol itself.
_NOT_PLAIN_SYMBOLS = C_KEYWORDS | CPP_KEYWORDS | STANDARD_NAMES


class _Names:
    """Every file-scope name one header declares, so two map items never generate the same one."""

    def __init__(self, device: Device) -> None:
        self.device = device
        # What each name is for: a description, or the parts it was made of (joined only for the error, as it is rare).
        self.seen: dict[str, str | tuple[str, ...]] = {}

    def add(self, name: str, what: str | tuple[str, ...]) -> str:
        if name in self.seen:
            first, second = (w if isinstance(w, str) else " ".join(w) for w in (self.seen[name], what))
            raise UsageError(
                f"{self.device.source_path}: generated C name {name} is used by both {first} and {second}; rename one in the map"
            )
        self.seen[name] = what
        return name


# -- literals --------------------------------------------------------------------------------


def c_unsigned(value: int) -> str:
    """An unsigned literal that keeps its value on 16-bit-int targets too (and 64-bit values on 32-bit-long ones)."""
    if value > 0xFFFFFFFF:
        return f"{value}ull"
    return f"{value}u" if value <= 0xFFFF else f"{value}ul"


def c_hex(value: int) -> str:
    if value > 0xFFFFFFFF:
        return f"0x{value:016X}ull"
    return f"0x{value:04X}u" if value <= 0xFFFF else f"0x{value:08X}ul"


def c_signed(value: int) -> str:
    """A signed literal safe inside a macro (parenthesised when negative; INT32_MIN and INT64_MIN spelled
    so they have their type; 64-bit values as long long)."""
    if value == -(1 << 31):
        return "(-2147483647 - 1)"
    if value == -(1 << 63):
        return "(-9223372036854775807ll - 1)"
    if not -(1 << 31) <= value < (1 << 31):
        return f"({value}ll)" if value < 0 else f"{value}ll"
    return f"({value})" if value < 0 else str(value)


def c_raw(value: int, signed: bool) -> str:
    return c_signed(value) if signed else c_unsigned(value)


def _negative(text: str) -> str:
    """A literal safe inside a macro: parenthesised when negative."""
    return f"({text})" if text.startswith("-") else text


def c_float(value: Fraction | float) -> str:
    text = f"{float(value):.9g}"
    if not any(c in text for c in ".e"):
        text += ".0"
    return _negative(text + "f")


def c_double(value: Fraction | float) -> str:
    """A double literal that reads back as the same double (repr: the shortest that does)."""
    text = repr(float(value))
    if not any(c in text for c in ".e"):
        text += ".0"
    return _negative(text)


def c_float_literal(value: float, data_type: DataType) -> str:
    """A literal of a float register's C type: `900.0f` for f16 and f32 (a float: rounded by the compiler as a float32 is), `0.1` for f64."""
    text = repr(float(value))
    if not any(c in text for c in ".e"):
        text += ".0"
    return _negative(text + "f" if data_type in (DataType.F16, DataType.F32) else text)


def c_value(value: int | float | str, reg: Register) -> str:
    """A raw min/max/default of a register as a C literal of its type."""
    if reg.type.is_bool:
        return "true" if value else "false"
    if isinstance(value, str):
        raise TypeError("text literals go through the c_str filter")
    if reg.type.is_float:
        return c_float_literal(float(value), reg.type)
    return c_raw(int(value), reg.signed)


class CType(NamedTuple):
    """C's spelling of a data type: the type of its value, and the unsigned type that holds its bits."""

    value: str
    bits: str


C_TYPES = {
    DataType.U16: CType("uint16_t", "uint16_t"),
    DataType.S16: CType("int16_t", "uint16_t"),
    DataType.U32: CType("uint32_t", "uint32_t"),
    DataType.S32: CType("int32_t", "uint32_t"),
    DataType.U64: CType("uint64_t", "uint64_t"),
    DataType.S64: CType("int64_t", "uint64_t"),
    DataType.F16: CType("float", "uint16_t"),  # converted by the shared header's regmap_f16_* (no _Float16 in C99 or C++)
    DataType.F32: CType("float", "uint32_t"),
    DataType.F64: CType("double", "uint64_t"),
    DataType.STRING: CType("char", "uint16_t"),
    DataType.BOOL: CType("bool", "bool"),
    DataType.TIMESTAMP: CType("uint32_t", "uint32_t"),
}
# The tables below are keyed by value strings (type, access, order, poll class), as the views spell them.
# The 16/32-bit integers of the first maps: their registers need no helper beyond the word conversions.
# A tuple: `in` compares by identity.
PLAIN_TYPES = (DataType.U16, DataType.S16, DataType.U32, DataType.S32)
# Shared helpers that move a register's value to and from its words on the wire (word and byte order applied).
WIRE_FUNCTIONS: dict[str, tuple[str, str]] = {
    t._value_: (f"regmap_{t._value_}_from_wire", f"regmap_{t._value_}_to_wire") for t in DataType if t is not DataType.BOOL
}
# A type whose helpers exist only where the C type is IEEE 754 (the shared header's REGMAP_HAS_F32/F64; an f16's value is a float).
FLOAT_GUARD = {"f16": "REGMAP_HAS_F32", "f32": "REGMAP_HAS_F32", "f64": "REGMAP_HAS_F64"}
ACCESS_MACRO = {
    Access.READ._value_: "REGMAP_ACCESS_R",
    Access.READ_WRITE._value_: "REGMAP_ACCESS_RW",
    Access.WRITE._value_: "REGMAP_ACCESS_W",
}
WORD_ORDER_MACRO = {WordOrder.HIGH_FIRST._value_: "REGMAP_HIGH_FIRST", WordOrder.LOW_FIRST._value_: "REGMAP_LOW_FIRST"}
# The shared header's enums, from the runtime's tables: spaces, types, paddings, poll classes, firmware formats.
SPACE_MACRO = {name: CIdentifier("REGMAP_SPACE", name) for name in SPACES}
TYPE_MACRO = {name: CIdentifier("REGMAP_TYPE", name) for name in TYPES}
PADDING_MACRO = {"nul": "REGMAP_PADDING_NUL", "space": "REGMAP_PADDING_SPACE"}
POLL_MACRO = {p._value_: CIdentifier("REGMAP_POLL", p._value_) for p in PollClass}
FIRMWARE_FORMAT_MACRO = {
    "decimal": "REGMAP_FIRMWARE_DECIMAL",
    "major_minor": "REGMAP_FIRMWARE_MAJOR_MINOR",
    "string": "REGMAP_FIRMWARE_STRING",
}
# The macro of each function code of each space (regmap_runtime.spaces.Space.codes).
FUNCTION_MACROS = {
    HOLDING.name: {
        "read": "REGMAP_FC_READ_HOLDING",
        "write_single": "REGMAP_FC_WRITE_SINGLE",
        "write_multiple": "REGMAP_FC_WRITE_MULTIPLE",
    },
    INPUT.name: {"read": "REGMAP_FC_READ_INPUT"},
    COIL.name: {
        "read": "REGMAP_FC_READ_COILS",
        "write_single": "REGMAP_FC_WRITE_SINGLE_COIL",
        "write_multiple": "REGMAP_FC_WRITE_MULTIPLE_COILS",
    },
    DISCRETE_INPUT.name: {"read": "REGMAP_FC_READ_DISCRETE_INPUTS"},
}


# The shared builders (and their parameters after the address) of each space's operations, and the
# name a device header's wrapper gets (`<device>_<suffix>`); holding's wrappers are the first maps' own.
class Builder(NamedTuple):
    shared: str
    suffix: str
    params: str  # after `uint16_t address`
    args: str
    limited_by: str  # "read", "write" or "": which device limit bounds its count


BUILDERS = {
    INPUT.name: {"read": Builder("regmap_rtu_build_read_input_registers", "build_read_input_registers", "uint16_t count", "count", "read")},
    COIL.name: {
        "read": Builder("regmap_rtu_build_read_coils", "build_read_coils", "uint16_t count", "count", "read"),
        "write_single": Builder("regmap_rtu_build_write_single_coil", "build_write_single_coil", "bool on", "on", ""),
        "write_multiple": Builder(
            "regmap_rtu_build_write_multiple_coils",
            "build_write_multiple_coils",
            "const bool *bits, uint16_t count",
            "bits, count",
            "write",
        ),
    },
    DISCRETE_INPUT.name: {
        "read": Builder("regmap_rtu_build_read_discrete_inputs", "build_read_discrete_inputs", "uint16_t count", "count", "read")
    },
}
# The shared parser of each space's operations (the tests' frames program calls them).
PARSERS = {
    HOLDING.name: {
        "read": "regmap_rtu_parse_read_response",
        "write_single": "regmap_rtu_parse_write_single_response",
        "write_multiple": "regmap_rtu_parse_write_multiple_response",
    },
    INPUT.name: {"read": "regmap_rtu_parse_read_input_response"},
    COIL.name: {
        "read": "regmap_rtu_parse_read_coils_response",
        "write_single": "regmap_rtu_parse_write_single_coil_response",
        "write_multiple": "regmap_rtu_parse_write_multiple_coils_response",
    },
    DISCRETE_INPUT.name: {"read": "regmap_rtu_parse_read_discrete_inputs_response"},
}
PARITY_CHAR = {"none": "'N'", "even": "'E'", "odd": "'O'"}


class Macro(NamedTuple):
    """A named constant of the header (a macro, an enum member)."""

    name: str
    value: str
    comment: str = ""  # plain text; the template escapes it


# A macro's name and value, for a macro only ever printed as a `#define` line: a plain pair costs less than a Macro.
Define = tuple[str, str]


def define_lines(macros: Iterable[Macro | Define]) -> str:
    """The `#define` of each macro, one a line, values in one column: what a header prints of a register's or an
    array's macros (a block the template prints as it is, not four pieces per macro)."""
    return "\n".join(f"#define {m[0]:<48} {m[1]}" for m in macros)


def comment_text(text: str) -> str:
    """`c_comment(text)`, without the split and join it spends on text whose whitespace is single spaces already
    (printable, no space doubled or at an end: most map text) when it has nothing to escape either."""
    if not text:
        return ""
    if text.isprintable() and "  " not in text and text[0] != " " and text[-1] != " ":
        return sentence_comment(text)
    return c_comment(text)


def sentence_comment(sentence: str) -> str:
    """`c_comment` of text `sentences` made, whose whitespace is single spaces already: text without a slash, a
    backslash or `??` is then its own escape (most comments)."""
    if "/" in sentence or "\\" in sentence or "??" in sentence:
        return c_comment(sentence)
    return sentence


class Context:
    """Names for one device: macro prefix, function prefix, and the address expression of each register."""

    def __init__(self, device: Device) -> None:
        self.device = device
        self.names = _Names(device)
        self.prefix = CIdentifier(device.id)
        self.lower = device.id  # only ever the start of a name; CSymbol checks the whole name
        self.arrays = {a.name: a for a in device.arrays}
        # The upper-case spelling of each part a constant's name was made of that is plain on its own: a name of
        # plain parts is plain, so the parts a header repeats (an owner, WORDS, ACCESS ...) are checked once, not per name.
        self._plain_parts: dict[str, str] = {self.prefix: self.prefix} if _PLAIN_UPPER.fullmatch(self.prefix) else {}
        self._refs: dict[tuple[str, ...], str] = {}  # the functions referred to: an enum's tests, once per register using it
        # Literals registers share, by what they depend on (a scale's three spellings ...): spelled once per device.
        self.literals: dict[tuple[object, ...], tuple[str, ...]] = {}
        # Per enum (by name): whether its members fit an int, its lowest and highest writable member (values._enum_span).
        self.enum_spans: dict[str, tuple[bool, int | None, int | None]] = {}

    def const(self, *parts: str, what: str = "") -> str:
        name = self._identifier(parts)
        seen = self.names.seen
        if name in seen:
            return self.names.add(name, what or parts)  # refused: two map items made the name
        seen[name] = what or parts
        return name

    def stem(self, owner: str) -> str:
        """`<PREFIX>_<OWNER>` when the prefix and the owner part are plain, for `owned`; "" when each name must take the
        full check. Only ever the start of a name: `owned` checks the whole (`INT8_MAX` is a standard name,
        `INT8_MAX_WORDS` is not)."""
        known = self._plain_parts
        if self.prefix not in known:
            return ""
        upper = known.get(owner)
        if upper is None:
            upper = owner.upper()
            if not _PLAIN_UPPER.fullmatch(upper):
                return ""
            known[owner] = upper
        return f"{self.prefix}_{upper}"

    def owned(self, stem: str, owner: str, suffix: str) -> str:
        """const(owner, suffix) for the dozen constants of one register: the owner spelled once (`stem`), a suffix met
        before joined to it by lookup."""
        upper = self._plain_parts.get(suffix) if stem else None
        if upper is not None:
            name = f"{stem}_{upper}"
            seen = self.names.seen
            if name not in seen and name not in STANDARD_NAMES:
                seen[name] = (owner, suffix)
                return name
        return self.const(owner, suffix)

    def _identifier(self, parts: tuple[str, ...]) -> str:
        """CIdentifier(prefix, *parts), with each plain part checked once per device."""
        known = self._plain_parts
        if self.prefix not in known:
            return CIdentifier(self.prefix, *parts)
        spelled: list[str] = [self.prefix]
        for part in parts:
            if part:
                upper = known.get(part)
                if upper is None:
                    upper = part.upper()
                    if not _PLAIN_UPPER.fullmatch(upper):
                        return CIdentifier(self.prefix, *parts)
                    known[part] = upper
                spelled.append(upper)
        name = "_".join(spelled)
        return name if name not in STANDARD_NAMES else CIdentifier(self.prefix, *parts)

    def symbol(self, *parts: str, what: str = "") -> str:
        referred = self._refs.get(parts)  # a helper's body may have named it first (symbol_ref)
        return self.names.add(referred or self._symbol(parts), what or parts)

    def _symbol(self, parts: tuple[str, ...]) -> str:
        """CSymbol(lower, *parts), the name a plain str when it takes none of CSymbol's changes: nearly every name."""
        if "" not in parts:
            name = f"{self.lower}_{'_'.join(parts)}".lower()
            if _PLAIN_LOWER.fullmatch(name) and not name.endswith("_t") and name not in _NOT_PLAIN_SYMBOLS:
                return name
        return CSymbol(self.lower, *parts)

    def owner(self, reg: Register) -> str:
        """The name the macros of a register carry: its own, or `<array>_<member>` for an array element."""
        return f"{reg.array.array}_{reg.array.member}" if reg.array else reg.name

    def addr(self, reg: Register) -> str:
        """C expression of a register's listed address."""
        name = CIdentifier(self.prefix, self.owner(reg), "ADDR")
        return f"{name}({reg.array.index})" if reg.array else name

    def pair_addr(self, reg: Register) -> str:
        name = CIdentifier(self.prefix, self.owner(reg), "PAIR_ADDR")
        return f"{name}({reg.array.index})" if reg.array else name

    def member_const(self, reg: Register, suffix: str) -> str:
        return CIdentifier(self.prefix, self.owner(reg), suffix)

    def symbol_ref(self, *parts: str) -> str:
        """A function the header declares (referring to it does not declare it again)."""
        name = self._refs.get(parts)
        if name is None:
            name = self._refs[parts] = self._symbol(parts)
        return name


def file_header(device: Device) -> list[str]:
    """The do-not-edit lines of every file generated for `device`."""
    return header_lines(device, "regmap generate")
