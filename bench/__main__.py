"""`python -m bench` (`make bench`): run every benchmark and rewrite docs/benchmarks.md."""

from __future__ import annotations

import argparse
import logging
import sys
import time
from pathlib import Path

from bench import bus, chelpers, floor, genspeed, optimal, overhead, plant, simload
from bench.common import FIXTURE_MAPS, MAPS, ROOT, machine, stage
from bench.report import Results, render, targets


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m bench", description=__doc__)
    parser.add_argument("--out", default=str(ROOT / "docs" / "benchmarks.md"), help="where to write the report")
    parser.add_argument("--quick", action="store_true", help="tiny inputs and few repeats: checks the code paths, not the speed")
    args = parser.parse_args(argv)
    logging.getLogger("pymodbus").setLevel(logging.CRITICAL)
    from regmap.frontend import load_map

    started = time.perf_counter()
    facts = machine()
    devices = [load_map(path, str(path.relative_to(ROOT))) for path in MAPS]
    if args.quick:
        devices = [d for d in devices if d.id == "id243pro"] or devices[:1]
    with stage("bus time of read_all() against the simulator"):
        bus_results = [bus.measure(d) for d in devices]
    with stage("read_all() with and without a learned device profile (lenient simulator)"):
        profiles = [bus.measure_profile(d) for d in devices]
    with stage("read-plan optimality (dynamic programme), per space and poll class, seed and fixture maps"):
        sweep = (2, 47, 125) if args.quick else range(2, 126)
        fixtures = [load_map(path, str(path.relative_to(ROOT))) for path in FIXTURE_MAPS]
        plans = [optimal.check(d, sweep) for d in (*devices, *fixtures)]
    with stage("generation speed"):
        gen = genspeed.measure(sizes=(200,), repeats=1, budget_s=30, maps=[MAPS[0]]) if args.quick else genspeed.measure()
    with stage("runtime overhead against raw pymodbus"):
        costs = overhead.measure_costs(3 if args.quick else 21)
        comparisons = overhead.measure(3 if args.quick else 41)
    with stage("C frame helpers"):
        c = chelpers.measure(iterations=2000 if args.quick else 200000, repeats=1 if args.quick else 7)
    with stage("simulator under load, beside a libmodbus server"):
        sim = simload.measure(2_000, 5_000, 500) if args.quick else simload.measure()
    with stage("regmap generate against its import floor (cold and warm), regmap import of a 20,000-row table"):
        gen_floor = floor.measure_generate(repeats=1 if args.quick else 9, maps=[MAPS[0]] if args.quick else None)
        big_import = floor.measure_import(200 if args.quick else floor.TABLE_ROWS)
    with stage("a plant's read_all() against the multi-unit simulator, beside its devices' own read_all()"):
        plant_run = plant.measure()
    results = Results(
        facts,
        bus_results,
        plans,
        gen,
        comparisons,
        costs,
        c,
        quick=args.quick,
        sim=sim,
        profiles=profiles,
        floor=gen_floor,
        big_import=big_import,
        plant=plant_run,
    )
    results.elapsed_s = time.perf_counter() - started
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(render(results), encoding="utf-8")
    print(f"bench: wrote {out} in {results.elapsed_s:.0f} s", file=sys.stderr)
    for target, measured, ok in targets(results):
        verdict = "n/a" if ok is None else ("met" if ok else "MISSED")
        print(f"  {verdict:>6}  {target}: {measured}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
