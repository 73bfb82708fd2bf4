"""C back end: a header per map (`<device>.h`) plus the shared RTU helpers (`regmap_rtu.h`).

The views compute every identifier, literal and expression; the templates only print, and escape
map text with `c_comment` / `c_str`. The headers are C99 and C++ (include and `extern "C"` guards),
static inline, allocation- and stdio-free. `names` holds the identifier and literal rules, `views`
the items of a header, `device` the header's context; `templates/` the header templates.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from regmap.backends.c.device import SHARED_HEADER, device_context, render_device, render_shared
from regmap.backends.c.names import CIdentifier, CSymbol, c_float, c_hex, c_raw, c_signed, c_unsigned
from regmap.backends.c.variants import too_many_variants
from regmap.backends.c.views import c_version
from regmap.diagnostics import Diagnostic, at
from regmap.keywords import C_KEYWORDS, CPP_KEYWORDS
from regmap.model import Device
from regmap.target import Files, ReservedWords, Target

if TYPE_CHECKING:
    from regmap.plant import Plant


def check(device: Device) -> list[Diagnostic]:
    """What the C header cannot say, at the map line that says it: a firmware gate whose version is not
    major.minor with parts up to 65535 (REGMAP_VERSION compares two 16-bit parts); more variants than
    a uint32_t has bits."""
    problems = []
    if too_many_variants(device):
        problems.append(at(device.source_path, device.info.id_pos, too_many_variants(device)))
    for reg in device.registers:
        for version in (reg.firmware.first, reg.firmware.until) if reg.firmware else ():
            if version is not None:
                try:
                    c_version(version)
                except ValueError as exc:
                    problems.append(at(device.source_path, reg.pos, f"{reg.name}: {exc}"))
    return sorted(set(problems))


# A device id prefixes every C name and names its header: `<id>.h` must not be the shared header either.
RESERVED_WORDS = ReservedWords(
    "a C/C++ keyword or the shared header's name", C_KEYWORDS | CPP_KEYWORDS | {SHARED_HEADER.removesuffix(".h")}
)


def render_plant(plant: Plant) -> Files:
    """The plant's header and schedule (backends/c/plant.py): imported only when a plant is rendered."""
    from regmap.backends.c.plant import render_plant as render

    return render(plant)


TARGET = Target(
    name="c",
    subdir="c",
    per_device=render_device,
    shared=render_shared,
    check=check,
    order=20,
    scale_from=True,
    reserved_words=RESERVED_WORDS,
    plant=render_plant,
)

__all__ = [
    "SHARED_HEADER",
    "TARGET",
    "CIdentifier",
    "CSymbol",
    "c_float",
    "c_hex",
    "c_raw",
    "c_signed",
    "c_unsigned",
    "check",
    "device_context",
    "render_device",
    "render_shared",
]
