"""The frames test program: a host C program that rebuilds every request frame of a map's `examples`
with the header's helpers and parses every response frame; the tests compile and run it."""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

from regmap.backends.c.names import CIdentifier, Context, CSymbol, c_hex, c_raw, c_signed, c_unsigned, file_header
from regmap.diagnostics import UsageError
from regmap.model import Device, Example, ExampleValue, Register
from regmap.render import environment
from regmap_runtime.rtu import EXCEPTION_FLAG, crc_ok, parse_frame
from regmap_runtime.spaces import HOLDING


@dataclass(frozen=True)
class Check:
    label: str
    got: str  # C expression
    want: str  # C expression


@dataclass(frozen=True)
class ScaledCheck:
    label: str
    raw: str
    scale: str
    value: str


@dataclass(frozen=True)
class FrameCase:
    template: str
    id: str
    comment: str
    frame: str  # C initialiser list of the frame's bytes
    slave: str
    call: str = ""  # request: the C call that builds the frame into `buf`
    words: tuple[str, ...] = ()  # write multiple: statements that fill `w`
    word_count: int = 0
    crc_wrong: bool = False  # the printed frame has a wrong CRC (an erratum without a correction)
    status: str = "REGMAP_OK"
    exception: str = ""
    checks: tuple[Check, ...] = ()
    scaled: tuple[ScaledCheck, ...] = ()


class _FrameError(ValueError):
    pass


class _Frames:
    """Turns the examples of one map into C test cases that use the header's names wherever the map has them."""

    def __init__(self, device: Device) -> None:
        self.device = device
        self.ctx = Context(device)
        self.requests: dict[str, _Request] = {}

    # expressions -------------------------------------------------------------------------

    def address(self, address: int) -> str:
        """C expression of an address: a register's macro when the map has one, else the number."""
        for reg in self.device.registers:
            if reg.address == address:
                return self.ctx.addr(reg)
        for reg in self.device.registers:
            if reg.paired and reg.first_address == address:
                return self.ctx.pair_addr(reg)
            if reg.address < address <= reg.last_address:
                return f"(uint16_t)({self.ctx.addr(reg)} + {address - reg.address}u)"
        return c_hex(address)  # not a register of the map

    def count(self, address: int, count: int) -> str:
        reg = next((r for r in self.device.registers if r.address == address), None)
        if reg is not None and reg.words == count:
            return self.ctx.member_const(reg, "WORDS")
        return c_unsigned(count)

    def word_of(self, reg: Register, raw: int) -> str:
        """C expression of the word of a one-word register holding `raw`, built with the header's names."""
        if reg.bitfields:
            owner = self.ctx.owner(reg)
            expr = "0u"
            covered = 0
            for b in reg.bitfields:
                field = (raw & b.mask) >> b.lsb
                member = b.enum.by_value(field) if b.enum else None
                value = CIdentifier(self.ctx.prefix, b.enum.name, member.name) if b.enum and member else c_unsigned(field)
                expr = f"{CSymbol(self.ctx.lower, owner, 'set', b.name)}({expr}, {value})"
                covered |= b.mask
            rest = raw & 0xFFFF & ~covered
            return f"(uint16_t)({expr} | {c_hex(rest)})" if rest else expr
        if reg.enum is not None:
            member = reg.enum.by_value(raw)
            if member is not None:
                name = CIdentifier(self.ctx.prefix, reg.enum.name, member.name)
                return f"regmap_s16_to_word({name})" if reg.signed else name
        if reg.signed:
            return f"regmap_s16_to_word({c_signed(raw)})"
        return c_unsigned(raw)

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

    def check_values_inside(self, ex: Example, start: int, count: int) -> None:
        """Every value an example gives must be carried by its frame (else the example contradicts itself)."""
        for v in ex.values:
            reg = v.register
            if (v.raw is not None or v.words is not None) and not (reg.first_address < start + count and start <= reg.last_address):
                raise _FrameError(
                    f"it gives a value for {reg.label} (0x{reg.address:04X}), which its frame"
                    f" (0x{start:04X}..0x{start + count - 1:04X}) does not carry"
                )

    def request(self, ex: Example) -> FrameCase:
        frame = ex.wire_frame
        parsed = parse_frame(frame, "request")
        if parsed.address is not None and parsed.kind != "unknown":
            self.check_values_inside(ex, parsed.address, parsed.count or 1)
        base = self._base(ex, "c/case_request.c.jinja")
        slave = base["slave"]
        if parsed.kind == "read_request" and parsed.address is not None and parsed.count is not None:
            self.requests[ex.id] = _Request(parsed.function, parsed.address, parsed.count, ex)
            build = self.ctx.symbol_ref("build_read")
            call = f"{build}(buf, sizeof buf, {slave}, {self.address(parsed.address)}, {self.count(parsed.address, parsed.count)})"
            return FrameCase(**base, call=call)
        if parsed.kind == "write_single" and parsed.address is not None:
            self.requests[ex.id] = _Request(parsed.function, parsed.address, 1, ex, parsed.words[0])
            call = self.single_write_command(ex, parsed.address, slave) or (
                f"{self.ctx.symbol_ref('build_write_single')}(buf, sizeof buf, {slave}, {self.address(parsed.address)},"
                f" {self.single_word(ex, parsed.address, parsed.words[0])})"
            )
            return FrameCase(**base, call=call)
        if parsed.kind == "write_multiple_request" and parsed.address is not None and parsed.count is not None:
            self.requests[ex.id] = _Request(parsed.function, parsed.address, parsed.count, ex)
            build = self.ctx.symbol_ref("build_write_multiple")
            call = f"{build}(buf, sizeof buf, {slave}, {self.address(parsed.address)}, w, {c_unsigned(parsed.count)})"
            base["template"] = "c/case_request_multiple.c.jinja"
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
            if v.raw is not None and v.register.words == 1 and v.register.address == address:
                return self.command_call(v.register, v.raw, slave)
        return None

    def single_word(self, ex: Example, address: int, word: int) -> str:
        """The word of a 0x06 frame, from the example's values when they describe it."""
        for v in ex.values:
            reg = v.register
            if v.raw is not None and reg.words == 1 and reg.address == address:
                return self.word_of(reg, v.raw)
            if v.words is not None and reg.wide and reg.address <= address <= reg.last_address:
                if len(v.words) != 1:
                    raise _FrameError(f"a 0x06 frame carries one word of {reg.name}, the example gives {len(v.words)}")
                return c_hex(v.words[0])  # one word of a 32-bit register, as the example gives it
        return c_hex(word)

    def carried(self, ex: Example, start: int, count: int, *, high_word: bool) -> Iterator[tuple[ExampleValue, list[int], str]]:
        """The example's values that have words among the frame's `count` words from `start`: each with the
        addresses of those words (from a pair's unused high word on when `high_word`) and the C index of
        the register's listed address among the frame's words."""
        base = self.address(start)
        for v in ex.values:
            reg = v.register
            first = reg.first_address if high_word else reg.address
            inside = [a for a in range(first, reg.last_address + 1) if start <= a < start + count]
            if inside and (v.raw is not None or v.words is not None):
                yield v, inside, f"(unsigned)({self.ctx.addr(reg)} - {base})"

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
            if reg.words == 1:
                word = self.word_of(reg, raw)
                statements.append(f"put(w, {count}u, {index}, {word});")
                if reg.paired:
                    high = f"(unsigned)({self.ctx.pair_addr(reg)} - {base})"
                    signed = self.ctx.member_const(reg, "SIGNED")
                    statements.append(f"put(w, {count}u, {high}, regmap_pair_high_word({word}, {signed}));")
            else:
                func = "regmap_s32_to_words" if reg.signed else "regmap_u32_to_words"
                order = self.ctx.member_const(reg, "WORD_ORDER")
                statements.append(f"{func}({c_raw(raw, reg.signed)}, {order}, at(w, {count}u, {index}, 2u));")
            filled.update(inside)
        for offset, literal in enumerate(frame_words):
            if start + offset not in filled:
                statements.append(f"put(w, {count}u, {offset}u, {c_hex(literal)}); /* no value in the example */")
        return tuple(statements)

    def response(self, ex: Example) -> FrameCase:
        frame = ex.wire_frame
        base = self._base(ex, "c/case_response.c.jinja")
        slave = base["slave"]
        request = self.requests.get(ex.request) if ex.request else None
        if request is None:
            request = _request_from_response(frame)
        status, exception = "REGMAP_OK", ""
        if base["crc_wrong"]:
            status = "REGMAP_ERR_CRC"
        elif frame[1] & EXCEPTION_FLAG:
            status = "REGMAP_ERR_EXCEPTION"
            exception = self.exception_name(frame[2])
        if request.function in HOLDING.codes.values() and request.example is not None:
            self.check_values_inside(ex, request.address, request.count)
        checks: list[Check] = []
        scaled: list[ScaledCheck] = []
        address = self.address(request.address)
        if request.function == HOLDING.read:
            count = self.count(request.address, request.count)
            call = (
                f"regmap_rtu_parse_read_response(frame, sizeof frame, {slave}, {count}, words, sizeof words / sizeof words[0], &exception)"
            )
            if status == "REGMAP_OK" and request.example is not None:
                checks, scaled = self.read_checks(ex, request.address, request.count)
        elif request.function == HOLDING.write_single:
            # The echo carries the request's word; the response's own values, when it has them, must give it too.
            described = ex if any(v.raw is not None or v.words is not None for v in ex.values) else request.example
            word = self.single_word(described, request.address, request.value) if described else c_hex(request.value)
            call = f"regmap_rtu_parse_write_single_response(frame, sizeof frame, {slave}, {address}, {word}, &exception)"
        elif request.function == HOLDING.write_multiple:
            count = c_unsigned(request.count)
            call = f"regmap_rtu_parse_write_multiple_response(frame, sizeof frame, {slave}, {address}, {count}, &exception)"
        else:
            call = f"regmap_rtu_check_response(frame, sizeof frame, {slave}, 0x{request.function:02X}u, &exception)"
        return FrameCase(**base, call=call, status=status, exception=exception, checks=tuple(checks), scaled=tuple(scaled))

    def exception_name(self, code: int) -> str:
        e = self.device.transport.exception(code)
        if e is not None:
            return CIdentifier(self.ctx.prefix, "EXCEPTION", e.name)
        return STANDARD_EXCEPTION_MACROS.get(code, f"0x{code:02X}u")

    def read_checks(self, ex: Example, start: int, count: int) -> tuple[list[Check], list[ScaledCheck]]:
        """Checks that the words a read response carries give each value the example records."""
        checks: list[Check] = []
        scaled: list[ScaledCheck] = []
        base = self.address(start)
        for v, own, index in self.carried(ex, start, count, high_word=False):
            reg = v.register
            if v.words is not None:
                for _, offset, given in _given_words(reg, v.words, own, "the response"):
                    checks.append(Check(f"{reg.name} word {offset}", f"word_at(words, {count}u, {index} + {offset}u)", given))
                continue
            raw = v.raw
            assert raw is not None
            if len(own) != reg.words:
                raise _FrameError(f"the response carries only part of {reg.name}, the example gives its whole raw value")
            word = f"word_at(words, {count}u, {index})"
            if reg.words == 1:
                raw_expr = f"regmap_s16_from_word({word})" if reg.signed else word
            else:
                func = "regmap_s32_from_words" if reg.signed else "regmap_u32_from_words"
                raw_expr = f"{func}(at(words, {count}u, {index}, 2u), {self.ctx.member_const(reg, 'WORD_ORDER')})"
            checks.append(Check(reg.name, raw_expr, c_raw(raw, reg.signed)))
            if reg.paired and reg.first_address >= start:
                high = f"word_at(words, {count}u, (unsigned)({self.ctx.pair_addr(reg)} - {base}))"
                signed = self.ctx.member_const(reg, "SIGNED")
                checks.append(Check(f"{reg.name} high word", high, f"regmap_pair_high_word({word}, {signed})"))
            if reg.bitfields and reg.words == 1:
                owner = self.ctx.owner(reg)
                for b in reg.bitfields:
                    getter = CSymbol(self.ctx.lower, owner, "get", b.name)
                    checks.append(Check(f"{reg.name}.{b.name}", f"{getter}({word})", c_unsigned((raw & b.mask) >> b.lsb)))
            elif reg.enum is not None and isinstance(v.value, str) and reg.enum.member(v.value) is not None:
                checks.append(Check(f"{reg.name} = {v.value}", raw_expr, CIdentifier(self.ctx.prefix, reg.enum.name, v.value)))
            elif isinstance(v.value, int | float) and not isinstance(v.value, bool) and reg.enum is None:
                scaled.append(ScaledCheck(reg.name, raw_expr, self.ctx.member_const(reg, "SCALE"), repr(float(v.value))))
        return checks, scaled


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


def _request_from_response(frame: bytes) -> _Request:
    """For a response that names no request: what the frame itself says it answers."""
    function = frame[1] & ~EXCEPTION_FLAG & 0xFF
    if function == HOLDING.read and not frame[1] & EXCEPTION_FLAG:
        return _Request(function, 0, max(1, frame[2] // 2))
    if len(frame) == 8:
        field = int.from_bytes(frame[4:6], "big")
        return _Request(function, int.from_bytes(frame[2:4], "big"), field, value=field)
    return _Request(function, 0, 1)


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
    return environment().get_template("c/frames_test.c.jinja").render(**frames_test_context(device))
