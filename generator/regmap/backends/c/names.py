"""C identifiers and literals: the validated names (`CIdentifier`, `CSymbol`), the per-device name
table that refuses two map items generating one name, and the C spelling of numbers."""

from __future__ import annotations

import re
from dataclasses import dataclass
from fractions import Fraction

from regmap.diagnostics import UsageError
from regmap.keywords import C_KEYWORDS, CPP_KEYWORDS
from regmap.model import Access, DataType, Device, Register, WordOrder
from regmap.render import header_lines
from regmap_runtime.spaces import COIL, DISCRETE_INPUT, HOLDING, INPUT

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
_RESERVED = re.compile(r"^_|__|_t$")
_UPPER = re.compile(r"^[A-Z_][A-Z0-9_]*$")
_LOWER = re.compile(r"^[a-z_][a-z0-9_]*$")


def _check_reserved(name: str) -> None:
    # Leading underscores and `__` anywhere are reserved to the implementation (C 7.1.3, C++
    # [lex.name]); `_t` names to POSIX.
    if _RESERVED.search(name):
        raise UsageError(f"{name!r} is a reserved C identifier (leading underscore, '__' or a '_t' suffix); rename it in the map")


class CIdentifier(str):
    """An upper-case C identifier for macros and enum constants, joined from parts: `[A-Z_][A-Z0-9_]*`,
    never reserved. Upper-case names cannot be C or C++ keywords; they can be standard macros."""

    def __new__(cls, *parts: str) -> CIdentifier:
        name = "_".join(p for p in parts if p).upper()
        if not _UPPER.match(name):
            raise UsageError(f"{name!r} is not a valid C identifier")
        _check_reserved(name)
        if name in STANDARD_NAMES:
            raise UsageError(f"{name!r} is a name of the C standard library; rename it in the map")
        return super().__new__(cls, name)


class CSymbol(str):
    """A lower-case C identifier for functions, types, tables and parameters. A C or C++ keyword
    gets a trailing underscore (`register` -> `register_`); reserved names are refused."""

    def __new__(cls, *parts: str) -> CSymbol:
        name = "_".join(p for p in parts if p).lower()
        if not _LOWER.match(name):
            raise UsageError(f"{name!r} is not a valid C identifier")
        if name in C_KEYWORDS or name in CPP_KEYWORDS or name in STANDARD_NAMES:
            name += "_"
        _check_reserved(name)
        return super().__new__(cls, name)


class _Names:
    """Every file-scope name one header declares, so two map items never generate the same one."""

    def __init__(self, device: Device) -> None:
        self.device = device
        self.seen: dict[str, str] = {}

    def add(self, name: str, what: str) -> str:
        if name in self.seen:
            raise UsageError(
                f"{self.device.source_path}: generated C name {name} is used by both {self.seen[name]} and {what}; rename one in the map"
            )
        self.seen[name] = what
        return name


# -- literals --------------------------------------------------------------------------------


def c_unsigned(value: int) -> str:
    """An unsigned literal that keeps its value on 16-bit-int targets too."""
    return f"{value}u" if value <= 0xFFFF else f"{value}ul"


def c_hex(value: int) -> str:
    return f"0x{value:04X}u" if value <= 0xFFFF else f"0x{value:08X}ul"


def c_signed(value: int) -> str:
    """A signed literal safe inside a macro (parenthesised when negative; INT32_MIN spelled so it is an int)."""
    if value == -(1 << 31):
        return "(-2147483647 - 1)"
    return f"({value})" if value < 0 else str(value)


def c_raw(value: int, signed: bool) -> str:
    return c_signed(value) if signed else c_unsigned(value)


def c_float(value: Fraction) -> str:
    text = f"{float(value):.9g}"
    if not any(c in text for c in ".e"):
        text += ".0"
    return text + "f"


@dataclass(frozen=True)
class CType:
    """C's spelling of a data type: the type of its value, and the unsigned type that holds its bits."""

    value: str
    bits: str


C_TYPES = {
    DataType.U16: CType("uint16_t", "uint16_t"),
    DataType.S16: CType("int16_t", "uint16_t"),
    DataType.U32: CType("uint32_t", "uint32_t"),
    DataType.S32: CType("int32_t", "uint32_t"),
}
ACCESS_MACRO = {Access.READ: "REGMAP_ACCESS_R", Access.READ_WRITE: "REGMAP_ACCESS_RW", Access.WRITE: "REGMAP_ACCESS_W"}
WORD_ORDER_MACRO = {WordOrder.HIGH_FIRST: "REGMAP_HIGH_FIRST", WordOrder.LOW_FIRST: "REGMAP_LOW_FIRST"}
# The macro of each function code of each space (regmap_runtime.spaces.Space.codes).
FUNCTION_MACROS = {
    HOLDING.name: {"read": "REGMAP_FC_READ_HOLDING", "write_single": "REGMAP_FC_WRITE_SINGLE", "write_multiple": "REGMAP_FC_WRITE_MULTIPLE"},
    INPUT.name: {"read": "REGMAP_FC_READ_INPUT"},
    COIL.name: {"read": "REGMAP_FC_READ_COILS", "write_single": "REGMAP_FC_WRITE_SINGLE_COIL", "write_multiple": "REGMAP_FC_WRITE_MULTIPLE_COILS"},
    DISCRETE_INPUT.name: {"read": "REGMAP_FC_READ_DISCRETE_INPUTS"},
}
PARITY_CHAR = {"none": "'N'", "even": "'E'", "odd": "'O'"}


class Context:
    """Names for one device: macro prefix, function prefix, and the address expression of each register."""

    def __init__(self, device: Device) -> None:
        self.device = device
        self.names = _Names(device)
        self.prefix = CIdentifier(device.id)
        self.lower = device.id  # only ever the start of a name; CSymbol checks the whole name
        self.arrays = {a.name: a for a in device.arrays}

    def const(self, *parts: str, what: str = "") -> str:
        return self.names.add(CIdentifier(self.prefix, *parts), what or " ".join(parts))

    def symbol(self, *parts: str, what: str = "") -> str:
        return self.names.add(CSymbol(self.lower, *parts), what or " ".join(parts))

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
        return CSymbol(self.lower, *parts)


def file_header(device: Device) -> list[str]:
    """The do-not-edit lines of every file generated for `device`."""
    return header_lines(device, "regmap generate")
