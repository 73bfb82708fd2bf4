"""The frames test program: a host C program that rebuilds every request frame of a map's `examples`
with the header's helpers and parses every response frame; the tests compile and run it.

Requests are built from the examples' recorded values (through the register's own helpers where it
has them: floats, 64-bit values, strings, swapped bytes, coils), never from the frame's bytes, and
must equal the frame byte for byte; responses are parsed with the parser of their function and must
give each recorded raw value (floats compared by their bits, strings by their text, coils by bit).
The expected values are the examples' own (the IEEE 754 bits of a float raw come from `struct`)."""

from __future__ import annotations

import struct
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

from regmap.backends.c.device import has_device_builder
from regmap.backends.c.names import (
    BUILDERS,
    PARSERS,
    CIdentifier,
    Context,
    CSymbol,
    c_float_literal,
    c_hex,
    c_raw,
    c_signed,
    c_unsigned,
    file_header,
)
from regmap.backends.c.views import modern
from regmap.diagnostics import UsageError
from regmap.model import DataType, Device, Example, ExampleValue, Register
from regmap.render import c_str, templates
from regmap_runtime.rtu import EXCEPTION_FLAG, crc_ok, parse_frame
from regmap_runtime.spaces import BY_FUNCTION, COIL_OFF, COIL_ON, DEFAULT_SPACE, HOLDING, SPACES


@dataclass(frozen=True)
class Check:
    label: str
    got: str  # C expression
    want: str  # C expression
    kind: str = "value"  # value (long long), u64 (unsigned long long: 64-bit values, float bits), text (a C string)


@dataclass(frozen=True)
class ScaledCheck:
    label: str
    raw: str
    scale: str
    value: str
    offset: str = ""  # the OFFSET macro, for a register that has one


@dataclass(frozen=True)
class FrameCase:
    template: str
    id: str
    comment: str
    frame: str  # C initialiser list of the frame's bytes
    slave: str
    call: str = ""  # request: the C call that builds the frame into `buf`
    words: tuple[str, ...] = ()  # write multiple: statements that fill `w` (registers) or `b` (coils)
    word_count: int = 0
    bits: bool = False  # a write multiple coils: `b` is a bool array
    crc_wrong: bool = False  # the printed frame has a wrong CRC (an erratum without a correction)
    status: str = "REGMAP_OK"
    exception: str = ""
    checks: tuple[Check, ...] = ()
    scaled: tuple[ScaledCheck, ...] = ()


class _FrameError(ValueError):
    pass


_FLOAT_BITS = {DataType.F32: (">f", ">I"), DataType.F64: (">d", ">Q")}


def _float_bits(raw: float, data_type: DataType) -> int:
    """The IEEE 754 bits of a float raw value, by `struct` (so the C side is checked against another encoder)."""
    value_format, bits_format = _FLOAT_BITS[data_type]
    bits: int = struct.unpack(bits_format, struct.pack(value_format, raw))[0]
    return bits


class _Frames:
    """Turns the examples of one map into C test cases that use the header's names wherever the map has them."""

    def __init__(self, device: Device) -> None:
        self.device = device
        self.ctx = Context(device)
        self.requests: dict[str, _Request] = {}

    # expressions -------------------------------------------------------------------------

    def _registers(self, space: str) -> list[Register]:
        return [r for r in self.device.registers if r.space == space]

    def address(self, address: int, space: str = DEFAULT_SPACE) -> str:
        """C expression of an address: a register's macro when the map has one, else the number."""
        registers = self._registers(space)
        for reg in registers:
            if reg.address == address:
                return self.ctx.addr(reg)
        for reg in registers:
            if reg.paired and reg.first_address == address:
                return self.ctx.pair_addr(reg)
            if reg.address < address <= reg.last_address:
                return f"(uint16_t)({self.ctx.addr(reg)} + {address - reg.address}u)"
        return c_hex(address)  # not a register of the map

    def count(self, address: int, count: int, space: str = DEFAULT_SPACE) -> str:
        reg = next((r for r in self._registers(space) if r.address == address), None)
        if reg is not None and reg.words == count:
            return self.ctx.member_const(reg, "BITS" if reg.space_info.bits else "WORDS")
        if reg is not None and reg.array is not None:
            array = self.ctx.arrays[reg.array.array]
            if reg.array.index == array.first_index and array.stride == 1 and len(array.members) == 1 and count == array.count:
                return CIdentifier(self.ctx.prefix, array.name, "COUNT")
        return c_unsigned(count)

    def raw_word(self, reg: Register, raw: int) -> str:
        """C expression of the raw value of a one-word register, built with the header's names."""
        known = all(b.enum is None or b.enum.by_value((raw & b.mask) >> b.lsb) is not None for b in reg.bitfields)
        if reg.bitfields and known:
            # The word built in the frames program's `fields` by the setters, each of which must accept its value.
            owner = self.ctx.owner(reg)
            steps = ["fields = 0u"]
            covered = 0
            for b in reg.bitfields:
                field = (raw & b.mask) >> b.lsb
                member = b.enum.by_value(field) if b.enum else None
                value = CIdentifier(self.ctx.prefix, b.enum.name, member.name) if b.enum and member else c_unsigned(field)
                steps.append(f"accepted({CSymbol(self.ctx.lower, owner, 'set', b.name)}(&fields, {value}))")
                covered |= b.mask
            rest = raw & 0xFFFF & ~covered
            return f"(uint16_t)({', '.join(steps)}, {f'fields | {c_hex(rest)}' if rest else 'fields'})"
        if reg.bitfields:
            return c_hex(raw)  # a field value its enum does not list: no setter takes it
        if reg.enum is not None:
            member = reg.enum.by_value(raw)
            if member is not None:
                name = CIdentifier(self.ctx.prefix, reg.enum.name, member.name)
                return f"(int16_t){name}" if reg.signed else name
        return c_signed(raw) if reg.signed else c_unsigned(raw)

    def word_of(self, reg: Register, raw: int) -> str:
        """C expression of the word on the wire of a one-word register holding `raw`."""
        value = self.raw_word(reg, raw)
        if modern(reg):
            if reg.signed and reg.bitfields:
                value = f"regmap_s16_from_word({value})"  # the fields make a word; the helper takes the signed value
            return f"{self.ctx.symbol_ref(self.ctx.owner(reg), 'to_wire')}({value})"
        if reg.signed and not reg.bitfields:
            return f"regmap_s16_to_word({value.removeprefix('(int16_t)')})"
        return value

    def command_call(self, reg: Register, raw: int, slave: str) -> str | None:
        """The header's command helper that writes `raw` to `reg`, when the map names one."""
        mine = [c for c in self.device.commands if c.register.name == reg.name]
        for c in mine:
            if c.argument is None and c.value == raw:
                return f"{CSymbol(self.ctx.lower, 'build', c.name)}(buf, sizeof buf, {slave})"
        for c in mine:
            if c.argument is not None and c.argument.min <= raw - c.value <= c.argument.max:
                return f"{CSymbol(self.ctx.lower, 'build', c.name)}(buf, sizeof buf, {slave}, {raw - c.value})"
        return None

    # cases ------------------------------------------------------------------------------

    def cases(self) -> list[FrameCase]:
        out = []
        for ex in self.device.examples:
            try:
                out.append(self.request(ex) if ex.direction == "request" else self.response(ex))
            except _FrameError as exc:
                raise UsageError(f"{self.device.source_path}: example {ex.id}: {exc}") from None
        return out

    def _base(self, ex: Example, template: str) -> dict[str, Any]:
        frame = ex.wire_frame
        return {
            "template": template,
            "id": ex.id,
            "comment": f"{ex.id} ({', '.join(ex.source)}): {ex.meaning}",
            "frame": ", ".join(f"0x{b:02X}" for b in frame),
            "slave": f"0x{frame[0]:02X}u",
            "crc_wrong": not crc_ok(frame),
        }

    def check_values_inside(self, ex: Example, start: int, count: int, space: str) -> None:
        """Every value an example gives must be carried by its frame (else the example contradicts itself)."""
        for v in ex.values:
            reg = v.register
            inside = reg.space == space and reg.first_address < start + count and start <= reg.last_address
            if (v.raw is not None or v.words is not None) and not inside:
                raise _FrameError(
                    f"it gives a value for {reg.label} ({reg.space_info.title} 0x{reg.address:04X}), which its frame"
                    f" ({SPACES[space].title} 0x{start:04X}..0x{start + count - 1:04X}) does not carry"
                )

    def _device_builder(self, space: str, operation: str) -> str:
        if space == HOLDING.name:
            return self.ctx.symbol_ref({"read": "build_read", "write_single": "build_write_single"}.get(operation, "build_write_multiple"))
        if has_device_builder(self.device, space, operation):
            return self.ctx.symbol_ref(BUILDERS[space][operation].suffix)
        return BUILDERS[space][operation].shared  # a table the map does not use: the shared builder itself

    def request(self, ex: Example) -> FrameCase:
        frame = ex.wire_frame
        parsed = parse_frame(frame, "request")
        known = BY_FUNCTION.get(frame[1])
        space = known[0].name if known else DEFAULT_SPACE
        if parsed.address is not None and parsed.kind != "unknown":
            self.check_values_inside(ex, parsed.address, parsed.count or 1, space)
        base = self._base(ex, "case_request.c.jinja")
        slave = base["slave"]
        if parsed.kind == "read_request" and parsed.address is not None and parsed.count is not None:
            self.requests[ex.id] = _Request(parsed.function, parsed.address, parsed.count, ex)
            build = self._device_builder(space, "read")
            address, count = self.address(parsed.address, space), self.count(parsed.address, parsed.count, space)
            return FrameCase(**base, call=f"{build}(buf, sizeof buf, {slave}, {address}, {count})")
        if parsed.kind == "write_single" and parsed.address is not None and SPACES[space].bits:
            word = parsed.words[0]
            self.requests[ex.id] = _Request(parsed.function, parsed.address, 1, ex, word)
            if word in (COIL_ON, COIL_OFF):
                on = self.single_bit(ex, parsed.address, space, word == COIL_ON)
                call = (
                    f"{self._device_builder(space, 'write_single')}(buf, sizeof buf, {slave}, {self.address(parsed.address, space)}, {on})"
                )
            else:  # not a valid 0x05 frame (an example of what a device refuses): the generic builder
                call = f"regmap_rtu_build_request(buf, sizeof buf, {slave}, 0x{frame[1]:02X}u, {c_hex(parsed.address)}, {c_hex(word)})"
            return FrameCase(**base, call=call)
        if parsed.kind == "write_single" and parsed.address is not None:
            self.requests[ex.id] = _Request(parsed.function, parsed.address, 1, ex, parsed.words[0])
            call = self.single_write_command(ex, parsed.address, slave) or (
                f"{self.ctx.symbol_ref('build_write_single')}(buf, sizeof buf, {slave}, {self.address(parsed.address)},"
                f" {self.single_word(ex, parsed.address, parsed.words[0])})"
            )
            return FrameCase(**base, call=call)
        if parsed.kind == "write_multiple_request" and parsed.address is not None and parsed.count is not None and SPACES[space].bits:
            self.requests[ex.id] = _Request(parsed.function, parsed.address, parsed.count, ex)
            build = self._device_builder(space, "write_multiple")
            address = self.address(parsed.address, space)
            call = f"{build}(buf, sizeof buf, {slave}, {address}, b, {self.count(parsed.address, parsed.count, space)})"
            base["template"] = "case_request_multiple.c.jinja"
            frame_bits = _unpack(frame[7:-2], parsed.count)
            statements = self.multiple_bits(ex, parsed.address, frame_bits, space)
            return FrameCase(**base, call=call, words=statements, word_count=parsed.count, bits=True)
        if parsed.kind == "write_multiple_request" and parsed.address is not None and parsed.count is not None:
            self.requests[ex.id] = _Request(parsed.function, parsed.address, parsed.count, ex)
            build = self.ctx.symbol_ref("build_write_multiple")
            call = f"{build}(buf, sizeof buf, {slave}, {self.address(parsed.address)}, w, {c_unsigned(parsed.count)})"
            base["template"] = "case_request_multiple.c.jinja"
            words = self.multiple_words(ex, parsed.address, parsed.words)
            return FrameCase(**base, call=call, words=words, word_count=len(parsed.words))
        body = frame[2:-2]
        if len(body) == 4:
            # Another function code (the manual's example of an unsupported one): the generic builder.
            first, second = int.from_bytes(body[:2], "big"), int.from_bytes(body[2:], "big")
            self.requests[ex.id] = _Request(frame[1], first, second, ex)
            call = f"regmap_rtu_build_request(buf, sizeof buf, {slave}, 0x{frame[1]:02X}u, {c_hex(first)}, {c_hex(second)})"
            return FrameCase(**base, call=call)
        raise _FrameError(f"cannot rebuild a {parsed.kind} request of {len(frame)} bytes")

    def single_write_command(self, ex: Example, address: int, slave: str) -> str | None:
        for v in ex.values:
            if isinstance(v.raw, int) and v.register.words == 1 and v.register.address == address and v.register.space == HOLDING.name:
                return self.command_call(v.register, v.raw, slave)
        return None

    def single_word(self, ex: Example, address: int, word: int) -> str:
        """The word of a 0x06 frame, from the example's values when they describe it."""
        for v in ex.values:
            reg = v.register
            if reg.space != HOLDING.name:
                continue
            if isinstance(v.raw, int) and reg.words == 1 and reg.address == address:
                return self.word_of(reg, v.raw)
            if v.words is not None and reg.words > 1 and reg.address <= address <= reg.last_address:
                if len(v.words) != 1:
                    raise _FrameError(f"a 0x06 frame carries one word of {reg.name}, the example gives {len(v.words)}")
                return c_hex(v.words[0])  # one word of a wide register, as the example gives it
        return c_hex(word)

    def single_bit(self, ex: Example, address: int, space: str, frame_on: bool) -> str:
        """The state a 0x05 frame writes, from the example's value for its coil when it gives one."""
        for v in ex.values:
            if v.register.space == space and v.register.address == address and v.raw is not None:
                return "true" if v.raw else "false"
        return "true" if frame_on else "false"

    def carried(
        self, ex: Example, start: int, count: int, *, high_word: bool, space: str = DEFAULT_SPACE
    ) -> Iterator[tuple[ExampleValue, list[int], str]]:
        """The example's values that have words (or bits) among the frame's `count` from `start`: each with the
        addresses of those words (from a pair's unused high word on when `high_word`) and the C index of
        the register's listed address among the frame's words."""
        base = self.address(start, space)
        for v in ex.values:
            reg = v.register
            if reg.space != space:
                continue
            first = reg.first_address if high_word else reg.address
            inside = [a for a in range(first, reg.last_address + 1) if start <= a < start + count]
            if inside and (v.raw is not None or v.words is not None):
                yield v, inside, f"(unsigned)({self.ctx.addr(reg)} - {base})"

    def wide_literal(self, reg: Register, raw: int | float) -> str:
        if reg.type.is_float:
            return c_float_literal(float(raw), reg.type)
        return c_raw(int(raw), reg.signed)

    def multiple_words(self, ex: Example, start: int, frame_words: tuple[int, ...]) -> tuple[str, ...]:
        """Statements that fill `w` (the words of a 0x10 frame) from the example's values through the header's helpers."""
        count = len(frame_words)
        base = self.address(start)
        filled: set[int] = set()
        statements = []
        for v, inside, index in self.carried(ex, start, count, high_word=True):
            reg = v.register
            if v.words is not None:
                for a, offset, given in _given_words(reg, v.words, [a for a in inside if a >= reg.address], "the frame"):
                    statements.append(f"put(w, {count}u, {index} + {offset}u, {given});")
                    filled.add(a)
                continue
            raw = v.raw
            assert raw is not None
            if len(inside) != reg.span:
                raise _FrameError(f"the frame carries only part of {reg.name}, the example gives its whole raw value")
            owner = self.ctx.owner(reg)
            if reg.type.is_string:
                to_wire = self.ctx.symbol_ref(owner, "to_wire")
                words = self.ctx.member_const(reg, "WORDS")
                statements.append(f"if (!{to_wire}({c_str(str(raw))}, at(w, {count}u, {index}, {words}))) {{")
                statements.append(f"    fail({c_str(ex.id)}, {c_str(f'{reg.name}: the text does not fit')});")
                statements.append("}")
            elif isinstance(raw, str):
                raise _FrameError(f"{reg.name} is {reg.type.value}; the example gives text {raw!r}")
            elif reg.words == 1:
                word = self.word_of(reg, int(raw))
                statements.append(f"put(w, {count}u, {index}, {word});")
                if reg.paired:
                    high = f"(unsigned)({self.ctx.pair_addr(reg)} - {base})"
                    signed = self.ctx.member_const(reg, "SIGNED")
                    statements.append(f"put(w, {count}u, {high}, regmap_pair_high_word({word}, {signed}));")
            elif modern(reg):
                to_wire = self.ctx.symbol_ref(owner, "to_wire")
                words = self.ctx.member_const(reg, "WORDS")
                statements.append(f"{to_wire}({self.wide_literal(reg, raw)}, at(w, {count}u, {index}, {words}));")
            else:
                func = "regmap_s32_to_words" if reg.signed else "regmap_u32_to_words"
                order = self.ctx.member_const(reg, "WORD_ORDER")
                statements.append(f"{func}({c_raw(int(raw), reg.signed)}, {order}, at(w, {count}u, {index}, 2u));")
            filled.update(inside)
        for offset, literal in enumerate(frame_words):
            if start + offset not in filled:
                statements.append(f"put(w, {count}u, {offset}u, {c_hex(literal)}); /* no value in the example */")
        return tuple(statements)

    def multiple_bits(self, ex: Example, start: int, frame_bits: list[bool], space: str) -> tuple[str, ...]:
        """Statements that fill `b` (the coils of a 0x0F frame) from the example's values, the rest from the frame."""
        count = len(frame_bits)
        filled: set[int] = set()
        statements = []
        for v, inside, index in self.carried(ex, start, count, high_word=False, space=space):
            statements.append(f"put_bit(b, {count}u, {index}, {'true' if v.raw else 'false'});")
            filled.update(inside)
        for offset, bit in enumerate(frame_bits):
            if start + offset not in filled:
                statements.append(f"put_bit(b, {count}u, {offset}u, {'true' if bit else 'false'}); /* no value in the example */")
        return tuple(statements)

    def response(self, ex: Example) -> FrameCase:
        frame = ex.wire_frame
        base = self._base(ex, "case_response.c.jinja")
        slave = base["slave"]
        request = self.requests.get(ex.request) if ex.request else None
        if request is None:
            request = self._request_from_response(ex)
        status, exception = "REGMAP_OK", ""
        if base["crc_wrong"]:
            status = "REGMAP_ERR_CRC"
        elif frame[1] & EXCEPTION_FLAG:
            status = "REGMAP_ERR_EXCEPTION"
            exception = self.exception_name(frame[2])
        known = BY_FUNCTION.get(request.function)
        checks: list[Check] = []
        scaled: list[ScaledCheck] = []
        if known is None:
            call = f"regmap_rtu_check_response(frame, sizeof frame, {slave}, 0x{request.function:02X}u, &exception)"
            return FrameCase(**base, call=call, status=status, exception=exception)
        space, operation = known[0].name, known[1]
        if request.example is not None:
            self.check_values_inside(ex, request.address, request.count, space)
        address = self.address(request.address, space)
        parser = PARSERS[space][operation]
        described = status == "REGMAP_OK" and request.example is not None
        if operation == "read" and SPACES[space].bits:
            count = self.count(request.address, request.count, space)
            call = f"{parser}(frame, sizeof frame, {slave}, {count}, bits, sizeof bits / sizeof bits[0], &exception)"
            if described:
                checks = self.bit_checks(ex, request.address, request.count, space)
        elif operation == "read":
            count = self.count(request.address, request.count, space)
            call = f"{parser}(frame, sizeof frame, {slave}, {count}, words, sizeof words / sizeof words[0], &exception)"
            if described:
                checks, scaled = self.read_checks(ex, request.address, request.count, space)
        elif operation == "write_single" and SPACES[space].bits:
            source = ex if any(v.raw is not None for v in ex.values) else request.example
            on = (
                self.single_bit(source, request.address, space, request.value == COIL_ON)
                if source
                else str(request.value == COIL_ON).lower()
            )
            call = f"{parser}(frame, sizeof frame, {slave}, {address}, {on}, &exception)"
        elif operation == "write_single":
            # The echo carries the request's word; the response's own values, when it has them, must give it too.
            source = ex if any(v.raw is not None or v.words is not None for v in ex.values) else request.example
            word = self.single_word(source, request.address, request.value) if source else c_hex(request.value)
            call = f"{parser}(frame, sizeof frame, {slave}, {address}, {word}, &exception)"
        else:
            count = self.count(request.address, request.count, space) if SPACES[space].bits else c_unsigned(request.count)
            call = f"{parser}(frame, sizeof frame, {slave}, {address}, {count}, &exception)"
        return FrameCase(**base, call=call, status=status, exception=exception, checks=tuple(checks), scaled=tuple(scaled))

    def _request_from_response(self, ex: Example) -> _Request:
        """For a response that names no request: what the frame says it answers, and for a read, the
        address its values' registers give when they are exactly the words it carries."""
        frame = ex.wire_frame
        function = frame[1] & ~EXCEPTION_FLAG & 0xFF
        known = BY_FUNCTION.get(function)
        if known is not None and known[1] == "read" and not frame[1] & EXCEPTION_FLAG:
            space = known[0]
            count = max(1, frame[2] * 8 if space.bits else frame[2] // 2)
            regs = sorted({v.register.name: v.register for v in ex.values if v.raw is not None}.values(), key=lambda r: r.address)
            if regs and all(r.space == space.name for r in regs):
                first = regs[0].first_address
                if not space.bits and sum(r.span for r in regs) == count and regs[-1].last_address == first + count - 1:
                    return _Request(function, first, count, ex)
            return _Request(function, 0, count)
        if len(frame) == 8:
            field = int.from_bytes(frame[4:6], "big")
            return _Request(function, int.from_bytes(frame[2:4], "big"), field, value=field)
        return _Request(function, 0, 1)

    def exception_name(self, code: int) -> str:
        e = self.device.transport.exception(code)
        if e is not None:
            return CIdentifier(self.ctx.prefix, "EXCEPTION", e.name)
        return STANDARD_EXCEPTION_MACROS.get(code, f"0x{code:02X}u")

    def bit_checks(self, ex: Example, start: int, count: int, space: str) -> list[Check]:
        """Checks that the bits a read response carries are the example's coils or inputs."""
        return [
            Check(v.register.name, f"bit_at(bits, {count}u, {index})", "true" if v.raw else "false")
            for v, _, index in self.carried(ex, start, count, high_word=False, space=space)
        ]

    def read_checks(self, ex: Example, start: int, count: int, space: str = DEFAULT_SPACE) -> tuple[list[Check], list[ScaledCheck]]:
        """Checks that the words a read response carries give each value the example records."""
        checks: list[Check] = []
        scaled: list[ScaledCheck] = []
        base = self.address(start, space)
        for v, own, index in self.carried(ex, start, count, high_word=False, space=space):
            reg = v.register
            if v.words is not None:
                for _, offset, given in _given_words(reg, v.words, own, "the response"):
                    checks.append(Check(f"{reg.name} word {offset}", f"word_at(words, {count}u, {index} + {offset}u)", given))
                continue
            raw = v.raw
            assert raw is not None
            if len(own) != reg.words:
                raise _FrameError(f"the response carries only part of {reg.name}, the example gives its whole raw value")
            owner = self.ctx.owner(reg)
            from_wire = self.ctx.symbol_ref(owner, "from_wire")
            words = f"at(words, {count}u, {index}, {self.ctx.member_const(reg, 'WORDS')})"
            word = f"word_at(words, {count}u, {index})"
            if reg.type.is_string:
                checks.append(Check(reg.name, f"text_of({from_wire}({words}, text, sizeof text))", c_str(str(raw)), "text"))
                continue
            if isinstance(raw, str):
                raise _FrameError(f"{reg.name} is {reg.type.value}; the example gives text {raw!r}")
            if reg.type.is_float:
                bits = "regmap_f32_to_bits" if reg.type is DataType.F32 else "regmap_f64_to_bits"
                raw_expr = f"{from_wire}({words})"
                checks.append(Check(f"{reg.name} (IEEE 754 bits)", f"{bits}({raw_expr})", c_hex(_float_bits(raw, reg.type)), "u64"))
            else:
                if modern(reg):
                    raw_expr = f"{from_wire}({word if reg.words == 1 else words})"
                elif reg.words == 1:
                    raw_expr = f"regmap_s16_from_word({word})" if reg.signed else word
                else:
                    func = "regmap_s32_from_words" if reg.signed else "regmap_u32_from_words"
                    raw_expr = f"{func}(at(words, {count}u, {index}, 2u), {self.ctx.member_const(reg, 'WORD_ORDER')})"
                kind = "u64" if reg.type is DataType.U64 else "value"
                checks.append(Check(reg.name, raw_expr, c_raw(int(raw), reg.signed), kind))
            if reg.paired and reg.first_address >= start:
                high = f"word_at(words, {count}u, (unsigned)({self.ctx.pair_addr(reg)} - {base}))"
                signed = self.ctx.member_const(reg, "SIGNED")
                checks.append(Check(f"{reg.name} high word", high, f"regmap_pair_high_word({word}, {signed})"))
            if reg.bitfields and reg.words == 1 and isinstance(raw, int):
                for b in reg.bitfields:
                    getter = CSymbol(self.ctx.lower, owner, "get", b.name)
                    checks.append(Check(f"{reg.name}.{b.name}", f"{getter}({raw_expr})", c_unsigned((raw & b.mask) >> b.lsb)))
            elif reg.enum is not None and isinstance(v.value, str) and reg.enum.member(v.value) is not None:
                checks.append(Check(f"{reg.name} = {v.value}", raw_expr, CIdentifier(self.ctx.prefix, reg.enum.name, v.value)))
            elif isinstance(v.value, int | float) and not isinstance(v.value, bool) and reg.enum is None:
                offset_macro = self.ctx.member_const(reg, "OFFSET") if modern(reg) else ""
                scaled.append(ScaledCheck(reg.name, raw_expr, self.ctx.member_const(reg, "SCALE"), repr(float(v.value)), offset_macro))
        return checks, scaled


def _unpack(data: bytes, count: int) -> list[bool]:
    """The first `count` bits of Modbus bit bytes, least significant bit of the first byte first."""
    if len(data) * 8 < count:
        raise _FrameError(f"the frame carries {len(data)} bytes of bits, {count} bits need {(count + 7) // 8}")
    return [bool(data[i // 8] >> (i % 8) & 1) for i in range(count)]


def _given_words(reg: Register, words: tuple[int, ...], own: list[int], carrier: str) -> list[tuple[int, int, str]]:
    """(address, offset in the register, C literal) of each word an example gives for `reg`, which the
    frame carries at the addresses `own`."""
    if len(words) != len(own):
        raise _FrameError(f"{carrier} carries {len(own)} words of {reg.name}, the example gives {len(words)}")
    return [(a, a - reg.address, c_hex(given)) for a, given in zip(own, words, strict=True)]


@dataclass(frozen=True)
class _Request:
    """What a response is checked against: the request it answers."""

    function: int
    address: int
    count: int
    example: Example | None = None
    value: int = 0  # the word of a write single


STANDARD_EXCEPTION_MACROS = {
    0x01: "REGMAP_EXC_ILLEGAL_FUNCTION",
    0x02: "REGMAP_EXC_ILLEGAL_DATA_ADDRESS",
    0x03: "REGMAP_EXC_ILLEGAL_DATA_VALUE",
    0x04: "REGMAP_EXC_SERVER_DEVICE_FAILURE",
    0x05: "REGMAP_EXC_ACKNOWLEDGE",
    0x06: "REGMAP_EXC_SERVER_DEVICE_BUSY",
    0x08: "REGMAP_EXC_MEMORY_PARITY_ERROR",
    0x0A: "REGMAP_EXC_GATEWAY_PATH_UNAVAILABLE",
    0x0B: "REGMAP_EXC_GATEWAY_TARGET_FAILED",
}


def frames_test_context(device: Device) -> dict[str, Any]:
    return {"header": file_header(device), "device": device, "include": f"{device.id}.h", "cases": _Frames(device).cases()}


def render_frames_test(device: Device) -> str:
    """A host C program (it uses stdio) that checks the header against every frame of the map's examples."""
    return templates(__name__).get_template("frames_test.c.jinja").render(**frames_test_context(device))
