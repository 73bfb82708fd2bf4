"""The device pages say which way each enum member goes, which registers act when written and which
commands are destructive; enums without directions keep their table as before."""

from __future__ import annotations

import re

from regmap.backends.markdown.page import render_device
from regmap.frontend import load_map

from conftest import ROOT


def page(name: str) -> str:
    device = load_map(ROOT / "maps" / f"{name}.yaml")
    return render_device(device)[f"{device.id}.md"]


def table_row(text: str, cell: str) -> list[str]:
    """The cells of the first table row whose cells include `cell`."""
    for line in text.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if line.startswith("|") and cell in cells:
            return cells
    raise AssertionError(f"no table row with {cell}")


def section(text: str, anchor: str) -> str:
    start = text.index(f'<a id="{anchor}"></a>')
    following = re.search(r"\n#{2,5} ", text[start:])
    return text[start : start + following.start()] if following else text[start:]


def test_member_direction_column() -> None:
    text = page("idm_rs")
    table = section(text, "enum-pr_trigger")
    assert "| Value | Hex | Name | Direction |" in table
    assert table_row(table, "`done_path_5`")[3] == "read only"
    assert table_row(table, "`start_path_0`")[3] == "write only"
    assert table_row(table, "`running_path_15`")[3] == "read only"
    assert "is a state the device reports and is never written" in table
    assert "Direction" not in section(text, "enum-loop_mode")  # no member goes one way only


def test_trigger_registers_are_marked() -> None:
    text = page("idm_rs")
    assert "| Trigger | a write makes the device act" in section(text, "pr_trigger")
    assert "| Trigger |" in section(text, "array-pr_path-special")  # Pr9.07 maps to Pr8.02
    assert "| Trigger |" not in section(text, "peak_current")
    assert "| Trigger |" in section(page("id243pro"), "virtual_in1")


def test_destructive_commands_are_marked() -> None:
    text = page("c630s")
    assert table_row(text, '<a id="command-software_reset"></a>`software_reset` **destructive**')
    assert table_row(text, '<a id="command-reset_abs_encoder_multiturn"></a>`reset_abs_encoder_multiturn` **destructive**')
    assert table_row(text, '<a id="command-fault_reset"></a>`fault_reset`')
    assert "A **destructive** command loses data or state" in text
