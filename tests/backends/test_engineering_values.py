"""`eng` prints a raw value as the documents print its engineering value; a register without scale or offset (most
of them) takes a shortcut past the fraction arithmetic (issue #36), which must print what the arithmetic prints."""

from __future__ import annotations

import dataclasses
from fractions import Fraction

from hypothesis import given
from hypothesis import strategies as st

from regmap.core.text import eng, number
from regmap.frontend import load_map
from regmap.model import Register

from conftest import MAPS

NUMERIC = [reg for path in MAPS for reg in load_map(path).registers if not reg.type.is_string and not reg.type.is_bool and reg.zone is None]
# Each register as the map has it, and with a scale and offset of every kind (none, only one, both).
REGISTERS = st.builds(
    lambda reg, scale, offset: dataclasses.replace(reg, scale=scale, offset=offset),
    st.sampled_from(NUMERIC),
    st.sampled_from([Fraction(1), Fraction(1, 10), Fraction(5), Fraction(1, 3)]),
    st.sampled_from([Fraction(0), Fraction(-40), Fraction(1, 2)]),
)


@given(st.one_of(st.sampled_from(NUMERIC), REGISTERS), st.integers(-(2**64), 2**64))
def test_an_integer_raw_value_prints_its_exact_engineering_value(reg: Register, raw: int) -> None:
    assert eng(reg, raw) == number(Fraction(raw) * reg.scale + reg.offset)
