"""Generation is atomic: a failed or killed run leaves the previous output intact."""

from __future__ import annotations

import os
import random
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from regmap.cli import main
from regmap.frontend import load_map
from regmap.generate import UTF8_SLICE, Target, generate, recover, utf8

from conftest import MAPS, ROOT, SMALL_MAPS
from support.trees import tree


def test_a_failing_target_changes_nothing(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    out = tmp_path / "generated"
    devices = [load_map(p) for p in SMALL_MAPS]
    generate(devices, out, ["python", "c"], complete=True)
    before = tree(out)

    def broken(directory: Path) -> None:
        raise RuntimeError("formatter crashed")

    from regmap.backends import python

    monkeypatch.setattr(python, "TARGET", Target("python", "python", python.render_device, python.render_shared, broken))
    with pytest.raises(RuntimeError):
        generate(devices, out, ["c", "python"], complete=True)
    assert tree(out) == before
    assert not list(tmp_path.glob(".regmap-staging-*")), "staging left behind"


def test_extra_files_are_swapped_in_with_the_targets(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The `--since` changelog pages go into the staged tree: a failed run writes none of them, and a
    complete run that replaces docs/ keeps them."""
    out = tmp_path / "generated"
    devices = [load_map(p) for p in SMALL_MAPS]
    page = {"docs/extra-changelog.md": "# page\n"}
    written = generate(devices, out, ["markdown"], complete=True, extra=page)
    assert (out / "docs" / "extra-changelog.md").read_text(encoding="utf-8") == "# page\n"
    assert out.resolve() / "docs" / "extra-changelog.md" in written
    before = tree(out)

    def broken(directory: Path) -> None:
        raise RuntimeError("formatter crashed")

    from regmap.backends import python

    monkeypatch.setattr(python, "TARGET", Target("python", "python", python.render_device, python.render_shared, broken))
    with pytest.raises(RuntimeError):
        generate(devices, out, ["markdown", "python"], complete=True, extra={"docs/extra-changelog.md": "# changed\n"})
    assert tree(out) == before


def test_invalid_map_changes_nothing(tmp_path: Path) -> None:
    out = tmp_path / "generated"
    subprocess.run(
        [sys.executable, "-m", "regmap", "generate", *map(str, SMALL_MAPS), "--out", str(out)], cwd=ROOT, check=True, capture_output=True
    )
    before = tree(out)
    broken = tmp_path / "broken.yaml"
    broken.write_text(SMALL_MAPS[0].read_text(encoding="utf-8").replace("map_version: 0.1.0", "map_version: one"), encoding="utf-8")
    result = subprocess.run(
        [sys.executable, "-m", "regmap", "generate", str(broken), "--out", str(out)], cwd=ROOT, capture_output=True, text=True, check=False
    )
    assert result.returncode == 1
    assert "map_version" in result.stderr
    assert tree(out) == before


def test_killed_runs_leave_old_or_new_never_half(tmp_path: Path) -> None:
    out = tmp_path / "generated"
    args = [sys.executable, "-m", "regmap", "generate", *map(str, MAPS), "--out", str(out)]
    subprocess.run(args, cwd=ROOT, check=True, capture_output=True)
    complete = tree(out)
    rng = random.Random(1234)
    for _ in range(6):
        process = subprocess.Popen(args, cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        time.sleep(rng.uniform(0.2, 1.5))
        process.send_signal(signal.SIGKILL)
        process.wait()
        recover(out)  # what the next run does first
        assert out.exists()
        assert tree(out) == complete, "a killed run left a partial tree"
    assert not list(tmp_path.glob(".regmap-staging-*"))


def test_recover_restores_output_killed_between_renames(tmp_path: Path) -> None:
    out = tmp_path / "generated"
    staging = tmp_path / ".regmap-staging-999999999-x"
    (staging / "previous").mkdir(parents=True)
    (staging / "previous" / "keep.txt").write_text("old", encoding="utf-8")
    assert not os.path.exists(out)
    recover(out)
    assert (out / "keep.txt").read_text(encoding="utf-8") == "old"
    assert not staging.exists()


def test_a_complete_run_replaces_only_its_targets_directories(tmp_path: Path) -> None:
    """The staged tree starts from the old output without the directories the run replaces: their stale files go,
    everything else (another target's directory, a file of the user's) stays; a run that is not complete keeps them."""
    out = tmp_path / "generated"
    devices = [load_map(p) for p in SMALL_MAPS]
    generate(devices, out, ["python", "c"], complete=True)
    (out / "notes.txt").write_text("mine\n", encoding="utf-8")
    (out / "c" / "stale.h").write_text("/* from a removed map */\n", encoding="utf-8")
    python_before = tree(out / "python")
    c_before = tree(out / "c")
    generate(devices, out, ["c"], complete=False)
    assert tree(out / "c") == c_before
    generate(devices, out, ["c"], complete=True)
    assert (out / "notes.txt").read_text(encoding="utf-8") == "mine\n"
    assert tree(out / "python") == python_before
    assert tree(out / "c") == {rel: content for rel, content in c_before.items() if rel != "stale.h"}


def test_a_run_that_ends_without_teardown_has_written_and_printed_everything(tmp_path: Path) -> None:
    """`regmap generate` ends with os._exit once it succeeded (entry.ENDS_WITHOUT_TEARDOWN): what it printed to a pipe
    and every file it wrote are all there, the same as a run in this process makes them."""
    out, here = tmp_path / "generated", tmp_path / "in-process"
    result = subprocess.run(
        [sys.executable, "-m", "regmap", "generate", *map(str, SMALL_MAPS), "--out", str(out)],
        cwd=ROOT,
        capture_output=True,
        text=True,
        check=False,
    )
    assert (result.returncode, result.stderr) == (0, "")
    assert result.stdout.startswith("regmap generate: ") and result.stdout.endswith(f" -> {out}/\n"), result.stdout
    assert main(["generate", *map(str, SMALL_MAPS), "--out", str(here)]) == 0
    assert tree(out) == tree(here) and tree(out)


def test_a_file_is_written_as_the_utf8_of_its_text_whatever_slices_it_is_encoded_by() -> None:
    """A long text is encoded slice by slice: the bytes are its UTF-8 all the same, characters at the cuts included."""
    wide, astral, latin = "\uff0c", "\U0001f600", "\u00b0"
    texts = [
        "",
        "a" * (UTF8_SLICE * 3),
        "a" * (UTF8_SLICE - 1) + wide + "b" * (UTF8_SLICE + 7),
        astral + "c" * UTF8_SLICE + astral + latin * 3,
        (latin + "d" * 100 + wide) * (UTF8_SLICE // 50),
        "e" * UTF8_SLICE + wide,
    ]
    assert [utf8(text) for text in texts] == [text.encode("utf-8") for text in texts]
