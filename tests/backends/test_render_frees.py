"""A generate run collects cycles rarely (cli/generate.py raises the collector's thresholds), so what a render or a
device's views hold must be freed by reference counting when the caller lets go: a cycle would keep tens of
thousands of view objects until the collector's next pass, which then had to walk them all."""

from __future__ import annotations

import gc
import os
import subprocess
import sys
import weakref
from collections.abc import Iterator
from pathlib import Path

import pytest

from regmap.backends.st.codec import DIALECTS, PLCOPEN
from regmap.backends.st.device import DeviceViews
from regmap.cli.generate import GC_THRESHOLDS
from regmap.frontend import load_map
from regmap.render import templates

from conftest import MAPS, ROOT


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


# `python -m regmap generate`, each pass of the collector written as it starts (the command ends with os._exit).
_PASSES_OF_A_RUN = """
import gc, os, runpy, sys
gc.callbacks.append(lambda phase, info: phase == "start" and os.write(2, f"pass {gc.get_threshold()}\\n".encode()))
sys.argv = ["regmap", "generate", "--out", sys.argv[1], *sys.argv[2:]]
runpy.run_module("regmap", run_name="__main__", alter_sys=True)
"""


def test_a_generate_run_makes_no_collector_pass_while_its_modules_load(tmp_path: Path) -> None:
    """The entry point's first threshold is above what importing the command's modules makes (all of it alive): a
    pass over them while they load, before the run raises the thresholds itself, was 0.7 % of a cold run's CPU."""
    env = {**os.environ, "REGMAP_NO_CACHE": "1"}
    done = subprocess.run(
        [sys.executable, "-c", _PASSES_OF_A_RUN, str(tmp_path / "out"), *map(str, MAPS)],
        capture_output=True,
        text=True,
        env=env,
        check=True,
    )
    passes = [line for line in done.stderr.splitlines() if line.startswith("pass ")]
    default, run = str(gc.get_threshold()), str(GC_THRESHOLDS)
    assert [line for line in passes if line[5:] not in (default, run)] == []
