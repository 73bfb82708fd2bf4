"""The functions beyond plain reads and writes: which a map may list, and what those that report data answer."""

from __future__ import annotations

from typing import Any

from regmap.frontend.values import _source
from regmap.frontend.yamlsource import Path
from regmap.model import DeviceIdentification, ServerId
from regmap_runtime.rtu import ENCAPSULATED_INTERFACE, REPORT_SERVER_ID, SERVED_FUNCTIONS

IDENTIFICATION_OBJECTS = ("vendor_name", "product_code", "revision", "vendor_url", "product_name", "model_name", "user_application_name")


def served_function_problems(t: dict[str, Any]) -> list[tuple[Path, str]]:
    """Every listed function is one regmap serves, and the functions that report data have it."""
    path: Path = ("transport", "function_codes")
    problems: list[tuple[Path, str]] = []
    served = ", ".join(f"0x{c:02X}" for c in sorted(SERVED_FUNCTIONS))
    for i, code in enumerate(t["function_codes"]):
        if code not in SERVED_FUNCTIONS:
            problems.append(((*path, i), f"function 0x{code:02X} is not one regmap can serve or build (it knows {served})"))
    for code, key, what in (
        (ENCAPSULATED_INTERFACE, "identification", "read device identification"),
        (REPORT_SERVER_ID, "server_id", "report server id"),
    ):
        if code in t["function_codes"] and key not in t:
            problems.append((path, f"function 0x{code:02X} ({what}) is listed: transport.{key} says what the device answers"))
    return problems


def identification(spec: dict[str, Any] | None) -> DeviceIdentification | None:
    if spec is None:
        return None
    objects = tuple((i, spec[key]) for i, key in enumerate(IDENTIFICATION_OBJECTS) if key in spec)
    return DeviceIdentification(objects=objects, source=_source(spec.get("source")))


def server_id(spec: dict[str, Any] | None) -> ServerId | None:
    if spec is None:
        return None
    return ServerId(
        id=bytes(spec["id"]),
        running=spec.get("run_indicator", True),
        additional_data=spec.get("additional_data", ""),
        source=_source(spec.get("source")),
    )
