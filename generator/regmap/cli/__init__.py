"""The `regmap` command line: one module per subcommand, each with `add_parser()` and `run()`.

Options may come anywhere, before the subcommand too (`regmap --tcp HOST:PORT read ...`, the order mbpoll users
type): they all go to the subcommand's parser (argparse's intermixed parsing). An argument error shows the
subcommand's own usage, and every outcome maps to one documented `ExitCode`.
"""

from __future__ import annotations

import argparse
import importlib
import keyword
import os
import sys
from collections.abc import Sequence
from types import ModuleType
from typing import NoReturn

from regmap import __version__
from regmap.diagnostics import ExitCode, LinkError, MapError, OutputError, UsageError
from regmap.tools.output import guarded_stdout

SUBCOMMANDS = (
    "validate",
    "show",
    "export",
    "generate",
    "frame",
    "decode",
    "read",
    "write",
    "dump",
    "command",
    "simulate",
    "diff",
    "import",
    "new",
    "probe",
)
ALIASES = {"list": "show"}


def _module(name: str) -> ModuleType:
    return importlib.import_module(f"regmap.cli.{name}_" if keyword.iskeyword(name) else f"regmap.cli.{name}")  # import -> import_.py


class _Parser(argparse.ArgumentParser):
    """A bad value of an option is one line (the option, the value, what is allowed), as regmap's own checks say it;
    the usage block stays for what is wrong with the command line's shape (a missing, extra or unknown argument)."""

    def error(self, message: str) -> NoReturn:
        if message.startswith("argument -") and not any(shape in message for shape in ("expected ", "not allowed with")):
            self.exit(ExitCode.USAGE, f"{self.prog}: error: {message}\n")
        super().error(message)


def build_parser(only: str | None = None) -> tuple[argparse.ArgumentParser, dict[str, argparse.ArgumentParser]]:
    """The parser and each subcommand's; with `only`, that subcommand's alone (the others' modules stay unimported)."""
    parser = _Parser(
        prog="regmap",
        description="Declarative Modbus register maps for motor drives: validate, generate, build and decode frames, talk to drives.",
        epilog="`regmap COMMAND --help` shows each command's options and examples. Exit statuses: README, 'Exit status'.",
    )
    parser.add_argument("--version", action="version", version=f"regmap {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    parsers = {name: _module(name).add_parser(sub) for name in SUBCOMMANDS if only in (None, name)}
    return parser, parsers


def _exit_for(exc: SystemExit) -> int:
    code = exc.code
    return code if isinstance(code, int) else ExitCode.USAGE if code else ExitCode.OK


def _tolerant_streams() -> None:
    """A terminal that cannot show Chinese (PYTHONIOENCODING=ascii) gets escapes, not a crash."""
    for stream in (sys.stdout, sys.stderr):
        reconfigure = getattr(stream, "reconfigure", None)
        if reconfigure is not None:
            reconfigure(errors="backslashreplace")


def _quiet_pymodbus() -> None:
    """pymodbus logs transport trouble itself; regmap reports it once, as one line of its own."""
    import logging

    logging.getLogger("pymodbus").setLevel(logging.CRITICAL)


def main(argv: Sequence[str] | None = None) -> int:
    _tolerant_streams()
    args_list = list(sys.argv[1:] if argv is None else argv)
    position = _command_position(args_list)
    named = None if position is None else ALIASES.get(args_list[position], args_list[position])
    if named != "generate":  # generate talks to no bus (tests/project/test_generate_imports.py): it skips importing logging
        _quiet_pymodbus()
    parser, parsers = build_parser(named if named in SUBCOMMANDS else None)
    if position is None or named not in parsers:
        try:
            words = [a for a in args_list if not a.startswith("-")]
            if words and args_list[0].startswith("-") and not {"-h", "--help", "--version"} & set(args_list):
                # Options first, then a misspelt command: any of these words may be an option's value, so name them all.
                parser.error(
                    f"no command among {', '.join(map(repr, words))} (choose from {', '.join(map(repr, [*SUBCOMMANDS, *ALIASES]))})"
                )
            parser.parse_args(args_list)  # --help, --version, or the error naming the valid commands
        except SystemExit as exc:
            return _exit_for(exc)
        return ExitCode.USAGE
    command = ALIASES.get(args_list[position], args_list[position])
    try:
        args = parsers[command].parse_intermixed_args(args_list[:position] + args_list[position + 1 :])
    except SystemExit as exc:
        return _exit_for(exc)
    args.command = command
    with guarded_stdout():
        return _run(command, args)


def command_of(args: Sequence[str]) -> str | None:
    """The command a command line runs (an alias as the command it names), or None if it names none."""
    position = _command_position(list(args))
    return None if position is None else ALIASES.get(args[position], args[position])


def _command_position(args: list[str]) -> int | None:
    """Where the command is: the first word that names one. Words before it must be options and their values
    (`--tcp 127.0.0.1:502 read`: the value is not the command); a first word that names no command, or --version,
    leaves it to the top parser (the error listing the commands, or the version)."""
    position = next((i for i, a in enumerate(args) if a in SUBCOMMANDS or a in ALIASES), None)
    if position and (not args[0].startswith("-") or "--version" in args[:position]):
        return None
    return position


def _run(command: str, args: argparse.Namespace) -> int:
    try:
        result = int(_module(command).run(args))
        sys.stdout.flush()  # here, not at exit: a full disk is reported like any other outcome
        return result
    except MapError as exc:
        for diag in exc.diagnostics:
            print(diag, file=sys.stderr)
        return ExitCode.INVALID_MAP
    except UsageError as exc:
        print(f"regmap {command}: error: {exc}", file=sys.stderr)
        return ExitCode.USAGE
    except LinkError as exc:
        print(f"regmap {command}: bus error: {exc}", file=sys.stderr)
        return ExitCode.BUS
    except OutputError as exc:
        print(f"regmap {command}: error: {exc}", file=sys.stderr)
        return ExitCode.OUTPUT
    except KeyboardInterrupt:
        print(f"regmap {command}: interrupted", file=sys.stderr)
        return ExitCode.INTERRUPTED
    except BrokenPipeError:
        return ExitCode.OK
    except Exception as exc:  # a bug in regmap, not bad input: one line unless asked for more
        if _from_an_interrupt(exc):
            print(f"regmap {command}: interrupted", file=sys.stderr)
            return ExitCode.INTERRUPTED
        if os.environ.get("REGMAP_DEBUG"):
            import traceback  # only here: a run without a bug does not pay for importing it

            traceback.print_exc()
        print(f"regmap {command}: internal error: {type(exc).__name__}: {exc} (set REGMAP_DEBUG=1 for the traceback)", file=sys.stderr)
        return ExitCode.INTERNAL


def _from_an_interrupt(exc: BaseException) -> bool:
    """A Ctrl-C that landed where Python wraps what it catches (a class being made during an import turns it into
    "RuntimeError: Error calling __set_name__ ..."): the user's interrupt, not a bug."""
    seen: set[int] = set()
    cause: BaseException | None = exc
    while cause is not None and id(cause) not in seen:
        if isinstance(cause, KeyboardInterrupt):
            return True
        seen.add(id(cause))
        cause = cause.__cause__ or cause.__context__
    return False
