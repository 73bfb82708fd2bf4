"""The generated plain-standard ST, run: matiec compiles it to C, gcc builds it with a driver
(tests/support/st_exec.py) that calls the decoders and encoders, and every answer equals the Python
runtime's, which the test computes (regmap_runtime.codec through core.decoding; nothing typed in).

Cases, per map (seed and fixture maps):
- every example frame the map carries (the manuals' golden frames): a read response's words decoded by
  the read block(s) they fall in; a write request's registers decoded, and their values encoded back
  into the frame's words;
- per read block: every register at its raw minimum, at its maximum, with 16#8000 in each word, with a
  pattern of distinct words (the word order), in the other word order where the device's is a
  parameter, and each enum member (and a value no member has);
- per encoder: the minimum, the maximum, one past each (refused), 16#8000, half a step (refused), the
  other word order, every enum member (a state the device only reports refused), text too long.

A refused value returns FALSE and leaves the output words as they were. Without matiec or gcc the test
skips (CI=true: fails).
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from fractions import Fraction
from pathlib import Path
from typing import Any

import pytest

from regmap.backends.st.functions import Block
from regmap.backends.st.names import StIdentifier
from regmap.backends.st.view_types import FunctionView
from regmap.backends.st.views import configurable, owner
from regmap.core.decoding import DecodedValue, decode_words
from regmap.frontend import load_map
from regmap.model import Register
from regmap_runtime.codec import RangeError, raw_to_value, raw_to_words, value_to_raw
from regmap_runtime.spaces import COIL_ON
from regmap_runtime.spec import HIGH_FIRST, LOW_FIRST, RegisterSpec

from conftest import FIXTURE_MAPS, MAPS, ROOT
from support.st_exec import SENTINEL, Decode, Encode, Result, StProgram
from support.st_matiec import matiec_and_gcc
from support.st_values import block_words as _block_words
from support.st_values import compare_value as _compare
from support.st_values import edge_words as _edge
from support.st_values import example_data as _example_data
from support.st_values import order_flag as _order_flag
from support.st_values import register_spec as _spec
from support.st_values import value_members as _members

Case = Decode | Encode


@pytest.fixture(scope="session")
def matiec() -> Path:
    return matiec_and_gcc()


# -- the decoders --------------------------------------------------------------------------------


class Decodes:
    """Decode cases of one device, each with the Python runtime's reading of its words."""

    def __init__(self, program: StProgram) -> None:
        self.program = program
        self.device = program.device
        self.cases: list[Decode] = []
        self.expected: dict[str, tuple[list[DecodedValue], bool]] = {}  # id -> the Python values, whether the whole block

    def add(self, case_id: str, block: Block, words: list[int], covered: set[str], high_word_first: bool | None) -> None:
        """`high_word_first`: the device's word-order parameter for the case (None: its default)."""
        takes_order = any(m.name == "bHighWordFirst" for m in block.decode.inputs)
        flag = _order_flag(self.device, high_word_first) if takes_order else None
        order = None if flag is None else (HIGH_FIRST if flag else LOW_FIRST)
        values = decode_words(self.device, block.address, words, space=block.space, word_order=order)
        values = [v for v in values if v.register in covered and v.raw is not None]  # not a pair's unused high word
        members = tuple(m for v in values for m in _members(self.device.register(str(v.register))))
        self.cases.append(Decode(case_id, block, tuple(words), members, flag))
        self.expected[case_id] = (values, covered == {r.name for r in block.registers})

    def block_edges(self, index: int, block: Block) -> None:
        """Every register of the block at once: minimum, maximum, 16#8000, a pattern, each enum member."""
        specs = {r.name: _spec(self.device, r) for r in block.registers}
        fills = {kind: _edge(specs, kind) for kind in ("min", "max", "w8000", "infinity", "nan", "na", "half")}
        fills["pattern"] = {}  # every word of the pattern
        enum_counts = [len(r.enum.members) + 1 for r in block.registers if r.enum is not None and not r.bitfields]
        for k in range(max(enum_counts, default=0)):
            fills[f"member{k}"] = _edge(specs, f"member{k}")
        names = {r.name for r in block.registers}
        for kind, by_register in fills.items():
            if not by_register and kind != "pattern":  # no register of the block has this edge (a float's infinity, an enum's member)
                continue
            words = _block_words(block, by_register)
            self.add(f"d{index}_{kind}", block, words, names, None)
            if kind == "pattern" and any(configurable(self.device, r) for r in block.registers):
                self.add(f"d{index}_pattern_low_first", block, words, names, False)

    def check(self, results: dict[str, Result]) -> tuple[int, list[str]]:
        compared = 0
        problems: list[str] = []
        for case in self.cases:
            values, whole = self.expected[case.id]
            got = results[case.id]
            all_valid = True
            for value in values:
                reg = self.device.register(str(value.register))
                valid, wrong = _compare(reg, value, got.values, self.program.value_types[StIdentifier(reg.name)])
                all_valid &= valid
                compared += 1
                problems += [f"{self.device.id} {case.id} {reg.name}: {w}" for w in wrong]
            if whole and got.ok != all_valid:
                problems.append(
                    f"{self.device.id} {case.id}: the decoder returned {got.ok}, the Python client reads every value: {all_valid}"
                )
        return compared, problems


# -- the encoders --------------------------------------------------------------------------------


class Encodes:
    """Encode cases of one device, each with the Python runtime's answer (words, or refused: None)."""

    def __init__(self, program: StProgram) -> None:
        self.program = program
        self.device = program.device
        self.cases: list[Encode] = []
        self.expected: dict[str, tuple[int, ...] | None] = {}

    def encoder(self, reg: Register) -> FunctionView | None:
        for label in (owner(reg), reg.name):
            function = self.program.functions.get(StIdentifier("F", self.device.id, "ENCODE", label))
            if function is not None:
                return function
        return None

    def add(self, case_id: str, reg: Register, value: Any, high_word_first: bool | None = None) -> None:
        """`value`: the engineering value as the Python client takes it (an enum member by name)."""
        function = self.encoder(reg)
        assert function is not None, reg.name
        takes_order = any(m.name == "bHighWordFirst" for m in function.inputs)
        if high_word_first is not None and not takes_order:
            return
        flag = _order_flag(self.device, high_word_first) if takes_order else None
        spec = _spec(self.device, reg)
        if flag is not None:
            spec = spec.in_word_order(HIGH_FIRST if flag else LOW_FIRST)
        st_value = _st_input(reg, value)
        if st_value is None:
            return
        output = function.in_outs[0].type
        words = 1 if output == "WORD" else int(output.split("..")[1].split("]")[0]) + 1
        self.cases.append(Encode(case_id, function, st_value, words, flag))
        self.expected[case_id] = _python_words(reg, spec, value)

    def edges(self) -> None:
        seen: set[str] = set()
        for reg in self.device.registers:
            function = self.encoder(reg) if reg.access.writable else None
            if function is None or function.name in seen:
                continue
            seen.add(function.name)
            spec = _spec(self.device, reg)
            for kind, value in _encode_edges(reg, spec):
                self.add(f"e_{reg.name}_{kind}", reg, value)
            if reg.wide and reg.type.numeric:
                self.add(f"e_{reg.name}_max_low_first", reg, raw_to_value(spec, spec.raw_max), False)

    def check(self, results: dict[str, Result]) -> list[str]:
        problems = []
        for case in self.cases:
            expected = self.expected[case.id]
            got = results[case.id]
            if expected is None:
                if got.ok or any(w != SENTINEL for w in got.words):
                    problems.append(f"{self.device.id} {case.id}: the Python client refuses it; ST returned {got.ok}, words {got.words}")
            elif not got.ok or got.words != expected:
                problems.append(f"{self.device.id} {case.id}: ST returned {got.ok} {got.words}, Python writes {expected}")
        return problems


def _python_words(reg: Register, spec: RegisterSpec[Any], value: Any) -> tuple[int, ...] | None:
    """The words the Python client writes for the value (a coil: the 0x05 word), or None when it refuses;
    an enum member the device only reports is refused too (the map's write direction)."""
    try:
        raw = value_to_raw(spec, value)
    except RangeError:
        return None
    for enum, part in (
        [(reg.enum, raw)] if reg.enum is not None and not reg.bitfields else [(b.enum, (int(raw) & b.mask) >> b.lsb) for b in reg.bitfields]
    ):
        member = enum.by_value(int(part)) if enum is not None else None
        if member is not None and not member.writable:
            return None
    if reg.type.is_bool:
        return (COIL_ON if raw else 0,)
    return tuple(raw_to_words(spec, raw, with_pair=True))


def _st_input(reg: Register, value: Any) -> int | float | bool | bytes | None:
    """The encoder's input for the engineering value: an enum member's index, text as bytes."""
    if reg.type.is_bool:
        return bool(value)
    if reg.type.is_string:
        return str(value).encode("latin-1" if reg.encoding == "ascii" else reg.encoding or "ascii", errors="strict")
    if reg.enum is not None and not reg.bitfields:
        index = next((i for i, m in enumerate(reg.enum.members) if m.name == value), None)
        return index
    if reg.bitfields:  # the whole word, as a bit string
        number = int(value)
        return number % (1 << reg.type.bits) if reg.type.raw_min <= number <= reg.type.raw_max else None
    if reg.scaled or reg.offset_set or reg.type.is_float:
        real = float(value)
        if (
            reg.type.is_float
            and not (reg.scaled or reg.offset_set)
            and reg.type.words == 2
            and math.isfinite(real)
            and abs(real) > 3.4028234663852886e38
        ):
            return None  # not a REAL: the ST input cannot hold it
        return real
    number = int(value)
    return number if reg.type.raw_min <= number <= reg.type.raw_max else None  # the input's own type


def _encode_edges(reg: Register, spec: RegisterSpec[Any]) -> Iterator[tuple[str, Any]]:
    if reg.type.is_bool:
        yield from (("on", True), ("off", False))
        return
    if reg.type.is_string:
        size = 2 * spec.words
        yield from (("empty", ""), ("full", "Z" * size), ("too_long", "Z" * (size + 1)), ("byte_e9", "\u00e9"))
        return
    if reg.enum is not None and not reg.bitfields:
        yield from ((f"member_{m.name}", m.name) for m in reg.enum.members)
        return
    low, high = spec.raw_min, spec.raw_max
    yield from (("min", raw_to_value(spec, low)), ("max", raw_to_value(spec, high)))
    yield from ((f"na_{i}", raw_to_value(spec, mark)) for i, mark in enumerate(spec.na))  # refused: no value to write
    if reg.type.is_float:
        yield from (("zero", 0.0), ("nan", math.nan), ("infinity", math.inf), ("minus_infinity", -math.inf))
        return
    assert isinstance(low, int) and isinstance(high, int)
    yield from (("min_less_1", raw_to_value(spec, low - 1)), ("max_plus_1", raw_to_value(spec, high + 1)))
    word = 0x8000 << (16 * (reg.type.words - 1))
    yield ("w8000", raw_to_value(spec, word - (1 << reg.type.bits) if reg.type.signed else word))
    if reg.scaled and high > low:
        step = Fraction(spec.scale_num, spec.scale_den)
        yield ("half_step", float(Fraction(raw_to_value(spec, low)) + step / 2))
    if reg.bitfields:
        yield ("all_ones", (1 << reg.type.bits) - 1 if not reg.type.signed else -1)


# -- the examples --------------------------------------------------------------------------------


def example_cases(program: StProgram, decodes: Decodes, encodes: Encodes) -> int:
    device = program.device
    count = 0
    for ex_id, kind, space, start, data in _example_data(device):
        count += 1
        end = start + len(data)
        for index, block in enumerate(program.blocks):
            if block.space != space or block.address >= end or block.address + block.count <= start:
                continue
            words = [data[a - start] if start <= a < end else 0 for a in range(block.address, block.address + block.count)]
            covered = {r.name for r in block.registers if start <= r.address and r.last_address < end}
            if covered:
                decodes.add(f"x_{ex_id}_{index}", block, words, covered, None)
        if kind != "write":
            continue
        for value in decode_words(device, start, data, space=space):
            reg = device.register(value.register) if value.register else None
            if reg is None or value.raw is None or encodes.encoder(reg) is None:
                continue
            first = reg.first_address
            if first < start:
                continue
            case_id = f"x_{ex_id}_{reg.name}"
            encodes.add(case_id, reg, value.value if not reg.bitfields else value.raw)
            if case_id in encodes.expected and not reg.type.is_bool:
                wire = tuple(data[first - start : reg.last_address + 1 - start])
                assert encodes.expected[case_id] == wire, (
                    f"the Python client writes {encodes.expected[case_id]} where {ex_id} carries {wire}"
                )
    return count


EDGE_MAPS = [ROOT / "tests" / "maps" / "st" / "short_text.yaml"]  # text one word long: matiec's FOR 0 TO 0


@pytest.mark.parametrize("map_path", [*MAPS, *FIXTURE_MAPS, *EDGE_MAPS], ids=lambda p: p.stem)
def test_compiled_st_decodes_and_encodes_as_the_python_client(map_path: Path, matiec: Path, tmp_path: Path) -> None:
    device = load_map(map_path, display_name=map_path.relative_to(ROOT).as_posix())
    program = StProgram(device)
    decodes, encodes = Decodes(program), Encodes(program)
    examples = example_cases(program, decodes, encodes)
    for index, block in enumerate(program.blocks):
        decodes.block_edges(index, block)
    encodes.edges()
    results = program.run(matiec, tmp_path, [*decodes.cases, *encodes.cases])
    compared, problems = decodes.check(results)
    problems += encodes.check(results)
    print(
        f"{device.id}: {examples} example frames, {len(decodes.cases)} decoder calls ({compared} register values), "
        f"{len(encodes.cases)} encoder calls ({sum(e is None for e in encodes.expected.values())} refused)",
    )
    assert not problems, f"{len(problems)} differences:\n" + "\n".join(problems[:40])
    reported = [
        f"e_{reg.name}_member_{m.name}"
        for reg in device.registers
        if reg.enum is not None and not reg.bitfields and encodes.encoder(reg) is not None
        for m in reg.enum.members
        if not m.writable
    ]
    tried = [case_id for case_id in reported if case_id in results]
    assert bool(tried) == bool(reported), "the encoders were not tried on the states the device only reports"
    assert all(not results[case_id].ok for case_id in tried), "a state the device only reports was encoded"
    assert examples or not device.examples, "no example frame was run"
