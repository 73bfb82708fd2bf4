"""A value table says which registers use it, whether a register holds the enum or one of its bitfields does."""

from __future__ import annotations

from regmap.backends.markdown.page import render_device
from regmap.frontend import load_map

from conftest import ROOT


def used_by(name: str, enum: str) -> str:
    device = load_map(ROOT / "maps" / f"{name}.yaml")
    text = render_device(device)[f"{device.id}.md"]
    table = text[text.index(f'<a id="enum-{enum}"></a>') :]
    return next(line for line in table.splitlines() if line.startswith("Used by: "))


def test_a_table_only_bitfields_use_lists_their_registers_and_fields() -> None:
    device = load_map(ROOT / "maps" / "idm_rs.yaml")
    users = [(r, b) for r in device.registers for b in r.bitfields if b.enum is not None and b.enum.name == "di_function"]
    assert users and not any(r.enum is not None and r.enum.name == "di_function" for r in device.registers)
    line = used_by("idm_rs", "di_function")
    for reg, field in users:  # DI1 ... DI7 in the map
        assert f"[`{reg.name}`](#{reg.name}) bits {field.bits_text} (`{field.name}`)" in line
    assert line.count(" bits ") == len(users)


def test_a_table_a_register_holds_lists_that_register() -> None:
    device = load_map(ROOT / "maps" / "c630s.yaml")
    reg, enum = next((r, r.enum) for r in device.registers if r.enum is not None and r.array is None)
    assert f"[`{reg.name}`](#{reg.name})" in used_by("c630s", enum.name)
