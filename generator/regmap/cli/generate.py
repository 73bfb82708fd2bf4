"""`regmap generate`: every back end's output, swapped into place atomically."""

from __future__ import annotations

import argparse
import gc
import os
from pathlib import Path

from regmap.cli.common import examples, load_all, load_plant, map_paths, plant_argument
from regmap.diagnostics import ExitCode, UsageError

HELP = "generate Python clients, C headers and docs from maps"


def add_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> argparse.ArgumentParser:
    p = sub.add_parser(
        "generate",
        help=HELP,
        description="Render every target for every map into OUT (default generated/). Output is swapped in only when every target "
        "succeeded, so a failure leaves the previous tree as it was.",
        epilog=examples(
            "regmap generate                                 # every maps/*.yaml -> generated/",
            "regmap generate maps/c630s.yaml --target c --out build/gen",
            "regmap generate --since v1.0.0                  # also changelog pages in the docs",
            "regmap generate maps/c630s.yaml --target esphome --select 'p0b,P02-00,fault_reset'",
            "regmap generate maps/idm_rs.yaml --target homeassistant --select @my-selection.txt",
            "regmap generate examples/plants/cell1.yaml      # a plant -> generated/plants/cell1/",
        ),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("maps", nargs="*", metavar="MAP", help="map files (default: every maps/*.yaml)")
    p.add_argument("--out", metavar="DIR", help="output directory (default: generated; for a plant: generated/plants/<plant id>)")
    p.add_argument(
        "--target",
        action="append",
        metavar="TARGET",
        help="only this target (repeatable): python, c, markdown, st, esphome, homeassistant, or a plugin's (default: all)",
    )
    p.add_argument(
        "--select",
        metavar="PATTERNS",
        help="esphome/homeassistant: the registers and commands to generate entities for: comma-separated glob patterns over "
        "register names, parameter ids, group ids and command names ('!' excludes), or @FILE (one pattern a line, # comments); "
        "default: every read-only register and every command (README 'Home Assistant and ESPHome')",
    )
    p.add_argument("--since", metavar="GITREV", help="also write docs/<device>-changelog.md: `regmap diff` of each map against GITREV")
    return p


def check_out_dir(out: Path) -> None:
    """OUT must be a directory regmap can write, or a new one in a directory that exists."""
    if out.exists() and not out.is_dir():
        raise UsageError(f"--out {out}: exists and is not a directory")
    parent = out if out.exists() else out.parent
    if not parent.exists():
        raise UsageError(f"--out {out}: the directory {parent} does not exist")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise UsageError(f"--out {out}: {parent} is not writable")


# A run builds the models and their views and keeps them to the end; the cyclic collector's passes over them were a
# tenth of a cold run's CPU and freed almost nothing (the views hold no cycles to speak of). Collect rarely, as mypy
# does for the same reason; reference counting still frees everything else at once.
GC_THRESHOLDS = (200_000, 30, 30)


def run(args: argparse.Namespace) -> int:
    before = gc.get_threshold()
    gc.set_threshold(*GC_THRESHOLDS)
    try:
        return _run(args)
    finally:  # a caller that runs the command in its own process (the tests, a build tool) keeps its own thresholds
        gc.set_threshold(*before)


def _run(args: argparse.Namespace) -> int:
    from regmap.generate import CachedOutputs, check_options, generate, target_names
    from regmap.outputcache import OutputCache, read_sources

    plant_path = plant_argument(args.maps)
    if plant_path is not None:
        return _generate_plant(args, plant_path)

    out = Path(args.out or "generated")
    check_out_dir(out)
    known = target_names()
    unknown = [t for t in args.target or [] if t not in known]
    if unknown:
        raise UsageError(f"--target {unknown[0]}: no such target (targets: {', '.join(known)})")
    targets = args.target or known
    options = {"select": args.select} if args.select is not None else {}
    check_options(targets, options)
    # Unchanged maps, same regmap: the finished files come from the output cache, and the maps need not be read again.
    cache = None if args.since or options else OutputCache.from_environment()
    sources = read_sources(map_paths(args.maps)) if cache is not None else None
    cached = CachedOutputs(cache, sources, targets) if cache is not None and sources is not None else None
    devices = [] if cached is not None and cached.complete(targets) else load_all(args.maps)
    pages: dict[str, str] = {}
    if args.since:
        from regmap.tools.diff import changelog_pages

        pages = changelog_pages(devices, args.since, targets)  # first: a bad revision writes nothing
    written = generate(devices, out, targets, complete=not args.maps, extra=pages, options=options, cached=cached)
    print(f"regmap generate: {len(written)} files for {len(sources or devices)} map(s), targets {', '.join(targets)} -> {out}/")
    return ExitCode.OK


def _generate_plant(args: argparse.Namespace, plant_path: str) -> int:
    from regmap.generate import generate_plant, plant_target_names

    for option, given in (("--select", args.select), ("--since", args.since)):
        if given is not None:
            raise UsageError(f"{option} applies to maps, not to a plant file")
    plant = load_plant(plant_path)
    out = Path(args.out or f"generated/plants/{plant.id}")
    if args.out is None:
        out.parent.mkdir(parents=True, exist_ok=True)
    check_out_dir(out)
    known = plant_target_names()
    unknown = [t for t in args.target or [] if t not in known]
    if unknown:
        raise UsageError(f"--target {unknown[0]}: not a plant target (plant targets: {', '.join(known) or '(none yet)'})")
    targets = args.target or known
    written = generate_plant(plant, out, targets)
    print(
        f"regmap generate: {len(written)} files for plant {plant.id} ({len(plant.devices)} devices), targets {', '.join(targets) or '(none)'} -> {out}/"
    )
    return ExitCode.OK
