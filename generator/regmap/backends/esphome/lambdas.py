"""C++ lambdas for what ESPHome's `value_type`s cannot say: byte-swapped values (ESPHome has no byte-swap
type), IEEE half floats and doubles (no FP16 or FP64 type), text as the Python client reads it, and writes of byte-swapped words.

Each lambda is written from integers and the register's type alone, never from map text (see
`homeauto.entities.Lambda`). They read the register's bytes from `data` at `item->offset` (the byte offset
ESPHome gives the item within its range's response), check the response is long enough, and convert
without undefined behaviour: bytes are assembled into an unsigned integer and reinterpreted with
`std::memcpy`; a double beyond float's range becomes an infinity rather than an out-of-range cast.
"""

from __future__ import annotations

from fractions import Fraction

from regmap.model import Bitfield, Register, WordOrder

_SIGNED = {16: "int16_t", 32: "int32_t", 64: "int64_t"}
_UNSIGNED = {16: "uint16_t", 32: "uint32_t", 64: "uint64_t"}


def wire_bytes(reg: Register) -> list[int]:
    """For each byte of the value, most significant first, its index among the register's wire bytes."""
    n = reg.words
    swapped = reg.byte_order.value == "low_first"
    out = []
    for k in range(2 * n):
        word, byte = divmod(k, 2)
        if reg.word_order is WordOrder.LOW_FIRST and reg.wide:
            word = n - 1 - word
        out.append(2 * word + (1 - byte if swapped else byte))
    return out


def _assemble(reg: Register) -> list[str]:
    size = 2 * reg.words
    lines = ["const std::size_t o = item->offset;", f"if (data.size() < o + {size}) return NAN;", "uint64_t raw = 0;"]
    lines += [f"raw = (raw << 8) | data[o + {i}];" for i in wire_bytes(reg)]
    return lines


def raw_lambda(reg: Register, field: Bitfield | None = None) -> str:
    """The register's raw value (a bitfield's, when given) as a float, from its wire bytes."""
    bits = 16 * reg.words
    lines = _assemble(reg)
    if field is None:
        lines += [f"if (raw == 0x{pattern:X}u) return NAN;  // the device's 'not available' marker" for pattern in reg.na_bits]
    if field is not None:
        lines.append(f"return static_cast<float>((raw >> {field.lsb}) & 0x{(1 << field.width) - 1:X}u);")
    elif reg.type.is_float and bits == 16:
        # A half (f16): sign, 5 exponent bits, 10 mantissa bits; std::ldexp is exact here (every half is a float).
        lines += [
            "const unsigned e = static_cast<unsigned>(raw >> 10) & 0x1Fu;",
            "const float m = static_cast<float>(raw & 0x3FFu);",
            "const float f = e == 0u ? std::ldexp(m, -24) : e == 31u ? (m != 0.0f ? NAN : INFINITY) : std::ldexp(m + 1024.0f, static_cast<int>(e) - 25);",
            "return (raw & 0x8000u) != 0u ? -f : f;",
        ]
    elif reg.type.is_float and bits == 32:
        lines += ["const uint32_t u = static_cast<uint32_t>(raw);", "float f;", "std::memcpy(&f, &u, sizeof f);", "return f;"]
    elif reg.type.is_float:
        lines += [
            "double d;",
            "std::memcpy(&d, &raw, sizeof d);",
            "if (std::isnan(d)) return NAN;",
            "if (d > 3.4028234663852886e38) return INFINITY;",
            "if (d < -3.4028234663852886e38) return -INFINITY;",
            "return static_cast<float>(d);",
        ]
    elif reg.type.signed:
        lines += [
            f"const {_UNSIGNED[bits]} u = static_cast<{_UNSIGNED[bits]}>(raw);",
            f"{_SIGNED[bits]} s;",
            "std::memcpy(&s, &u, sizeof s);",
            "return static_cast<float>(s);",
        ]
    else:
        lines.append("return static_cast<float>(raw);")
    return "\n".join(lines)


def number_read_lambda(reg: Register) -> str:
    """A byte-swapped 16-bit number's engineering value (raw x scale + offset) from its wire bytes."""
    body = raw_lambda(reg).rsplit("\n", 1)
    last = body[1].removeprefix("return ").removesuffix(";")
    return f"{body[0]}\nconst float raw_value = {last};\nreturn raw_value * {_float(reg.scale)} + {_float(reg.offset)};"


def number_write_lambda(reg: Register) -> str:
    """The raw word ESPHome should send for a number's value x, bytes swapped for the wire; ESPHome then
    writes it as U_WORD (llroundf, & 0xFFFF), so every 16-bit word is exact in a float."""
    return "\n".join(
        [
            f"const int64_t raw = llroundf((x - {_float(reg.offset)}) / {_float(reg.scale)});",
            "const uint16_t u = static_cast<uint16_t>(static_cast<uint64_t>(raw) & 0xFFFFu);",
            "return static_cast<float>(static_cast<uint16_t>((u << 8) | (u >> 8)));",
        ]
    )


def offset_read_lambda(reg: Register) -> str:
    """A number's value with its offset: ESPHome's number divides by `multiply` only."""
    return f"return x + {_float(reg.offset)};"


def offset_write_lambda(reg: Register) -> str:
    """The raw value ESPHome should write for x (with a write_lambda ESPHome no longer applies `multiply`)."""
    return f"return (x - {_float(reg.offset)}) / {_float(reg.scale)};"


def text_lambda(reg: Register) -> str:
    """The text the Python client reads: bytes in order (bytes of each word swapped when the device swaps
    them), up to the first NUL, trailing spaces removed for space padding; ascii bytes above 0x7F and
    latin-1 text become UTF-8 (U+FFFD for the former), utf-8 bytes pass as they are."""
    size = 2 * reg.words
    index = "o + (i ^ 1)" if reg.byte_order.value == "low_first" else "o + i"
    lines = [
        "const std::size_t o = item->offset;",
        "std::string text;",
        f"for (std::size_t i = 0; i < {size} && {index} < data.size(); i++) {{",
        f"  const uint8_t b = data[{index}];",
        "  if (b == 0) break;",
    ]
    if reg.encoding == "ascii":
        lines += [
            "  if (b > 0x7F) {",
            "    text += static_cast<char>(0xEF);",
            "    text += static_cast<char>(0xBF);",
            "    text += static_cast<char>(0xBD);",
            "  } else {",
            "    text += static_cast<char>(b);",
            "  }",
        ]
    elif reg.encoding == "latin-1":
        lines += [
            "  if (b > 0x7F) {",
            "    text += static_cast<char>(0xC0 | (b >> 6));",
            "    text += static_cast<char>(0x80 | (b & 0x3F));",
            "  } else {",
            "    text += static_cast<char>(b);",
            "  }",
        ]
    else:
        lines.append("  text += static_cast<char>(b);")
    lines.append("}")
    if reg.padding == "space":
        lines.append("while (!text.empty() && text.back() == ' ') text.pop_back();")
    lines.append("return text;")
    return "\n".join(lines)


def time_lambda(reg: Register) -> str:
    """A timestamp's ISO 8601 text from its unsigned 32-bit seconds (exact: a sensor's float would round
    to 128 s), the civil date by days-from-civil's inverse (proleptic Gregorian, no library, no zone):
    `Z` after a utc time, nothing after a local one; no text for a "not available" marker."""
    lines = [*_assemble(reg)[:1], f"if (data.size() < o + {2 * reg.words}) return {{}};", "uint64_t raw = 0;"]
    lines += [f"raw = (raw << 8) | data[o + {i}];" for i in wire_bytes(reg)]
    lines += [f"if (raw == 0x{pattern:X}u) return {{}};  // the device's 'not available' marker" for pattern in reg.na_bits]
    lines += [
        "const int64_t days = static_cast<int64_t>(raw / 86400u);",
        "const unsigned secs = static_cast<unsigned>(raw % 86400u);",
        "const int64_t z = days + 719468;",
        "const int64_t era = z / 146097;",
        "const int64_t doe = z - era * 146097;",
        "const int64_t yoe = (doe - doe / 1460 + doe / 36524 - doe / 146096) / 365;",
        "const int64_t doy = doe - (365 * yoe + yoe / 4 - yoe / 100);",
        "const int64_t mp = (5 * doy + 2) / 153;",
        "const unsigned day = static_cast<unsigned>(doy - (153 * mp + 2) / 5 + 1);",
        "const unsigned month = static_cast<unsigned>(mp < 10 ? mp + 3 : mp - 9);",
        "const unsigned year = static_cast<unsigned>(yoe + era * 400 + (month <= 2 ? 1 : 0));",
        "char text[32];",
        f'snprintf(text, sizeof text, "%04u-%02u-%02uT%02u:%02u:%02u{"Z" if reg.zone == "utc" else ""}", year, month, day, '
        "secs / 3600u, secs / 60u % 60u, secs % 60u);",
        "return std::string(text);",
    ]
    return "\n".join(lines)


def _float(value: Fraction | float) -> str:
    text = f"{float(value):.17g}"
    return text if any(c in text for c in ".en") else text + ".0"
