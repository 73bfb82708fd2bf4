"""Reference codecs and a reference Modbus TCP server on libmodbus, for tests that check regmap's own
codecs and clients against code that is not regmap's.

- `LibmodbusRef` talks to one long-running tests/c/libmodbus_ref.c: floats through libmodbus's
  modbus_set_float_* / modbus_get_float_*, coil bits through modbus_get_byte_from_bits /
  modbus_set_bits_from_bytes.
- `running_libmodbus_server` runs tests/c/libmodbus_tables_server.c on four tables given as a dict and,
  at the end, returns the tables as the server holds them (what a client wrote).

A byte order names the bytes of the IEEE 754 single (a b c d, big-endian, struct's ">f") as they go
on the wire: register 0's high byte, its low byte, register 1's high byte, its low byte. So abcd is
big-endian, cdab swaps the words, badc swaps the bytes in each word, dcba is little-endian.
libmodbus's getters follow their names; its 3.1.6 setters do not (modbus_set_float_abcd writes badc,
and so on, on a little-endian host): `LibmodbusRef.set_float` uses the setter that writes the order
asked for, found at start-up by reading each setter's output back with libmodbus's getters
(`LibmodbusRef.setter_for`); `libmodbus_set_float` calls a setter by its own name.

Test files get the fixtures by importing them (pytest finds the fixtures among a test module's names;
the functions carry other names than the fixtures, so ruff sees no redefinition in the tests):

    from support.libmodbus_ref import LibmodbusRef, LibmodbusServerFactory, libmodbus_ref_fixture, libmodbus_server_fixture  # noqa: F401

    def test_floats(libmodbus_ref: LibmodbusRef) -> None: ...                   # session scoped
    def test_client(libmodbus_server: LibmodbusServerFactory) -> None:
        port, finish = libmodbus_server({"holding": {0x100: 7}})
        ...                                                                      # a client talks to port
        assert finish()["holding"][0x100] == 8

Both programs are compiled once per session (cc, pkg-config and libmodbus-dev; without them the tests
are skipped, except under CI=true where they fail).
"""

from __future__ import annotations

import os
import select
import signal
import struct
import subprocess
import time
from collections.abc import Callable, Iterator, Sequence
from contextlib import ExitStack, contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import NamedTuple

import pytest

from conftest import ROOT, require_tool

C_DIR = ROOT / "tests" / "c"
ORDERS = ("abcd", "badc", "cdab", "dcba")
SPACES = ("coil", "discrete_input", "holding", "input")
CFLAGS = ("-std=c99", "-Wall", "-Wextra", "-Wpedantic", "-Werror", "-O2")
READY_TIMEOUT = 20.0

Tables = dict[str, dict[int, int]]

# A float with four different bytes (40 49 0f db), so each order puts them somewhere else.
_CALIBRATION_BITS = 0x40490FDB


class LibmodbusRefError(ValueError):
    """The reference program refused a command (its "error ..." line)."""


@dataclass(frozen=True)
class LibmodbusPrograms:
    ref: Path  # tests/c/libmodbus_ref.c, compiled
    tables_server: Path  # tests/c/libmodbus_tables_server.c, compiled


_PROGRAMS: list[LibmodbusPrograms] = []


def libmodbus_flags() -> list[str]:
    """The compiler and linker flags for libmodbus; skips (fails under CI=true) without pkg-config or libmodbus-dev."""
    pkg_config = require_tool("pkg-config")
    flags = subprocess.run([pkg_config, "--cflags", "--libs", "libmodbus"], capture_output=True, text=True, check=False)
    if flags.returncode != 0:
        message = "libmodbus-dev is not installed (.ci/run installs it)"
        if os.environ.get("CI") == "true":
            pytest.fail(message)
        pytest.skip(message)
    return flags.stdout.split()


def build_libmodbus_program(source: Path, binary: Path) -> Path:
    """`source` compiled against libmodbus with the tests' warning flags."""
    cc = require_tool("cc")
    build = subprocess.run([cc, *CFLAGS, "-o", str(binary), str(source), *libmodbus_flags()], capture_output=True, text=True, check=False)
    assert build.returncode == 0, f"{source.name} does not compile:\n{build.stderr}"
    return binary


def libmodbus_programs(factory: pytest.TempPathFactory) -> LibmodbusPrograms:
    """Both programs, compiled on the first call of the session; skips (fails under CI=true) without cc,
    pkg-config or libmodbus-dev."""
    if _PROGRAMS:
        return _PROGRAMS[0]
    out = factory.mktemp("libmodbus")
    built = {name: build_libmodbus_program(C_DIR / f"{name}.c", out / name) for name in ("libmodbus_ref", "libmodbus_tables_server")}
    _PROGRAMS.append(LibmodbusPrograms(built["libmodbus_ref"], built["libmodbus_tables_server"]))
    return _PROGRAMS[0]


def _float_from_bits(bits: int) -> float:
    return float(struct.unpack(">f", bits.to_bytes(4, "big"))[0])


class LibmodbusRef:
    """One libmodbus_ref process, answering a line for every line."""

    def __init__(self, binary: Path) -> None:
        self._process = subprocess.Popen(
            [str(binary)], stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, bufsize=1
        )
        self.setter_for: dict[str, str] = self._calibrate()
        """The order asked for -> the libmodbus setter (modbus_set_float_<name>) that writes it."""

    def command(self, line: str) -> str:
        """One raw command line and its answer line (an "error ..." line is returned, not raised)."""
        assert "\n" not in line, line
        stdin, stdout = self._process.stdin, self._process.stdout
        assert stdin is not None and stdout is not None
        stdin.write(line + "\n")
        stdin.flush()
        answer = stdout.readline()
        if not answer.endswith("\n"):
            raise RuntimeError(f"libmodbus_ref stopped (exit {self._process.poll()}) at {line!r}: {answer!r}")
        return answer[:-1]

    def _ask(self, line: str) -> str:
        answer = self.command(line)
        if answer.startswith("error"):
            raise LibmodbusRefError(f"{line!r}: {answer}")
        return answer

    def libmodbus_set_float(self, function: str, value: float) -> tuple[int, int]:
        """The registers modbus_set_float_<function> writes for `value` (as a float32, rounded to nearest;
        too large is inf), by the function's name, whatever order it really writes."""
        if function not in ORDERS:
            raise ValueError(f"no modbus_set_float_{function}")
        w0, w1 = self._ask(f"set_float {function} {float(value).hex()}").split()
        return int(w0, 16), int(w1, 16)

    def set_float(self, order: str, value: float) -> tuple[int, int]:
        """Registers 0 and 1 of `value` in byte order `order` (see the module's docstring), by libmodbus."""
        if order not in ORDERS:
            raise ValueError(f"unknown byte order {order!r}")
        return self.libmodbus_set_float(self.setter_for[order], value)

    def get_float_bits(self, order: str, w0: int, w1: int) -> int:
        """The raw bits of modbus_get_float_<order>({w0, w1}) (exact for every NaN)."""
        if order not in ORDERS:
            raise ValueError(f"unknown byte order {order!r}")
        return int(self._ask(f"get_float {order} {w0} {w1}").split()[1], 16)

    def get_float(self, order: str, w0: int, w1: int) -> float:
        """modbus_get_float_<order>({w0, w1}), exactly through its bits (a NaN's payload may not survive
        the conversion to a Python float: get_float_bits compares NaNs exactly)."""
        return _float_from_bits(self.get_float_bits(order, w0, w1))

    def pack_bits(self, bits: Sequence[int]) -> bytes:
        """The bytes of `bits` in a 0x01/0x02 response or a 0x0F request, by modbus_get_byte_from_bits."""
        answer = self._ask(" ".join(["set_bits", str(len(bits)), *(str(int(b)) for b in bits)]))
        return bytes.fromhex(answer)

    def unpack_bits(self, n: int, data: bytes) -> list[int]:
        """The first `n` bits of `data` ((n + 7) // 8 bytes), by modbus_set_bits_from_bytes."""
        answer = self._ask(" ".join(["get_bits", str(n), *(str(b) for b in data)]))
        return [int(b) for b in answer.split()]

    def close(self) -> None:
        if self._process.stdin is not None:
            self._process.stdin.close()
        try:
            self._process.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self._process.kill()
            self._process.wait()
        if self._process.stdout is not None:
            self._process.stdout.close()

    def _calibrate(self) -> dict[str, str]:
        value = _float_from_bits(_CALIBRATION_BITS)
        setter_for: dict[str, str] = {}
        for function in ORDERS:
            w0, w1 = self.libmodbus_set_float(function, value)
            read_as = [order for order in ORDERS if self.get_float_bits(order, w0, w1) == _CALIBRATION_BITS]
            assert len(read_as) == 1, f"modbus_set_float_{function} wrote {w0:#06x} {w1:#06x}, read back by {read_as}"
            setter_for[read_as[0]] = function
        assert sorted(setter_for) == sorted(ORDERS), f"libmodbus's setters write only {setter_for}"
        return setter_for


class ServerHandle(NamedTuple):
    port: int
    finish: Callable[[], Tables]  # the final tables; stops the server (later calls return the same)


LibmodbusServerFactory = Callable[[Tables], ServerHandle]


class _TablesServer:
    def __init__(self, binary: Path, tables: Tables, workdir: Path) -> None:
        workdir.mkdir(parents=True, exist_ok=True)
        table_file = workdir / "tables.txt"
        lines = [f"{space} {address} {int(value)}" for space, entries in tables.items() for address, value in sorted(entries.items())]
        table_file.write_text("".join(line + "\n" for line in lines), encoding="utf-8")
        self._stderr_path = workdir / "server.stderr"
        self._result: Tables | None = None
        with self._stderr_path.open("w", encoding="utf-8") as stderr:
            self._process = subprocess.Popen(
                [str(binary), "0", str(table_file)], stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=stderr, text=True
            )
        self.port = self._read_port()

    def _stderr(self) -> str:
        return self._stderr_path.read_text(encoding="utf-8")

    def _read_port(self) -> int:
        stdout = self._process.stdout
        assert stdout is not None
        deadline = time.monotonic() + READY_TIMEOUT
        line = ""
        while not line and time.monotonic() < deadline:
            if select.select([stdout], [], [], 0.1)[0]:
                line = stdout.readline()
                break
        words = line.split()
        if len(words) != 2 or words[0] != "listening":
            self.stop()
            raise AssertionError(f"libmodbus_tables_server did not start (said {line!r}): {self._stderr()}")
        return int(words[1])

    def finish(self) -> Tables:
        if self._result is None:
            try:
                out, _ = self._process.communicate("dump\n", timeout=READY_TIMEOUT)
            except subprocess.TimeoutExpired:
                self.stop()
                raise
            assert self._process.returncode == 0, f"libmodbus_tables_server exited {self._process.returncode}: {self._stderr()}"
            self._result = parse_dump(out)
        return self._result

    def stop(self) -> None:
        if self._process.poll() is None:
            self._process.send_signal(signal.SIGTERM)  # it dumps and exits
            try:
                self._process.communicate(timeout=10)
            except subprocess.TimeoutExpired:
                self._process.kill()
                self._process.communicate()


def parse_dump(text: str) -> Tables:
    """The tables of a libmodbus_tables_server dump ("SPACE ADDR VALUE" lines)."""
    tables: Tables = {space: {} for space in SPACES}
    for line in text.splitlines():
        space, address, value = line.split()
        tables[space][int(address)] = int(value)
    return tables


@contextmanager
def running_libmodbus_server(binary: Path, tables: Tables, workdir: Path) -> Iterator[ServerHandle]:
    """libmodbus_tables_server on 127.0.0.1 with `tables` ({"coil"|"discrete_input"|"holding"|"input":
    {address: value}}), ready when entered; stopped on exit if finish() was not called."""
    server = _TablesServer(binary, tables, workdir)
    try:
        yield ServerHandle(server.port, server.finish)
    finally:
        server.stop()


@pytest.fixture(name="libmodbus_ref", scope="session")
def libmodbus_ref_fixture(tmp_path_factory: pytest.TempPathFactory) -> Iterator[LibmodbusRef]:
    """One LibmodbusRef for the session."""
    ref = LibmodbusRef(libmodbus_programs(tmp_path_factory).ref)
    yield ref
    ref.close()


@pytest.fixture(name="libmodbus_server")
def libmodbus_server_fixture(tmp_path_factory: pytest.TempPathFactory, tmp_path: Path) -> Iterator[LibmodbusServerFactory]:
    """start(tables) -> (port, finish): libmodbus_tables_server on those tables; any still running at the
    end of the test are stopped."""
    binary = libmodbus_programs(tmp_path_factory).tables_server
    with ExitStack() as stack:
        count = iter(range(1 << 30))

        def start(tables: Tables) -> ServerHandle:
            return stack.enter_context(running_libmodbus_server(binary, tables, tmp_path / f"libmodbus-server-{next(count)}"))

        yield start
