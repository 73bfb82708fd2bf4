"""The generated Python plant binds each device's client to the variant the plant file names: against
`regmap simulate PLANT --bus` (each meter played as its variant), `read_all()` reads every register each meter's
model has, in the shared schedule's order, and not one request is answered with an exception."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from regmap.frontend.plant import load_plant
from regmap.runtime_bridge import plant_schedule

from conftest import free_port
from support.plant_tcp_bus import serve_bus
from support.plants import METER_VARIANTS, generate_python_plant, write_meter_plant

_EXCHANGE = re.compile(
    r"> MBAP transaction \d+, unit (\d+), PDU ([0-9a-f]{2})[^\n]*\n(?:(?!\S).*\n)*?  < MBAP transaction \d+, unit \d+, PDU ([0-9a-f]{2})"
)


def test_read_all_of_a_plant_of_two_variants_gets_every_value_and_no_exception(tmp_path: Path) -> None:
    plant_file = write_meter_plant(tmp_path, "meters", f"tcp: {{host: 127.0.0.1, port: {free_port()}}}")
    module = generate_python_plant(plant_file, tmp_path / "out")
    plant = load_plant(plant_file)
    (bus,) = plant.buses
    with serve_bus(plant, bus, tmp_path) as served, module.Meters(line1_port=served.port) as meters:
        assert meters.m1.variant == "single_phase" and meters.m3.variant == "three_phase"
        values = meters.read_all()
        sent = meters.m1.requests_sent
        with pytest.raises(TypeError, match="voltage_l2 exists only on the variant") as refused:
            meters.m1.read_voltage_l2()  # refused by the single-phase client: nothing sent
        assert type(refused.value).__name__ == "AccessError"  # the generated tree's own runtime's
        assert meters.m1.requests_sent == sent
    for name, (_, variant) in METER_VARIANTS.items():
        device = bus.device(name).device
        has = {r.name for r in device.registers if r.access.readable and r.on_variant(variant)}
        assert set(values[name]) == has, name
    assert "voltage_l2" in values["m3"] and "voltage_l2" not in values["m1"]
    exchanges = _EXCHANGE.findall(served.log.read_text(encoding="utf-8"))
    (schedule,) = plant_schedule(plant)
    assert [int(unit) for unit, _, _ in exchanges] == [e.slave for e in schedule.entries]  # every request, in order
    assert [answer for _, asked, answer in exchanges] == [asked for _, asked, _ in exchanges]  # no exception answer (0x8N)
