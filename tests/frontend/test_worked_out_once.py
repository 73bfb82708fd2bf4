"""Facts the model works out once (issue #36) say what their sources say, however often and in whatever order they
are asked: a data type's facts from the runtime's table, an access's from its letters, read_all()'s plan of a device
from its registers, and `regmap generate` leaves a caller's garbage-collector settings as it found them."""

from __future__ import annotations

import gc
from dataclasses import replace
from pathlib import Path

from regmap.cli import main
from regmap.frontend import load_map
from regmap.model import Access, DataType, PollClass
from regmap.runtime_bridge import read_plan
from regmap_runtime.plan import ReadBlock
from regmap_runtime.types import TYPES

from conftest import MAPS

FACTS = ("words", "wide", "bits", "signed", "raw_min", "raw_max", "kind", "numeric", "is_float", "is_string", "is_bool", "is_timestamp")


def test_each_data_type_carries_the_runtime_tables_facts() -> None:
    for data_type in DataType:
        info = TYPES[data_type.value]
        assert data_type.info is info
        for fact in FACTS:
            assert getattr(data_type, fact) == getattr(info, fact), (data_type, fact)


def test_each_access_reads_and_writes_as_its_letters_say() -> None:
    assert [(a.value, a.readable, a.writable) for a in Access] == [("r", True, False), ("rw", True, True), ("w", False, True)]


def test_a_register_changed_by_replace_is_measured_again() -> None:
    device = load_map(MAPS[0])
    wide = next(r for r in device.registers if r.wide)
    assert (wide.words, wide.last_address) == (wide.type.words, wide.address + wide.type.words - 1)
    narrowed = replace(wide, type=DataType.U16, address=wide.address + 7, paired=False)
    assert (narrowed.words, narrowed.wide, narrowed.last_address, narrowed.first_address) == (1, False, wide.address + 7, wide.address + 7)


def _blocks(plan: list[ReadBlock]) -> list[tuple[str, int, int, tuple[str, ...]]]:
    return [(b.space, b.address, b.count, tuple(s.name for s in b.registers)) for b in plan]


def test_the_whole_plan_planned_once_is_the_plan_of_that_device_only() -> None:
    """read_all()'s plan is kept per device; a narrower question (registers, a poll class) is never answered from it,
    and neither is another device's, nor a changed copy's."""
    device = load_map(MAPS[0])
    whole = _blocks(read_plan(device))
    assert _blocks(read_plan(device)) == whole
    kept = read_plan(device)
    kept.clear()  # a caller's list is its own: emptying it leaves the kept plan whole
    assert _blocks(read_plan(device)) == whole
    fast = {r.name for r in device.registers if r.poll is PollClass.FAST and r.access.readable}
    assert fast != {name for block in whole for name in block[3]}  # the poll-class question has another answer
    assert {name for block in _blocks(read_plan(device, poll=PollClass.FAST)) for name in block[3]} == fast
    one = next(r for r in device.registers if r.access.readable)
    assert [b[3] for b in _blocks(read_plan(device, [one]))] == [(one.name,)]
    fewer = replace(device, registers=device.registers[1:])
    assert _blocks(read_plan(fewer)) != whole
    other = load_map(MAPS[1])
    assert _blocks(read_plan(other)) != whole


def test_generate_leaves_the_callers_garbage_collector_settings(tmp_path: Path) -> None:
    before = gc.get_threshold()
    gc.set_threshold(1234, 5, 6)
    try:
        assert main(["generate", str(MAPS[0]), "--target", "esphome", "--out", str(tmp_path / "out")]) == 0
        assert gc.get_threshold() == (1234, 5, 6)
    finally:
        gc.set_threshold(*before)


def test_the_escaping_caches_are_bounded() -> None:
    """Texts escaped once per process, in caches a long-running process (a build server, a test run) cannot grow
    without bound; a text met again is answered from the cache, the same as escaped afresh."""
    from regmap.backends.markdown import text as md
    from regmap.backends.st.names import _spelled
    from regmap.render import TEXT_CACHE_SIZE, st_comment, xml_text

    for cached in (st_comment, xml_text, _spelled, md.md_text, md.code, md.anchor):
        assert cached.cache_info().maxsize == TEXT_CACHE_SIZE, cached
    assert 0 < TEXT_CACHE_SIZE <= 1 << 16
    assert st_comment("a (* b *) c") == st_comment("a (* b *) c") == "a ( * b * ) c"
    assert xml_text("<a & b>") == "&lt;a &amp; b&gt;"
    from fractions import Fraction

    from regmap.core.text import _scaled_number

    assert 0 < (_scaled_number.cache_info().maxsize or 0) <= 1 << 16  # engineering values, kept the same way
    assert _scaled_number(15, Fraction(1, 10), Fraction(0)) == _scaled_number(15, Fraction(1, 10), Fraction(0)) == "1.5"


def test_what_is_worked_out_once_per_device_goes_with_the_device() -> None:
    """A process that loads many maps (a test run, a build server) keeps the specs and plans of live devices only."""
    from regmap import runtime_bridge

    device = load_map(MAPS[0])
    key = id(device)
    read_plan(device)
    assert key in runtime_bridge._SPECS and key in runtime_bridge._PLANS
    del device
    gc.collect()
    assert key not in runtime_bridge._SPECS and key not in runtime_bridge._PLANS
