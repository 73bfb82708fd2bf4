"""`scale_from` in the runtime and the field tools (value = raw x 10^sf, sf another register's signed raw value):
reads scale by the sf read with the point, writes by a fresh read of it, and nothing is shown or sent raw as if
it were the value. Expected values come from the map's defaults (what the simulator serves) and Decimal."""

from __future__ import annotations

import json
import subprocess
import sys
from decimal import Decimal
from pathlib import Path
from typing import Any

import pytest

from regmap.core.decoding import decode_words
from regmap.frontend import load_map
from regmap.model import Device
from regmap.runtime_bridge import runtime_device
from regmap_runtime.client import SyncClient
from regmap_runtime.codec import RangeError, raw_to_words
from regmap_runtime.plan import ReadBlock
from regmap_runtime.scaling import scaled, unscaled

from conftest import ROOT, SimulatorFactory

MAP = ROOT / "tests" / "maps" / "scaled_from" / "inverter.yaml"
POINTS = ("a", "w", "wh", "wmax_lim_pct")


def _expected(device: Device, name: str, raw: int | None = None, sf: int | None = None) -> float:
    """raw x 10^sf as an exact decimal, then the nearest float (the map's defaults unless given)."""
    reg = device.register(name)
    raw = reg.default if raw is None else raw  # type: ignore[assignment]
    sf = device.register(reg.scale_from or "").default if sf is None else sf  # type: ignore[assignment]
    return float(Decimal(raw).scaleb(sf))  # type: ignore[arg-type]


def _client(device: Device, port: int) -> SyncClient:
    cls: type[SyncClient] = type("Inverter", (SyncClient,), {"DEVICE": runtime_device(device)})
    return cls.tcp("127.0.0.1", port, timeout=1.0)


@pytest.mark.parametrize(("raw", "sf"), [(1234, -2), (-1500, 1), (3, -1), (7, 0), (65535, -4), (1, 3)])
def test_scaled_is_the_correctly_rounded_product(raw: int, sf: int) -> None:
    assert scaled(raw, sf) == float(Decimal(raw).scaleb(sf))
    assert scaled(None, sf) is None and scaled(raw, None) is None


def test_unscaled_takes_only_whole_multiples() -> None:
    spec = runtime_device(load_map(MAP)).registers[-2]  # wmax_lim_pct
    assert spec.name == "wmax_lim_pct"
    assert unscaled(spec, 50.5, -1) == 505
    assert unscaled(spec, "12.3", -1) == 123
    assert unscaled(spec, 3000, 2) == 30
    for value, sf in ((50.55, -1), (3001, 2), ("x", 0), (float("nan"), 0)):
        with pytest.raises(RangeError):
            unscaled(spec, value, sf)
    with pytest.raises(RangeError, match="not available"):
        unscaled(spec, 1, None)


def test_a_client_reads_points_scaled_by_their_factors(simulator: SimulatorFactory) -> None:
    device = load_map(MAP)
    sim = simulator(MAP)
    assert sim.port is not None
    with _client(device, sim.port) as client:
        every = client.read_all()
        for name in POINTS:
            assert every[name] == _expected(device, name), name
            spec: Any = next(s for s in client.DEVICE.registers if s.name == name)
            assert client.read(spec) == _expected(device, name)
            assert set(client.read_many(spec)) == {name}  # the sf is read with it, not returned
            assert len(client.plan_reads(client.with_scale_factors([spec]))) == 1  # adjacent: one request


def test_a_write_uses_a_fresh_scale_factor_and_refuses_what_raw_cannot_carry(simulator: SimulatorFactory) -> None:
    device = load_map(MAP)
    sim = simulator(MAP)
    assert sim.port is not None
    reg, sf = device.register("wmax_lim_pct"), device.register("wmax_lim_pct_sf").default
    assert isinstance(sf, int)
    with _client(device, sim.port) as client:
        spec: Any = next(s for s in client.DEVICE.registers if s.name == reg.name)
        client.write(spec, 50.5)
        assert client.read_raw(reg.address, 1) == raw_to_words(spec, unscaled(spec, 50.5, sf))
        assert client.read(spec) == 50.5
        too_big = int(reg.raw_max) + 1
        for refused, reason in ((50.55, "whole multiple"), (_expected(device, reg.name, too_big, sf), f"raw {too_big} is outside")):
            with pytest.raises(RangeError, match=reason) as refusal:
                client.write(spec, refused)
            assert reg.unit is None or f"{too_big} {reg.unit}" not in str(refusal.value)  # a raw number is not the value
            assert client.read(spec) == 50.5  # nothing was sent
        client.write(spec, 505, raw=True)
        assert client.read(spec) == 50.5


def test_not_available_factor_or_point_reads_as_none() -> None:
    device = load_map(MAP)
    cls: type[SyncClient] = type("Inverter", (SyncClient,), {"DEVICE": runtime_device(device)})
    client = cls.tcp("127.0.0.1", 1)
    specs = {s.name: s for s in cls.DEVICE.registers}
    block = ReadBlock(2, 2, (specs["w"], specs["w_sf"]))
    assert client.values_of(block, [100, 2]) == {"w": scaled(100, 2), "w_sf": 2}
    assert client.values_of(block, [100, 0x8000])["w"] is None  # the sf's marker
    assert client.values_of(block, [0x8000, 2])["w"] is None  # the point's own marker
    with pytest.raises(ValueError, match="not read with it"):
        client.values_of(ReadBlock(2, 1, (specs["w"],)), [100])  # never the raw number as the value
    assert client.values_of(ReadBlock(2, 1, (specs["w"],)), [100], {"w_sf": -1})["w"] == scaled(100, -1)


def test_decode_scales_only_with_the_factor_in_the_same_words() -> None:
    device = load_map(MAP)
    both = {v.register: v for v in decode_words(device, 2, [0xFFFE, 0x0002])}  # w = -2, w_sf = 2
    assert both["w"].value == scaled(-2, 2) and "10^2" in both["w"].text
    alone = {v.register: v for v in decode_words(device, 2, [0xFFFE])}
    assert alone["w"].value is None and "w_sf is not in these words" in alone["w"].text
    na = {v.register: v for v in decode_words(device, 2, [5, 0x8000])}
    assert na["w"].value is None and "not available" in na["w"].text


def _regmap(*args: object) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "regmap", *map(str, args)], cwd=ROOT, capture_output=True, text=True, check=False)


def test_the_cli_reads_scaled_values_and_refuses_an_unscaled_write(simulator: SimulatorFactory, tmp_path: Path) -> None:
    device = load_map(MAP)
    sim = simulator(MAP)
    link = ("--tcp", f"127.0.0.1:{sim.port}")
    result = _regmap("read", MAP, *POINTS, *link, "--json")
    assert result.returncode == 0, result
    values: dict[str, Any] = {v["register"]: v["value"] for v in json.loads(result.stdout)}
    assert values == {name: _expected(device, name) for name in POINTS}
    refused = _regmap("write", MAP, "wmax_lim_pct=50", *link)
    assert refused.returncode != 0 and "--raw" in refused.stderr
    assert _regmap("frame", "write", MAP, "wmax_lim_pct=50").returncode != 0


def test_show_gives_the_factor_and_raw_numbers_only() -> None:
    device = load_map(MAP)
    reg = device.register("wmax_lim_pct")
    shown = _regmap("show", MAP, reg.name)
    assert shown.returncode == 0, shown
    facts = {line.split(maxsplit=1)[0]: line.split(maxsplit=1)[1] for line in shown.stdout.splitlines()[1:] if line.strip()}
    assert facts["scale"] == f"10^{reg.scale_from} (read from the device)"
    assert facts["range"] == f"raw {reg.raw_min}..{reg.raw_max}" and facts["default"] == f"raw {reg.default}"
