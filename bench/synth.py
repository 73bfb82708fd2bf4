"""Synthetic but valid maps of any size, shaped like the real ones, for generation-speed runs.

Like the real maps, about a third of the registers are listed one by one (scaled values with units
and ranges, enums, signed 32-bit values, a few bitfield registers, English and Chinese titles, gaps
between blocks) and the rest come from parameter tables (arrays). The mix is the same at every size,
so the growth ratio measures the generator, not a change of input. The front end refuses maps of
more than 200k YAML values; arrays keep the 50k-register map far below that, as they do in real maps.
"""

from __future__ import annotations

from pathlib import Path

LISTED_SHARE = 0.3  # registers listed one by one; the rest are array elements
GROUP_SIZE = 100
ENUMS = 20
ENUM_MEMBERS = 5
ARRAY_ELEMENTS = 50

# One array element: 10 members, 11 words (one s32).
MEMBERS = [
    "{name: mode, word_offset: 0, title: Mode, title_zh: 模式, enum: choice_0, default: 0}",
    "{name: position, word_offset: 1, type: s32, title: Target position, title_zh: 位置, unit: pulse, min: -2000000000, max: 2000000000, default: 0}",
    "{name: speed, word_offset: 3, type: s16, title: Speed, title_zh: 速度, unit: rpm, min: -6000, max: 6000, default: 60}",
    "{name: acceleration, word_offset: 4, title: Acceleration time, title_zh: 加速度, unit: ms/Krpm, min: 1, max: 32767, default: 100}",
    "{name: deceleration, word_offset: 5, title: Deceleration time, title_zh: 减速度, unit: ms/Krpm, min: 1, max: 32767, default: 100}",
    "{name: dwell, word_offset: 6, title: Dwell time, title_zh: 停顿时间, unit: ms, min: 0, max: 60000, default: 0}",
    "{name: current, word_offset: 7, title: Current, title_zh: 电流, unit: A, scale: 0.1, min: 0, max: 80, default: 22}",
    "{name: gain, word_offset: 8, title: Gain, title_zh: 增益, scale: 0.01, min: 0, max: 10000, default: 100}",
    "{name: jump, word_offset: 9, title: Next element, title_zh: 跳转, min: 0, max: 1023, default: 0}",
    "{name: flags, word_offset: 10, title: Flags, title_zh: 标志, min: 0, max: 255, default: 0}",
]
MEMBER_WORDS = 11


def _listed(i: int, address: int) -> tuple[str, int]:
    """One listed register (flow style, as the maps write short ones) and the words it takes."""
    name = f"param_{i:05d}"
    title = f"title: Synthetic parameter {i}, title_zh: 合成参数 {i}"
    kind = i % 10
    if kind == 0:
        return f"      - {{name: {name}, address: {address}, type: s32, {title}, unit: pulse, min: -1000000, max: 1000000, default: 0}}", 2
    if kind in (1, 2):
        enum = f"choice_{i % ENUMS}"
        return f"      - {{name: {name}, address: {address}, {title}, enum: {enum}, default: 0}}", 1
    if kind == 3 and i % 100 == 3:
        bits = (
            "bitfields: [{name: enable, bits: 0, title: Enable, title_zh: 使能}, "
            "{name: function, bits: '1-4', title: Function, enum: choice_1}, "
            "{name: inverted, bits: 7, title: Inverted, title_zh: 取反}]"
        )
        return f"      - {{name: {name}, address: {address}, {title}, {bits}}}", 1
    if kind in (3, 4, 5):
        return f"      - {{name: {name}, address: {address}, {title}, unit: A, scale: 0.1, min: 0, max: 80, default: 22}}", 1
    if kind == 6:
        return f"      - {{name: {name}, address: {address}, type: s16, {title}, unit: rpm, min: -6000, max: 6000, default: 0}}", 1
    return f"      - {{name: {name}, address: {address}, {title}, min: 0, max: 65535, default: {i % 1000}}}", 1


def synthetic_map(registers: int, device_id: str | None = None) -> str:
    """YAML text of a valid map with exactly `registers` registers."""
    device_id = device_id or f"synthetic_{registers}"
    elements = round(registers * (1 - LISTED_SHARE)) // len(MEMBERS)
    listed = registers - elements * len(MEMBERS)
    lines = [
        f"# Synthetic map of {registers} registers for `make bench` (bench/synth.py); not a real device.",
        "format: regmap/1",
        "device:",
        f"  id: {device_id}",
        "  vendor: Bench",
        f"  model: Synthetic {registers}",
        "  manual: {title: Synthetic manual, file: synthetic.txt, language: en}",
        "  map_version: 1.0.0",
        "transport:",
        "  serial: {baud: 38400, baud_rates: [9600, 19200, 38400, 115200], parity: none, data_bits: 8, stop_bits: 1, source: '1'}",
        "  slave_ids: {min: 1, max: 247, source: '1'}",
        "  broadcast_id: 0",
        "  function_codes: [0x03, 0x06, 0x10]",
        "  max_read_registers: 125",
        "  max_write_registers: 123",
        "  word_order: high_first",
        "  undocumented_addresses: reject",
        "enums:",
    ]
    for e in range(ENUMS):
        lines += [f"  choice_{e}:", f"    title: Choice {e}", f"    title_zh: 选择 {e}", "    source: '2'", "    values:"]
        lines += [f"      - {{value: {v}, name: option_{v}, title: Option {v}, title_zh: 选项 {v}}}" for v in range(ENUM_MEMBERS)]
    lines.append("groups:")
    address = 0
    for i in range(listed):
        if i % GROUP_SIZE == 0:
            g = i // GROUP_SIZE
            lines += [
                f"  - id: group_{g:04d}",
                f"    title: Parameter group {g}",
                f"    title_zh: 参数组 {g}",
                f"    source: '3.{g}'",
                "    defaults: {type: u16, access: rw}",
                "    registers:",
            ]
        if i % 10 == 9:
            address += 1  # a gap, as between the parameters of the real maps
        line, words = _listed(i, address)
        lines.append(line)
        address += words
    if elements:
        lines += [
            "  - id: tables",
            "    title: Parameter tables",
            "    title_zh: 参数表",
            "    source: '4'",
            "    defaults: {type: u16, access: rw}",
            "    registers:",
        ]
        base = (address + 0x100) & ~0xFF  # the tables start on a fresh page, after a gap
        for a, start in enumerate(range(0, elements, ARRAY_ELEMENTS)):
            count = min(ARRAY_ELEMENTS, elements - start)
            lines += [
                f"      - array: table_{a:03d}",
                f"        title: Table {a}",
                f"        title_zh: 表 {a}",
                "        element_title: 'T{n}'",
                f"        count: {count}",
                f"        base: {base}",
                f"        stride: {MEMBER_WORDS}",
                "        source: '4'",
                "        members:",
            ]
            lines += [f"          - {m}" for m in MEMBERS]
            base += count * MEMBER_WORDS
        if base > 0x10000:
            raise ValueError(f"{registers} registers do not fit the 16-bit address space")
    return "\n".join(lines) + "\n"


def write_synthetic_map(directory: Path, registers: int) -> Path:
    path = directory / f"synthetic_{registers}.yaml"
    path.write_text(synthetic_map(registers), encoding="utf-8")
    return path
