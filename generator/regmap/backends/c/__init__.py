"""C back end: a header per map (`<device>.h`) plus the shared RTU helpers (`regmap_rtu.h`).

The views compute every identifier, literal and expression; the templates only print, and escape
map text with `c_comment` / `c_str`. The headers are C99 and C++ (include and `extern "C"` guards),
static inline, allocation- and stdio-free. `names` holds the identifier and literal rules, `views`
the items of a header, `device` the header's context, and `frames_test` the C program that checks
a header against every frame of its map's examples (the tests compile and run it).
"""

from __future__ import annotations

from regmap.backends.c.device import SHARED_HEADER, device_context, render_device, render_shared
from regmap.backends.c.frames_test import frames_test_context, render_frames_test
from regmap.backends.c.names import CIdentifier, CSymbol, c_float, c_hex, c_raw, c_signed, c_unsigned
from regmap.generate import Target

TARGET = Target(name="c", subdir="c", per_device=render_device, shared=render_shared)

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
    "device_context",
    "frames_test_context",
    "render_device",
    "render_frames_test",
    "render_shared",
]
