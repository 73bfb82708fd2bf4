"""What several back ends need from the model in the same form: runtime specs and the read plan.

The read plan is computed once, by the very planner the runtime uses, so the Python client's
`read_all()`, the C read-plan tables and the benchmarks agree request for request.
"""

from __future__ import annotations

from typing import Any

from regmap_runtime.plan import ReadBlock, plan_reads
from regmap_runtime.spec import RegisterSpec

from regmap.model import Device


def documented_addresses(device: Device) -> frozenset[int]:
    """Addresses the device answers reads of: every word of every readable register (pairs included)."""
    return frozenset(a for r in device.registers if r.access.readable for a in range(r.first_address, r.last_address + 1))


def runtime_specs(device: Device) -> list[RegisterSpec[Any]]:
    return [
        RegisterSpec(
            name=r.name,
            address=r.address,
            data_type=r.type.value,
            access=r.access.value,
            word_order=r.word_order.value,
            paired=r.paired,
            scale_num=r.scale.numerator,
            scale_den=r.scale.denominator,
            min=r.min,
            max=r.max,
            unit=r.unit,
            param=r.param,
        )
        for r in device.registers
    ]


def read_plan(device: Device) -> list[ReadBlock]:
    """The requests `read_all()` issues, in order."""
    t = device.transport
    return plan_reads(runtime_specs(device), t.max_read_registers, None if t.tolerates_gaps else documented_addresses(device))
