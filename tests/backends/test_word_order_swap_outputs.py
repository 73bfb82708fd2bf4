"""The float meter's word-order switch (a magic float, `word_order_register.swap_value`) and its read alignment
as the C header, the ST constants and the Markdown page give them (tests/maps/fixtures/float_meter.yaml)."""

from __future__ import annotations

import re
import struct
import subprocess
from pathlib import Path

from regmap.backends.c import render_device as c_files
from regmap.backends.c import render_shared
from regmap.backends.markdown import render_device as md_files
from regmap.backends.st import render_device as st_files
from regmap.frontend import load_map

from conftest import ROOT, require_tool

DEVICE = load_map(ROOT / "tests" / "maps" / "fixtures" / "float_meter.yaml")
PREFIX = "FIXTURE_FLOAT_METER"


def test_the_c_header_gives_the_swap_value_and_it_encodes_as_the_magic_float(tmp_path: Path) -> None:
    for rel, text in {**render_shared([DEVICE]), **c_files(DEVICE)}.items():
        (tmp_path / rel).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / rel).write_text(text, encoding="utf-8")
    header = next(text for rel, text in c_files(DEVICE).items() if rel.endswith(".h"))
    assert re.search(rf"#define {PREFIX}_WORD_ORDER_REGISTER_SWAP +2141\.0f ", header)
    assert f"{PREFIX}_WORD_ORDER_REGISTER_HIGH_FIRST" not in header
    program = tmp_path / "swap.c"
    program.write_text(
        f"""#define {PREFIX}_IMPLEMENTATION
#include <stdio.h>
#include "{DEVICE.id}.h"
int main(void) {{
    uint16_t hi[2], lo[2];
    regmap_f32_to_wire({PREFIX}_WORD_ORDER_REGISTER_SWAP, REGMAP_HIGH_FIRST, REGMAP_HIGH_FIRST, hi);
    regmap_f32_to_wire({PREFIX}_WORD_ORDER_REGISTER_SWAP, REGMAP_LOW_FIRST, REGMAP_HIGH_FIRST, lo);
    printf("%04X %04X %04X %04X %04X\\n", (unsigned){PREFIX}_WORD_ORDER_REGISTER_ADDR, hi[0], hi[1], lo[0], lo[1]);
    return 0;
}}
""",
        encoding="utf-8",
    )
    gcc = require_tool("gcc")
    built = subprocess.run(
        [gcc, "-std=c99", "-Wall", "-Wextra", "-Werror", f"-I{tmp_path}", str(program), "-o", str(tmp_path / "swap")],
        capture_output=True,
        text=True,
        check=False,
    )
    assert built.returncode == 0, built.stderr
    ran = subprocess.run([str(tmp_path / "swap")], capture_output=True, text=True, check=True)
    high, low = struct.unpack(">HH", struct.pack(">f", 2141.0))
    assert ran.stdout.split() == ["0110", f"{high:04X}", f"{low:04X}", f"{low:04X}", f"{high:04X}"]


def test_the_st_constants_give_the_swap_value() -> None:
    text = "\n".join(t for rel, t in st_files(DEVICE).items() if rel.endswith("_constants.st"))
    assert re.search(rf"{PREFIX}_WORD_ORDER_SWAP : REAL := 2141\.0;", text), text[:2000]
    assert re.search(rf"{PREFIX}_WORD_ORDER_REGISTER_ADDR : UINT := 16#0110;", text)


def test_the_page_states_the_swap_and_the_alignment() -> None:
    (page,) = (t for rel, t in md_files(DEVICE).items() if rel.endswith(".md"))
    assert "| Word-order register | [`word_order_swap`](#word_order_swap): writing 2141.0 swaps the word order" in page
    assert re.search(
        r"\| Read alignment \| reads of holding registers and input registers start on an address that is a multiple of 2", page
    )
    assert "the device answers exception 0x02 otherwise" in page and "may be read alone: [`ct_ratio`](#ct_ratio)" in page
