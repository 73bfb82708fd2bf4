"""docs/benchmarks.md from the measurements: tables, an inline SVG plot, and the targets checked."""

from __future__ import annotations

import datetime as dt
import math
from collections.abc import Sequence
from dataclasses import dataclass

from bench.bus import BusResult, ProfileResult
from bench.chelpers import CASES, CResult
from bench.common import Machine
from bench.floor import (
    BEFORE_BRANCH_COLD,
    BEFORE_BRANCH_COMMIT,
    BEFORE_BRANCH_WARM,
    BEFORE_COLD,
    BEFORE_DRAFT_SHA256,
    BEFORE_IMPORT_CPU_S,
    BEFORE_IMPORT_MIB,
    BEFORE_IMPORT_NOTE,
    BEFORE_IMPORT_WALL_S,
    BEFORE_WARM,
    FLOOR_IMPORTS,
    GENERATE_RATIO_TARGET,
    IMPORT_TARGET_MIB,
    IMPORT_TARGET_S,
    JUDGED_ON,
    GenerateFloor,
    ImportRun,
    Ratio,
)
from bench.genspeed import GenRun, GenSpeed
from bench.optimal import PlanCheck
from bench.overhead import ClientCost, Comparison
from bench.plant import PlantRun
from bench.plot import Series, loglog
from bench.simload import LEVELS, SimLoad

OVERHEAD_TARGET = 0.15
SPEEDUP_TARGET = 5.0
THREE_MAPS_TARGET_S = 1.0
TEN_K_TARGET_S = 3.0
GROWTH_TARGET = 12.0
SIM_RATIO_TARGET = 0.8  # issue 31, item 7: the simulator with ten clients against a libmodbus server
M0_TARGET = 1024


@dataclass
class Results:
    machine: Machine
    bus: list[BusResult]
    plans: list[PlanCheck]
    gen: GenSpeed | None
    overhead: list[Comparison]
    costs: list[ClientCost]
    c: CResult | None
    elapsed_s: float = 0.0
    quick: bool = False
    sim: SimLoad | None = None
    profiles: list[ProfileResult] | None = None
    floor: GenerateFloor | None = None
    big_import: ImportRun | None = None
    plant: PlantRun | None = None


def _on_base(ratio: Ratio, measured: tuple[float, float, float]) -> str:
    """The base's ratio: from the same runs when the bench could run it, else as measured when the round began."""
    if ratio.base_ratio is not None:
        return f"{BEFORE_BRANCH_COMMIT} in the same runs {ratio.base_ratio:.2f}×"
    return f"{BEFORE_BRANCH_COMMIT} as measured {measured[2]:.2f}×"


def ms(seconds: float) -> str:
    return f"{seconds * 1000:.1f} ms" if seconds < 10 else f"{seconds:.1f} s"


def us(seconds: float) -> str:
    return f"{seconds * 1e6:.0f} µs" if seconds >= 1e-5 else f"{seconds * 1e6:.2f} µs"


def secs(seconds: float) -> str:
    return f"{seconds:.2f} s"


def pct(ratio: float) -> str:
    return f"{ratio * 100:+.1f} %"


def yes(ok: bool | None) -> str:
    return "n/a" if ok is None else ("**met**" if ok else "**missed**")


def table(header: Sequence[str], rows: Sequence[Sequence[object]], align: str = "") -> list[str]:
    align = align or "l" + "r" * (len(header) - 1)
    marks = {"l": "---", "r": "--:", "c": ":-:"}
    out = ["| " + " | ".join(header) + " |", "|" + "|".join(marks[a] for a in align) + "|"]
    out += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
    return [*out, ""]


def _gen_run(run: GenRun | None) -> str:
    if run is None:
        return "not run"
    if run.timed_out_after is not None:
        return f"> {run.timed_out_after:.0f} s (stopped)"
    return secs(run.wall)


def targets(r: Results) -> list[tuple[str, str, bool | None]]:
    rows: list[tuple[str, str, bool | None]] = []
    optimal = all(p.optimal for p in r.plans) if r.plans else None
    rows.append(
        (
            "read plan = proven optimum for every map",
            ", ".join(f"{p.device_id}: {p.plan_requests} = DP {p.optimum.requests}" for p in r.plans) or "not run",
            optimal,
        )
    )
    idm = next((b for b in r.bus if b.device_id == "idm_rs"), None)
    rows.append(
        (
            f"≥ {SPEEDUP_TARGET:g}× less wire time than one request per register (iDM-RS, all parameters)",
            f"{idm.speedup:.2f}×" if idm else "not run",
            idm.speedup >= SPEEDUP_TARGET if idm else None,
        )
    )
    if r.gen is not None:
        three = r.gen.three_maps
        rows.append(
            (f"three maps generated in < {THREE_MAPS_TARGET_S:g} s (whole process)", _gen_run(three), three.wall < THREE_MAPS_TARGET_S)
        )
        ten = r.gen.synthetic_run(10000)
        ten_ok = None if ten is None else (ten.timed_out_after is None and ten.wall < TEN_K_TARGET_S)
        rows.append((f"10k registers generated in < {TEN_K_TARGET_S:g} s", _gen_run(ten), ten_ok))
        growth = r.gen.growth(1000, 10000)
        rows.append(
            (
                f"growth 1k → 10k ≤ {GROWTH_TARGET:g}×",
                f"{growth:.1f}×" if growth else "not run",
                None if growth is None else growth <= GROWTH_TARGET,
            )
        )
    if r.floor is not None:
        f = r.floor
        rows.append(
            (
                f"`regmap generate` ≤ {GENERATE_RATIO_TARGET:g}× the CPU of `{FLOOR_IMPORTS}`",
                f"cold {f.cold.ratio:.2f}× (before {BEFORE_COLD[2]:.2f}×, {_on_base(f.cold, BEFORE_BRANCH_COLD)}), "
                f"warm {f.warm.ratio:.2f}× (before {BEFORE_WARM[2]:.2f}×, {_on_base(f.warm, BEFORE_BRANCH_WARM)}): "
                f"judged on the {JUDGED_ON} run",
                f.met,
            )
        )
    if r.big_import is not None:
        b = r.big_import
        rows.append(
            (
                f"`regmap import` of {b.rows:,} rows ≤ {IMPORT_TARGET_S:g} s",
                f"{secs(b.wall_s)} wall, {secs(b.cpu_s)} CPU, exit {b.status} (before {secs(BEFORE_IMPORT_WALL_S)} wall, "
                f"{secs(BEFORE_IMPORT_CPU_S)} CPU, exit 1)",
                b.status == 0 and b.wall_s <= IMPORT_TARGET_S,
            )
        )
        rows.append(
            (
                f"… peak memory ≤ {IMPORT_TARGET_MIB:g} MiB",
                f"{b.peak_mib:.0f} MiB (before {BEFORE_IMPORT_MIB:.0f} MiB)",
                b.peak_mib <= IMPORT_TARGET_MIB,
            )
        )
    if r.overhead:
        worst = max(r.overhead, key=lambda c: c.overhead)
        rows.append(
            (
                f"generated client overhead ≤ {OVERHEAD_TARGET * 100:g} % over raw pymodbus",
                f"worst {pct(worst.overhead)} ({worst.case})",
                worst.overhead <= OVERHEAD_TARGET,
            )
        )
    if r.sim is not None and r.sim.blocked is None:
        for clients in (1, 10):
            ours, theirs = r.sim.run("regmap simulate", clients), r.sim.run("libmodbus", clients)
            ratio = r.sim.ratios.get(clients)
            measured = (
                "not run"
                if ours is None or theirs is None or ratio is None
                else (f"{ratio:.2f}× ({ours.rate:,.0f} vs {theirs.rate:,.0f} req/s)")
            )
            target = SIM_RATIO_TARGET if clients == 10 else None
            label = f"simulator vs libmodbus, 1-register reads, {clients} client{'s' if clients > 1 else ''}"
            if target is not None:
                label += f" ≥ {target:g}×"
            rows.append((label, measured, None if target is None or ratio is None else ratio >= target))
    if r.plant is not None:
        p = r.plant
        rows.append(
            (
                f"plant `read_all()` ({p.plant_id}, {p.devices} devices) costs no more wire time than its devices' own plans",
                f"{ms(p.plant_wire_s)} in {p.plant_requests} requests vs {ms(p.single_wire_s)} in {p.single_requests}",
                p.plant_requests == p.single_requests and p.plant_wire_s <= p.single_wire_s * 1.000001 and p.order_matches,
            )
        )
    if r.c is not None:
        size = r.c.m0_text
        rows.append(
            (
                "frame helpers + CRC ≤ 1 KiB text on Cortex-M0 (-Os)",
                f"{size} bytes" if size is not None else (r.c.blocked or "not run"),
                None if size is None else size <= M0_TARGET,
            )
        )
    return rows


def _machine(m: Machine, r: Results) -> list[str]:
    rows = [
        ("CPU", f"{m.cpu} ({m.cores} cores)"),
        ("OS", m.os),
        ("Python", m.python),
        *((name, version) for name, version in m.packages),
        *((name, version) for name, version in m.tools),
        ("load average when `make bench` started (1/5/15 min)", m.load_before),
        ("`make bench` took", f"{r.elapsed_s:.0f} s"),
    ]
    out = table(["", ""], rows, "ll")
    out += [f"- {note}" for note in m.notes]
    return [*out, ""] if m.notes else out


def _bus(r: Results) -> list[str]:
    out = [
        "Each map's generated client (`generated/python/`) reads through `regmap.tools.simulator.Simulator`, served in this",
        "process with RTU framing over loopback TCP; the simulator's statistics count every frame and byte it",
        "received and sent. Wire time is what those frames take on the RS-485 line at the map's default baud: each",
        "byte one character (start + data + parity + stop bits), and per request the device's turnaround (end of",
        "request → start of answer) and the pause before the next request, each at least the 3.5-character silence that",
        "ends an RTU frame. The lower bound assumes every readable word travels once, in requests filled to the",
        "device's limit (registers per request, and message bytes where the manual limits them), with no gap words.",
        "",
    ]
    rows = []
    for b in r.bus:
        line = b.line
        rows.append(
            [
                f"`{b.device_id}`",
                f"{line.baud} bit/s, {line.bits_per_char}-bit chars ({line.char_s * 1e6:.0f} µs)",
                f"{line.turnaround_s * 1000:.2f} + {line.idle_s * 1000:.2f} ms",
                f"{b.registers} ({b.words} words)",
                f"{b.plan.requests} / {b.plan.bytes_total} B / **{ms(b.plan.wire_s)}**",
                f"{b.per_register.requests} / {b.per_register.bytes_total} B / {ms(b.per_register.wire_s)}",
                f"{b.bound.requests} / {b.bound.bytes_total} B / {ms(b.bound.wire_s)}",
                f"**{b.speedup:.2f}×**",
                f"{b.plan.wire_s / b.bound.wire_s:.2f}×",
            ]
        )
    out += table(
        [
            "map",
            "line",
            "turnaround + pause",
            "readable registers",
            "read plan: requests / bytes / wire time",
            "one request per register",
            "lower bound",
            "per register ÷ plan",
            "plan ÷ bound",
        ],
        rows,
        "lllrrrrrr",
    )
    for b in r.bus:
        check = "equal `read_plan(device)` byte for byte" if b.plan_matches_frames else "**differ from `read_plan(device)`**"
        t1 = ""
        if b.line.manual_t1_s is not None:
            t1 = (
                f" Cross-check: the model puts a one-register read, start of request to end of answer, at "
                f"{b.line.model_t1_s * 1000:.2f} ms; the manual's T1 (开始接收至发送完成时间) is {b.line.manual_t1_s * 1000:.2f} ms."
            )
        out.append(
            f"- `{b.device_id}`: turnaround from {b.line.turnaround_source}. The {b.plan.requests} request frames the "
            f"simulator received for `read_all()` {check}; every frame it received was one whole read request with a valid CRC.{t1}"
        )
    idm_bus = next((b for b in r.bus if b.device_id == "idm_rs"), None)
    idm_plan = next((p for p in r.plans if p.device_id == "idm_rs"), None)
    on_bus = {b.device_id for b in r.bus}
    if idm_bus is not None and idm_plan is not None:
        out += [
            "",
            f"Why the plan needs {idm_plan.plan_requests} requests where the bound needs {idm_bus.bound.requests}: the maps say "
            "`undocumented_addresses: reject`, so no request may span an address the manual does not list, and the "
            "parameters are spread over many short runs. If a device answered reads across gaps, the same planner would "
            f"need {', '.join(f'`{p.device_id}` {p.tolerant_requests}' for p in r.plans if p.device_id in on_bus)} requests (a what-if, not measured "
            "on the bus: the manuals do not say the drives allow it; measured below on a simulator that does).",
        ]
    return [*out, *_profiles(r), ""]


def _profiles(r: Results) -> list[str]:
    if not r.profiles:
        return []
    out = [
        "",
        "### With a learned device profile",
        "",
        "The same read_all(), against a simulator playing a drive that answers reads across undocumented addresses",
        "(`regmap simulate --answer-gaps`): first with the map's plan, then with the profile `regmap probe` learned from",
        "that simulator (`SyncClient(..., profile=...)`), which widens the readable addresses by exactly the gap runs",
        "the probe saw answering. Wire time as above.",
        "",
    ]
    rows = [
        [
            f"`{p.device_id}`",
            p.probe_requests,
            p.gap_runs,
            f"{p.without.requests} / {p.without.bytes_total} B / {ms(p.without.wire_s)}",
            f"{p.learned.requests} / {p.learned.bytes_total} B / **{ms(p.learned.wire_s)}**",
            f"{p.bound.requests} / {p.bound.bytes_total} B / {ms(p.bound.wire_s)}",
            f"{p.without.wire_s / p.learned.wire_s:.2f}×",
            f"{p.learned.wire_s / p.bound.wire_s:.2f}×",
        ]
        for p in r.profiles
    ]
    out += table(
        [
            "map",
            "probe requests",
            "gap runs proved",
            "map's plan: requests / bytes / wire time",
            "with the profile",
            "lower bound",
            "map ÷ profile",
            "profile ÷ bound",
        ],
        rows,
        "lrrrrrrr",
    )
    return out


def _plans(r: Results) -> list[str]:
    out = [
        "`bench/optimal.py` finds the fewest requests by dynamic programming over the readable registers in address order",
        "(independently of the greedy planner), under the planner's constraints: one space per request, at most",
        "`max_read_registers` per request (`max_read_coils` bits for coils and discrete inputs), no register split,",
        "requests of several registers start at a paired register's high word and span only documented addresses unless",
        "the map tolerates gaps, a lone register reads only its own words. Among plans with the fewest requests it also",
        "finds the fewest words. The check is repeated for every limit from 2 to 125 (registers and bits alike) on each",
        "map's registers, and, for the maps with several spaces or poll classes (the fixture maps of issue #19, marked",
        "*fixture*), on each space's and each poll class's registers alone (`read_all(poll=...)`).",
        "",
    ]
    rows = [
        [
            f"`{p.device_id}`" + (" *fixture*" if p.device_id.startswith("fixture_") else ""),
            p.limit,
            p.plan_requests,
            p.optimum.requests,
            p.plan_words,
            p.optimum.words,
            p.overlaps,
            f"{p.sweep_instances - len(p.sweep_mismatches)}/{p.sweep_instances}",
            "**optimal**" if p.optimal else "**not optimal**",
        ]
        for p in r.plans
    ]
    out += table(
        [
            "map",
            "max registers",
            "plan requests",
            "DP minimum",
            "plan words",
            "DP fewest words",
            "overlapping registers",
            "limits 2..125 where plan = DP",
            "verdict",
        ],
        rows,
    )
    parts = [(p, part) for p in r.plans for part in p.parts]
    if parts:
        out += ["", "Per space and per poll class:", ""]
        out += table(
            ["map", "registers of", "registers", "plan requests", "DP minimum", "limits where plan = DP", "verdict"],
            [
                [
                    f"`{p.device_id}`",
                    part.part,
                    part.registers,
                    part.plan_requests,
                    part.optimum.requests,
                    f"{p.sweep_instances - len(part.sweep_mismatches)}/{p.sweep_instances}",
                    "**optimal**" if part.optimal else "**not optimal**",
                ]
                for p, part in parts
            ],
        )
    return out


def _phase_table(phases: dict[str, dict[str, float]]) -> list[str]:
    labels = list(phases)
    stages: list[str] = []
    for spent in phases.values():
        stages += [s for s in spent if s not in stages]
    rows = [[stage, *(secs(phases[label][stage]) if stage in phases[label] else "–" for label in labels)] for stage in stages]
    return table(["stage (in-process, one run)", *labels], rows)


def _gen(r: Results) -> list[str]:
    gen = r.gen
    if gen is None:
        return ["Not run.", ""]
    out = [
        "Whole-process wall time of `regmap generate` (all targets: Python, C, Markdown) into a fresh temp directory,",
        "median of the runs shown; CPU is user + system time of the process. The synthetic maps (`bench/synth.py`)",
        "have the real maps' mix: a third of the registers listed one by one (scaled, enum, signed 32-bit, bitfield",
        "registers, Chinese titles, gaps), the rest in parameter tables (arrays).",
        "",
    ]
    runs = [gen.three_maps, *gen.synthetic]
    rows = []
    previous: GenRun | None = None
    for run in runs:
        done = bool(run.wall_s) and run.timed_out_after is None
        exponent = "–"
        if done and previous is not None and run.label.startswith("synthetic"):
            exponent = f"{math.log(run.wall / previous.wall) / math.log(run.registers / previous.registers):.2f}"
        rows.append(
            [
                run.label,
                run.registers,
                run.files or "–",
                _gen_run(run),
                secs(run.cpu) if run.cpu_s else "–",
                f"{len(run.wall_s)}" + (" (stopped)" if run.timed_out_after else ""),
                ", ".join(f"{w:.2f}" for w in run.wall_s) or "–",
                f"{run.wall / run.registers * 1e6:.0f} µs" if done else "–",
                exponent,
            ]
        )
        if done and run.label.startswith("synthetic"):
            previous = run
    out += table(
        ["input", "registers", "files", "wall (median)", "CPU (median)", "runs", "each run (s)", "per register", "growth exponent"],
        rows,
        "lrrrrrlrr",
    )
    out += [
        "Growth exponent: log(time ratio) / log(size ratio) from the previous synthetic size; 1 is linear, 2 quadratic.",
        "",
    ]
    growth = gen.growth(1000, 10000)
    if growth is not None:
        out += [f"Growth 1k → 10k registers: **{growth:.1f}×** wall time for 10× the registers (linear would be 10×).", ""]
    stopped = [run for run in gen.synthetic if run.timed_out_after is not None]
    if stopped:
        out += [
            f"Stopped to keep `make bench` under five minutes: {', '.join(f'{run.label} after {run.timed_out_after:.0f} s' for run in stopped)}. "
            "The stage breakdown and profile below show where the time goes.",
            "",
        ]
    points = [(run.registers, run.wall) for run in gen.synthetic if run.wall_s and run.timed_out_after is None]
    if len(points) >= 2:
        x0, y0 = points[0]
        linear = Series("linear from 1k", tuple((x, y0 * x / x0) for x, _ in points), "#999", dashed=True, markers=False)
        series = [Series("synthetic maps", tuple(points), "#1f77b4"), linear]
        if gen.three_maps.wall_s:
            series.append(Series(gen.three_maps.label, ((gen.three_maps.registers, gen.three_maps.wall),), "#d62728"))
        svg = loglog("regmap generate: wall time against registers", "registers in the map", "wall time", series)
        out += ['<div class="bench-plot">', svg, "</div>", ""]
    if gen.phases:
        out += [
            "Where the time goes (`bench/phases.py`: the same command in one process, each stage timed by wrapping the",
            "function `regmap generate` calls; stages nest: the back ends are inside \u201cback ends, writing and post-processing\u201d):",
            "",
            *_phase_table(gen.phases),
        ]
    if gen.profile:
        out += [
            f"A generation target is missed, so `make bench` profiled {gen.profile_label} with cProfile (which slows pure",
            "Python several times over, so read the shares, not the seconds): the functions with the most time of their own.",
            "",
        ]
        out += table(
            ["function", "calls", "own time", "cumulative"],
            [[f"`{name}`", calls, secs(own), secs(cumulative)] for name, calls, own, cumulative in gen.profile],
        )
    return out


def _overhead(r: Results) -> list[str]:
    out = [
        "The generated iDM-RS client against raw pymodbus doing the same work: the same requests (the read plan's",
        "addresses and counts, worked out before timing) and the same typed values (raw side: pymodbus's",
        "`convert_from_registers`, then scale, enum member or bitfield value, in a table-driven loop; both sides'",
        "results are compared). Decoding starts from pymodbus's response object. Round trips go to `regmap simulate`",
        "(Modbus TCP on loopback, a separate process). Samples alternate generated/raw (ABBA); overhead = ratio of",
        "medians − 1. CPU is this process's CPU time (the simulator's is not in it).",
        "",
    ]
    rows = [
        [
            c.case,
            c.detail,
            us(c.generated_s),
            us(c.raw_s),
            f"**{pct(c.overhead)}**",
            pct(c.cpu_overhead),
            c.samples,
        ]
        for c in r.overhead
    ]
    out += table(["case", "work", "generated", "raw pymodbus", "overhead (wall)", "overhead (CPU)", "samples"], rows, "llrrrrr")
    if r.costs:
        out += [
            "The generated client's own work in `read_many()` (a transport that answers at once, so no pymodbus I/O):",
            "",
        ]
        rows = [[c.case, us(c.read_many_s), us(c.plan_s), us(c.decode_s), f"{c.plan_s / c.read_many_s * 100:.0f} %"] for c in r.costs]
        out += table(["call", "read_many() without I/O", "planning", "decoding", "planning share"], rows)
    return out


def _c(r: Results) -> list[str]:
    c = r.c
    if c is None:
        return ["Not run.", ""]
    out = [f"Header: {c.header}.", ""]
    if c.m0_text is not None:
        out += [
            f"Cortex-M0 text (`{c.compilers.get('m0', '')}`, `arm-none-eabi-size`; `bench/c/m0_frames.c` wraps each "
            "static inline helper out of line, so the object holds what a firmware calling them links):",
            "",
        ]
        out += table(
            ["set", "text", "target"],
            [
                [
                    "every frame helper + CRC (build read / write single / write multiple, response length, parse the three responses, CRC)",
                    f"**{c.m0_text} B**",
                    f"≤ {M0_TARGET} B",
                ],
                ["a master that only reads (build read, parse read response, response length, CRC)", f"{c.m0_text_read_only} B", ""],
            ],
            "lrr",
        )
        out += table(["function (full set)", "bytes"], [[f"`{name}`", size] for name, size in c.m0_symbols])
    if c.blocked:
        out += [f"**Blocked:** {c.blocked}.", ""]
    if c.host_ns:
        out += [
            f"Host time per operation (`{c.compilers.get('host', '')}`, median of 7 loops), with `regmap_runtime.rtu` (Python) for scale:",
            "",
        ]
        out += table(
            ["operation", "C", "Python (regmap_runtime.rtu)"],
            [
                [CASES.get(name, name), f"{ns:.0f} ns", f"{c.python_ns[name] / 1000:.1f} µs" if name in c.python_ns else "–"]
                for name, ns in c.host_ns.items()
            ],
            "lrr",
        )
    return out


def _sim(r: Results) -> list[str]:
    s = r.sim
    if s is None:
        return ["Not run.", ""]
    if s.blocked is not None:
        return [f"Blocked: {s.blocked}.", ""]
    out = [
        "`regmap simulate maps/idm_rs.yaml` (Modbus TCP, one process: its sockets read and written directly, all on one",
        "epoll that the asyncio loop watches, a repeated read answered from the answer cache while the device's memory",
        "is unchanged) and a libmodbus",
        "server (bench/c/modbus_server.c: `modbus_receive`/`modbus_reply`, select() over clients) on loopback, both",
        f"running, the load sent to each in turn, {s.rounds} rounds per level (the median round shown; the ratio is the",
        "median of the rounds' ratios). Load: bench/c/modbus_load.c, N threads with a libmodbus connection each, one",
        "1-register read of Pr5.00 at a time per client; latency is per request, as the client sees it.",
        "",
    ]
    rows = []
    for clients in LEVELS:
        ours, theirs = s.run("regmap simulate", clients), s.run("libmodbus", clients)
        if ours is None or theirs is None:
            continue
        rows.append(
            [
                clients,
                ours.requests,
                f"{ours.rate:,.0f}",
                f"{ours.p50_us:.0f} µs",
                f"{ours.p99_us:.0f} µs",
                f"{theirs.rate:,.0f}",
                f"{theirs.p50_us:.0f} µs",
                f"{theirs.p99_us:.0f} µs",
                f"{s.ratios.get(clients, ours.rate / theirs.rate):.2f}",
                ours.errors + theirs.errors,
            ]
        )
    out += table(["clients", "requests", "simulate req/s", "p50", "p99", "libmodbus req/s", "p50", "p99", "req/s ratio", "errors"], rows)
    rss_rows = [
        [server, f"{before / 1024:.1f} MB", f"{after / 1024:.1f} MB", f"{(after - before) / 1024:+.1f} MB"]
        for server, (before, after) in s.rss_kb.items()
    ]
    out += [f"Resident memory (VmRSS) after a warm-up and after {s.rss_requests:,} more requests from 10 clients:", ""]
    out += table(["server", "before", "after", "growth"], rss_rows)
    ten, ten_ref = s.run("regmap simulate", 10), s.run("libmodbus", 10)
    if ten is not None and ten_ref is not None and "regmap simulate" in s.rss_kb:
        before, after = s.rss_kb["regmap simulate"]
        out += [
            f"With 10 clients the simulator answers {ten.rate:,.0f} requests/s ({s.ratios.get(10, ten.rate / ten_ref.rate):.2f}× libmodbus), p99"
            f" {ten.p99_us / 1000:.1f} ms; its memory moved {(after - before) / 1024:+.1f} MB over {s.rss_requests:,} requests"
            " (no per-request retention: counters, a 64-frame ring and at most 4,096 kept answers).",
            "",
        ]
    return out


def _plant(r: Results) -> list[str]:
    p = r.plant
    if p is None:
        return ["Not run.", ""]
    out = [
        f"`examples/plants/{p.plant_id}.yaml`, bus {p.bus} ({p.devices} devices), generated as a Python plant, its bus moved to",
        "loopback Modbus TCP and polled against the simulator's multi-unit server (bench/plant.py). Wire time is what the",
        f"requests the simulator counted take on the plant's line ({p.line}): RTU request and answer bytes, the addressed",
        "device's turnaround (its map's timing row for the baud, else its response delay) and the 3.5-character silence.",
        "",
    ]
    budget = ms(p.budget_s) if p.budget_s is not None else "n/a"
    out += table(
        ["poll", "requests", "wire time"],
        [
            ["the plant's `read_all()` (devices interleaved, one connection)", p.plant_requests, ms(p.plant_wire_s)],
            ["the sum of each device's own `read_all()`", p.single_requests, ms(p.single_wire_s)],
            ["the schedule's budget (`plant_schedule`, the C/ST poll tables)", p.plant_requests, budget],
        ],
    )
    out += [f"The simulator saw the schedule's order of slave ids: {yes(p.order_matches)}.", ""]
    return out


def _floor(r: Results) -> list[str]:
    if r.floor is None and r.big_import is None:
        return ["Not run.", ""]
    out = [
        "Issue #36, `bench/floor.py`. CPU seconds (user + system, the child's and its children's: ruff included) of",
        f'`regmap generate` (every target, the three maps) and of `python -c "{FLOOR_IMPORTS}"`, run in pairs',
        "(alternating order) with regmap's bytecode cached; the ratio is the median of the pairs' ratios. Cold: `REGMAP_NO_CACHE=1`,",
        "every target rendered from the maps, its compiled templates cached (`regmap/render.py`, filled by one untimed run, as",
        "Python's bytecode is). Warm: the output cache (`regmap/outputcache.py`) filled by one untimed run, so",
        "unchanged maps are neither read nor rendered again. Before: the same code on ac2dd2b (`BEFORE_*` in bench/floor.py).",
        "",
    ]
    if r.floor is not None:
        rows = []
        runs = [("cold", r.floor.cold, BEFORE_COLD, BEFORE_BRANCH_COLD), ("warm", r.floor.warm, BEFORE_WARM, BEFORE_BRANCH_WARM)]
        if r.floor.uncached is not None:  # before the template cache there was none to turn off: its cold run is the one
            runs.append(("cold, no template cache", r.floor.uncached, BEFORE_COLD, BEFORE_BRANCH_COLD))
        for label, ratio, before, branch in runs:
            rows.append(
                (
                    label,
                    len(ratio.generate_s),
                    f"{secs(ratio.generate)} (before {secs(before[0])}; {BEFORE_BRANCH_COMMIT} {secs(ratio.base or branch[0])})",
                    f"{secs(ratio.floor)} (before {secs(before[1])})",
                    f"**{ratio.ratio:.2f}×** (before {before[2]:.2f}×; {_on_base(ratio, branch)})",
                    yes(ratio.ratio <= GENERATE_RATIO_TARGET),
                )
            )
        out += table(["run", "pairs", "generate CPU", "floor CPU", "ratio (median)", f"≤ {GENERATE_RATIO_TARGET:g}×"], rows, "lrrrrc")
        out += [
            f"- The ≤ {GENERATE_RATIO_TARGET:g}× target is judged on the **{JUDGED_ON}** run (a changed map, every target rendered): "
            + ("met." if r.floor.met else "**missed**."),
            "- The warm run is what an unchanged tree costs (the output cache); the cold run without the template cache is a",
            "  first run after installing or upgrading regmap (templates compiled, as Python compiles its modules once).",
            f"- Before, there was no cache: its warm run rendered everything too. {BEFORE_BRANCH_COMMIT}: this round's base, its",
            "  generate run in turn with this tree's and the floor in the same pairs (its source from `git archive`), the fair",
            '  comparison on a shared machine; "as measured" where git could not give it: the figure taken when the round began.',
            "",
        ]
    if r.big_import is not None:
        b = r.big_import
        same = "yes" if b.draft_sha256 == BEFORE_DRAFT_SHA256 else "**no**"
        out += table(
            ["rows", "wall", "CPU", "peak memory", "exit", "draft = before's bytes"],
            [
                (f"{b.rows:,}", secs(b.wall_s), secs(b.cpu_s), f"{b.peak_mib:.0f} MiB", b.status, same),
                ("before", secs(BEFORE_IMPORT_WALL_S), secs(BEFORE_IMPORT_CPU_S), f"{BEFORE_IMPORT_MIB:.0f} MiB", 1, "—"),
            ],
        )
        out += [
            "- The table: 10 columns (address, name, title, type, access, scale, unit, min, max, default), every register u16",
            "  with scale 0.1 (`bench.floor.write_table`); peak memory is the child's maximum resident set.",
            f"- Before: {BEFORE_IMPORT_NOTE}.",
            f"- Now: {b.verdict}",
            "- Wall time on this 2-core machine follows its load (see Machine): the CPU figure is the one to compare across runs.",
            "",
        ]
    return out


def render(r: Results) -> str:
    when = dt.datetime.now(dt.UTC).strftime("%Y-%m-%d %H:%M UTC")
    out = [
        "# Benchmarks",
        "",
        f"<!-- Written by `make bench` (bench/) on {when}; do not edit, run `make bench` again. -->",
        "",
        f"Measured by `make bench` on {when} on the machine described below"
        + (" (quick mode: tiny inputs, figures not meaningful)" if r.quick else "")
        + ". Timings are medians of repeated runs; comparisons are ratios of medians measured side by side in the same run.",
        "",
        "## Targets",
        "",
        *table(["target", "measured", ""], [(t, m, yes(ok)) for t, m, ok in targets(r)], "llc"),
        "## Machine",
        "",
        *_machine(r.machine, r),
        "## 1. Bus time of `read_all()`",
        "",
        *_bus(r),
        "## 2. Read-plan optimality",
        "",
        *_plans(r),
        "## 3. Generation speed",
        "",
        *_gen(r),
        "## 4. Runtime overhead",
        "",
        *_overhead(r),
        "## 5. C frame helpers",
        "",
        *_c(r),
        "## 6. Simulator under load",
        "",
        *_sim(r),
        "## 7. Generation against its import floor; a 20,000-row import",
        "",
        *_floor(r),
        "## 8. A plant's poll cycle",
        "",
        *_plant(r),
    ]
    return "\n".join(out).rstrip("\n") + "\n"
