"""`replaced` makes what `dataclasses.replace` makes, without the old record's cached values."""

from __future__ import annotations

import dataclasses

import pytest

from regmap.frontend.copies import replaced
from regmap.frontend.load import load_map
from regmap.model import Group, Register


def _a_register() -> Register:
    device = load_map("maps/c630s.yaml")
    return next(r for g in device.groups for r in g.registers if r.array is None)


def test_a_replaced_register_is_what_dataclasses_replace_makes() -> None:
    reg = _a_register()
    copy = replaced(reg, name="other", address=reg.address + 7)
    standard = dataclasses.replace(reg, name="other", address=reg.address + 7)
    assert copy == standard
    assert list(vars(copy).items()) == list(vars(standard).items())
    assert type(copy) is Register


def test_a_replaced_register_keeps_none_of_the_old_ones_cached_values() -> None:
    reg = _a_register()
    assert reg.first_address == reg.address - (1 if reg.paired else 0)  # cached in the old register's __dict__
    copy = replaced(reg, address=reg.address + 100)
    assert "first_address" not in vars(copy)
    assert copy.first_address == reg.first_address + 100


def test_replaced_refuses_a_field_the_record_has_not() -> None:
    group = Group(id="g", title="G", registers=())
    with pytest.raises(TypeError, match="no init field colour"):
        replaced(group, colour="red")
    assert replaced(group, title="H") == Group(id="g", title="H", registers=())
