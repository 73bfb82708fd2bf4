"""f16 in ESPHome: modbus_controller has no FP16 value_type, so a half-float register is read as U_WORD and
converted in a lambda; `esphome config` accepts the package, the lambda (compiled with g++, run) gives every
one of the 65,536 bit patterns the value Python's struct 'e' gives, in both byte orders, and a setting coded
as a half is a select over the half's bits."""

from __future__ import annotations

import math
import shutil
import struct
import subprocess
from pathlib import Path
from typing import Any

import pytest

from regmap.backends.esphome.package import render_package
from regmap.frontend import load_map
from regmap.homeauto.selection import select
from regmap.model import Device

from support.half_map import half, half_bits, write_half_map
from support.homeauto_roundtrip import EVERYTHING
from support.homeauto_yaml import esphome_config, load


@pytest.fixture
def device(tmp_path: Path) -> Device:
    return load_map(write_half_map(tmp_path))


def _package(device: Device) -> str:
    (text,) = render_package(device, select(device, EVERYTHING)).values()
    return text


def _entities(text: str, platform: str) -> dict[int, dict[str, Any]]:
    return {int(e["address"]): e for e in load(text).get(platform, []) if e.get("platform") == "modbus_controller"}


def test_esphome_config_accepts_the_half_floats(esphome: Path, device: Device, tmp_path: Path) -> None:
    esphome_config(esphome, tmp_path, _package(device))


def test_a_half_is_read_as_a_word_and_decoded_as_struct_e(device: Device, tmp_path: Path) -> None:
    compiler = shutil.which("g++")
    if compiler is None:
        pytest.skip("g++ is not installed")
    sensors = _entities(_package(device), "sensor")
    cases = {0x0000: False, 0x0002: True}  # temperature (high byte first), humidity (bytes swapped)
    functions, calls = [], []
    for address, swapped in cases.items():
        entity = sensors[address]
        assert entity["value_type"] == "U_WORD" and "lambda" in entity, entity
        code = getattr(entity["lambda"], "value", entity["lambda"])
        functions.append(f"static float lambda_{address}(Item *item, const std::vector<uint8_t> &data) {{\n{code}\n}}\n")
        first, second = ("b & 0xFF", "b >> 8") if swapped else ("b >> 8", "b & 0xFF")
        calls.append(
            f"for (unsigned b = 0; b < 0x10000u; b++) {{ Item item{{1}}; std::vector<uint8_t> data{{0xAA, "
            f"static_cast<uint8_t>({first}), static_cast<uint8_t>({second})}};\n"
            f'float f = lambda_{address}(&item, data); uint32_t u; std::memcpy(&u, &f, sizeof u); std::printf("%08x\\n", u); }}'
        )
    source = tmp_path / "half.cpp"
    source.write_text(
        "#include <cmath>\n#include <cstdint>\n#include <cstdio>\n#include <cstring>\n#include <vector>\n"
        "struct Item { std::size_t offset; };\n" + "".join(functions) + "int main() {\n" + "\n".join(calls) + "\nreturn 0;\n}\n",
        encoding="utf-8",
    )
    flags = ["-std=gnu++20", "-Wall", "-Wextra", "-Werror", "-fsanitize=undefined", "-fno-sanitize-recover=all"]
    built = subprocess.run([compiler, *flags, str(source), "-o", str(tmp_path / "half")], capture_output=True, text=True, check=False)
    assert built.returncode == 0, built.stderr[-3000:]
    ran = subprocess.run([str(tmp_path / "half")], capture_output=True, text=True, check=False, timeout=120)
    assert ran.returncode == 0 and not ran.stderr, ran.stderr[-3000:]
    lines = ran.stdout.split()
    assert len(lines) == 2 * 0x10000
    for k, line in enumerate(lines):
        got = struct.unpack(">f", int(line, 16).to_bytes(4, "big"))[0]
        expected = half(k % 0x10000)
        if math.isnan(expected):
            assert math.isnan(got), hex(k)
        else:
            assert got == expected and math.copysign(1, got) == math.copysign(1, expected), (hex(k), got, expected)


def test_a_setting_coded_as_a_half_is_a_select_of_its_bits(device: Device) -> None:
    (select_entity,) = [e for e in _entities(_package(device), "select").values() if int(e["address"]) == 0x0101]
    assert select_entity["value_type"] == "U_WORD"
    assert sorted(select_entity["optionsmap"].values()) == sorted(half_bits(float(v)) for v in (0, 1, 2))
