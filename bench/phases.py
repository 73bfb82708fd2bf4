"""`python -m bench.phases [--profile] OUT MAP...`: run `regmap generate` in this process and print, as
JSON, the seconds spent in each stage (imports, YAML, schema, semantic checks, each back end, writing,
ruff); with --profile, under cProfile, also the functions with the most time of their own.

Stages are timed by wrapping the functions `regmap generate` calls; a stage whose function is not
found (renamed since) is simply left out, so the breakdown degrades rather than breaks.
"""

from __future__ import annotations

import time

T0 = time.perf_counter()

import dataclasses  # noqa: E402
import functools  # noqa: E402
import json  # noqa: E402
import sys  # noqa: E402
from collections.abc import Callable  # noqa: E402
from typing import Any  # noqa: E402

SPENT: dict[str, float] = {}


def _timed(stage: str, fn: Callable[..., Any]) -> Callable[..., Any]:
    @functools.wraps(fn)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        start = time.perf_counter()
        try:
            return fn(*args, **kwargs)
        finally:
            SPENT[stage] = SPENT.get(stage, 0.0) + time.perf_counter() - start

    return wrapper


def _wrap(owner: Any, name: str, stage: str) -> None:
    fn = getattr(owner, name, None)
    if not callable(fn):  # a renamed stage must break the bench, not drop out of its breakdown unseen
        raise AttributeError(f"bench: {getattr(owner, '__name__', owner)}.{name} is gone; time its successor")
    setattr(owner, name, _timed(stage, fn))


def _top(profile: Any, count: int) -> list[tuple[str, int, float, float]]:
    """(function, calls, own seconds, cumulative seconds) of the `count` functions with the most own time."""
    import os
    import pstats

    stats: dict[tuple[str, int, str], tuple[int, int, float, float, Any]] = pstats.Stats(profile).stats  # type: ignore[attr-defined]
    rows = []
    for (filename, line, name), (_, calls, own, cumulative, _) in stats.items():
        where = f"{os.path.relpath(filename)}:{line}" if filename and not filename.startswith("~") else "built-in"
        rows.append((f"{name} ({where})", calls, own, cumulative))
    return sorted(rows, key=lambda row: -row[2])[:count]


def main(argv: list[str]) -> int:
    profile = argv[:1] == ["--profile"]
    if profile:
        argv = argv[1:]
    out, maps = argv[0], argv[1:]
    import regmap.cli as cli
    import regmap.frontend.load as load
    import regmap.generate as generate
    from regmap.backends import c, markdown, python

    SPENT["start-up and imports"] = time.perf_counter() - T0
    _wrap(load, "read_yaml", "YAML parsing")
    _wrap(load, "_schema_problems", "JSON Schema")
    _wrap(load, "elaborate", "semantic checks and model")
    _wrap(load, "check_references", "semantic checks and model")
    for module in (python, c, markdown):
        target = module.TARGET
        replaced = {
            "per_device": _timed(f"back end {target.name}", target.per_device),
            "shared": _timed(f"back end {target.name}", target.shared),
        }
        if target.post is not None:
            replaced["post"] = _timed(f"{target.name}: post-processing (ruff format)", target.post)
        module.TARGET = dataclasses.replace(target, **replaced)  # type: ignore[attr-defined]
    _wrap(generate, "render", "back ends (all)")
    _wrap(generate, "generate", "back ends, writing and post-processing")
    start = time.perf_counter()
    top: list[tuple[str, int, float, float]] = []
    if profile:
        import cProfile

        profiler = cProfile.Profile()
        status = profiler.runcall(cli.main, ["generate", *maps, "--out", out])
        top = _top(profiler, 12)
    else:
        status = cli.main(["generate", *maps, "--out", out])
    SPENT["total in process"] = time.perf_counter() - T0
    SPENT["command"] = time.perf_counter() - start
    print(json.dumps({"status": status, "spent": SPENT, "top": top}))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
