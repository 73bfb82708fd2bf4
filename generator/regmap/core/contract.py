"""`regmap export`: the elaborated model as JSON. Its shape is a documented contract (README)."""

from __future__ import annotations

from collections.abc import Sequence
from fractions import Fraction
from typing import Any

from regmap.model import Bitfield, Device, EnumType, Example, FirmwareGate, Register, Transport


def _scale(scale: Fraction) -> int | float:
    return int(scale) if scale.denominator == 1 else float(scale)


def _gate(gate: FirmwareGate | None) -> dict[str, str | None] | None:
    return None if gate is None else {"from": gate.first, "until": gate.until}


def _enum(e: EnumType) -> dict[str, Any]:
    return {
        "title": e.title,
        "title_zh": e.title_zh,
        "source": list(e.source),
        "values": [
            {"value": m.value, "name": m.name, "title": m.title, "title_zh": m.title_zh, "symbol": m.symbol, "description": m.description}
            for m in e.members
        ],
    }


def _bitfield(b: Bitfield) -> dict[str, Any]:
    return {
        "name": b.name,
        "lsb": b.lsb,
        "msb": b.msb,
        "mask": b.mask,
        "title": b.title,
        "title_zh": b.title_zh,
        "description": b.description,
        "enum": b.enum.name if b.enum else None,
    }


def na_json(r: Register) -> list[int | float | str]:
    """The register's "not available" markers as a map spells them: raw values, and `nan` for any NaN."""
    return [*r.na, *(["nan"] if r.na_nan else [])]


def register_json(r: Register) -> dict[str, Any]:
    return {
        "name": r.name,
        "param": r.param,
        "address": r.address,
        "words": r.words,
        "type": r.type.value,
        "word_order": r.word_order.value if r.wide else None,
        "word_order_fixed": r.word_order_fixed,
        "paired": r.paired,
        "access": r.access.value,
        "unit": r.unit,
        "scale": _scale(r.scale),
        "min": r.min,
        "max": r.max,
        "default": r.default,
        "enum": r.enum.name if r.enum else None,
        "bitfields": [_bitfield(b) for b in r.bitfields],
        "takes_effect": r.takes_effect,
        "settable": r.settable,
        "modes": list(r.modes),
        "group": r.group,
        "array": None if r.array is None else {"name": r.array.array, "index": r.array.index, "member": r.array.member},
        "title": r.title,
        "title_zh": r.title_zh,
        "description": r.description,
        "range_text": r.range_text,
        "source": list(r.source),
        "notes": r.notes,
        "errata": list(r.errata),
        # appended, never inserted: a reader of the older shape still finds every key it knew
        "space": r.space,
        "byte_order": r.byte_order.value if r.type.info.has_byte_order else None,
        "offset": _scale(r.offset),
        "encoding": r.encoding if r.type.is_string else None,
        "padding": r.padding if r.type.is_string else None,
        "firmware": _gate(r.firmware),
        "poll": r.poll.value,
        "na": na_json(r),
        "zone": r.zone,
        "scale_from": r.scale_from,  # value = raw x 10^(this register's raw value), read at run time; `scale` is then 1
    }


def _word_order_register_json(t: Transport) -> dict[str, Any] | None:
    w = t.word_order_register
    if w is None:
        return None
    if w.swap_value is not None:
        return {"register": w.register.name, "swap_value": w.swap_value}
    return {"register": w.register.name, "high_first": w.high_first, "low_first": w.low_first}


def _transport_json(t: Transport) -> dict[str, Any]:
    return {
        "baud": t.baud,
        "baud_rates": list(t.baud_rates),
        "parity": t.parity,
        "data_bits": t.data_bits,
        "stop_bits": t.stop_bits,
        "slave_ids": {"min": t.slave_min, "max": t.slave_max},
        "broadcast_id": t.broadcast_id,
        "function_codes": list(t.function_codes),
        "max_read_registers": t.max_read_registers,
        "max_write_registers": t.max_write_registers,
        "max_message_bytes": t.max_message_bytes,
        "word_order": t.word_order.value,
        "word_order_register": _word_order_register_json(t),
        "read_alignment": None
        if t.read_alignment is None
        else {
            "words": t.read_alignment.words,
            "spaces": list(t.read_alignment.spaces),
            "exception": t.read_alignment.exception,
            "exempt": [r.name for r in t.read_alignment.exempt],
        },
        "crc_byte_order": t.crc_byte_order,
        "undocumented_addresses": t.undocumented_addresses,
        "response_delay_ms": t.response_delay_ms,
        "exceptions": [{"code": e.code, "name": e.name, "title": e.title, "title_zh": e.title_zh} for e in t.exceptions],
        "byte_order": t.byte_order.value,
        "max_read_coils": t.max_read_coils,
        "max_write_coils": t.max_write_coils,
    }


def _device_json(device: Device) -> dict[str, Any]:
    info = device.info
    return {
        "id": info.id,
        "vendor": info.vendor,
        "vendor_zh": info.vendor_zh,
        "model": info.model,
        "description": info.description,
        "manual": {
            "title": info.manual_title,
            "version": info.manual_version,
            "file": info.manual_file,
            "language": info.manual_language,
        },
        "firmware": info.firmware,
        "map_version": info.map_version,
        "fingerprint": device.fingerprint,
        "transport": _transport_json(device.transport),
        "firmware_register": None
        if info.firmware_register is None
        else {
            "register": info.firmware_register.register.name,
            "format": info.firmware_register.format,
            "decimals": info.firmware_register.decimals,
        },
    }


def _examples_json(examples: Sequence[Example]) -> list[dict[str, Any]]:
    return [
        {
            "id": x.id,
            "source": list(x.source),
            "direction": x.direction,
            "frame": x.frame.hex(" ").upper(),
            "request": x.request,
            "meaning": x.meaning,
            "values": [
                {"register": v.register.name, "raw": v.raw, "words": None if v.words is None else list(v.words), "value": v.value}
                for v in x.values
            ],
            "erratum": x.erratum,
            "corrected_frame": None if x.corrected_frame is None else x.corrected_frame.hex(" ").upper(),
        }
        for x in examples
    ]


def export_json(device: Device) -> dict[str, Any]:
    return {
        "device": _device_json(device),
        "groups": [{"id": g.id, "title": g.title, "title_zh": g.title_zh, "source": list(g.source)} for g in device.groups],
        "arrays": [
            {
                "name": a.name,
                "title": a.title,
                "count": a.count,
                "index_base": a.index_base,
                "base": a.base,
                "stride": a.stride,
                "members": [{"name": m.name, "offset": m.offset, "words": m.words} for m in a.members],
            }
            for a in device.arrays
        ],
        "registers": [register_json(r) for r in device.registers],
        "enums": {e.name: _enum(e) for e in device.enums},
        "commands": [
            {
                "name": c.name,
                "title": c.title,
                "title_zh": c.title_zh,
                "register": c.register.name,
                "address": c.register.address,
                "value": c.value,
                "argument": None if c.argument is None else {"name": c.argument.name, "min": c.argument.min, "max": c.argument.max},
                "source": list(c.source),
            }
            for c in device.commands
        ],
        "faults": [
            {
                "code": f.code,
                "value": f.value,
                "name": f.name,
                "title": f.title,
                "title_zh": f.title_zh,
                "kind": f.kind,
                "resettable": f.resettable,
                "source": list(f.source),
            }
            for f in device.faults
        ],
        "examples": _examples_json(device.examples),
        "errata": [
            {
                "id": e.id,
                "title": e.title,
                "readings": [{"source": list(r.source), "says": r.says} for r in e.readings],
                "choice": e.choice,
                "reason": e.reason,
                "registers": list(e.registers),
            }
            for e in device.errata
        ],
    }
