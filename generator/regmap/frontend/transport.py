"""The map's transport section, checked against its registers for the cross-reference stage."""

from __future__ import annotations

from typing import Any, Protocol

from regmap.frontend.alignment import read_alignment, swap_value_problems
from regmap.frontend.functions import identification, served_function_problems, server_id
from regmap.frontend.stages import Problems
from regmap.frontend.values import _source, serial_choices
from regmap.frontend.yamlsource import Path
from regmap.model import BadCrc, ModbusException, Register, TimingRow, Transport, WordOrder, WordOrderRegister
from regmap_runtime.spaces import MAX_READ_BITS, MAX_WRITE_BITS, SPACES


class ReferenceHost(Protocol):
    """What the cross-reference stage lends: its problems, the registers, and selector lookup."""

    problems: Problems
    registers: list[Register]
    register_paths: tuple[Path, ...]

    def _ref(self, selector: str, by_selector: dict[str, Register], path: Path, what: str) -> Register | None: ...


def elaborate_transport(host: ReferenceHost, t: dict[str, Any], by_selector: dict[str, Register]) -> Transport:
    path: Path = ("transport",)
    serial = t["serial"]
    rates, parities = serial_choices(serial, lambda key, message: host.problems.add((*path, "serial", key), message))
    ids = t["slave_ids"]
    if ids["min"] > ids["max"]:
        host.problems.add((*path, "slave_ids", "min"), f"slave id min {ids['min']} is greater than max {ids['max']}")
    word_order_register = None
    if "word_order_register" in t:
        word_order_register = _word_order_register(host, t, by_selector)
    max_bytes = t.get("max_message_bytes")
    if max_bytes is not None:
        if 5 + 2 * t["max_read_registers"] > max_bytes:
            host.problems.add(
                (*path, "max_read_registers"),
                f"a read response of {t['max_read_registers']} registers is {5 + 2 * t['max_read_registers']} bytes, more than max_message_bytes {max_bytes}",
            )
        if 9 + 2 * t["max_write_registers"] > max_bytes:
            host.problems.add(
                (*path, "max_write_registers"),
                f"a write request of {t['max_write_registers']} registers is {9 + 2 * t['max_write_registers']} bytes, more than max_message_bytes {max_bytes}",
            )
    _check_space_limits(host, t, max_bytes)
    for where, message in served_function_problems(t):
        host.problems.add(where, message)
    codes = [e["code"] for e in t.get("exceptions", [])]
    for i, code in enumerate(codes):
        if code in codes[:i]:
            host.problems.add((*path, "exceptions", i, "code"), f"duplicate exception code 0x{code:02X}")
    crc = t.get("bad_crc", {"reply": "silent"})
    if crc["reply"] == "exception" and crc["code"] not in codes:
        listed = ", ".join(f"0x{c:02X}" for c in codes) or "none"
        host.problems.add(
            (*path, "bad_crc", "code"),
            f"bad_crc answers exception 0x{crc['code']:02X}, which transport.exceptions does not list (listed: {listed})",
        )
    bad_crc = BadCrc(reply=crc["reply"], code=crc.get("code"), source=_source(crc.get("source")), notes=crc.get("notes", ""))
    return Transport(
        baud=serial["baud"],
        baud_rates=rates,
        parity=serial["parity"],
        parities=parities,
        data_bits=serial["data_bits"],
        stop_bits=serial["stop_bits"],
        slave_min=ids["min"],
        slave_max=ids["max"],
        broadcast_id=t.get("broadcast_id"),
        function_codes=tuple(t["function_codes"]),
        max_read_registers=t["max_read_registers"],
        max_write_registers=t["max_write_registers"],
        max_message_bytes=max_bytes,
        word_order=WordOrder(t["word_order"]),
        byte_order=WordOrder(t.get("byte_order", "high_first")),
        max_read_coils=t.get("max_read_coils", MAX_READ_BITS),
        max_write_coils=t.get("max_write_coils", MAX_WRITE_BITS),
        word_order_register=word_order_register,
        read_alignment=read_alignment(host, t, by_selector),
        crc_byte_order=t.get("crc_byte_order", "low_first"),
        undocumented_addresses=t.get("undocumented_addresses", "reject"),
        bad_crc=bad_crc,
        response_delay_ms=t.get("response_delay_ms"),
        timing=tuple(TimingRow(**row) for row in t.get("timing", [])),
        exceptions=tuple(
            ModbusException(code=e["code"], name=e["name"], title=e["title"], title_zh=e.get("title_zh"), source=_source(e.get("source")))
            for e in t.get("exceptions", [])
        ),
        identification=identification(t.get("identification")),
        server_id=server_id(t.get("server_id")),
        source=_source(t.get("source")) + _source(serial.get("source")),
        notes="\n".join(x for x in (t.get("notes", ""), serial.get("notes", "")) if x),
    )


def _check_space_limits(host: ReferenceHost, t: dict[str, Any], max_bytes: int | None) -> None:
    """Every function code the map's registers need is one the device lists, and bit requests fit its messages."""
    path: Path = ("transport",)
    listed = set(t["function_codes"])
    needed: dict[int, Register] = {}
    writers: dict[tuple[int, ...], Register] = {}
    for reg in host.registers:
        space = SPACES[reg.space]
        if reg.access.readable:
            needed.setdefault(space.read, reg)
        codes = tuple(c for c in (space.write_single, space.write_multiple) if c is not None)
        if reg.access.writable and codes and not listed & set(codes):  # a read-only space: reported on the register
            writers.setdefault(codes, reg)
    for code, reg in sorted(needed.items()):
        if code not in listed:
            host.problems.add(
                (*path, "function_codes"),
                f"{reg.name} is in {SPACES[reg.space].title}, which are read with function 0x{code:02X}; function_codes does not list it",
            )
    for codes, reg in sorted(writers.items()):
        either = " or ".join(f"0x{c:02X}" for c in codes)
        host.problems.add(
            (*path, "function_codes"),
            f"{reg.name} is writable (access {reg.access.value}) in {SPACES[reg.space].title}, which are written with {either}; function_codes lists neither",
        )
    if max_bytes is None:
        return
    for key, fixed, what in (("max_read_coils", 5, "a read response"), ("max_write_coils", 9, "a write request")):
        if key in t and fixed + (t[key] + 7) // 8 > max_bytes:
            host.problems.add(
                (*path, key),
                f"{what} of {t[key]} coils is {fixed + (t[key] + 7) // 8} bytes, more than max_message_bytes {max_bytes}",
            )


def _word_order_register(host: ReferenceHost, t: dict[str, Any], by_selector: dict[str, Register]) -> WordOrderRegister | None:
    path: Path = ("transport",)
    w = t["word_order_register"]
    reg = host._ref(w["register"], by_selector, (*path, "word_order_register", "register"), "word_order_register")
    if reg is None:
        return None
    if "swap_value" in w:
        for where, message in swap_value_problems(t, reg):
            host.problems.add(where, message)
        return WordOrderRegister(register=reg, swap_value=w["swap_value"])
    control = WordOrderRegister(register=reg, high_first=w["high_first"], low_first=w["low_first"])
    if reg.default is not None and reg.default not in (w["high_first"], w["low_first"]):
        host.problems.add(
            (*path, "word_order_register"),
            f"word_order_register: the default {reg.default} of {reg.name} is neither the high_first value {w['high_first']} nor the low_first value {w['low_first']}",
        )
    elif reg.default is not None:
        configured = "high_first" if reg.default == w["high_first"] else "low_first"
        if configured != t["word_order"]:
            host.problems.add(
                (*path, "word_order"),
                f"word_order {t['word_order']} disagrees with the default of {reg.name} ({reg.default} = {configured})",
            )
    return control
