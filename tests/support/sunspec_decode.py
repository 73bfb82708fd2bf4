"""Run with pysunspec2's own Python (the `sunspec` tool env): decode SunSpec model blocks the way pysunspec2 does.

stdin: a JSON list of {"file": model JSON path, "len": L, "data": hex of the block from the ID point on};
stdout: a JSON list, per block, of [register name, value, computed value] for every point (None: pysunspec2 reads
it as not implemented; the computed value is pysunspec2's `cvalue`, scaled by the point's scale factor), named as
regmap's SunSpec import names them (`<group>_<n>_<point>`, snake case).
"""

from __future__ import annotations

import json
import re
import sys
from typing import Any

from sunspec2.device import Model  # type: ignore[import-not-found]


def _snake(name: str) -> str:
    out = re.sub(r"(?<=[a-z0-9])(?=[A-Z])", "_", name)
    return re.sub(r"[^a-z0-9]+", "_", out.lower()).strip("_")


def _walk(group: Any, prefix: str, out: list[list[Any]]) -> None:
    for name, point in group.points.items():
        value = point.value
        shown = value.hex() if isinstance(value, bytes) else value
        try:
            computed = point.cvalue if point.sf_required else shown
        except Exception as exc:  # reported as the point's computed value, so the test names the point
            computed = f"pysunspec2 error: {type(exc).__name__}: {exc}"
        out.append([prefix + _snake(name), shown, computed])
    for name, sub in group.groups.items():
        if isinstance(sub, list):
            for i, item in enumerate(sub):
                _walk(item, f"{prefix}{_snake(name)}_{i + 1}_", out)
        else:
            _walk(sub, f"{prefix}{_snake(name)}_", out)


def main() -> None:
    results = []
    for block in json.load(sys.stdin):
        with open(block["file"], encoding="utf-8") as f:
            definition = json.load(f)
        model = Model(model_id=definition["id"], model_len=block["len"], model_def=definition, data=bytes.fromhex(block["data"]))
        out: list[list[Any]] = []
        _walk(model, "", out)
        results.append({"points": out, "error": model.error_info})
    json.dump(results, sys.stdout)


if __name__ == "__main__":
    main()
