"""The `regmap` command (console script and `python -m regmap`): Ctrl-C at any moment is one line and exit 130, also
while the command line is still being imported. Only `sys`, which the interpreter always has, is imported outside the
`try`: an import there could be interrupted with a traceback."""

import sys


def main() -> int:
    try:
        import gc
        import signal

        # A map or a big table becomes hundreds of thousands of small objects and almost no cycles: at the collector's
        # default (a pass every 700 allocations) whole seconds go into finding nothing. Importing a command's modules
        # alone makes some 60,000 (functions, code, classes), none of them garbage: a pass over them while they load
        # cost a cold `regmap generate` 0.7 % of its CPU when the first threshold was 50,000.
        gc.set_threshold(200_000, 20, 100)

        sys.unraisablehook = _interrupt_again
        from regmap.cli import command_of
        from regmap.cli import main as cli_main

        status = cli_main()
        signal.signal(signal.SIGINT, signal.SIG_IGN)  # done: a late Ctrl-C must not kill the interpreter's exit
        if status == 0 and command_of(sys.argv[1:]) in ENDS_WITHOUT_TEARDOWN:
            _exit_now(status)
    except (KeyboardInterrupt, RuntimeError) as exc:
        if not _interrupted(exc):
            raise
        import signal

        signal.signal(signal.SIGINT, signal.SIG_IGN)
        from regmap.diagnostics import ExitCode

        print("regmap: interrupted", file=sys.stderr)
        status = ExitCode.INTERRUPTED
    _forget_the_interrupt()
    return status


# `generate` has written, closed and swapped in every file and flushed what it printed before it returns, and it starts
# no thread: freeing its models and rendered text object by object at exit only costs CPU (mypy ends so, --fast-exit).
ENDS_WITHOUT_TEARDOWN = frozenset({"generate"})


def _exit_now(status: int) -> None:
    """End the process at once; if what was printed cannot be flushed, return to the normal exit, which reports it."""
    import os

    try:
        sys.stdout.flush()
        sys.stderr.flush()
    except (OSError, ValueError):
        return
    os._exit(status)


def _interrupted(exc: BaseException) -> bool:
    """A KeyboardInterrupt, or one that Python wrapped while making a class during an import (RuntimeError:
    "Error calling __set_name__ ..." caused by it)."""
    cause: BaseException | None = exc
    while cause is not None:
        if isinstance(cause, KeyboardInterrupt):
            return True
        cause = cause.__cause__
    return False


def _interrupt_again(unraisable: "sys.UnraisableHookArgs") -> None:
    """A Ctrl-C that lands in a callback (a weakref's, during an import) is dropped by Python with 'Exception ignored';
    raised again, it lands in regmap's code and ends the run like any other."""
    import signal

    if isinstance(unraisable.exc_value, KeyboardInterrupt):
        signal.raise_signal(signal.SIGINT)
    else:
        sys.__unraisablehook__(unraisable)


def _forget_the_interrupt() -> None:
    """Under `python -m`, CPython ends by killing itself with SIGINT when a KeyboardInterrupt once left an exec() of a
    string (a dataclass being made during an import), even one handled since; an exec() of a string that succeeds clears
    that mark, so the status is the one returned."""
    exec("")
