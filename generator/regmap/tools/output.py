"""Every file regmap writes goes through `write_output`, and `check_output` refuses, before any work, what it could not write.

A regular file (or a new one) is replaced whole or not at all: a temporary file beside it, fsync, rename. A symlink is
followed: the file it ends at is replaced, the link stays. A device or a FIFO is written in place, never replaced.
`-` (the text, not a Path) is standard output.
"""

from __future__ import annotations

import contextlib
import enum
import io
import os
import stat
import sys
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING

from regmap.diagnostics import OutputError, UsageError
from regmap.records import dataclass

if TYPE_CHECKING:
    from _typeshed import ReadableBuffer

STDOUT = "-"


def is_stdout(where: str | Path) -> bool:
    """`-` given on the command line; a Path never is (Path('./-') is a file named -)."""
    return isinstance(where, str) and where == STDOUT


class _Kind(enum.Enum):
    NEW = "new"  # nothing there yet: created through a temporary file
    REGULAR = "regular"  # replaced through a temporary file, its mode kept
    DIRECT = "direct"  # a device or a FIFO: opened and written, never replaced


@dataclass(frozen=True)
class _Destination:
    path: Path  # the file written: the given path, or the file its symlinks end at
    kind: _Kind


def _destination(path: Path, label: str) -> _Destination:
    target = Path(os.path.realpath(path))
    via = f" ({path} is a symlink to {target})" if os.path.islink(path) else ""
    try:
        mode = os.lstat(target).st_mode
    except FileNotFoundError:
        if not target.parent.is_dir():
            folder = target.parent if via else path.parent
            raise UsageError(f"{label}: the directory {folder} does not exist{via}") from None
        return _Destination(target, _Kind.NEW)
    if stat.S_ISREG(mode):
        return _Destination(target, _Kind.REGULAR)
    if stat.S_ISCHR(mode) or stat.S_ISBLK(mode) or stat.S_ISFIFO(mode):
        return _Destination(target, _Kind.DIRECT)
    if stat.S_ISDIR(mode):
        raise UsageError(f"{label}: is a directory{via}")
    if stat.S_ISLNK(mode):
        raise UsageError(f"{label}: a loop of symlinks")
    raise UsageError(f"{label}: not a file, a device or a FIFO{via}")


def check_output(where: str | Path, option: str, *, stdout: bool = False, binary: bool = False) -> None:
    """Refuse now, before any work or bus traffic, an output that `write_output` would refuse or could not write."""
    if is_stdout(where):
        if not stdout:
            raise UsageError(f"{option} -: standard output is not possible here; give a file name (./- for a file named -)")
        if binary and sys.stdout.isatty():
            raise UsageError(f"{option} -: a binary file is not written to a terminal; redirect standard output or give a file name")
        return
    label = f"{option} {where}"
    destination = _destination(Path(where), label)
    if destination.kind is _Kind.DIRECT:
        if not os.access(destination.path, os.W_OK):
            raise OutputError(f"{label}: {destination.path} is not writable")
    elif not os.access(destination.path.parent, os.W_OK | os.X_OK):
        raise OutputError(f"{label}: the directory {destination.path.parent} is not writable")


def write_output(where: str | Path, data: bytes, option: str = "output") -> None:
    """Write `data` to `where` (see the module's docstring); a failure is an OutputError naming it, nothing half-written."""
    if is_stdout(where):
        sys.stdout.flush()  # text printed before comes first
        sys.stdout.buffer.write(data)
        sys.stdout.buffer.flush()
        return
    path = Path(where)
    destination = _destination(path, f"{option} {path}")
    try:
        if destination.kind is _Kind.DIRECT:
            _write_in_place(destination.path, data)
        else:
            _replace(destination.path, data, keep_mode=destination.kind is _Kind.REGULAR)
    except OSError as exc:
        raise OutputError(f"cannot write {path}: {exc.strerror or exc}") from None


def _write_in_place(path: Path, data: bytes) -> None:
    write_all(os.open(path, os.O_WRONLY | os.O_NOCTTY), data)  # no O_CREAT: it exists, and must not become a regular file


def write_all(fd: int, data: bytes) -> None:
    """Write every byte of `data` to the descriptor (os.write may take only part), then close it."""
    try:
        view = memoryview(data)
        while view:
            view = view[os.write(fd, view) :]
    finally:
        os.close(fd)


def _replace(path: Path, data: bytes, *, keep_mode: bool) -> None:
    """A reader sees the old file or the new one, never half of one."""
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}-", dir=path.parent)
    try:
        with os.fdopen(fd, "wb") as handle:
            handle.write(data)
            handle.flush()
            os.fsync(handle.fileno())
        os.chmod(tmp, path.stat().st_mode & 0o777 if keep_mode else 0o666 & ~_umask())
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


class StdoutError(OutputError):
    """Standard output could not be written (a full disk; a closed pipe is BrokenPipeError, left as it is)."""


class _GuardedRaw(io.FileIO):
    """Standard output's file descriptor, whose write failures are StdoutErrors; after one, later writes are dropped, so
    the interpreter's flush at exit does not print 'Exception ignored' under the one line regmap printed."""

    failed = False

    def write(self, data: ReadableBuffer, /) -> int:
        if self.failed:
            return memoryview(data).nbytes
        try:
            return super().write(data)
        except BrokenPipeError:
            self.failed = True
            raise
        except OSError as exc:
            self.failed = True
            raise StdoutError(f"cannot write to standard output: {exc.strerror or exc}") from None


@contextlib.contextmanager
def guarded_stdout() -> Iterator[None]:
    """sys.stdout for the run, with write failures told apart from the others' (StdoutError). A stdout that is not the
    process's own (a test's capture) is left as it is."""
    captured = sys.stdout is not sys.__stdout__
    original = sys.stdout
    fileno = None
    with contextlib.suppress(OSError, ValueError):
        fileno = None if captured else original.fileno()
    if fileno is None:
        yield
        return
    original.flush()
    raw = _GuardedRaw(fileno, "w", closefd=False)
    sys.stdout = io.TextIOWrapper(
        io.BufferedWriter(raw), encoding=original.encoding, errors="backslashreplace", line_buffering=bool(original.line_buffering)
    )
    try:
        yield
    finally:
        with contextlib.suppress(OSError):
            sys.stdout.flush()
        sys.stdout = original
