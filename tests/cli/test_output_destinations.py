"""Where regmap's outputs go (issue 28): a symlink is followed, a device or a FIFO is written in place and never replaced,
a directory is refused before any work, `-` is standard output, a full disk is one line and exit 74, and Ctrl-C at any
moment, even while the command line is still being imported, is one line and exit 130."""

from __future__ import annotations

import errno
import io
import json
import os
import re
import select
import shutil
import signal
import socket
import stat
import subprocess
import sys
import threading
import time
from pathlib import Path
from typing import IO

import openpyxl
import pytest

from regmap.diagnostics import ExitCode
from regmap.frontend import load_map

from conftest import ROOT
from support.tables import table_changing_a_default

IDM = str(ROOT / "maps" / "idm_rs.yaml")
SMALL = ROOT / "tests" / "maps" / "small" / "idm_rs_small.yaml"
CONSOLE_SCRIPT = Path(sys.executable).parent / "regmap"


def regmap(*args: str, cwd: Path = ROOT, stdout: int | IO[str] = subprocess.PIPE) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "regmap", *args], cwd=cwd, stdout=stdout, stderr=subprocess.PIPE, text=True, check=False, timeout=120
    )


def one_line_error(result: subprocess.CompletedProcess[str], code: int, *needles: str) -> None:
    assert result.returncode == code, (result.returncode, result.stdout, result.stderr)
    assert len(result.stderr.strip().splitlines()) == 1, result.stderr
    assert "Traceback" not in result.stderr and "internal error" not in result.stderr and "Exception ignored" not in result.stderr
    for needle in needles:
        assert needle in result.stderr, result.stderr


def device_node(path: Path, minor: int) -> Path:
    """A character device like /dev/null (minor 3) or /dev/full (minor 7), made in tmp_path: the real ones stay untouched."""
    try:
        os.mknod(path, 0o666 | stat.S_IFCHR, os.makedev(1, minor))
    except PermissionError:
        pytest.skip("making a device node needs root (CAP_MKNOD)")
    return path


def exported_json() -> str:
    return regmap("export", IDM).stdout


# -- 1. output paths are written, not replaced -----------------------------------------------------


def test_export_follows_a_symlink_and_keeps_the_link(tmp_path: Path) -> None:
    target = tmp_path / "target.json"
    target.write_text("{}\n")
    target.chmod(0o640)
    link = tmp_path / "link.json"
    link.symlink_to(target.name)
    result = regmap("export", IDM, "--out", str(link))
    assert result.returncode == 0, result.stderr
    assert link.is_symlink() and os.readlink(link) == target.name
    assert json.loads(target.read_text(encoding="utf-8")) == json.loads(exported_json())
    assert stat.S_IMODE(target.stat().st_mode) == 0o640


def test_import_into_a_symlinked_map_updates_the_map_it_names(tmp_path: Path) -> None:
    real = tmp_path / "maps" / "idm_rs_small.yaml"
    real.parent.mkdir()
    shutil.copy(SMALL, real)
    link = tmp_path / "idm_rs_small.yaml"
    link.symlink_to(real)
    table, reg, default = table_changing_a_default(load_map(SMALL), tmp_path)
    result = regmap("import", str(table), "--into", str(link))
    assert result.returncode == 0, result.stderr
    assert link.is_symlink() and link.resolve() == real
    updated = load_map(real).registers
    assert next(r for r in updated if r.name == reg.name).default == default


def test_a_dangling_symlink_gets_its_target_created(tmp_path: Path) -> None:
    link = tmp_path / "link.json"
    link.symlink_to("made.json")
    result = regmap("export", IDM, "--out", str(link))
    assert result.returncode == 0, result.stderr
    assert link.is_symlink() and (tmp_path / "made.json").is_file() and not (tmp_path / "made.json").is_symlink()
    assert json.loads((tmp_path / "made.json").read_text(encoding="utf-8"))["device"]["id"] == "idm_rs"


def test_a_fifo_is_written_in_place(tmp_path: Path) -> None:
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    received: list[bytes] = []
    reader = threading.Thread(target=lambda: received.append(fifo.read_bytes()), daemon=True)
    reader.start()
    result = regmap("export", IDM, "--out", str(fifo))
    reader.join(timeout=30)
    assert result.returncode == 0, result.stderr
    assert stat.S_ISFIFO(os.lstat(fifo).st_mode)
    assert received and json.loads(received[0]) == json.loads(exported_json())


def test_a_full_device_is_exit_74_and_stays_a_device(tmp_path: Path) -> None:
    full = device_node(tmp_path / "full", 7)
    result = regmap("export", IDM, "--out", str(full))
    one_line_error(result, ExitCode.OUTPUT, f"cannot write {full}: No space left on device")
    assert stat.S_ISCHR(os.lstat(full).st_mode) and os.lstat(full).st_rdev == os.makedev(1, 7)
    assert [p.name for p in tmp_path.iterdir()] == ["full"]  # no temporary file left beside it


def test_a_null_device_is_written_and_stays_a_device(tmp_path: Path) -> None:
    null = device_node(tmp_path / "null", 3)
    result = regmap("export", IDM, "--format", "csv", "--out", str(null))
    assert (result.returncode, result.stderr) == (0, "")
    assert stat.S_ISCHR(os.lstat(null).st_mode) and os.lstat(null).st_size == 0


def test_a_socket_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "sock"
    with socket.socket(socket.AF_UNIX) as server:
        server.bind(str(path))
        result = regmap("export", IDM, "--out", str(path))
    one_line_error(result, ExitCode.USAGE, f"--out {path}: not a file, a device or a FIFO")


@pytest.mark.parametrize(
    "command",
    [
        ("export", IDM, "--out", "{dir}"),
        ("export", IDM, "--format", "xlsx", "--out", "{dir}"),
        ("export", IDM, "--out", "{dir}/link"),
        ("import", str(ROOT / "tests" / "maps" / "nonexistent.csv"), "--into", "{dir}"),
    ],
    ids=["export", "export-xlsx", "export-via-symlink", "import"],
)
def test_a_directory_is_refused_before_any_work(command: tuple[str, ...], tmp_path: Path) -> None:
    (tmp_path / "link").symlink_to(tmp_path)
    args = [a.replace("{dir}", str(tmp_path)) for a in command]
    result = regmap(*args)
    one_line_error(result, ExitCode.USAGE, "is a directory")
    assert result.stdout == ""
    assert sorted(p.name for p in tmp_path.iterdir()) == ["link"]


def test_probe_refuses_a_directory_profile_before_any_bus_traffic(tmp_path: Path) -> None:
    with socket.socket() as listener:
        listener.bind(("127.0.0.1", 0))
        listener.listen()
        port = listener.getsockname()[1]
        started = time.monotonic()
        result = regmap("probe", IDM, "--tcp", f"127.0.0.1:{port}", "--profile", str(tmp_path), "--budget", "30")
        elapsed = time.monotonic() - started
        connected, _, _ = select.select([listener], [], [], 0)
    one_line_error(result, ExitCode.USAGE, f"--profile {tmp_path}: is a directory")
    assert not connected, "the probe connected to the drive before refusing --profile"
    assert elapsed < 10


def test_a_write_error_keeps_the_old_file_and_removes_the_temporary(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from regmap.diagnostics import OutputError
    from regmap.tools.output import write_output

    path = tmp_path / "drive.json"
    path.write_bytes(b"old\n")

    def full_disk(fd: int) -> None:
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(os, "fsync", full_disk)
    with pytest.raises(OutputError, match=f"^cannot write {re.escape(str(path))}: No space left on device$"):
        write_output(path, b"new contents\n", "--out")
    assert path.read_bytes() == b"old\n"
    assert [p.name for p in tmp_path.iterdir()] == ["drive.json"]


def test_generate_out_a_symlink_to_a_directory_generates_into_its_target(tmp_path: Path) -> None:
    real = tmp_path / "real"
    real.mkdir()
    (real / "keep.txt").write_text("kept\n")
    link = tmp_path / "gen"
    link.symlink_to("real")
    result = regmap("generate", str(SMALL), "--target", "c", "--out", str(link))
    assert result.returncode == 0, result.stderr
    assert link.is_symlink() and os.readlink(link) == "real"
    assert (real / "c" / "idm_rs_small.h").is_file() and (real / "keep.txt").read_text() == "kept\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["gen", "real"]  # no staging directory left


# -- 2. `-` is standard output ---------------------------------------------------------------------


@pytest.mark.parametrize("fmt", ["json", "csv", "xlsx"])
def test_out_dash_is_standard_output(fmt: str, tmp_path: Path) -> None:
    to_file = tmp_path / f"file.{fmt}"
    assert regmap("export", IDM, "--format", fmt, "--out", str(to_file)).returncode == 0
    result = subprocess.run(
        [sys.executable, "-m", "regmap", "export", IDM, "--format", fmt, "--out", "-"], cwd=tmp_path, capture_output=True, check=False
    )
    assert (result.returncode, result.stderr) == (0, b"")
    assert sorted(p.name for p in tmp_path.iterdir()) == [to_file.name]  # no file named -
    assert result.stdout == to_file.read_bytes()
    if fmt == "xlsx":
        assert openpyxl.load_workbook(io.BytesIO(result.stdout)).sheetnames[0] == "registers"


def test_xlsx_to_a_terminal_is_refused(tmp_path: Path) -> None:
    controller, terminal = os.openpty()
    try:
        result = regmap("export", IDM, "--format", "xlsx", "--out", "-", cwd=tmp_path, stdout=terminal)
    finally:
        os.close(terminal)
        os.close(controller)
    assert result.returncode == ExitCode.USAGE, result.stderr
    assert (
        result.stderr
        == "regmap export: error: --out -: a binary file is not written to a terminal; redirect standard output or give a file name\n"
    )
    assert list(tmp_path.iterdir()) == []


def test_new_out_dash_prints_the_skeleton(tmp_path: Path) -> None:
    result = regmap("new", "acme_x1", "--vendor", "Acme", "--model", "X1", "--out", "-", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert "device:" in result.stdout and "id: acme_x1" in result.stdout
    assert list(tmp_path.iterdir()) == []


# -- 4. a full standard output, and Ctrl-C ---------------------------------------------------------


@pytest.mark.parametrize(
    "command",
    [("show", IDM), ("frame", IDM, "read", "peak_current")],
    ids=["show: fails while printing", "frame: one line, fails at the last flush"],
)
def test_a_full_standard_output_is_exit_74(command: tuple[str, ...], tmp_path: Path) -> None:
    full = device_node(tmp_path / "full", 7)
    with full.open("w") as stdout:
        result = regmap(*command, stdout=stdout)
    assert result.returncode == ExitCode.OUTPUT, result.stderr
    assert result.stderr == f"regmap {command[0]}: error: cannot write to standard output: No space left on device\n"


def test_a_closed_pipe_stays_quiet() -> None:
    # The JSON (some 450 kB) is more than a pipe holds, so the reader's going away is seen: as `| head -1`.
    with subprocess.Popen(
        [sys.executable, "-m", "regmap", "export", IDM], cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE
    ) as process:
        assert process.stdout is not None and process.stderr is not None
        process.stdout.readline()
        process.stdout.close()
        stderr = process.stderr.read()
    assert (process.returncode, stderr) == (0, b"")


IMPORTED = re.compile(rb"^import time:.*\|\s*(\S+)$")  # PYTHONPROFILEIMPORTTIME: one line per module imported


def _interrupt(command: list[str], delay: float) -> tuple[int, list[str]]:
    """Start `command`, send SIGINT `delay` seconds after regmap's first own import; its status and stderr lines."""
    environment = {**os.environ, "PYTHONPROFILEIMPORTTIME": "1"}
    with subprocess.Popen([*command, "show", IDM], cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=environment) as process:
        assert process.stderr is not None
        imported: list[bytes] = []
        while b"regmap.entry" not in imported[:-1]:
            line = process.stderr.readline()
            assert line, imported
            found = IMPORTED.match(line.rstrip(b"\n"))
            imported += [found.group(1)] if found else []
        time.sleep(delay)
        process.send_signal(signal.SIGINT)
        rest = process.stderr.read()
    return process.returncode, [line for line in rest.decode().splitlines() if not line.startswith("import time:")]


@pytest.mark.parametrize("launcher", ["python -m regmap", "console script"])
@pytest.mark.parametrize("delay", [0.0, 0.01, 0.03, 0.06, 0.1, 0.2, 0.3, 0.5])
def test_ctrl_c_at_any_moment_is_exit_130(launcher: str, delay: float) -> None:
    # Counted from the first import after regmap.entry's, the first of regmap's own `main`. Before it the interpreter
    # is starting (site, runpy, finding the package, the console script's own lines; some 20-40 ms), no line of regmap
    # has run, and SIGINT ends it as it ends any Python program that has not started. The ~0.3 s of imports after it
    # are the moment a Ctrl-C used to print a traceback.
    command = [sys.executable, "-m", "regmap"] if launcher == "python -m regmap" else [str(CONSOLE_SCRIPT)]
    # On a busy machine this process may be scheduled again only after `show` has finished: a Ctrl-C after the work
    # changes nothing (exit 0, silent). Such a try proves nothing, so an early delay is tried again until one lands.
    for _attempt in range(5):
        status, said = _interrupt(command, delay)
        if status != ExitCode.OK:
            break
        assert said == []
        if delay >= 0.2:  # late enough that `show` may well have finished: exit 0 is a right answer
            return
    assert status == ExitCode.INTERRUPTED, said
    assert len(said) == 1 and re.fullmatch(r"regmap( show)?: interrupted", said[0]), said


def test_a_ctrl_c_python_wrapped_during_an_import_is_an_interrupt(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """Python 3.11 turns a KeyboardInterrupt inside a class being made (a dataclass field's __set_name__, while a
    subcommand's modules import) into "RuntimeError: Error calling __set_name__": still the user's Ctrl-C, exit 130."""
    import argparse
    import types

    import regmap.cli as cli

    def run(args: argparse.Namespace) -> int:
        try:
            raise KeyboardInterrupt
        except KeyboardInterrupt as interrupt:
            raise RuntimeError("Error calling __set_name__ on 'Field' instance 'pos' in 'Register'") from interrupt

    monkeypatch.setattr(cli, "_module", lambda name: types.SimpleNamespace(run=run))
    assert cli._run("show", argparse.Namespace()) == 130
    assert capsys.readouterr().err == "regmap show: interrupted\n"
