"""The `regmap` command (console script and `python -m regmap`): Ctrl-C at any moment is one line and exit 130, also
while the command line is still being imported. Nothing is imported outside the `try` but what the interpreter has."""

from __future__ import annotations

import signal
import sys


def main() -> int:
    try:
        from regmap.cli import main as cli_main

        status = cli_main()
        signal.signal(signal.SIGINT, signal.SIG_IGN)  # done: a late Ctrl-C must not kill the interpreter's exit
        return status
    except KeyboardInterrupt:
        signal.signal(signal.SIGINT, signal.SIG_IGN)
        from regmap.diagnostics import ExitCode

        print("regmap: interrupted", file=sys.stderr)
        return ExitCode.INTERRUPTED
