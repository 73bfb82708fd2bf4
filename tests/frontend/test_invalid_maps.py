"""Golden test of the invalid-map corpus: every `tests/maps/invalid/<case>.yaml` is rejected by the real
`regmap validate`, with exactly the error text committed beside it in `<case>.expected`.

The cases are found by walking the folder; `make regen` rewrites the expected texts (tests/support/regen.py).
"""

from __future__ import annotations

import difflib
import re
import subprocess
from pathlib import Path

import pytest

from support import regen

CASES = regen.cases()
MESSAGE = re.compile(r"^(?P<file>[^:]+):(?P<line>[0-9]+):(?P<col>[0-9]+): \S")


@pytest.fixture(scope="module")
def results(request: pytest.FixtureRequest) -> dict[Path, subprocess.CompletedProcess[str]]:
    """The selected cases, run in one parallel sweep: each run is a fresh interpreter, and there are many."""
    selected = [
        case
        for item in request.session.items
        if isinstance(item, pytest.Function) and item.module is request.module and item.originalname == "test_invalid_map"
        if isinstance(case := item.callspec.params["case"], Path)
    ]
    return regen.validate_all(selected)


def test_corpus_is_large_and_complete() -> None:
    assert len(CASES) >= 45, f"only {len(CASES)} invalid maps in {regen.shown(regen.INVALID)}"
    missing = [regen.shown(regen.expected_path(c)) for c in CASES if not regen.expected_path(c).exists()]
    assert not missing, f"no expected text for {', '.join(missing)}; run `{regen.REGEN_COMMAND}`"
    orphans = [regen.shown(p) for p in regen.INVALID.glob("*.expected") if not p.with_suffix(".yaml").exists()]
    assert not orphans, f"expected texts without a map: {', '.join(orphans)}"


@pytest.mark.parametrize("case", CASES, ids=[c.stem for c in CASES])
def test_invalid_map(case: Path, results: dict[Path, subprocess.CompletedProcess[str]]) -> None:
    result = results[case]
    shown = regen.shown(case)
    command = f"regmap validate {shown}"
    problem = regen.rejection_problem(result)
    assert problem is None, f"`{command}`: {problem}\n--- stderr ---\n{result.stderr}"

    line_count = max(1, case.read_bytes().count(b"\n") + 1)
    for message in result.stderr.splitlines():
        match = MESSAGE.match(message)
        assert match is not None, f"not `file:line:col: message`: {message!r}"
        assert match["file"] == shown, message
        assert 1 <= int(match["line"]) <= line_count, f"line out of the file: {message}"
        assert int(match["col"]) >= 1, message

    expected_file = regen.expected_path(case)
    expected = expected_file.read_text(encoding="utf-8") if expected_file.exists() else ""
    if result.stderr != expected:
        diff = "".join(
            difflib.unified_diff(
                expected.splitlines(keepends=True),
                result.stderr.splitlines(keepends=True),
                fromfile=regen.shown(expected_file),
                tofile=f"{command} (stderr now)",
            )
        )
        pytest.fail(
            f"the errors for {shown} changed:\n{diff}\nIf the new text is right, run `{regen.REGEN_COMMAND}` and commit the result.",
            pytrace=False,
        )
