"""The README's examples work as printed.

Every command line of every ```sh block is run, in README order, in a scratch copy of the repository
(a git repository of its own, so `PATH@HEAD` works and nothing is written into the tree under test).
The `# ...` lines right after a command (no blank line between) are its output: each must appear, in
that order, in what the command prints (stdout, then stderr); one ending in `...` is a prefix, and
`# exit status N` says the command exits N (otherwise it must exit 0). A `#` line after a blank line
is prose. Durations (`9.8 s`) are not compared.

A line that names a drive (`--tcp HOST:PORT`, or a serial device `/dev/tty...` for regmap or mbpoll)
talks to a simulator there: the block's own `regmap simulate ... &` line for that address, else one
the test starts for the block's map (on loopback TCP, or on a socat pseudo-terminal pair for a serial
device). The simulator's address replaces the README's in the line and in its expected output,
nothing else. `make X` lines are checked with `make -n X`. Another program than regmap and make must
be installed (skipped without it, except under CI=true). The lines in NOT_RUN are not run, each for
the reason given.
"""

from __future__ import annotations

import os
import re
import shlex
import shutil
import subprocess
import sys
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path

import pytest

from conftest import (
    GENERATED,
    GENERATED_PY,
    ROOT,
    RunningSimulator,
    SimulatorFactory,
    free_port,
    generated_runtime_name,
    mypy_strict,
    require_tool,
    wait_for,
)

README_PATH = ROOT / "README.md"
README = README_PATH.read_text(encoding="utf-8")
BIN = Path(sys.executable).parent  # the venv whose `regmap` the README's lines run

NOT_RUN = {
    r"\. \.venv/bin/activate": "the lines run .venv's regmap from PATH already",
}
# A simulated drive answers on loopback; the README's devices and hosts are replaced by it.
LIVE_ADDRESS = re.compile(r"--tcp\s+(\S+)|(/dev/tty[\w.-]+)")
DURATION = re.compile(r"\b\d+(?:\.\d+)? s\b")
FINGERPRINT = re.compile(r"\bfingerprint [0-9a-f]{16}\b")  # changes with every edit of the map
EXIT_STATUS = re.compile(r"^exit status (\d+)$")
COMMAND_TIMEOUT_S = 300


@dataclass
class Command:
    text: str  # as the README prints it
    line: int  # its line in README.md
    expected: list[str] = field(default_factory=list)  # the `# ...` output lines after it, without `# `

    @property
    def status(self) -> int:
        stated = [int(m.group(1)) for m in map(EXIT_STATUS.match, self.expected) if m]
        return stated[-1] if stated else 0

    @property
    def output(self) -> list[str]:
        return [e for e in self.expected if not EXIT_STATUS.match(e)]


@dataclass
class Block:
    line: int  # the README line of its ```sh
    commands: list[Command]


def sh_blocks(text: str) -> list[Block]:
    """Every ```sh block, its command lines and the output each one shows."""
    blocks = []
    for match in re.finditer(r"^```sh\n(.*?)^```", text, re.S | re.M):
        first = text.count("\n", 0, match.start(1)) + 1
        commands: list[Command] = []
        previous_was_command_or_output = False
        for offset, raw in enumerate(match.group(1).splitlines()):
            stripped = raw.strip()
            if not stripped:
                previous_was_command_or_output = False
            elif stripped.startswith("#"):
                if previous_was_command_or_output and commands:
                    commands[-1].expected.append(stripped[1:].strip())
            else:
                if commands and commands[-1].text.endswith("\\"):
                    commands[-1].text = commands[-1].text[:-1] + " " + stripped
                else:
                    commands.append(Command(stripped, first + offset))
                previous_was_command_or_output = True
        blocks.append(Block(first, commands))
    return blocks


def not_run(command: Command) -> str | None:
    return next((reason for pattern, reason in NOT_RUN.items() if re.fullmatch(pattern, command.text)), None)


def normalized(line: str) -> str:
    """A line as compared: runs of blanks are one space (mbpoll prints tabs), durations and map fingerprints any."""
    return FINGERPRINT.sub("fingerprint <fingerprint>", DURATION.sub("<duration> s", " ".join(line.split())))


def assert_prints(command: Command, result: subprocess.CompletedProcess[str]) -> None:
    """The stated exit status, and each expected line among the output lines, in order."""
    where = f"README.md:{command.line}: {command.text}"
    printed = [normalized(line) for line in (result.stdout + "\n" + result.stderr).splitlines()]
    assert result.returncode == command.status, (
        f"{where}: exit status {result.returncode}, the README says {command.status}\n{result.stdout}{result.stderr}"
    )
    position = 0
    for expected in command.output:
        want = normalized(expected)
        prefix = want.endswith("...")
        for index in range(position, len(printed)):
            if printed[index].startswith(want[:-3].rstrip()) if prefix else printed[index] == want:
                position = index + 1
                break
        else:
            raise AssertionError(
                f"{where}: prints no line {expected!r} (after the lines already matched); it printed:\n" + "\n".join(printed)
            )


@pytest.fixture(scope="module")
def scratch(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The repository's files as they are now (committed or not), as a git repository with one commit."""
    git = require_tool("git")
    root = tmp_path_factory.mktemp("readme") / "regmap"
    files = subprocess.run([git, "ls-files", "-co", "--exclude-standard"], cwd=ROOT, capture_output=True, text=True, check=True)
    for name in files.stdout.splitlines():
        if (ROOT / name).is_file():
            (root / name).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(ROOT / name, root / name)
    identity = ["-c", "user.name=readme", "-c", "user.email=readme@example.invalid", "-c", "commit.gpgsign=false"]
    for args in (["init", "-q"], ["add", "-A"], [*identity, "commit", "-q", "-m", "the README's tree"]):
        subprocess.run([git, *args], cwd=root, capture_output=True, check=True)
    return root


class Simulators:
    """The simulated drives one block talks to, by the address the README gives them; stopped when the
    block ends. A serial device is one end of a socat pseudo-terminal pair, the simulator on the other."""

    def __init__(self, cwd: Path, scratch_dir: Path) -> None:
        self.cwd = cwd
        self.scratch_dir = scratch_dir
        self.addresses: dict[str, str] = {}  # the README's address -> the simulator's
        self.running: list[RunningSimulator] = []  # and the socat pairs they serve on (stopped the same way)

    def start(self, readme_address: str, simulate_argv: list[str]) -> None:
        """Start `regmap simulate` (its arguments without an address) where `readme_address` points."""
        number = len(self.running)
        log = self.scratch_dir / f"simulator-{number}.log"
        if readme_address.startswith("/dev/"):
            socat = require_tool("socat")
            sim_end, client_end = self.scratch_dir / f"pty-{number}-sim", self.scratch_dir / f"pty-{number}-client"
            pair = [f"pty,raw,echo=0,link={sim_end}", f"pty,raw,echo=0,link={client_end}"]
            pty_pair = subprocess.Popen([socat, *pair], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, text=True)
            self.running.append(RunningSimulator(pty_pair))
            wait_for(lambda: sim_end.exists() and client_end.exists(), 10, "socat's pseudo-terminals")
            argv, actual = [*simulate_argv, "--serial", str(sim_end)], str(client_end)
        else:
            port = free_port()
            argv, actual = [*simulate_argv, "--tcp", f"127.0.0.1:{port}"], f"127.0.0.1:{port}"
        with log.open("wb") as output:
            process = subprocess.Popen(argv, cwd=self.cwd, env=with_venv(), stdout=output, stderr=subprocess.STDOUT, text=True)
        self.running.append(RunningSimulator(process))
        # It prints its "on ADDRESS ...; Ctrl-C stops" line once it serves.
        wait_for(lambda: "Ctrl-C stops" in log.read_text(errors="replace") or process.poll() is not None, 20, f"{shlex.join(argv)}")
        assert process.poll() is None, f"{shlex.join(argv)} exited: {log.read_text(errors='replace')}"
        self.addresses[readme_address] = actual

    def stop(self) -> None:
        for running in reversed(self.running):  # each simulator before its pty pair
            running.stop()


def with_venv() -> dict[str, str]:
    return {**os.environ, "PATH": f"{BIN}{os.pathsep}{os.environ.get('PATH', '')}"}


def shell(command: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    result = subprocess.run(["bash", "-c", command], cwd=cwd, env=with_venv(), capture_output=True, check=False, timeout=COMMAND_TIMEOUT_S)
    # `--out -` may print a binary file: shown, not decoded
    return subprocess.CompletedProcess(
        result.args, result.returncode, result.stdout.decode(errors="replace"), result.stderr.decode(errors="replace")
    )


def addresses(text: str) -> list[str]:
    """The drives a line talks to: `--tcp HOST:PORT` and serial devices, as the README writes them."""
    return [m.group(1) or m.group(2) for m in LIVE_ADDRESS.finditer(text)]


def without_address(argv: list[str]) -> list[str]:
    """A `regmap simulate ... &` line's arguments without its --tcp/--serial (the test picks them) and `&`."""
    out: list[str] = []
    skip = False
    for arg in argv:
        if skip:
            skip = False
        elif arg in ("--tcp", "--serial"):
            skip = True
        elif arg != "&":
            out.append(arg)
    return out


def run_block(block: Block, cwd: Path, scratch_dir: Path) -> Iterator[int]:
    """Run a block's lines in order; yields the README line of each one run."""
    simulators = Simulators(cwd, scratch_dir)
    the_map: str | None = None  # the map of the block's latest regmap line: the drive a map-less line (mbpoll) talks to
    try:
        for command in block.commands:
            if not_run(command) is not None:
                continue
            words = shlex.split(command.text, comments=True)
            if words[0] == "make":
                result = subprocess.run(
                    ["make", "-n", *words[1:]], cwd=ROOT, capture_output=True, text=True, check=False, timeout=COMMAND_TIMEOUT_S
                )
                assert result.returncode == 0, f"README.md:{command.line}: make -n has no such target: {result.stderr}"
                yield command.line
                continue
            if words[0] != "regmap":
                require_tool(words[0])
            the_map = next((w for w in words if w.endswith(".yaml")), the_map)
            if words[:2] == ["regmap", "simulate"] and words[-1] == "&":
                [readme_address] = addresses(command.text)
                simulators.start(readme_address, [str(BIN / "regmap"), *without_address(words[1:])])
                yield command.line
                continue
            text, expected = command.text, command.expected
            for readme_address in addresses(command.text):
                if readme_address not in simulators.addresses:  # a drive of the map as the factory ships it
                    assert the_map is not None, f"README.md:{command.line}: no map in the block says which drive {readme_address} is"
                    simulators.start(readme_address, [str(BIN / "regmap"), "simulate", the_map])
                actual = simulators.addresses[readme_address]
                text = text.replace(readme_address, actual)
                expected = [e.replace(readme_address, actual) for e in expected]
            assert_prints(Command(text, command.line, expected), shell(text, cwd))
            yield command.line
    finally:
        simulators.stop()


BLOCKS = sh_blocks(README)


def test_the_readme_has_command_blocks_and_outputs() -> None:
    """The parser finds what the README holds (a parser that found nothing would pass every block)."""
    commands = [c for b in BLOCKS for c in b.commands]
    assert len(BLOCKS) >= 5 and len(commands) >= 25
    assert sum(len(c.output) for c in commands) >= 15
    unmatched = [pattern for pattern in NOT_RUN if not any(re.fullmatch(pattern, c.text) for c in commands)]
    assert not unmatched, f"NOT_RUN lists lines the README no longer has: {unmatched}"


@pytest.mark.parametrize("block", BLOCKS, ids=[f"line{b.line}" for b in BLOCKS])
def test_every_command_line_prints_what_the_readme_says(block: Block, scratch: Path, tmp_path: Path) -> None:
    ran = list(run_block(block, scratch, tmp_path))
    assert len(ran) == len([c for c in block.commands if not_run(c) is None])


def test_a_changed_output_line_fails() -> None:
    """The check can fail: one expected line edited by hand is reported, with its README line."""
    [block] = [b for b in BLOCKS if any(c.text.startswith("regmap frame maps/idm_rs.yaml write peak_current=1.5") for c in b.commands)]
    [command] = [c for c in block.commands if c.text.startswith("regmap frame maps/idm_rs.yaml write peak_current=1.5")]
    edited = Command(command.text, command.line, [e.replace("99 DF", "99 DE") for e in command.expected])
    result = shell(command.text, ROOT)
    assert_prints(command, result)
    with pytest.raises(AssertionError, match=rf"README.md:{command.line}: .* prints no line '01 06 01 91 00 0F 99 DE'"):
        assert_prints(edited, result)


def test_a_serial_line_of_another_program_talks_to_the_same_drive(tmp_path: Path) -> None:
    """Lines added later (mbpoll beside regmap) run the same way: one simulated drive per device name."""
    require_tool("mbpoll")
    [block] = sh_blocks(
        "```sh\n"
        "regmap write maps/idm_rs.yaml Pr5.00=1.5 --serial /dev/ttyUSB0\n"
        "mbpoll -m rtu -a 1 -b 19200 -P even -r 402 -c 1 -1 /dev/ttyUSB0   # mbpoll counts from 1\n"
        "# [402]: 15\n"
        "```\n"
    )
    assert list(run_block(block, ROOT, tmp_path)) == [2, 3]
    block.commands[1].expected = ["[402]: 22"]
    with pytest.raises(AssertionError, match=r"README\.md:3: mbpoll .* prints no line '\[402\]: 22'"):
        list(run_block(block, ROOT, tmp_path))


def _block(language: str, contains: str) -> str:
    for match in re.finditer(rf"```{language}\n(.*?)```", README, re.S):
        if contains in match.group(1):
            return match.group(1)
    raise AssertionError(f"no {language} block with {contains!r} in the README")


def test_c_example_compiles(tmp_path: Path) -> None:
    cc = require_tool("gcc")
    source = tmp_path / "readme.c"
    source.write_text(_block("c", "idm_rs.h"), encoding="utf-8")
    flags = ["-std=c99", "-Wall", "-Wextra", "-Wpedantic", "-Werror", "-Wconversion", "-Wno-missing-prototypes"]
    result = subprocess.run(
        [cc, *flags, "-I", str(GENERATED / "c"), "-c", str(source), "-o", str(tmp_path / "readme.o")],
        capture_output=True,
        text=True,
        check=False,
    )
    assert result.returncode == 0, result.stderr


PYTHON_BLOCKS = [m.group(1) for m in re.finditer(r"```python\n(.*?)```", README, re.S) if "generated/python" in m.group(1)]


@pytest.mark.parametrize("code", PYTHON_BLOCKS, ids=[f"block{i}" for i in range(len(PYTHON_BLOCKS))])
def test_python_examples_type_check(code: str, tmp_path: Path) -> None:
    """Each Python example that imports from generated/python type-checks there, the runtime copy's
    versioned name included (generated/python/regmap_runtime_<digest>)."""
    for name in re.findall(r"\b(regmap_runtime_\w+)", code):
        assert name == generated_runtime_name(), (
            f"the README imports {name}; generated/python holds {generated_runtime_name()}: write that name in README.md"
        )
    program = tmp_path / "readme_example.py"
    program.write_text(code.replace('sys.path.insert(0, "generated/python")', "pass"), encoding="utf-8")
    result = mypy_strict(str(program))
    assert result.returncode == 0, result.stdout


def test_the_profile_example_plans_with_what_the_probe_proved(simulator: SimulatorFactory, tmp_path: Path) -> None:
    """The README's load_profile example, run against the drive its probe example describes (with the
    profile that probe wrote): it reads the registers it says in the requests it says."""
    [code] = [c for c in PYTHON_BLOCKS if "load_profile" in c]
    claim = re.search(r"# (\d+) registers in (\d+) requests", code)
    assert claim is not None, "the profile example says how many registers and requests"
    registers, requests = (int(n) for n in claim.groups())
    drive_options = ("--max-read", "20", "--answer-gaps")
    profile = tmp_path / "drive.json"
    probed = simulator(ROOT / "maps" / "idm_rs.yaml", *drive_options)
    probe = shell(f"regmap probe maps/idm_rs.yaml --tcp 127.0.0.1:{probed.port} --profile {profile}", ROOT)
    assert probe.returncode == 8, probe.stdout + probe.stderr  # it disagrees with the map, as the README shows
    log = tmp_path / "bus.log"
    drive = simulator(ROOT / "maps" / "idm_rs.yaml", *drive_options, "--log", str(log))
    program = tmp_path / "profile_example.py"
    program.write_text(
        code.replace('"generated/python"', repr(str(GENERATED_PY)))
        .replace('"127.0.0.1", 5020', f'"127.0.0.1", {drive.port}')
        .replace('"drive.json"', repr(str(profile))),
        encoding="utf-8",
    )
    result = subprocess.run([sys.executable, str(program)], capture_output=True, text=True, check=False, timeout=COMMAND_TIMEOUT_S)
    assert (result.returncode, result.stdout.strip()) == (0, str(registers)), result.stderr
    # The simulator logs a request once it has answered it: wait for the last one, then count.
    wait_for(lambda: _requests(log) >= requests, 10, f"{requests} requests in the simulator's log")
    assert _requests(log) == requests


def _requests(log: Path) -> int:
    """Requests in a simulator's --log: one line each that starts with its time."""
    if not log.exists():
        return 0
    return sum(1 for line in log.read_text(encoding="utf-8").splitlines() if line[:1].isdigit())


def test_map_table_matches_the_maps() -> None:
    from regmap.frontend import load_map

    from conftest import MAPS

    for path in MAPS:
        device = load_map(path)
        row = re.search(rf"^\| `maps/{path.name}` \|[^|]*\| (\d+) \| (\d+) \| (\d+) \|$", README, re.M)
        assert row is not None, f"README has no row for maps/{path.name}"
        assert tuple(int(x) for x in row.groups()) == (len(device.registers), len(device.examples), len(device.errata)), (
            f"README row of {path.name} is stale"
        )
