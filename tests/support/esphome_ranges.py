"""The reads ESPHome's modbus_controller makes of a validated config: a port of `create_register_ranges_()`
(esphome/components/modbus_controller/modbus_controller.cpp), written here apart from the back end.

Items are sorted by register type, force_new_range first, then start address and byte offset; an item
joins the current range when it is not force_new_range and either re-reads the previous item's words (same
start and count) or starts where the range ends; an item at the range's start address joins it as it is."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

# value_type -> registers (modbus_controller's TYPE_REGISTER_MAP)
TYPE_WORDS = {"U_WORD": 1, "S_WORD": 1, "U_DWORD": 2, "S_DWORD": 2, "U_DWORD_R": 2, "S_DWORD_R": 2, "FP32": 2, "FP32_R": 2}
TYPE_WORDS |= {"U_QWORD": 4, "S_QWORD": 4, "U_QWORD_R": 4, "S_QWORD_R": 4, "RAW": 1}
TYPE_ORDER = {"custom": 0, "coil": 1, "discrete_input": 2, "holding": 3, "read": 4}  # ModbusRegisterType's values
PLATFORMS = ("sensor", "binary_sensor", "text_sensor", "number", "select", "switch", "output")


@dataclass
class Item:
    name: str
    register_type: str
    start: int
    count: int
    offset: int  # bytes (bits for coils and discrete inputs)
    force: bool
    size: int
    address: int = 0  # where the item's own value starts, as configured: start + offset / 2


@dataclass
class Range:
    register_type: str
    start: int
    count: int
    items: list[Item] = field(default_factory=list)


def items_of(config: dict[str, Any]) -> list[Item]:
    out = []
    for platform in PLATFORMS:
        for e in config.get(platform, []) or []:
            if e.get("platform") != "modbus_controller" or "address" not in e:
                continue
            kind = str(e.get("register_type", "holding"))
            count = int(e.get("register_count") or TYPE_WORDS.get(str(e.get("value_type", "U_WORD")), 1))
            bits = kind in ("coil", "discrete_input")
            size = 1 if bits else int(e.get("response_size") or 0) or 2 * count
            offset = int(e.get("offset", 0) or 0)
            start = int(e["address"])
            own = start + (offset if bits else offset // 2)
            out.append(Item(str(e.get("id", e.get("name"))), kind, start, count, offset, bool(e.get("force_new_range")), size, own))
    return out


def ranges(items: list[Item]) -> list[Range]:
    order = sorted(items, key=lambda i: (TYPE_ORDER[i.register_type], not i.force, i.start, i.offset))
    out: list[Range] = []
    current: Range | None = None
    prev: Item | None = None
    buffer_offset = 0
    index = 0
    while index < len(order):
        curr = order[index]
        if current is None:
            current = Range(curr.register_type, curr.start, curr.count)
            buffer_offset = curr.size
        elif not curr.force and current.register_type == curr.register_type and prev is not None:
            if curr.start == current.start + current.count - prev.count and curr.count == prev.count and curr.size == prev.size:
                curr.start, curr.offset = current.start, curr.offset + prev.offset
            elif curr.start == current.start + current.count:
                curr.start, curr.offset = current.start, curr.offset + buffer_offset
                buffer_offset += curr.size
                current.count += curr.count
        if curr.start == current.start and curr.register_type == current.register_type:
            current.items.append(curr)
            index += 1
        else:
            out.append(current)
            current, buffer_offset = None, 0
        prev = curr
    if current is not None:
        out.append(current)
    return out
