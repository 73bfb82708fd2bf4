"""The SunSpec model definitions pysunspec2 ships (in its own tool env), and maps of a chain of them."""

from __future__ import annotations

import subprocess
from pathlib import Path
from typing import Any

from regmap.tools.configimport import sunspec
from regmap.tools.configimport.draft import map_text

from conftest import skip_or_fail
from support.tool_envs import ToolUnavailable, find


def pysunspec_python() -> Path:
    """pysunspec2's Python (the `sunspec` tool env of `make tools`); a skip, or under CI a failure, when it is not built."""
    try:
        return find("sunspec")
    except ToolUnavailable as exc:
        skip_or_fail(str(exc))


def model_files(python: Path) -> list[Path]:
    """Every model_<id>.json pysunspec2 ships, by model id."""
    out = subprocess.run(
        [str(python), "-c", "import sunspec2, os; print(os.path.dirname(sunspec2.__file__))"], capture_output=True, text=True, check=True
    )
    return sorted((Path(out.stdout.strip()) / "models" / "json").glob("model_*.json"), key=lambda p: int(p.stem.split("_")[1]))


def chain_map(python: Path, ids: list[int], path: Path, repeats: int = 1, values: dict[str, Any] | None = None) -> Path:
    """The map of a device with these models chained from 40000, with `values` (register name -> raw) as defaults."""
    files = {int(p.stem.split("_")[1]): p for p in model_files(python)}
    imported = sunspec.device(sunspec.read_models([files[i] for i in ids]), 40000, repeats)
    (device,) = imported.devices
    for reg in device.registers:
        if values and reg.key in values:
            reg.default = values[reg.key]
    path.write_text(map_text(device, path.stem, "SunSpec", "simulated inverter", "pysunspec2 models", imported.report), encoding="utf-8")
    return path
