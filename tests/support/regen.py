"""Rewrite the expected error text of every invalid map from what `regmap validate` prints now.

Each case is `tests/maps/invalid/<case>.yaml` with its expected stderr beside it in `<case>.expected`.
`make regen` runs this script; it writes only those `.expected` files and prints each one it changed.
A case that is not rejected cleanly (exit status 1, nothing on stdout, no traceback) is reported and left
alone, so a crash or a map that became valid is never recorded as the expected output.

`tests/frontend/test_invalid_maps.py` imports this module for the same paths and the same command; importing it
runs nothing.
"""

from __future__ import annotations

import os
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
INVALID = ROOT / "tests" / "maps" / "invalid"
REGEN_COMMAND = "make regen"


def cases() -> list[Path]:
    """Every invalid map, found by walking the folder."""
    return sorted(INVALID.glob("*.yaml"))


def expected_path(case: Path) -> Path:
    return case.with_suffix(".expected")


def shown(case: Path) -> str:
    """The path as the command is given it, relative to the project root: what every message starts with."""
    return case.relative_to(ROOT).as_posix()


def command(case: Path) -> list[str]:
    return [sys.executable, "-m", "regmap", "validate", shown(case)]


def validate(case: Path) -> subprocess.CompletedProcess[str]:
    """Run the real CLI on one case from the project root."""
    env = {**os.environ, "PYTHONIOENCODING": "utf-8"}
    env.pop("REGMAP_DEBUG", None)  # the expected text is what a user sees, without tracebacks
    return subprocess.run(command(case), cwd=ROOT, env=env, capture_output=True, text=True, encoding="utf-8", timeout=120, check=False)


def validate_all(paths: list[Path]) -> dict[Path, subprocess.CompletedProcess[str]]:
    """`validate` for every case, a few at a time (each is a fresh interpreter)."""
    with ThreadPoolExecutor(max_workers=max(2, os.cpu_count() or 1)) as pool:
        return dict(zip(paths, pool.map(validate, paths), strict=True))


def rejection_problem(result: subprocess.CompletedProcess[str]) -> str | None:
    """Why `result` is not a clean rejection of a map, or None when it is one."""
    if "Traceback" in result.stdout + result.stderr:
        return "it printed a Python traceback"
    if result.returncode != 1:
        return f"exit status {result.returncode}, expected 1"
    if result.stdout:
        return f"it printed on stdout: {result.stdout.strip()!r}"
    if not result.stderr:
        return "it printed no message"
    return None


def main() -> int:
    paths = cases()
    results = validate_all(paths)
    changed = refused = 0
    for case in paths:
        result = results[case]
        problem = rejection_problem(result)
        if problem is not None:
            print(f"regen: {shown(case)} is not rejected cleanly ({problem}); its .expected is left as it was", file=sys.stderr)
            for line in result.stderr.splitlines()[-5:]:
                print(f"    {line}", file=sys.stderr)
            refused += 1
            continue
        target = expected_path(case)
        old = target.read_text(encoding="utf-8") if target.exists() else None
        if old == result.stderr:
            continue
        with target.open("w", encoding="utf-8", newline="\n") as out:
            out.write(result.stderr)
        changed += 1
        print(f"regen: {'wrote' if old is None else 'updated'} {shown(target)}")
    orphans = sorted(p for p in INVALID.glob("*.expected") if not p.with_suffix(".yaml").exists())
    for orphan in orphans:
        print(f"regen: {shown(orphan)} has no {orphan.with_suffix('.yaml').name}; delete it", file=sys.stderr)
    print(f"regen: {len(paths)} invalid maps, {changed} expected texts changed")
    return 1 if refused or orphans else 0


if __name__ == "__main__":
    raise SystemExit(main())
