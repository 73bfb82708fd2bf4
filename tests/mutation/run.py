"""`make mutate`: apply each curated mutant to a scratch copy, regenerate, run the tests that should
catch it (never the drift test), and print a table and the score.

A mutant is one plausible single-line bug (tests/mutation/mutants.yaml: the file, the line as it is,
the line as a developer's slip would make it, why it is plausible, and the tests that must fail).
Exit status 0 when every mutant is killed, 1 when one survives, 2 when the list is stale (a line
no longer exists exactly once) or the unmutated tests fail.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

from regmap.frontend.yamlsource import YamlProblem, read_yaml

ROOT = Path(__file__).resolve().parents[2]
MUTANTS = Path(__file__).with_name("mutants.yaml")
DRIFT = "tests/project/test_generated_drift.py"


@dataclass(frozen=True)
class Mutant:
    id: str
    file: str
    original: str
    mutant: str
    why: str
    tests: tuple[str, ...]


def load() -> list[Mutant]:
    """The curated mutants; a key given twice in one entry (the second would silently win) is an error."""
    try:
        data, _ = read_yaml(MUTANTS.read_text(encoding="utf-8"))
    except YamlProblem as exc:
        raise SystemExit(f"{MUTANTS.relative_to(ROOT)}:{exc.line}:{exc.column}: {exc.message}") from None
    return [Mutant(m["id"], m["file"], m["original"], m["mutant"], m["why"], tuple(m["tests"])) for m in data["mutants"]]


def _copy_tree(scratch: Path) -> None:
    files = subprocess.run(
        ["git", "ls-files", "-co", "--exclude-standard"], cwd=ROOT, capture_output=True, text=True, check=True
    ).stdout.split()
    for name in files:
        source = ROOT / name
        if source.is_file():
            target = scratch / name
            target.parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(source, target)


def _env(scratch: Path) -> dict[str, str]:
    # The scratch copy has no ../shared beside it: point it at the repository's, else every test that
    # needs the manuals or matiec would skip and its mutants "survive".
    shared = os.environ.get("REGMAP_SHARED_DIR") or str(ROOT.parent / "shared")
    return {**os.environ, "PYTHONPATH": str(scratch / "generator"), "PYTHONDONTWRITEBYTECODE": "1", "REGMAP_SHARED_DIR": shared}


def _tests(scratch: Path, tests: tuple[str, ...]) -> subprocess.CompletedProcess[str]:
    command = [sys.executable, "-m", "pytest", "-x", "-q", "-p", "no:cacheprovider", "--deselect", DRIFT, *tests]
    return subprocess.run(command, cwd=scratch, env=_env(scratch), capture_output=True, text=True, check=False, timeout=900)


def _regenerate(scratch: Path) -> bool:
    """As `make generate`: the maps' tree, then each example plant's (generated/plants/<plant id>/)."""
    plants = sorted(p.relative_to(scratch).as_posix() for p in (scratch / "examples" / "plants").glob("*.yaml"))
    for args in [[], *([plant] for plant in plants)]:
        result = subprocess.run(
            [sys.executable, "-m", "regmap", "generate", *args], cwd=scratch, env=_env(scratch), capture_output=True, text=True, check=False
        )
        if result.returncode != 0:
            return False
    return True


def main(argv: list[str]) -> int:
    import argparse

    parser = argparse.ArgumentParser(prog="tests/mutation/run.py", description=__doc__.split("\n\n")[0])
    parser.add_argument("ids", nargs="*", metavar="ID", help="the mutants to run (default: all of tests/mutation/mutants.yaml)")
    wanted = set(parser.parse_args(argv).ids)
    mutants = load()
    unknown = wanted - {m.id for m in mutants}
    if unknown:
        parser.error(f"no mutant named {', '.join(sorted(unknown))}")
    if wanted:
        mutants = [m for m in mutants if m.id in wanted]
    with tempfile.TemporaryDirectory(prefix="regmap-mutate-") as tmp:
        scratch = Path(tmp)
        _copy_tree(scratch)
        stale = [m.id for m in mutants if (scratch / m.file).read_text(encoding="utf-8").count(m.original) != 1]
        if stale:
            print(f"stale mutants (their line is not in the file exactly once): {', '.join(stale)}")
            return 2
        every_test = tuple(sorted({t for m in mutants for t in m.tests}))
        baseline = _tests(scratch, every_test)
        if baseline.returncode != 0:
            print("the unmutated tests fail; fix them first:\n" + baseline.stdout[-3000:])
            return 2
        rows = []
        for m in mutants:
            path = scratch / m.file
            pristine = path.read_text(encoding="utf-8")
            path.write_text(pristine.replace(m.original, m.mutant), encoding="utf-8")
            start = time.perf_counter()
            try:
                killed = not _regenerate(scratch) or _tests(scratch, m.tests).returncode != 0
            finally:
                path.write_text(pristine, encoding="utf-8")
            rows.append((m, killed, time.perf_counter() - start))
            print(f"  {m.id:<40} {'killed' if killed else 'SURVIVED':<9} {rows[-1][2]:6.1f} s", flush=True)
        _regenerate(scratch)
    killed_count = sum(1 for _, k, _ in rows if k)
    print("\n| mutant | file | why | result | time |\n|---|---|---|---|---|")
    for m, killed, spent in rows:
        print(f"| {m.id} | `{m.file}` | {m.why} | {'killed' if killed else '**survived**'} | {spent:.1f} s |")
    print(f"\nscore: {killed_count}/{len(rows)} killed ({100 * killed_count / max(len(rows), 1):.0f} %)")
    return 0 if killed_count == len(rows) else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
