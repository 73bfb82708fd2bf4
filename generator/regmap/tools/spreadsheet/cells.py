"""Cell readers: a cell as manuals print it -> a value, or a `CellProblem` saying why it cannot be read.

Conservative on purpose: a range like `0~∞`, a unit not in `UNITS` or a default that is not a
number is reported, never guessed.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from decimal import Decimal, InvalidOperation
from fractions import Fraction

from regmap_runtime.types import TYPES as DATA_TYPES


class CellProblem(ValueError):
    """A cell that cannot be read; the message says what was expected."""


EMPTY = {"", "-", "--", "—", "/", "n/a", "N/A", "无"}
"""Cells that say "nothing here" (the manuals print '-')."""


def blank(text: str) -> bool:
    return text.strip() in EMPTY


def _clean(text: str) -> str:
    return " ".join(text.replace("\u3000", " ").replace("～", "~").replace("－", "-").replace("＋", "+").split())


_HEX = re.compile(r"^(?:0[xX]([0-9A-Fa-f]+)|([0-9A-Fa-f]+)[hH])$")


def integer(text: str, what: str = "number") -> int:
    """`401`, `-32768`, `0x0191`, `0191h`, `+5`."""
    t = _clean(text)
    m = _HEX.match(t)
    if m:
        return int(m.group(1) or m.group(2), 16)
    if re.fullmatch(r"[+-]?[0-9]+", t):
        return int(t)
    raise CellProblem(f"cannot read {what} {text!r}")


def address(text: str) -> int:
    """`0x000C`, `000CH`, `12`, and the high and low bytes apart (`00 0C`)."""
    t = _clean(text)
    pair = re.fullmatch(r"([0-9A-Fa-f]{2}) ([0-9A-Fa-f]{2})", t)
    value = int(pair.group(1) + pair.group(2), 16) if pair else integer(text, "address")
    if not 0 <= value <= 0xFFFF:
        raise CellProblem(f"address {text!r} is outside 0..0xFFFF")
    return value


def address_with_o(text: str) -> tuple[int, str | None]:
    """An address, and what was corrected to read it: a letter O typed for a zero (`0x00O1`) is read as 0, and said."""
    try:
        return address(text), None
    except CellProblem:
        if "O" not in text.upper():
            raise
        fixed = re.sub("[Oo]", "0", text)
        try:
            value = address(fixed)
        except CellProblem:
            raise CellProblem(f"cannot read address {text!r}") from None
        return value, f"address {text.strip()!r} read as 0x{value:04X}: a letter O taken for a zero"


MODICON_SPACES = {0: "coil", 1: "discrete_input", 3: "input", 4: "holding"}
"""The first digit of a Modicon register number (0xxxx, 1xxxx, 3xxxx, 4xxxx and the six-digit 4xxxxx)."""


def modicon(text: str) -> tuple[str, int] | None:
    """`30001` -> (input, 0), `400001` -> (holding, 0), `00017` and `17` -> (coil, 16); None for a cell no Modicon number."""
    t = _clean(text)
    if re.fullmatch(r"[0-9]{1,4}", t) and int(t) >= 1:  # a coil's 0xxxx whose leading zeros a spreadsheet dropped
        return MODICON_SPACES[0], int(t) - 1
    if not re.fullmatch(r"[0-9]{5,6}", t):
        return None
    base = 10 ** (len(t) - 1)
    band, number = divmod(int(t), base)
    if band not in MODICON_SPACES or not 1 <= number <= min(base - 1, 0x10000):
        return None
    return MODICON_SPACES[band], number - 1


_DECIMAL = re.compile(r"^[+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)$")


def decimal(text: str, what: str = "number") -> Decimal:
    """A printed number in engineering units: `2.00`, `-500.0`, `0x01FF`; the digits after the point count."""
    t = _clean(text)
    if _HEX.match(t):
        return Decimal(integer(t, what))
    if not _DECIMAL.match(t):
        raise CellProblem(f"cannot read {what} {text!r}")
    try:
        return Decimal(t)
    except InvalidOperation:  # pragma: no cover - the pattern admits only numbers
        raise CellProblem(f"cannot read {what} {text!r}") from None


def places(value: Decimal) -> int:
    exponent = value.as_tuple().exponent
    return -exponent if isinstance(exponent, int) and exponent < 0 else 0


_RANGE = re.compile(r"^(?P<lo>[^~]+?)\s*~\s*(?P<hi>[^~]+)$")
_NUMBER = r"[+-]?(?:0[xX][0-9A-Fa-f]+|[0-9]+(?:\.[0-9]+)?)"
_RANGE_REMARK = re.compile(rf"^(?P<lo>{_NUMBER})\s*~\s*(?P<hi>{_NUMBER})(?:\s*[,，]\s*|\s+)(?P<remark>\S.*)$")  # `0~99, 对应...`
_VALUE = r"(0[xX][0-9A-Fa-f]+|[0-9]+)"
_VALUE_LIST = re.compile(rf"(?:^|\s){_VALUE}\s*[:：-]\s*(?=\S)")


@dataclass(frozen=True)
class PrintedRange:
    lo: Decimal
    hi: Decimal
    unit: str | None = None  # a unit printed inside the range (`0rpm~9000rpm`)
    listed: bool = False  # read from a list of values (`0: speed 1: position ...`), not an a~b range


def printed_range(text: str) -> PrintedRange:
    """`0~65535`, `-32768~32767`, `0.0~300.0`, `0rpm~9000rpm`, `0x0001~0x0004`; a list of values `0: ... 1: ...`."""
    t = _clean(text)
    m = _RANGE_REMARK.match(t) or _RANGE.match(t)
    if m:
        lo_text, hi_text = m.group("lo"), m.group("hi")
        lo_num, lo_unit = _number_and_unit(lo_text)
        hi_num, hi_unit = _number_and_unit(hi_text)
        if lo_num is None or hi_num is None or (lo_unit and hi_unit and lo_unit != hi_unit):
            raise CellProblem(f"cannot read range {text!r}")
        unit = lo_unit or hi_unit
        if unit is not None and unit not in UNITS:
            raise CellProblem(f"cannot read range {text!r}: unknown unit {unit!r}")
        if lo_num > hi_num:
            raise CellProblem(f"range {text!r} runs backwards")
        return PrintedRange(lo_num, hi_num, UNITS[unit] if unit else None)
    values = [int(v, 0) for v in _VALUE_LIST.findall(t)]
    if values and re.match(rf"^{_VALUE}\s*[:：-]", t) and values == sorted(set(values)):
        return PrintedRange(Decimal(values[0]), Decimal(values[-1]), listed=True)
    table = value_table(t)
    if table is not None:
        return PrintedRange(Decimal(min(v for v, _ in table)), Decimal(max(v for v, _ in table)), listed=True)
    raise CellProblem(f"cannot read range {text!r}")


_PAIR = re.compile(r"(?:^|(?<=[,;，；\s]))(0[xX][0-9A-Fa-f]+|[0-9]+)\s*[=:：]\s*")


def value_table(text: str) -> list[tuple[int, str]] | None:
    """The values a cell lists: `0 = 2400, 1 = 4800`, `0: k, 1: M`, `60, 100, 200` -> [(value, as printed)]; None for
    any other text (a range, a sentence). Two values at least, each once."""
    t = _clean(text)
    if re.fullmatch(r"[0-9]+(?:\s*[,;，；]\s*[0-9]+)+", t):
        members = [(int(v), v) for v in re.split(r"\s*[,;，；]\s*", t)]
    else:
        parts = _PAIR.split(t)
        if parts[0].strip() or len(parts) < 5:
            return None
        members = [(int(v, 0), title.strip().rstrip(",;，；").strip()) for v, title in zip(parts[1::2], parts[2::2], strict=True)]
        if any(not title for _, title in members):
            return None
    values = [v for v, _ in members]
    return members if len(set(values)) == len(values) else None


def _number_and_unit(text: str) -> tuple[Decimal | None, str | None]:
    m = re.fullmatch(r"([+-]?(?:0[xX][0-9A-Fa-f]+|[0-9]+(?:\.[0-9]*)?))\s*(\S.*)?", text.strip())
    if not m:
        return None, None
    try:
        return decimal(m.group(1)), m.group(2)
    except CellProblem:
        return None, None


UNITS: dict[str, str] = {
    **{u: u for u in ("A", "mA", "V", "mV", "kV", "W", "kW", "Ω", "Hz", "kHz", "ms", "s", "us", "μs", "ns", "min", "h", "rpm", "rps")},
    **{u: u for u in ("r", "%", "°", "°C", "P/r", "P/R", "ppr", "pulse", "bps", "Nm", "N·m", "mH", "kg·cm²")},
    **{u: u for u in ("Wh", "kWh", "MWh", "var", "kvar", "varh", "kvarh", "VA", "kVA", "mm", "m", "bar", "Pa", "kPa", "MPa")},
    "Ah": "Ah",
    "kVAh": "kVAh",
    "ohm": "Ω",
    "℃": "°C",
    "度": "°",
    "秒": "s",
    "毫秒": "ms",
    "分": "min",
    "分钟": "min",
    "倍": "times",
    "times": "times",
    "编码器单位": "encoder unit",
    "指令单位": "command unit",
    "编码器 / 指令单位": "encoder/command unit",
    "编码器/指令单位": "encoder/command unit",
    "encoder unit": "encoder unit",
    "command unit": "command unit",
    "encoder/command unit": "encoder/command unit",
}
"""Units the importer knows, as printed -> as the maps write them. Anything else is reported."""

UNIT_WORDS: dict[str, str] = {
    **{w: "V" for w in ("v", "volt", "volts")},
    **{w: "A" for w in ("a", "amp", "amps", "ampere", "amperes")},
    **{w: "W" for w in ("w", "watt", "watts")},
    **{w: "kW" for w in ("kw", "kilowatt", "kilowatts")},
    **{w: "var" for w in ("var", "vars")},
    "kvar": "kvar",
    "varh": "varh",
    "kvarh": "kvarh",
    "va": "VA",
    "kva": "kVA",
    "vah": "VAh",
    "kvah": "kVAh",
    "wh": "Wh",
    "kwh": "kWh",
    "ah": "Ah",
    "hz": "Hz",
    **{w: "°" for w in ("degree", "degrees")},
    **{w: "°C" for w in ("degrees c", "deg c", "degc")},
    **{w: "min" for w in ("minute", "minutes")},
    **{w: "s" for w in ("second", "seconds", "sec")},
    **{w: "h" for w in ("hour", "hours")},
    **{w: "%" for w in ("percent", "per cent")},
}
"""Units written out as words, or in a case the symbol does not have (VAr, KWH): compared lower-case. No
symbol whose case carries meaning (mW and MW) is here."""


def unit(text: str) -> tuple[str | None, Fraction | None]:
    """`A` -> (A, None); `0.1A` / `0.1 A` -> (A, 1/10); `25ns` -> (ns, 25); `-` -> (None, None)."""
    t = _clean(text)
    if t in EMPTY or t.lower() == "none":
        return None, None
    if t.lower() in UNIT_WORDS:
        return UNIT_WORDS[t.lower()], None
    if t in UNITS or _squash(t) in UNITS:  # cells break words across lines: 编码器 单位
        return UNITS.get(t) or UNITS[_squash(t)], None
    m = re.fullmatch(r"([0-9]+(?:\.[0-9]+)?)\s*(\S.*)", t)
    if m and m.group(2) in UNITS:
        return UNITS[m.group(2)], Fraction(m.group(1))
    raise CellProblem(f"cannot read unit {text!r}")


TAKES_EFFECT = {
    "立即生效": "immediately",
    "立即": "immediately",
    "实时生效": "immediately",
    "再次通电": "after_restart",
    "重新上电": "after_restart",
    "断电重启": "after_restart",
    "重启生效": "after_restart",
    "上电生效": "after_restart",
    "停机生效": "when_stopped",
    "immediately": "immediately",
    "immediate": "immediately",
    "after_restart": "after_restart",
    "after restart": "after_restart",
    "power cycle": "after_restart",
    "when_stopped": "when_stopped",
    "when stopped": "when_stopped",
}

SETTABLE = {
    "运行设定": "always",
    "停机设定": "when_stopped",
    "显示": "display_only",
    "always": "always",
    "when_stopped": "when_stopped",
    "display_only": "display_only",
}

ACCESS = {
    "r": "r",
    "ro": "r",
    "read": "r",
    "只读": "r",
    "rw": "rw",
    "r/w": "rw",
    "read/write": "rw",
    "read only": "r",
    "read-only": "r",
    "write only": "w",
    "write-only": "w",
    "读写": "rw",
    "w": "w",
    "wo": "w",
    "r/wp": "rw",
    "rwp": "rw",
    "write": "w",
    "只写": "w",
}

TYPES = {
    **{t: t for t in DATA_TYPES},
    "uint16": "u16",
    "int16": "s16",
    "uint32": "u32",
    "int32": "s32",
    "uint64": "u64",
    "int64": "s64",
    "word": "u16",
    "dword": "u32",
    "float16": "f16",
    "half": "f16",
    "float": "f32",
    "float32": "f32",
    "real": "f32",
    "double": "f64",
    # the width in the name, as datasheets print it
    **{f"{p}{n}": f"{k}{n}" for n in (16, 32, 64) for p, k in (("i", "s"), ("s", "s"), ("u", "u"), ("int", "s"), ("uint", "u"))},
    "f32": "f32",
    "f64": "f64",
    "float 32": "f32",
    "bitfield16": "u16",
    "bitfield32": "u32",
    "e16": "u16",
    "e32": "u32",
    "enum16": "u16",
    "enum32": "u32",
    "float64": "f64",
    "lreal": "f64",
    "str": "string",
    "text": "string",
    "ascii": "string",
    "boolean": "bool",
    "bit": "bool",
    "无符号16位": "u16",
    "有符号16位": "s16",
    "无符号32位": "u32",
    "有符号32位": "s32",
    "浮点数": "f32",
    "浮点": "f32",
    "单精度浮点": "f32",
    "双精度浮点": "f64",
    "字符串": "string",
    "布尔": "bool",
    "位": "bool",
}

TYPE_NOTES = {
    "bitfield16": "the table prints the type Bitfield16: a 16-bit field whose bits it does not list here",
    "bitfield32": "the table prints the type Bitfield32: a 32-bit field whose bits it does not list here",
    "e16": "the table prints the type E16: a 16-bit code whose values it does not list here",
    "e32": "the table prints the type E32: a 32-bit code whose values it does not list here",
    "enum16": "the table prints the type enum16: a 16-bit code whose values it does not list here",
    "enum32": "the table prints the type enum32: a 32-bit code whose values it does not list here",
}
"""Types read by their width whose meaning the map must still be told."""

WORD_ORDERS = {"high_first": "high_first", "low_first": "low_first"}

SPACES = {
    **{s: s for s in ("holding", "input", "coil", "discrete_input")},
    "holding register": "holding",
    "holding registers": "holding",
    "input register": "input",
    "input registers": "input",
    "coils": "coil",
    "discrete input": "discrete_input",
    "discrete inputs": "discrete_input",
    "4x": "holding",
    "3x": "input",
    "0x": "coil",
    "1x": "discrete_input",
    "保持寄存器": "holding",
    "输入寄存器": "input",
    "线圈": "coil",
    "线圈状态": "coil",
    "离散输入": "discrete_input",
    "输入状态": "discrete_input",
    "离散量输入": "discrete_input",
}
"""A register's Modbus table as tables print it. A read function code (03, 0x04, `03/06/10`) says it too."""

_READ_CODES = {1: "coil", 2: "discrete_input", 3: "holding", 4: "input"}
_FUNCTION_CODES = re.compile(r"^(?:0x)?0?([1-4])(?:h)?(?:\s*[/,、]\s*(?:0x)?[0-9a-f]{1,2}h?)*$", re.IGNORECASE)


def space(text: str) -> str | None:
    """`input register`, `3x`, `输入寄存器` or a read function code (`04`, `0x03/0x06/0x10`) -> a space name."""
    t = _clean(text)
    if t in EMPTY:
        return None
    m = _FUNCTION_CODES.match(t)
    if m:
        return _READ_CODES[int(m.group(1))]
    return choice(text, SPACES, "space")


BYTE_ORDERS = {
    "high_first": "high_first",
    "low_first": "low_first",
    "big endian": "high_first",
    "big-endian": "high_first",
    "little endian": "low_first",
    "little-endian": "low_first",
    "ab": "high_first",
    "ba": "low_first",
    "swapped": "low_first",
    "not swapped": "high_first",
    "高字节在前": "high_first",
    "低字节在前": "low_first",
    "高位在前": "high_first",
    "低位在前": "low_first",
}

ORDER_NAMES = {
    "abcd": ("high_first", "high_first"),
    "cdab": ("low_first", "high_first"),
    "badc": ("high_first", "low_first"),
    "dcba": ("low_first", "low_first"),
    "abcdefgh": ("high_first", "high_first"),
    "ghefcdab": ("low_first", "high_first"),
    "badcfehg": ("high_first", "low_first"),
    "hgfedcba": ("low_first", "low_first"),
}
"""The four-letter names of wide values' orders -> (word order, byte order)."""


def byte_order(text: str) -> tuple[str | None, str] | None:
    """(word order or None, byte order): `low_first` -> (None, low_first); `CDAB` -> (low_first, high_first)."""
    t = _clean(text)
    if t in EMPTY:
        return None
    named = ORDER_NAMES.get(t.lower())
    if named is not None:
        return named
    found = choice(text, BYTE_ORDERS, "byte order")
    return None if found is None else (None, found)


POLLS = {
    **{p: p for p in ("static", "fast", "normal", "slow")},
    "once": "static",
    "静态": "static",
    "一次": "static",
    "快": "fast",
    "快速": "fast",
    "普通": "normal",
    "正常": "normal",
    "慢": "slow",
    "慢速": "slow",
}

ENCODINGS = {"ascii": "ascii", "latin-1": "latin-1", "latin1": "latin-1", "iso-8859-1": "latin-1", "utf-8": "utf-8", "utf8": "utf-8"}
ENCODINGS |= {"gbk": "gbk", "gb2312": "gbk"}
PADDINGS = {"nul": "nul", "null": "nul", "\\0": "nul", "0x00": "nul", "space": "space", "空格": "space"}


def na_marks(text: str) -> list[int | float | str]:
    """ "Not available" markers as datasheets print them: `0xFFFF`, `7FFFh`, `-1`, `-1.0`, `NaN`, separated by
    commas, semicolons, slashes or `or` (`nan` stands for any NaN of a float, as in a map)."""
    marks: list[int | float | str] = []
    for part in re.split(r"\s*(?:[,;/]|\bor\b)\s*", _clean(text)):
        if not part:
            continue
        if part.lower() == "nan":
            marks.append("nan")
        elif _HEX.match(part) or re.fullmatch(r"[+-]?[0-9]+", part):
            marks.append(integer(part, "'not available' marker"))
        else:
            marks.append(float(decimal(part, "'not available' marker")))
    if not marks:
        raise CellProblem(f"cannot read 'not available' markers {text!r}")
    return marks


def variant_names(text: str) -> list[str]:
    """The variants a register is on, as datasheets print them (`Three-phase`, `X1-4 / X1-6`, `A and B`): each
    made a snake_case name (`three_phase`, `x1_4`) by lowering it and joining its words with `_`."""
    names: list[str] = []
    for part in re.split(r"\s*(?:[,;/、，]|\band\b)\s*", _clean(text)):
        if not part:
            continue
        name = re.sub(r"[^a-z0-9]+", "_", part.lower()).strip("_")
        if not _IDENT.match(name):
            raise CellProblem(f"cannot read variant {part!r}: it makes no snake_case name (letters first)")
        if name not in names:
            names.append(name)
    if not names:
        raise CellProblem(f"cannot read variants {text!r}")
    return names


def version(text: str) -> str:
    """A firmware version: digits and dots (`2.10`, `V2.1` -> `2.1`)."""
    t = _clean(text)
    if t[:1] in ("v", "V"):
        t = t[1:]
    if not re.fullmatch(r"[0-9]+(?:\.[0-9]+)*", t):
        raise CellProblem(f"cannot read firmware version {text!r} (expected digits and dots, as 2.10)")
    return t


def _squash(text: str) -> str:
    """Table cells break words across lines (`停机 生效`): compare without spaces."""
    return "".join(_clean(text).split())


def choice(text: str, table: dict[str, str], what: str) -> str | None:
    t = _clean(text)
    if t in EMPTY:
        return None
    for key in (t, t.lower(), _squash(t)):
        if key in table:
            return table[key]
    raise CellProblem(f"cannot read {what} {text!r}")


def modes(text: str) -> list[str]:
    """`PST`, `PS`, `ALL`, `P, S`, `-` -> a subset of [P, S, T] in that order."""
    t = _squash(text).upper().replace(",", "")
    if t in {"", "-", "--", "—"}:
        return []
    if t == "ALL":
        return ["P", "S", "T"]
    if not t or any(c not in "PST" for c in t) or len(set(t)) != len(t):
        raise CellProblem(f"cannot read modes {text!r}")
    return [m for m in "PST" if m in t]


def boolean(text: str, what: str) -> bool | None:
    t = _clean(text).lower()
    if t in EMPTY:
        return None
    if t in {"true", "yes", "y", "1", "是"}:
        return True
    if t in {"false", "no", "n", "0", "否"}:
        return False
    raise CellProblem(f"cannot read {what} {text!r}")


def text_list(text: str) -> list[str]:
    """`7.3, 6.2.2` or one item per line."""
    t = text.strip()
    if t in EMPTY:
        return []
    return [p.strip() for p in re.split(r"[,\n;，；]", t) if p.strip()]


_IDENT = re.compile(r"^[a-z][a-z0-9_]*$")


def identifier(text: str, what: str) -> str:
    t = text.strip()
    if not _IDENT.match(t):
        raise CellProblem(f"cannot read {what} {text!r}: not a snake_case identifier")
    return t


_BITFIELD = re.compile(
    r"^(?P<bits>[0-9]+(?:-[0-9]+)?)\s+(?P<name>[a-z][a-z0-9_]*)(?:\s+<(?P<enum>[a-z][a-z0-9_]*)>)?(?::\s*(?P<title>.*))?$"
)


def bitfields(text: str) -> list[dict[str, object]]:
    """The export's readable form, one field per line: `8-10 function <di_function>: DI function`."""
    out: list[dict[str, object]] = []
    for line in text.splitlines():
        line = line.strip()
        if not line:
            continue
        m = _BITFIELD.match(line)
        if not m:
            raise CellProblem(f"cannot read bitfield {line!r} (expected 'BITS NAME [<ENUM>]: TITLE')")
        bits: object = int(m.group("bits")) if "-" not in m.group("bits") else m.group("bits")
        field: dict[str, object] = {"name": m.group("name"), "bits": bits, "title": (m.group("title") or "").strip() or m.group("name")}
        if m.group("enum"):
            field["enum"] = m.group("enum")
        out.append(field)
    return out


def raw_from(value: Decimal, scale: Fraction, what: str, text: str, offset: Fraction = Fraction(0)) -> int:
    """Engineering value -> raw integer, (value - offset) / scale; refuses a value that is not a whole number of steps."""
    raw = (Fraction(value) - offset) / scale
    if raw.denominator != 1:
        raise CellProblem(f"{what} {text!r} is not a whole number of steps of {float(scale):g}")
    return int(raw)
