"""The docs of issue #19's fixture maps: each register's space (with its function codes), type, word and
byte order, offset, firmware gate and poll class appear as the model says; the four-letter byte
orders agree with the bytes of the fixtures' example frames (decoded here with `struct`); the
overview names the spaces, the coil limits, the byte order and the firmware register.

The expected spellings are written out here (≥, ABCD ...), not taken from the back end."""

from __future__ import annotations

import importlib.util
import os
import struct
import subprocess
import sys
from pathlib import Path

import pytest

from regmap.frontend import load_map
from regmap.generate import generate
from regmap.model import ByteOrder, Device, FirmwareGate, PollClass, Register, WordOrder

from conftest import FIXTURE_MAPS, ROOT

SPACE_TITLES = {"holding": "holding registers", "input": "input registers", "coil": "coils", "discrete_input": "discrete inputs"}
READ_CODE = {"holding": "0x03", "input": "0x04", "coil": "0x01", "discrete_input": "0x02"}
WRITE_CODES = {"holding": "0x06/0x10", "coil": "0x05/0x0F"}
QUICK_SPACE = {"holding": "holding", "input": "input", "coil": "coil", "discrete_input": "discrete input"}
ORDERS = {  # (word order, byte order) -> the bytes of a big-endian value ABCD... as they travel
    (1, "high_first", "high_first"): "AB",
    (1, "high_first", "low_first"): "BA",
    (2, "high_first", "high_first"): "ABCD",
    (2, "low_first", "high_first"): "CDAB",
    (2, "high_first", "low_first"): "BADC",
    (2, "low_first", "low_first"): "DCBA",
    (4, "high_first", "high_first"): "ABCDEFGH",
    (4, "low_first", "high_first"): "GHEFCDAB",
    (4, "high_first", "low_first"): "BADCFEHG",
    (4, "low_first", "low_first"): "HGFEDCBA",
}
TYPE_WORDS = {"u16": 1, "s16": 1, "u32": 2, "s32": 2, "f32": 2, "u64": 4, "s64": 4, "f64": 4}
STRUCT = {"u16": ">H", "s16": ">h", "u32": ">I", "s32": ">i", "f32": ">f", "u64": ">Q", "s64": ">q", "f64": ">d"}


def _name(path: Path) -> str:
    return path.relative_to(ROOT).as_posix()


@pytest.fixture(scope="module")
def devices() -> dict[str, Device]:
    return {p.stem: load_map(p, _name(p)) for p in FIXTURE_MAPS}


@pytest.fixture(scope="module")
def docs(devices: dict[str, Device], tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("fixture-docs")
    generate(list(devices.values()), out, ["markdown"], complete=True)
    return out / "docs"


@pytest.fixture(scope="module")
def pages(devices: dict[str, Device], docs: Path) -> dict[str, str]:
    return {stem: (docs / f"{d.id}.md").read_text(encoding="utf-8") for stem, d in devices.items()}


def _section(page: str, anchor: str) -> str:
    start = page.index(f'<a id="{anchor}"></a>')
    line_start = page.rfind("\n", 0, start) + 1
    level = len(page[line_start:start].strip())
    ends = [e for e in (page.find("\n" + "#" * n + " ", start) for n in range(2, level + 1)) if e != -1]
    return page[line_start : min(ends) if ends else len(page)]


def _facts(section: str) -> dict[str, str]:
    """The Item | Value table of a section (its first one)."""
    out: dict[str, str] = {}
    for line in section.split("| Item | Value |", 1)[1].split("\n\n", 1)[0].splitlines()[2:]:
        cells = [c.strip() for c in line.strip("|").split(" | ")]
        out[cells[0]] = " | ".join(cells[1:])
    return out


def _quick_row(page: str, reg: Register) -> dict[str, str]:
    """The register's quick-reference row, by column header."""
    quick = _section(page, "quick-reference")
    anchor = f"(#array-{reg.array.array})" if reg.array else f"(#{reg.name})"
    for table in quick.split("\n\n"):
        lines = [line for line in table.splitlines() if line.startswith("| ")]
        row = next((line for line in lines[1:] if anchor in line), None)
        if row is not None:
            header = [c.strip() for c in lines[0].strip("|").split(" | ")]
            return dict(zip(header, (c.strip() for c in row.strip().strip("|").split(" | ")), strict=True))
    raise AssertionError(f"{reg.name}: no quick-reference row")


def _gate(gate: FirmwareGate) -> str:
    if gate.first and gate.until:
        return f"{gate.first} ≤ firmware < {gate.until}"
    return f"firmware ≥ {gate.first}" if gate.first else f"firmware < {gate.until}"


def _expected_order(reg: Register) -> str:
    return ORDERS[(TYPE_WORDS[reg.type.value], reg.word_order.value if reg.wide else "high_first", reg.byte_order.value)]


def _plain(device: Device) -> list[Register]:
    return [r for r in device.registers if r.array is None]


@pytest.mark.parametrize("stem", [p.stem for p in FIXTURE_MAPS])
def test_each_register_shows_space_type_order_gate_and_poll(stem: str, devices: dict[str, Device], pages: dict[str, str]) -> None:
    device, page = devices[stem], pages[stem]
    swapping = device.transport.byte_order is ByteOrder.LOW_FIRST or any(
        r.byte_order is ByteOrder.LOW_FIRST and not r.type.is_bool for r in device.registers
    )
    several_spaces = {r.space for r in device.registers} != {"holding"}
    gated = any(r.firmware is not None for r in device.registers)
    polled = any(r.poll is not PollClass.NORMAL for r in device.registers)
    for reg in _plain(device):
        facts = _facts(_section(page, reg.name))
        row = _quick_row(page, reg)
        assert facts["Type"].startswith(reg.type.value), (reg.name, facts["Type"])
        assert row["Type"].startswith(reg.type.value), (reg.name, row["Type"])
        # space and function codes: in the quick reference and the details, on a device with several spaces
        if several_spaces:
            # a write-only register (the float meter's word-order switch) names no read code
            used = [READ_CODE[reg.space]] if reg.access.readable else []
            codes = "/".join(used + ([WRITE_CODES[reg.space]] if reg.access.writable else []))
            assert row["Space"] == f"{QUICK_SPACE[reg.space]} {codes}", (reg.name, row)
            read = f"read with {READ_CODE[reg.space]}"
            assert facts["Space"].startswith(f"{SPACE_TITLES[reg.space]}: ") and (read in facts["Space"]) == reg.access.readable, (
                reg.name,
                facts,
            )
            if reg.access.writable:
                assert facts["Space"].endswith("written with " + WRITE_CODES[reg.space])
        else:
            assert "Space" not in row and "Space" not in facts
        # word and byte order: the four-letter name in the type cell where the bytes are swapped (the word
        # order alone already says CDAB there), and in the facts of every wide or swapped value
        if reg.type.value in TYPE_WORDS:
            order = _expected_order(reg)
            wide = TYPE_WORDS[reg.type.value] > 1
            if wide:
                first = "high" if reg.word_order is WordOrder.HIGH_FIRST else "low"
                assert f"{TYPE_WORDS[reg.type.value]} words, {first} first" in row["Type"], (reg.name, row["Type"])
            if reg.byte_order is ByteOrder.LOW_FIRST:
                assert f"({order})" in row["Type"], (reg.name, row["Type"], order)
            else:
                assert "(CDAB)" not in row["Type"] and "(ABCD)" not in row["Type"], (reg.name, row["Type"])
            if swapping or reg.type.value in ("u64", "s64", "f32", "f64"):
                assert facts["Word and byte order"].endswith(": " + order), (reg.name, facts)
        if reg.type.is_string:
            assert (
                f"{reg.words} words = {2 * reg.words} bytes of {reg.encoding.upper().replace('LATIN-1', 'Latin-1')} text" in facts["Type"]
            )
            assert ("space padded" if reg.padding == "space" else "NUL padded") in facts["Type"]
            assert reg.byte_order is ByteOrder.HIGH_FIRST or "bytes swapped" in row["Type"]
        if reg.type.is_bool:
            assert "Word and byte order" not in facts
        # offset beside scale: value = raw × scale + offset
        if reg.offset != 0:
            sign = "−" if reg.offset < 0 else "+"
            assert facts["Scale and offset"].startswith(f"raw × {float(reg.scale):g} {sign} {abs(float(reg.offset)):g} = value"), facts
        # firmware gates and poll classes
        if gated:
            assert row["Firmware"] == (_gate(reg.firmware) if reg.firmware else "—"), (reg.name, row)
        if reg.firmware is not None:
            assert facts["Firmware"].startswith(_gate(reg.firmware)), (reg.name, facts)
        else:
            assert "Firmware" not in facts
        if polled:
            assert row["Poll"] == reg.poll.value and facts["Poll class"].startswith(reg.poll.value + ":"), (reg.name, row, facts)
        else:
            assert "Poll" not in row and "Poll class" not in facts


@pytest.mark.parametrize("stem", [p.stem for p in FIXTURE_MAPS])
def test_array_members_show_their_space(stem: str, devices: dict[str, Device], pages: dict[str, str]) -> None:
    device, page = devices[stem], pages[stem]
    for array in device.arrays:
        first = device.register(f"{array.name}_{array.first_index}_{array.members[0].name}")
        row = _quick_row(page, first)
        assert row["Space"].startswith(QUICK_SPACE[first.space] + " " + READ_CODE[first.space])
        section = _section(page, f"array-{array.name}")
        unit = "bit" if first.space in ("coil", "discrete_input") else "word"
        assert f"| Stride | {array.stride} {unit}{'s' if array.stride != 1 else ''} per element |" in section
        assert f"numbered from {array.index_base}" in section
        assert f"(n − {array.index_base})" in row["Address (dec)"], row


def test_group_level_keys_are_said_once_for_the_group(devices: dict[str, Device], pages: dict[str, str]) -> None:
    meter = _section(pages["power_meter"], "group-power_quality")
    assert meter.split("\n\n")[2] == "Every register of this group: input registers, firmware ≥ 2.00."
    assert "Every register of this group: poll class static." in _section(pages["power_meter"], "group-nameplate")
    drive = _section(pages["swapped_gated"], "group-diagnostics")
    assert "Every register of this group: firmware ≥ 2.5, poll class slow." in drive
    assert "Every register of this group" not in _section(pages["swapped_gated"], "group-control")  # gates differ per register
    assert "Every register of this group: coils." in _section(pages["remote_io"], "group-outputs")


def test_overview_names_spaces_limits_byte_order_and_firmware_register(pages: dict[str, str]) -> None:
    io = _facts(_section(pages["remote_io"], "device-overview"))
    assert io["Spaces"] == (
        "holding registers (0x03/0x06/0x10): 3; input registers (0x04): 1; coils (0x01/0x05/0x0F): 20; discrete inputs (0x02): 22"
    )
    assert io["Max bits per request"] == "read 2000, write 1968 (coils and discrete inputs)"
    assert "Byte order" not in io and "Firmware register" not in io
    drive = _facts(_section(pages["swapped_gated"], "device-overview"))
    assert drive["Byte order"].startswith("low byte first (bytes swapped) in each word") and drive["Byte order"].endswith("DCBA")
    assert (
        drive["Firmware register"]
        == "[`firmware`](#firmware) at `0x0000`: major version in the high byte, minor in the low byte (0x0203 = version 2.3)"
    )
    assert drive["Firmware-gated registers"].startswith("4 registers")
    meter = _facts(_section(pages["power_meter"], "device-overview"))
    assert meter["Firmware register"].endswith("a decimal number with 2 decimals (210 = version 2.10)")
    assert "Spaces" in meter and "Max bits per request" not in meter  # no coils or discrete inputs
    assert "by poll class: static 2, fast 1, normal 4, slow 2" in meter["Reading everything"]
    assert "(raw × scale + offset)" in _section(pages["power_meter"], "quick-reference")


def _frame(hex_text: str) -> bytes:
    return bytes.fromhex(hex_text)


def _letters(value_bytes: bytes, wire: bytes) -> set[str]:
    """Every four-letter order under which `wire` carries `value_bytes` (big-endian, A first)."""
    return {
        name
        for (words, _, _), name in ORDERS.items()
        if 2 * words == len(value_bytes) and bytes(value_bytes[ord(c) - ord("A")] for c in name) == wire
    }


def test_documented_orders_match_the_example_frames(devices: dict[str, Device], pages: dict[str, str]) -> None:
    """Each numeric value an example response carries: the wire bytes, against struct's big-endian bytes
    of the recorded raw value, give the order the page names for its register."""
    checked = []
    for stem, device in devices.items():
        page = pages[stem]
        for ex in device.examples:
            if ex.direction != "response" or ex.frame[1] not in (0x03, 0x04):
                continue
            data = ex.frame[3:-2]
            if ex.request is not None:
                start = int.from_bytes(device.example(ex.request).frame[2:4], "big")
            elif len(ex.values) == 1 and len(data) == 2 * ex.values[0].register.words:
                start = ex.values[0].register.address  # a response printed alone: it carries its one register
            else:
                continue
            for value in ex.values:
                reg = value.register
                if reg.type.value not in STRUCT or not isinstance(value.raw, int | float):
                    continue
                at = 2 * (reg.address - start)
                wire = data[at : at + 2 * reg.words]
                orders = _letters(struct.pack(STRUCT[reg.type.value], value.raw), wire)
                assert orders, f"{ex.id}: {reg.name} raw {value.raw} is not in the frame in any order"
                documented = _expected_order(reg)
                assert documented in orders, (ex.id, reg.name, orders, documented)
                facts = _facts(_section(page, reg.name))
                shown = facts.get("Word and byte order", _quick_row(page, reg)["Type"])
                if documented not in ("AB", "ABCD", "ABCDEFGH") or "Word and byte order" in facts:
                    assert documented in shown, (reg.name, shown)
                checked.append((stem, reg.name, documented))
    assert ("swapped_gated", "position", "DCBA") in checked and ("power_meter", "current_l1", "CDAB") in checked
    assert ("swapped_gated", "firmware", "BA") in checked and ("power_meter", "active_energy", "ABCDEFGH") in checked


def test_string_default_is_escaped_text(devices: dict[str, Device], pages: dict[str, str]) -> None:
    facts = _facts(_section(pages["power_meter"], "meter_label"))
    assert facts["Default"] == '""'
    row = _quick_row(pages["power_meter"], devices["power_meter"].register("meter_label"))
    assert row["Default"] == '""' and row["Type"] == "string, 4 words"


def test_float_range_and_default_in_engineering_units(pages: dict[str, str]) -> None:
    facts = _facts(_section(pages["power_meter"], "demand_period"))
    assert (facts["Range"], facts["Default"]) == ("1 … 3600 s", "900 s")
    assert _facts(_section(pages["power_meter"], "power_factor"))["Range"] == "-1 … 1"
    temperature = _facts(_section(pages["power_meter"], "temperature"))
    assert temperature["Scale and offset"] == "raw × 0.1 − 40 = value in °C"


def test_fixture_pages_build_strict(docs: Path, devices: dict[str, Device], tmp_path: Path) -> None:
    """mkdocs --strict checks every link and anchor of the new columns and facts (and docs/map-format.md)."""
    if importlib.util.find_spec("mkdocs") is None:
        pytest.fail("mkdocs is not installed (pip install -e '.[dev]')")
    result = subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "-f", str(ROOT / "mkdocs.yml"), "-d", str(tmp_path / "site")],
        env={**os.environ, "REGMAP_DOCS_DIR": str(docs)},
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
    )
    output = result.stdout + result.stderr
    assert result.returncode == 0 and "WARNING" not in output, output
    for device in devices.values():
        assert 'id="device-overview"' in (tmp_path / "site" / f"{device.id}.html").read_text(encoding="utf-8")
