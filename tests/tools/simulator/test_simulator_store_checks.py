"""The store remembers the answers of its address checks (the hot path of a polling client) without
changing them: a longer read over a gap is still refused, and a client sweeping addresses cannot grow
the memory without bound."""

from __future__ import annotations

from regmap.frontend import load_map
from regmap.tools.simulator.store import ILLEGAL_ADDRESS, READ_CHECKS_KEPT, DeviceStore

from conftest import ROOT

METER_MAP = load_map(ROOT / "tests" / "maps" / "fixtures" / "power_meter.yaml")
CT_RATIO = METER_MAP.register("ct_ratio").address  # 0x0121 after it is no register of the meter
assert METER_MAP.covering(CT_RATIO + 1, "holding") is None


def test_a_remembered_check_is_the_check_of_that_count() -> None:
    store = DeviceStore(METER_MAP, 1)
    assert store.read(CT_RATIO, 1) == [1]
    assert store.read(CT_RATIO, 2) == ILLEGAL_ADDRESS
    assert store.read(CT_RATIO, 1) == [1]


def test_the_remembered_checks_stay_bounded() -> None:
    store = DeviceStore(METER_MAP, 1)
    for address in range(0x2000, 0x2000 + 3 * READ_CHECKS_KEPT):
        assert store.read(address, 1) == ILLEGAL_ADDRESS
    assert len(store._unreadable) <= READ_CHECKS_KEPT
