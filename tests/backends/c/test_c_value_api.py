"""The C headers' value helpers (<name>_is_in_range, _encode, _decode, the enum tests and the bitfield
setters), compiled and run: gcc and clang, C99 and C++17, -Wall -Wextra -Wpedantic -Werror, and once
under AddressSanitizer and UndefinedBehaviorSanitizer.

The test program is generated here from the model and the Python runtime, never from the header:
every value a write may take and every edge (min, max, one step beyond each, half a step off the
resolution, NaN, a member the device only reports, a value the enum lacks, a field value wider than
the field), each example value of the map, both word orders of a register whose order follows the
device's word-order register. The expected words and values come from the runtime's codec
(`value_to_raw`, `raw_to_words`, `raw_to_value`) and the model (`EnumMember.writable`), so a header
that agrees with itself but not with the map or the wire fails here.
"""

from __future__ import annotations

import functools
import math
import os
import subprocess
import time
from collections.abc import Iterator
from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path
from typing import Any

import pytest

from regmap.backends.c.names import C_TYPES, CIdentifier, Context, CSymbol, c_float_literal, c_hex, c_raw
from regmap.backends.c.values import ValueView, configurable, value_view
from regmap.frontend import load_map
from regmap.generate import render
from regmap.model import Device, Register
from regmap.runtime_bridge import runtime_specs
from regmap_runtime.codec import RangeError, raw_to_value, raw_to_words, value_to_raw
from regmap_runtime.spec import HIGH_FIRST, LOW_FIRST, RegisterSpec
from regmap_runtime.types import swap_bytes

from conftest import FIXTURE_MAPS, MAPS, require_tool

ALL = [*MAPS, *FIXTURE_MAPS]
FLAGS = ("-Wall", "-Wextra", "-Wpedantic", "-Werror")
COMPILERS = {
    "gcc-c99": ("gcc", "-std=c99", "-O1", *FLAGS),
    "clang-c99": ("clang", "-std=c99", "-O1", *FLAGS),
    "g++-c++17": ("g++", "-x", "c++", "-std=c++17", "-O1", *FLAGS),
    "clang++-c++17": ("clang++", "-x", "c++", "-std=c++17", "-O1", *FLAGS),
    "clang-c99-sanitizers": ("clang", "-std=c99", "-g", "-fsanitize=address,undefined", "-fno-sanitize-recover=all", *FLAGS),
}
ORDERS = {HIGH_FIRST: "REGMAP_HIGH_FIRST", LOW_FIRST: "REGMAP_LOW_FIRST"}

PROLOGUE = """\
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "{header}"

static unsigned checks, failures;

static void expect(bool ok, int line, const char *what)
{{
    ++checks;
    if (!ok) {{
        ++failures;
        printf("FAIL line %d: %s\\n", line, what);
    }}
}}
#define EXPECT(cond) expect((cond), __LINE__, #cond)

static bool same(const uint16_t *got, const uint16_t *want, size_t count)
{{
    return memcmp(got, want, count * sizeof *got) == 0;
}}

/* Words the helpers must leave as they are when they refuse a value. */
static void fill(uint16_t *words, size_t count)
{{
    size_t i;
    for (i = 0u; i < count; ++i) {{
        words[i] = 0xA5A5u;
    }}
}}

static bool untouched(const uint16_t *words, size_t count)
{{
    size_t i;
    for (i = 0u; i < count; ++i) {{
        if (words[i] != 0xA5A5u) {{
            return false;
        }}
    }}
    return true;
}}

int main(void)
{{
    (void)same;
    (void)fill;
    (void)untouched;
"""

EPILOGUE = """\
    printf("%u checks, %u failures\\n", checks, failures);
    return failures == 0u ? 0 : 1;
}
"""


@functools.cache
def _device(path: Path) -> Device:
    return load_map(path)


@functools.cache
def _specs(path: Path) -> dict[str, RegisterSpec[Any]]:
    return {s.name: s for s in runtime_specs(_device(path))}


@dataclass(frozen=True)
class Accepted:
    value: str  # C expression of the engineering value _encode takes
    raw: int | float
    decoded: str  # C expression of the value _decode gives


def _owners(device: Device) -> Iterator[tuple[str, Register]]:
    """(the name the helpers carry, a register with that range): a register, an array member whose elements share
    their range, or each element of one whose elements differ."""
    done: set[str] = set()
    for reg in device.registers:
        if reg.array is None:
            yield reg.name, reg
            continue
        owner = f"{reg.array.array}_{reg.array.member}"
        if owner in done:
            continue
        done.add(owner)
        elements = [r for r in device.registers if r.array and (r.array.array, r.array.member) == (reg.array.array, reg.array.member)]
        if len({(r.raw_min, r.raw_max) for r in elements}) == 1:
            yield owner, reg
        else:
            yield from ((r.name, r) for r in elements)


def _same_owner(a: Register, b: Register) -> bool:
    """The same register, or elements of one array member (whose helpers are the member's when they share their range)."""
    if a.array is None or b.array is None:
        return a.name == b.name
    return (a.array.array, a.array.member) == (b.array.array, b.array.member) and (a.raw_min, a.raw_max) == (b.raw_min, b.raw_max)


def _writable_raw(reg: Register, spec: RegisterSpec[Any], value: Any) -> int | float | None:
    """The raw value a write of `value` sends, or None where it must be refused: what the runtime refuses,
    and (from the model) a member of the register's or a field's enum that the device only reports."""
    try:
        raw = value_to_raw(spec, value)
    except RangeError:
        return None
    assert not isinstance(raw, str)
    if reg.bitfields:
        for b in reg.bitfields:
            member = b.enum.by_value((int(raw) & b.mask) >> b.lsb) if b.enum else None
            if member is not None and not member.writable:
                return None
    elif reg.enum is not None:
        member = reg.enum.by_value(int(raw))
        if member is None or not member.writable:
            return None
    return raw


def _nan_words(spec: RegisterSpec[Any]) -> list[int]:
    """A quiet NaN's words on the wire (the codec refuses to encode NaN: it is no value)."""
    words = list(spec.type_info.to_words(math.nan))
    if spec.byte_order != HIGH_FIRST:
        words = swap_bytes(words)
    return words[::-1] if spec.word_order != HIGH_FIRST else words


def _scaled(reg: Register) -> bool:
    return reg.scale != 1 or reg.offset_set


def _eng(spec: RegisterSpec[Any], raw: int | float) -> float:
    return float(raw_to_value(spec, raw))


def _double(value: float) -> str:
    if math.isnan(value):
        return "NAN"
    if math.isinf(value):
        return "INFINITY" if value > 0 else "(-INFINITY)"
    text = repr(value)
    return f"({text})" if text.startswith("-") else text


class _Program:
    def __init__(self, path: Path) -> None:
        self.path = path
        self.device = _device(path)
        self.ctx = Context(self.device)
        self.specs = _specs(path)
        self.lines: list[str] = []

    def enum_constant(self, reg: Register, raw: int) -> str | None:
        member = reg.enum.by_value(raw) if reg.enum else None
        return CIdentifier(self.device.id, reg.enum.name, member.name) if reg.enum and member else None

    def as_value(self, reg: Register, spec: RegisterSpec[Any], raw: int | float) -> str:
        """The C expression of the value the helpers take for `raw`: an enum constant, a double, a float or an integer."""
        if reg.bitfields:
            return c_hex(int(raw) & ((1 << (16 * reg.words)) - 1))
        constant = self.enum_constant(reg, int(raw)) if reg.enum else None
        if constant is not None:
            return constant
        if reg.type.is_float and not _scaled(reg):
            return c_float_literal(float(raw), reg.type)
        if _scaled(reg):
            return _double(_eng(spec, raw))
        return c_raw(int(raw), reg.signed)

    def accepted(self, reg: Register, spec: RegisterSpec[Any], raw: int | float) -> Accepted | None:
        """The case of a raw value a write may send, with the engineering value that gives it (checked by the runtime)."""
        if reg.enum is not None and not reg.bitfields:
            member = reg.enum.by_value(int(raw))
            if member is None:
                return None
            value: Any = member.name
        elif reg.bitfields or not _scaled(reg):
            value = raw
        else:
            value = _eng(spec, raw)
        if _writable_raw(reg, spec, value) != raw:
            return None
        return Accepted(self.as_value(reg, spec, raw), raw, self.as_value(reg, spec, raw))

    def refused_values(self, reg: Register, spec: RegisterSpec[Any]) -> Iterator[tuple[str, str]]:
        """(C value, why) of values _encode must refuse; the runtime and the model agree that each is refused."""
        lo, hi = reg.raw_min, reg.raw_max
        if reg.enum is not None and not reg.bitfields:
            yield from self.refused_members(reg, spec)
            return
        if reg.bitfields:
            yield from self.refused_words(reg, spec)
            return
        if reg.type.is_float:
            candidates: list[tuple[float, str]] = [(math.nan, "NaN"), (math.inf, "infinity")]
            if _scaled(reg):
                candidates += [(_eng(spec, lo) - 1.0, "below min"), (_eng(spec, hi) + 1.0, "above max")]
            for value, why in candidates:
                if value_refused(spec, value):
                    literal = _double(value) if _scaled(reg) or reg.type.words == 4 else f"(float){_double(value)}"
                    yield literal, why
            return
        if _scaled(reg):
            step = float(reg.scale)
            half = float(Fraction(int(lo)) * reg.scale + reg.offset + reg.scale / 2)
            for value, why in (
                (_eng(spec, lo) - abs(step), "min - 1 step"),
                (_eng(spec, hi) + abs(step), "max + 1 step"),
                (half, "half a step off the resolution"),
                (math.nan, "NaN"),
            ):
                if value_refused(spec, value) and (why != "half a step off the resolution" or hi > lo):
                    yield _double(value), why
            return
        if lo > reg.type.raw_min:
            assert value_refused(spec, int(lo) - 1)
            yield c_raw(int(lo) - 1, reg.signed), "min - 1"
        if hi < reg.type.raw_max:
            assert value_refused(spec, int(hi) + 1)
            yield c_raw(int(hi) + 1, reg.signed), "max + 1"

    def refused_members(self, reg: Register, spec: RegisterSpec[Any]) -> Iterator[tuple[str, str]]:
        e = reg.enum
        assert e is not None
        type_name = CSymbol(self.device.id, e.name)
        for m in e.members:
            constant = CIdentifier(self.device.id, e.name, m.name)
            if not m.writable:
                yield constant, f"{m.name}: a state the device only reports"
            elif _writable_raw(reg, spec, m.name) is None:
                yield constant, f"{m.name}: outside the register's range"
        values = {m.value for m in e.members}
        top = max(values)
        if min(values) >= 0 and top < 1 << 31:
            # A value the enum lacks inside the values its C++ type holds (all bits of its largest member).
            gaps = [v for v in range(0, 1 << top.bit_length()) if v not in values][:2]
            yield from ((f"({type_name}){v}", f"{v}: not a member") for v in gaps)

    def refused_words(self, reg: Register, spec: RegisterSpec[Any]) -> Iterator[tuple[str, str]]:
        """A bitfield register's words with one field set to a value its enum lacks or only reports."""
        base = int(reg.default) if isinstance(reg.default, int) else 0
        for b in reg.bitfields:
            if b.enum is None:
                continue
            for v in range(b.max_value + 1):
                member = b.enum.by_value(v)
                if member is not None and member.writable:
                    continue
                word = (base & ~b.mask) | (v << b.lsb)
                if _writable_raw(reg, spec, word) is None:
                    yield c_hex(word), f"{b.name} = {v}: {'a state the device only reports' if member else 'not a member'}"
                    break

    def raws(self, reg: Register, spec: RegisterSpec[Any]) -> list[int | float]:
        """The raw values every register is tried with: its min, max, default, every enum member, the examples' values."""
        values: list[int | float] = []
        for raw in (reg.raw_min, reg.raw_max, reg.default):
            if isinstance(raw, int | float) and not isinstance(raw, bool) and math.isfinite(raw):
                values.append(raw)
        if reg.enum is not None and not reg.bitfields:
            values += [m.value for m in reg.enum.members]
        for ex in self.device.examples:
            for v in ex.values:
                if _same_owner(v.register, reg) and isinstance(v.raw, int | float) and not isinstance(v.raw, bool):
                    values.append(v.raw)
        values += [*reg.na, *([math.nan] if reg.na_nan else [])]
        return list(dict.fromkeys(values))

    def not_available(self, view: ValueView, reg: Register, spec: RegisterSpec[Any], raw: int | float, words: str, arg: str) -> list[str]:
        """The device's "not available" marker: _is_available and _decode say no (the output untouched), and
        a write refuses it as a value."""
        lines = [f"        {{ static const uint16_t marker[] = {{ {words} }}; /* raw {raw!r}: not available */"]
        if view.decode:
            lines += [
                "            unsigned char kept[sizeof out];",
                "            memset(&out, 0x5A, sizeof out); memcpy(kept, &out, sizeof out);",
                f"            EXPECT(!{view.available}(marker{arg}));",
                f"            EXPECT(!{view.decode}(marker{arg}, &out) && memcmp(&out, kept, sizeof out) == 0);",
            ]
        if view.encode and raw == raw:
            value = self.as_value(reg, spec, raw)
            lines += [
                f"            EXPECT(!{view.in_range}({value}));",
                f"            fill(got, {reg.words}u); EXPECT(!{view.encode}({value}{arg}, got) && untouched(got, {reg.words}u));",
            ]
        return [*lines, "        }"]

    def orders(self, reg: Register) -> list[str]:
        return list(ORDERS) if configurable(self.ctx, reg) else [""]

    def add(self, label: str, reg: Register) -> int:
        view = value_view(self.ctx, reg, label)
        if view is None:
            return 0
        spec = self.specs[reg.name]
        before = len(self.lines)
        lines = self.lines
        if view.guard:
            lines.append(f"#if {view.guard}")
        for order in self.orders(reg):
            ordered = spec.in_word_order(order or None)
            arg = f", {ORDERS[order]}" if order else ""
            lines.append(f"    {{ /* {label}{f' ({order})' if order else ''} */")
            lines.append(f"        uint16_t got[{reg.words}];")
            lines.append(f"        {view.value_type} out;")
            lines.append("        memset(got, 0, sizeof got); memset(&out, 0, sizeof out);")
            for raw in self.raws(reg, spec):
                words = ", ".join(c_hex(w) for w in (raw_to_words(ordered, raw) if raw == raw else _nan_words(ordered)))
                if spec.is_na(raw):
                    lines += self.not_available(view, reg, spec, raw, words, arg)
                    continue
                case = self.accepted(reg, spec, raw) if view.encode else None
                if case is not None:
                    lines.append(f"        {{ static const uint16_t want[] = {{ {words} }}; /* raw {raw!r} */")
                    lines.append(f"            EXPECT({view.in_range}({case.value}));")
                    lines.append(
                        f"            fill(got, {reg.words}u); EXPECT({view.encode}({case.value}{arg}, got) && same(got, want, {reg.words}u));"
                    )
                    if view.decode:
                        lines.append(f"            EXPECT({view.decode}(want{arg}, &out) && out == {case.decoded});")
                    lines.append("        }")
                elif view.decode and (reg.enum is None or reg.bitfields or self.enum_constant(reg, int(raw))):
                    lines.append(f"        {{ static const uint16_t want[] = {{ {words} }}; /* raw {raw!r}, read only */")
                    lines.append(f"            EXPECT({view.decode}(want{arg}, &out) && out == {self.as_value(reg, spec, raw)});")
                    lines.append("        }")
            if view.encode:
                for value, why in self.refused_values(reg, spec):
                    lines.append(f"        /* refused: {why} */")
                    lines.append(f"        EXPECT(!{view.in_range}({value}));")
                    lines.append(
                        f"        fill(got, {reg.words}u); EXPECT(!{view.encode}({value}{arg}, got) && untouched(got, {reg.words}u));"
                    )
            if view.decode and reg.enum is not None and reg.type.is_float:
                half = min(m.value for m in reg.enum.members) + 0.5  # a setting coded as a float: no member is 0.5 off
                words = ", ".join(c_hex(w) for w in raw_to_words(ordered, half))
                lines.append(f"        {{ static const uint16_t half[] = {{ {words} }}; /* {half}: no member */")
                lines.append(f"            EXPECT(!{view.decode}(half{arg}, &out));")
                lines.append("        }")
            if view.decode and reg.enum is not None and not reg.bitfields:
                lacking = next((v for v in range(0, 0x10000) if reg.enum.by_value(v) is None and v <= reg.type.raw_max), None)
                if lacking is not None:
                    words = ", ".join(c_hex(w) for w in raw_to_words(ordered, lacking))
                    lines.append(f"        {{ static const uint16_t lacking[] = {{ {words} }}; /* {lacking}: not a member */")
                    lines.append("            unsigned char kept[sizeof out];")
                    lines.append("            memset(&out, 0x5A, sizeof out); memcpy(kept, &out, sizeof out);")
                    lines.append(f"            EXPECT(!{view.decode}(lacking{arg}, &out) && memcmp(&out, kept, sizeof out) == 0);")
                    lines.append("        }")
            lines.append("    }")
        if view.guard:
            lines.append("#endif")
        return len(self.lines) - before

    def setters(self) -> None:
        """Each setter refuses a value wider than its field, or one its enum lacks (false, the word unchanged); in C,
        where an int converts to the enum parameter (C++ does not compile that call)."""
        self.lines.append("#ifndef __cplusplus")
        done: set[str] = set()
        for reg in self.device.registers:
            owner = self.ctx.owner(reg)
            if not reg.bitfields or owner in done:
                continue
            done.add(owner)
            for b in reg.bitfields:
                setter = CSymbol(self.device.id, owner, "set", b.name)
                word_type = C_TYPES[reg.type].bits
                for value in [b.max_value + 1] if b.width < 16 * reg.words else []:
                    cast = f"({CSymbol(self.device.id, b.enum.name)})" if b.enum else ""
                    self.lines.append(f"    {{ {word_type} w = 0x1234u; EXPECT(!{setter}(&w, {cast}{c_hex(value)}) && w == 0x1234u); }}")
        self.lines.append("#endif")

    def source(self) -> str:
        for label, reg in _owners(self.device):
            self.add(label, reg)
        self.setters()
        return PROLOGUE.format(header=f"{self.device.id}.h") + "\n".join(self.lines) + "\n" + EPILOGUE


def value_refused(spec: RegisterSpec[Any], value: float | int) -> bool:
    try:
        value_to_raw(spec, value)
    except RangeError:
        return True
    return False


@pytest.fixture(scope="module")
def headers(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The headers as `regmap generate --target c` writes them now."""
    out = tmp_path_factory.mktemp("c-values")
    for rel, text in render([_device(p) for p in ALL], ["c"])["c"].items():
        (out / rel).write_text(text, encoding="utf-8")
    return out


def _build_and_run(compiler: str, source: Path, headers: Path, tmp_path: Path) -> subprocess.CompletedProcess[str]:
    tool, *flags = COMPILERS[compiler]
    binary = tmp_path / f"{source.stem}-{compiler}"
    built = subprocess.run(
        [require_tool(tool), *flags, "-I", str(headers), str(source), "-o", str(binary)], capture_output=True, text=True, check=False
    )
    assert built.returncode == 0 and not built.stderr.strip(), f"{compiler}:\n{built.stderr[-4000:]}"
    env = {**os.environ, "ASAN_OPTIONS": "detect_leaks=0"}
    return subprocess.run([str(binary)], capture_output=True, text=True, check=False, timeout=120, env=env)


@pytest.mark.parametrize("compiler", COMPILERS)
@pytest.mark.parametrize("map_path", ALL, ids=lambda p: p.stem)
def test_value_helpers_on_every_edge(map_path: Path, compiler: str, headers: Path, tmp_path: Path) -> None:
    started = time.monotonic()
    source = tmp_path / f"{_device(map_path).id}_values.c"
    source.write_text(_Program(map_path).source(), encoding="utf-8")
    run = _build_and_run(compiler, source, headers, tmp_path)
    assert run.returncode == 0, run.stdout[-4000:] + run.stderr[-4000:]
    checks = int(run.stdout.strip().splitlines()[-1].split()[0])
    assert checks > 20, run.stdout
    print(f"{map_path.stem} {compiler}: {checks} checks in {time.monotonic() - started:.1f} s")


def test_the_program_covers_what_the_brief_names() -> None:
    """The cases that must be there: pr_trigger's done_path_5 (reported only) refused and start_path_5 accepted,
    a too-wide field, both word orders of a 32-bit register that follows the C630S word-order parameter, every example."""
    idm = next(p for p in MAPS if p.stem == "idm_rs")
    source = _Program(idm).source()
    assert "EXPECT(!idm_rs_pr_trigger_is_in_range(IDM_RS_PR_TRIGGER_DONE_PATH_5));" in source
    assert "EXPECT(idm_rs_pr_trigger_is_in_range(IDM_RS_PR_TRIGGER_START_PATH_5));" in source
    assert "EXPECT(!idm_rs_di1_function_set_function(&w, (idm_rs_di_function)0x0080u) && w == 0x1234u);" in source
    c630s_path = next(p for p in MAPS if p.stem == "c630s")
    c630s, ctx = _Program(c630s_path).source(), Context(_device(c630s_path))
    following = [label for label, reg in _owners(_device(c630s_path)) if configurable(ctx, reg) and reg.access.writable]
    assert following, "no C630S register follows the word-order parameter"
    for label in following:
        for order in ORDERS.values():
            assert f"{CSymbol('c630s', label, 'encode')}(" in c630s and f"{order}, got) && same(" in c630s, (label, order)
    for path in ALL:
        device = _device(path)
        text = _Program(path).source()
        for ex in device.examples:
            for v in ex.values:
                reg = v.register
                if isinstance(v.raw, int) and reg.type.numeric and not reg.type.is_bool:
                    assert f"/* raw {v.raw!r}" in text, f"{device.id}: example {ex.id} {reg.name} = {v.raw} has no case"


@pytest.mark.parametrize("map_path", ALL, ids=lambda p: p.stem)
def test_a_read_only_register_has_no_encoder(map_path: Path, headers: Path) -> None:
    """A register a write cannot reach has no _encode or _is_in_range (a call to one does not compile); one a read
    cannot reach has no _decode; every other numeric register has each helper its access allows."""
    device = _device(map_path)
    header = (headers / f"{device.id}.h").read_text(encoding="utf-8")
    for label, reg in _owners(device):
        if not reg.type.numeric or reg.type.is_bool:
            continue
        for suffix, present in (("encode", reg.access.writable), ("is_in_range", reg.access.writable), ("decode", reg.access.readable)):
            name = CSymbol(device.id, label, suffix)
            assert (f" {name}(" in header) == present, f"{name}: access {reg.access.value}"


def test_cpp_refuses_an_int_where_a_setter_takes_its_enum(headers: Path, tmp_path: Path) -> None:
    """In C++ the enum parameter is a type: `_set_function(&raw, 0x80)` does not compile (in C it compiles and is refused)."""
    source = tmp_path / "wide.cpp"
    source.write_text(
        '#include "idm_rs.h"\nbool f(uint16_t *raw) { return idm_rs_di1_function_set_function(raw, 0x80); }\n', encoding="utf-8"
    )
    built = subprocess.run(
        [require_tool("g++"), "-std=c++17", "-c", "-I", str(headers), str(source), "-o", str(tmp_path / "wide.o")],
        capture_output=True,
        text=True,
        check=False,
    )
    assert built.returncode != 0 and "idm_rs_di_function" in built.stderr, built.stderr


@pytest.mark.parametrize("map_path", ALL, ids=lambda p: p.stem)
def test_ratio_literals_share_the_raw_values_signedness(map_path: Path, headers: Path, tmp_path: Path) -> None:
    """_SCALE_NUM/_DEN and _OFFSET_NUM/_DEN are `u` literals beside an unsigned raw value and signed beside a signed one
    (MISRA C:2012 10.4): `raw * NUM / DEN` in the raw value's own type compiles under -Wsign-conversion and
    gives the Python client's value for the register's extreme raw values."""
    device = _device(map_path)
    lines = [f'#include "{device.id}.h"', "#include <stdio.h>", "int main(void)", "{", "    int failures = 0;"]
    for label, reg in _owners(device):
        if not reg.type.numeric or reg.type.is_float or reg.type.is_bool or reg.array is not None:
            continue
        prefix = CIdentifier(device.id, label)
        c_type = C_TYPES[reg.type].value
        for raw in (reg.raw_min, reg.raw_max):
            if abs(int(raw) * reg.scale.numerator) >= 1 << 62:
                continue
            want = Fraction(int(raw)) * reg.scale
            if want.denominator != 1 or (not reg.signed and want < 0):
                continue  # a division that truncates: C's and Python's differ by design
            lines.append(
                f"    if (({c_type})({c_raw(int(raw), reg.signed)}) * {prefix}_SCALE_NUM / {prefix}_SCALE_DEN != ({c_type}){c_raw(int(want), reg.signed)}) {{"
                f' ++failures; printf("{label} {raw}\\n"); }}'
            )
    lines += ["    return failures == 0 ? 0 : 1;", "}"]
    source = tmp_path / "ratios.c"
    source.write_text("\n".join(lines) + "\n", encoding="utf-8")
    binary = tmp_path / "ratios"
    built = subprocess.run(
        [
            require_tool("gcc"),
            "-std=c99",
            *FLAGS,
            "-Wconversion",
            "-Wsign-conversion",
            "-Wsign-compare",
            "-I",
            str(headers),
            str(source),
            "-o",
            str(binary),
        ],
        capture_output=True,
        text=True,
        check=False,
    )
    assert built.returncode == 0, built.stderr[-3000:]
    run = subprocess.run([str(binary)], capture_output=True, text=True, check=False, timeout=60)
    assert run.returncode == 0, run.stdout
    header = (headers / f"{device.id}.h").read_text(encoding="utf-8")
    for reg in device.registers:
        if reg.array is not None or not reg.type.numeric or reg.type.is_bool:
            continue
        for macro in ("SCALE_NUM", "SCALE_DEN"):
            name = CIdentifier(device.id, reg.name, macro)
            line = next(x for x in header.splitlines() if x.startswith(f"#define {name} "))
            assert line.endswith("u") == (not reg.signed and reg.scale > 0), line
