"""`regmap import` of Home Assistant `data_type: custom` sensors: each value the `structure` unpacks is a register,
decoded from the same words to the same value as HA's own `struct.unpack`; what no register can hold is reported."""

from __future__ import annotations

import random
import struct
import subprocess
import sys
from pathlib import Path

import pytest

from regmap.diagnostics import ExitCode
from regmap.frontend import load_map
from regmap.runtime_bridge import runtime_specs
from regmap.tools.configimport.hastruct import StructureError, structure_fields
from regmap_runtime.codec import words_to_raw

# (structure, count): as HA users write them for meters and inverters
READABLE = [
    (">i", 2),
    ("<I", 2),
    (">hhf", 4),
    ("<hHq", 6),
    ("@hi", 4),  # native order: i aligned to 4 bytes, so a pad word after h
    (">2x2h", 3),
    (">4sH", 3),
    ("!d", 4),
    (">eh", 2),  # a half float (HA's float16): an f16
    ("<2e", 2),
]


def _regmap(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([str(Path(sys.executable).with_name("regmap")), *args], capture_output=True, text=True, check=False)


def _config(tmp_path: Path, sensors: str) -> Path:
    config = tmp_path / "configuration.yaml"
    config.write_text("modbus:\n  - name: hub\n    type: tcp\n    host: h\n    port: 502\n    sensors:\n" + sensors, encoding="utf-8")
    return config


@pytest.mark.parametrize(("structure", "count"), READABLE, ids=[s for s, _ in READABLE])
def test_every_value_decodes_as_home_assistant_unpacks_it(tmp_path: Path, structure: str, count: int) -> None:
    config = _config(
        tmp_path,
        f"      - name: Packed\n        address: 100\n        data_type: custom\n        count: {count}\n        structure: '{structure}'\n",
    )
    run = _regmap("import", str(config), "--into", str(tmp_path / "packed.yaml"))
    assert run.returncode == ExitCode.OK, run.stderr + run.stdout
    specs = sorted(runtime_specs(load_map(tmp_path / "packed.yaml")), key=lambda s: s.address)
    rng = random.Random(structure)
    for _ in range(50):
        words = [rng.randrange(0x10000) for _ in range(count)]
        for text in (s for s in specs if s.data_type == "string"):  # text as a device sends it: ASCII
            at = text.address - 100
            words[at : at + text.string_words] = [
                rng.randrange(0x20, 0x7F) << 8 | rng.randrange(0x20, 0x7F) for _ in range(text.string_words)
            ]
        expected = [v for v in struct.unpack(structure, b"".join(w.to_bytes(2, "big") for w in words))]
        got = [words_to_raw(s, words[s.address - 100 : s.address - 100 + s.words]) for s in specs]
        same = [
            (e.rstrip(b"\0").decode("latin-1") == g) if isinstance(e, bytes) else (e == g or (e != e and g != g))
            for e, g in zip(expected, got, strict=True)
        ]
        assert all(same), (structure, words, expected, got)


def test_several_values_are_several_registers_and_the_report_says_so(tmp_path: Path) -> None:
    config = _config(
        tmp_path,
        "      - name: Phase currents\n        address: 10\n        data_type: custom\n        count: 3\n"
        "        structure: '>3h'\n        scale: 0.1\n        unit_of_measurement: A\n",
    )
    run = _regmap("import", str(config), "--into", str(tmp_path / "meter.yaml"))
    assert run.returncode == ExitCode.OK, run.stderr
    regs = load_map(tmp_path / "meter.yaml").registers
    assert [(r.address, r.type.value, float(r.scale), r.unit) for r in regs] == [(a, "s16", 0.1, "A") for a in (10, 11, 12)]
    assert "'>3h' (big endian): 3 values, imported as 3 registers" in run.stdout


@pytest.mark.parametrize(
    ("structure", "count", "reason"),
    [
        (">bb", 1, "does not fill whole registers"),
        (">hb", 2, "is 3 bytes, but count 2 reads 4"),
        (">q", 2, "is 8 bytes, but count 2 reads 4"),
        (">hz", 2, "bad char"),
    ],
)
def test_a_structure_no_register_can_hold_is_refused_with_the_reason(structure: str, count: int, reason: str) -> None:
    with pytest.raises(StructureError, match=reason):
        structure_fields(structure, count)


def test_an_unreadable_structure_is_reported_and_the_rest_imported(tmp_path: Path) -> None:
    config = _config(
        tmp_path,
        "      - name: Bytes\n        address: 1\n        data_type: custom\n        count: 1\n        structure: '>BB'\n"
        "      - name: Plain\n        address: 2\n",
    )
    run = _regmap("import", str(config), "--into", str(tmp_path / "dev.yaml"))
    assert run.returncode == ExitCode.OK, run.stderr
    assert (
        "configuration.yaml:7: Bytes: structure '>BB': 'B' at byte 0 (1 byte(s)) does not fill whole registers: not imported" in run.stdout
    )
    assert [r.address for r in load_map(tmp_path / "dev.yaml").registers] == [2]
