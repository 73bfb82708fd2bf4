"""The `regmap` command (console script and `python -m regmap`): Ctrl-C at any moment is one line and exit 130, also
while the command line is still being imported. Only `sys`, which the interpreter always has, is imported outside the
`try`: an import there could be interrupted with a traceback."""

import sys


def main() -> int:
    try:
        import signal

        from regmap.cli import main as cli_main

        status = cli_main()
        signal.signal(signal.SIGINT, signal.SIG_IGN)  # done: a late Ctrl-C must not kill the interpreter's exit
    except KeyboardInterrupt:
        import signal

        signal.signal(signal.SIGINT, signal.SIG_IGN)
        from regmap.diagnostics import ExitCode

        print("regmap: interrupted", file=sys.stderr)
        status = ExitCode.INTERRUPTED
    _forget_the_interrupt()
    return status


def _forget_the_interrupt() -> None:
    """Under `python -m`, CPython ends by killing itself with SIGINT when a KeyboardInterrupt once left an exec() of a
    string (a dataclass being made during an import), even one handled since; an exec() of a string that succeeds clears
    that mark, so the status is the one returned."""
    exec("")
