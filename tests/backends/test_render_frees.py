"""A generate run collects cycles rarely (cli/generate.py raises the collector's thresholds), so what a render or a
device's views hold must be freed by reference counting when the caller lets go: a cycle would keep tens of
thousands of view objects until the collector's next pass, which then had to walk them all."""

from __future__ import annotations

import gc
import weakref
from collections.abc import Iterator

import pytest

from regmap.backends.st.codec import DIALECTS, PLCOPEN
from regmap.backends.st.device import DeviceViews
from regmap.frontend import load_map
from regmap.render import templates

from conftest import ROOT


@pytest.fixture
def no_collector() -> Iterator[None]:
    gc.collect()
    gc.disable()
    try:
        yield
    finally:
        gc.enable()


class _Given:
    """An object a template is given: it is freed once nothing holds it."""

    label = "given"


def test_a_render_that_defines_a_macro_lets_its_context_go(no_collector: None) -> None:
    env = templates("regmap.backends.python")
    # The macro reads a variable of the render (as the client template's macros read the device): it holds the context.
    template = env.from_string("{% macro show() %}[{{ given.label }}]{% endmacro %}{{ show() }}")
    given = _Given()
    alive = weakref.ref(given)
    assert template.render(given=given) == "[given]"
    del given
    assert alive() is None


def test_a_devices_st_views_are_freed_with_it(no_collector: None) -> None:
    device = load_map(ROOT / "maps" / "idm_rs.yaml")
    views = DeviceViews(device, [])
    for dialect in (*DIALECTS, PLCOPEN):
        views.context(dialect)
    alive = weakref.ref(views)
    del views
    assert alive() is None
