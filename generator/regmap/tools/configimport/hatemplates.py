"""Template sensors of a Home Assistant package that regmap's Home Assistant back end writes for a register scaled
by another (`scale_from`: value = raw x 10^sf): a template of exactly that shape over two modbus sensors of one
device (the point's raw integer, its sf's s16) makes the point's register `scale_from` the sf's, with the
template's name, unit and the `na` markers its availability lists. Any other template is not read (as before).
"""

from __future__ import annotations

import re
import unicodedata
from typing import Any

from regmap.tools.configimport.draft import Device, Imported, identifier

_SOURCE = r"(sensor\.[a-z0-9_]+)"
SCALED_STATE = re.compile(
    rf"\{{% set raw = states\('{_SOURCE}'\) \| int\(none\) %\}}\{{% set sf = states\('{_SOURCE}'\) \| int\(none\) %\}}"
    r"\{% if raw is integer and sf is integer %\}\{\{ raw \* 10 \*\* sf if sf >= 0 else raw / 10 \*\* -sf \}\}\{% endif %\}"
)
_QUOTES = re.compile("['\u2018\u2019\"]")
_NOT_SLUG = re.compile(r"[^a-z0-9]+")
INTEGERS = ("s16", "u16", "s32", "u32", "s64", "u64")


def entity_id(name: str) -> str:
    """The id HA gives a sensor named `name` when it first sees it (its slugify, for ASCII text)."""
    text = unicodedata.normalize("NFKD", name).encode("ascii", "ignore").decode().lower()
    return "sensor." + (_NOT_SLUG.sub("_", _QUOTES.sub("", text)).strip("_") or "unknown")


def _markers(availability: str, source: str) -> list[int | float] | None:
    """The `na` markers the availability template lists for `source` (None: it lists none)."""
    found = re.search(rf"states\('{re.escape(source)}'\) \| int\(none\) not in \[(-?\d+(?:, -?\d+)*)\]", availability)
    return [int(v) for v in found[1].split(", ")] if found else None


def scaled_templates(data: Any, sensors: dict[str, tuple[Device, Imported]], report: list[str]) -> None:
    """Make each point a template of the generated shape shows `scale_from` its sf (`sensors`: the modbus sensors
    read so far by entity id, each with its device)."""
    blocks = data.get("template") if isinstance(data, dict) else None
    for block in blocks if isinstance(blocks, list) else []:
        entities = block.get("sensor") if isinstance(block, dict) else None
        for entity in entities if isinstance(entities, list) else []:
            state = entity.get("state") if isinstance(entity, dict) else None
            found = SCALED_STATE.fullmatch(state) if isinstance(state, str) else None
            if found is None or found[1] not in sensors or found[2] not in sensors:
                continue
            (device, raw), (sf_device, sf) = sensors[found[1]], sensors[found[2]]
            if device is not sf_device or raw.type not in INTEGERS or sf.type != "s16" or raw.scale != 1 or raw.offset != 0:
                continue
            availability = str(entity.get("availability", ""))
            raw.na = _markers(availability, found[1]) or raw.na
            sf.na = _markers(availability, found[2]) or sf.na
            raw.key = str(entity.get("unique_id") or entity.get("name") or raw.key)
            raw.title = str(entity.get("name") or raw.title)
            if isinstance(entity.get("unit_of_measurement"), str):
                raw.unit = entity["unit_of_measurement"]
            raw.scale_from = identifier(sf.key, "register")
            report.append(f"{raw.origin}: {raw.title}: value = raw x 10^sf from its template sensor (scale_from {raw.scale_from})")
