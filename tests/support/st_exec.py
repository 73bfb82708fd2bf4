"""Run the generated plain-standard Structured Text: matiec (`iec2c`) turns it into C, gcc compiles that C
with a driver written here, and the driver calls the generated decoders and encoders on the cases a
test gives, printing what they return.

matiec emits every ST FUNCTION as a C function `BOOL F(BOOL EN, BOOL *ENO, inputs..., in-outs as
pointers)` and every STRUCT as a C struct with the member names in upper case, so the driver calls them
directly (no ST test program, no PLC cycle). The raw structs, the values struct and the functions'
parameters are read from the ST back end's own views, which name what the ST declares; the values the
test expects come from the Python runtime, never from these views.

One line per case on stdout: `<id> <returned 0/1> <member>=<value> ...` for a decoder (the values members
the case asks for) and `<id> <returned 0/1> <word> ...` for an encoder (its output words, which start as
16#DEAD so that a refusal that still wrote shows).
"""

from __future__ import annotations

import math
import struct
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

from regmap.backends.st.codec import IEC
from regmap.backends.st.device import device_views
from regmap.backends.st.functions import Block
from regmap.backends.st.view_types import FunctionView
from regmap.model import Device

from support.st_matiec import DRIVER_PRELUDE, build_and_run, decoding_program, iec2c, program_text, st_files

UNSIGNED = {"USINT", "UINT", "UDINT", "ULINT", "BYTE", "WORD", "DWORD", "LWORD"}
SIGNED = {"SINT", "INT", "DINT", "LINT"}
SENTINEL = 0xDEAD


@dataclass(frozen=True)
class Decode:
    id: str
    block: Block
    words: tuple[int, ...]  # one per address of the block (a bit block: one bit per address)
    members: tuple[str, ...]  # the values members to print
    high_word_first: bool | None = None  # for a decoder that takes the device's word order
    before: tuple[tuple[Block, tuple[int, ...]], ...] = ()  # blocks decoded first into the same values (a poll's earlier reads)


@dataclass(frozen=True)
class Encode:
    id: str
    function: FunctionView
    value: int | float | bool | bytes  # an enum member: its index; text: its bytes
    words: int  # output words
    high_word_first: bool | None = None
    scale_factor: tuple[int, bool] | None = None  # a `scale_from` encoder's nSf and bSfAvailable


@dataclass
class Result:
    ok: bool
    values: dict[str, str] = field(default_factory=dict)
    words: tuple[int, ...] = ()


class StProgram:
    """One device's iec/ ST, its views, and the C driver that runs cases on it."""

    def __init__(self, device: Device) -> None:
        self.device = device
        self.files = st_files(device)
        self.views = device_views(device, IEC, [])
        self.blocks: list[Block] = self.views["plan"]
        self.values_type: str = self.views["values"].type_name
        self.value_types: dict[str, str] = {m.name: m.type for m in self.views["values"].members}
        self.functions: dict[str, FunctionView] = {f.name: f for f in self.views["functions"]}
        self.enums: dict[str, tuple[str, ...]] = {e.type_name: tuple(m.name for m in e.members) for e in self.views["enums"]}

    # -- the driver --------------------------------------------------------------------------

    def _print_member(self, name: str) -> str:
        kind = self.value_types[name]
        target = f"v.{name.upper()}"
        if kind in UNSIGNED:
            return f'printf(" {name}=%llu", (unsigned long long){target});'
        if kind in SIGNED:
            return f'printf(" {name}=%lld", (long long){target});'
        if kind == "BOOL":
            return f'printf(" {name}=%d", (int){target});'
        if kind == "REAL":
            return f'printf(" {name}=%.9g", (double){target});'
        if kind == "LREAL":
            return f'printf(" {name}=%.17g", {target});'
        if kind == "STRING":
            return f'printf(" {name}="); for (i = 0; i < {target}.len; i++) printf("%02X", {target}.body[i]); printf("-");'
        assert kind in self.enums, kind
        return f'printf(" {name}=%d", (int){target});'

    def _fill(self, block: Block, words: Sequence[int]) -> list[str]:
        """Statements that put the block's words (wire order) into `raw`, member by member."""
        if block.bits:
            lines = []
            for offset, bit in enumerate(words):
                if bit:
                    lines.append(f"raw.BITS.table[{offset // 8}] |= {1 << (offset % 8)};")
            return lines
        lines = []
        at = 0
        for member in block.struct.members:
            target = f"raw.{member.name.upper()}"
            if member.type.startswith("ARRAY[0.."):
                count = int(member.type.split("..")[1].split("]")[0]) + 1
                lines += [f"{target}.table[{k}] = {words[at + k]}u;" for k in range(count)]
                at += count
                continue
            word = words[at]
            at += 1
            if member.type in ("INT", "SINT"):
                lines.append(f"{target} = (INT){word - 0x10000 if word & 0x8000 else word};")
            elif member.type == "BOOL":
                lines.append(f"{target} = {1 if word else 0};")
            else:
                lines.append(f"{target} = {word}u;")
        assert at == len(words), (block.struct.type_name, at, len(words))
        return lines

    def _decode(self, case: Decode) -> list[str]:
        order = "" if case.high_word_first is None else f", {int(case.high_word_first)}"
        before: list[str] = []
        for block, words in case.before:
            before += [
                "{",
                f"    {block.struct.type_name} raw;",
                "    memset(&raw, 0, sizeof raw);",
                *("    " + line for line in self._fill(block, words)),
                f"    (void){block.decode.name}(1, &eno, raw, &v);",
                "}",
            ]
        return [
            "{",
            f"    {case.block.struct.type_name} raw;",
            f"    {self.values_type} v;",
            "    memset(&raw, 0, sizeof raw);",
            "    memset(&v, 0, sizeof v);",
            *("    " + line for line in before),
            *("    " + line for line in self._fill(case.block, case.words)),
            f"    ok = {case.block.decode.name}(1, &eno, raw{order}, &v);",
            f'    printf("{case.id} %d", (int)ok);',
            *("    " + self._print_member(name) for name in case.members),
            '    printf("\\n");',
            "}",
        ]

    def _literal(self, kind: str, value: int | float | bool | bytes) -> tuple[list[str], str]:
        """(statements, expression) of an input of ST type `kind`."""
        if kind == "STRING":
            assert isinstance(value, bytes)
            body = ", ".join(str(b) for b in value)
            return [f"STRING s = {{{len(value)}, {{{body}}}}};"] if value else ["STRING s = {0, {0}};"], "s"
        if kind == "BOOL":
            return [], "1" if value else "0"
        if kind in self.enums:
            return [], f"({kind}){int(value)}"
        if kind in ("REAL", "LREAL"):
            assert isinstance(value, float | int)
            number = float(value)
            if math.isnan(number):
                return [], f"({kind})NAN"
            if math.isinf(number):
                return [], f"({kind})({'-' if number < 0 else ''}INFINITY)"
            if kind == "REAL":
                number = struct.unpack("<f", struct.pack("<f", number))[0]
            return [], f"({kind}){number!r}"
        assert isinstance(value, int), (kind, value)
        if kind in UNSIGNED:
            return [], f"({kind}){value}ULL"
        if value == -(1 << 63):
            return [], f"({kind})(-9223372036854775807LL - 1)"
        return [], f"({kind}){value}LL"

    def _encode(self, case: Encode) -> list[str]:
        function = case.function
        value_input = next(m for m in function.inputs if m.name != "bHighWordFirst")
        setup, expression = self._literal(value_input.type, case.value)
        args = [expression]
        if case.scale_factor is not None:
            args += [f"(INT){case.scale_factor[0]}", str(int(case.scale_factor[1]))]
        if case.high_word_first is not None:
            args.append(str(int(case.high_word_first)))
        return [
            "{",
            f"    WORD out[{case.words}];",
            *(f"    {line}" for line in setup),
            f"    for (i = 0; i < {case.words}; i++) out[i] = {SENTINEL}u;",
            f"    ok = {function.name}(1, &eno, {', '.join(args)}, (void *)out);",
            f'    printf("{case.id} %d", (int)ok);',
            f'    for (i = 0; i < {case.words}; i++) printf(" %u", (unsigned)out[i]);',
            '    printf("\\n");',
            "}",
        ]

    def driver(self, cases: Sequence[Decode | Encode]) -> str:
        body: list[str] = []
        for case in cases:
            body += self._decode(case) if isinstance(case, Decode) else self._encode(case)
        return "\n".join(
            [
                *DRIVER_PRELUDE,
                "int main(void) {",
                "    BOOL ok, eno;",
                "    int i;",
                "    (void)i;",
                *("    " + line for line in body),
                "    return 0;",
                "}",
                "",
            ]
        )

    # -- build and run -----------------------------------------------------------------------

    def run(self, matiec: Path, work: Path, cases: Sequence[Decode | Encode]) -> dict[str, Result]:
        source = program_text(self.files, decoding_program(self.files, self.values_type), "P_DECODE_ALL")
        compiled = iec2c(matiec, source, work, self.device.id)
        assert compiled.returncode == 0 and not compiled.errors, compiled.output[-3000:]
        stdout = build_and_run(matiec, compiled, self.driver(cases), work / f"{self.device.id}_st")
        results: dict[str, Result] = {}
        for line in stdout.splitlines():
            case_id, ok, *rest = line.split(" ")
            if rest and "=" in rest[0]:
                results[case_id] = Result(ok == "1", values=dict(item.split("=", 1) for item in rest))
            else:
                results[case_id] = Result(ok == "1", words=tuple(int(w) for w in rest))
        assert set(results) == {c.id for c in cases}, "the driver skipped cases"
        return results
