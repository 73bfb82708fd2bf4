"""One selector grammar for `frame read`, `read` and `dump` (issue #28 items 3, 9, 7).

SELECTOR [COUNT] ...: a plain decimal number right after a selector is its COUNT, in every command;
mbpoll's -r (1-based) and -c; Modicon reference numbers with --modicon, each conversion said on
stderr; "did you mean" offers the zero-padded parameter id first. Live reads run against
`regmap simulate` and are compared with the frames `regmap frame` builds through the simulator's log.
"""

from __future__ import annotations

import itertools
import json
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

from regmap.frontend import load_map

from conftest import ROOT, SimulatorFactory

IDM = "maps/idm_rs.yaml"
C630S = "maps/c630s.yaml"
REMOTE_IO = "tests/maps/fixtures/remote_io.yaml"
POWER_METER = "tests/maps/fixtures/power_meter.yaml"


def regmap(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "regmap", *args], cwd=ROOT, capture_output=True, text=True, check=False, timeout=60)


def frame(*args: str) -> list[str]:
    result = regmap("frame", *args)
    assert result.returncode == 0, result.stderr
    return result.stdout.splitlines()


def one_line_error(result: subprocess.CompletedProcess[str], *needles: str) -> str:
    assert result.returncode == 2, (result.returncode, result.stdout, result.stderr)
    assert result.stdout == ""
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and "internal error" not in result.stderr and "Traceback" not in result.stderr, result.stderr
    for needle in needles:
        assert needle in lines[0], lines[0]
    return lines[0]


def pdu(frame_hex: str) -> str:
    """The PDU of an RTU frame as `frame` prints it (no slave id, no CRC), as the simulator's log shows it."""
    return " ".join(frame_hex.split()[1:-2])


def requests(log: Path) -> list[str]:
    """The request PDUs in a simulator log, in order."""
    return re.findall(r"> MBAP transaction \d+, unit \d+, PDU ([0-9A-F ]+)", log.read_text(encoding="utf-8"))


# -- item 3: one grammar for frame read and read -----------------------------------------------


def test_read_with_a_count_sends_the_frame_that_frame_read_builds(simulator: SimulatorFactory, tmp_path: Path) -> None:
    log = tmp_path / "bus.log"
    sim = simulator(ROOT / IDM, "--log", str(log))
    built = frame(IDM, "read", "Pr5.22", "3")
    got = regmap("read", IDM, "Pr5.22", "3", "--json", "--tcp", f"127.0.0.1:{sim.port}")
    assert got.returncode == 0, got.stderr
    sim.stop()
    assert requests(log) == [pdu(f) for f in built]
    shown = [v["param"] for v in json.loads(got.stdout)]
    assert shown[0] == "Pr5.22" and len(shown) == 3 and "loop_mode" not in got.stdout  # 3 is a count, not loop_mode's address


def test_read_words_reads_what_frame_read_words_builds(simulator: SimulatorFactory, tmp_path: Path) -> None:
    log = tmp_path / "bus.log"
    sim = simulator(ROOT / IDM, "--log", str(log))
    where = ("--tcp", f"127.0.0.1:{sim.port}")
    built = frame(IDM, "read", "--words", "0x01BC", "2")
    words = regmap("read", IDM, "--words", "0x01BC", "2", "--json", *where)
    value = regmap("read", IDM, "Pr5.22", "--json", *where)
    assert words.returncode == 0 and value.returncode == 0, (words.stderr, value.stderr)
    sim.stop()
    assert requests(log)[0] == pdu(built[0])
    rows = json.loads(words.stdout)
    assert [(r["address"], r["space"]) for r in rows] == [(0x01BC, "holding"), (0x01BD, "holding")]
    assert [r["word"] for r in rows[1:]] == json.loads(value.stdout)[0]["words"]  # the low word of the pair is the value


def test_a_count_is_the_same_in_frame_and_read_for_each_selector() -> None:
    # `Pr5.00 3 Pr5.22`: three from Pr5.00 on, then Pr5.22; `-c 3` is the COUNT of one selector.
    assert frame(IDM, "read", "Pr5.00", "3") == frame(IDM, "read", "Pr5.00", "-c", "3") == frame(IDM, "read", "401", "3")
    both = frame(IDM, "read", "Pr5.00", "3", "Pr5.22")
    assert both == frame(IDM, "read", "Pr5.00", "3") + frame(IDM, "read", "Pr5.22")


def test_a_count_too_big_says_the_rule_and_the_other_spelling() -> None:
    one_line_error(regmap("frame", IDM, "read", "401", "445"), "plain decimal number right after a selector is its COUNT", "0x01BD")


@pytest.mark.parametrize(
    ("args", "needles"),
    [
        (("Pr5.22", "3", "-c", "3"), ("two counts",)),
        (("Pr5.22", "Pr5.00", "-c", "2"), ("-c 2 counts from one start",)),
        (("-r", "402", "Pr5.00"), ("either -r or SELECTORs",)),
        (("-r", "0"), ("count from 1",)),
        (("Pr5.22", "0"), ("COUNT 0",)),
        (("--modicon", "30402", "-t", "holding"), ("Modicon 30402 is an input register", "-t/--space says holding")),
        (("--modicon", "401"), ("no Modicon number",)),
        (("--modicon", "20001"), ("no Modicon number",)),
    ],
)
def test_conflicting_spellings_are_one_line(args: tuple[str, ...], needles: tuple[str, ...]) -> None:
    one_line_error(regmap("frame", IDM, "read", *args), *needles)
    one_line_error(regmap("read", IDM, *args, "--tcp", "127.0.0.1:9"), *needles)  # refused before any port is opened


# -- item 9: mbpoll's -r and Modicon numbers, opted into and said ------------------------------


def test_mbpoll_r_is_one_based_and_said() -> None:
    result = regmap("frame", IDM, "read", "-r", "402", "-c", "3")
    assert result.returncode == 0, result.stderr
    assert result.stdout.splitlines() == frame(IDM, "read", "0x0191", "3")
    assert "-r 402 is address 401 (0x0191)" in result.stderr
    assert frame(REMOTE_IO, "read", "--words", "-t", "1", "-r", "197", "-c", "22") == frame(
        REMOTE_IO, "read", "--words", "-t", "1", "0xC4", "22"
    )


def test_read_and_dump_take_r(simulator: SimulatorFactory) -> None:
    sim = simulator(ROOT / IDM)
    where = ("--tcp", f"127.0.0.1:{sim.port}")
    read = regmap("read", IDM, "-r", "402", "--json", *where)
    dump = regmap("dump", IDM, "-r", "402", "-c", "3", "--json", *where)
    counted = regmap("read", IDM, "Pr5.00", "3", "--json", *where)
    assert read.returncode == dump.returncode == counted.returncode == 0, (read.stderr, dump.stderr, counted.stderr)
    assert [v["address"] for v in json.loads(read.stdout)] == [401]
    assert json.loads(dump.stdout) == json.loads(counted.stdout)
    assert "-r 402 is address 401" in read.stderr and "-r 402 is address 401" in dump.stderr


@pytest.mark.parametrize(
    ("map_path", "modicon", "named", "space"),
    [
        (REMOTE_IO, "00020", "relay_20_on", "coil"),
        (REMOTE_IO, "000020", "relay_20_on", "coil"),
        (REMOTE_IO, "10197", "input_197_active", "discrete input"),
        (REMOTE_IO, "30009", "analog_in_9", "input register"),
        (REMOTE_IO, "40108", "config_108", "holding register"),
        (REMOTE_IO, "400110", "config_110", "holding register"),
        (POWER_METER, "30001", "voltage_l1", "input register"),
        (POWER_METER, "300003", "current_l1", "input register"),
        (IDM, "40402", "peak_current", "holding register"),
    ],
)
def test_modicon_numbers_name_the_space_and_count_from_one(map_path: str, modicon: str, named: str, space: str) -> None:
    result = regmap("frame", map_path, "read", "--modicon", modicon)
    assert result.returncode == 0, result.stderr
    assert result.stdout.splitlines() == frame(map_path, "read", named)
    assert re.search(rf"note: Modicon {modicon} is {space} \d+ \(0x[0-9A-F]{{4}}; mbpoll -t \d -r \d+\)", result.stderr), result.stderr


def test_modicon_writes_and_word_writes() -> None:
    result = regmap("frame", IDM, "write", "--modicon", "40402=1.5")
    assert result.returncode == 0 and result.stdout.splitlines() == frame(IDM, "write", "peak_current=1.5")
    assert "Modicon 40402 is holding register 401" in result.stderr
    assert frame(REMOTE_IO, "write", "--words", "--modicon", "00020=1,0,1") == frame(REMOTE_IO, "write", "--words", "-t", "0", "0x13=1,0,1")
    one_line_error(regmap("frame", REMOTE_IO, "write", "--words", "--modicon", "00020=1", "40108=5"), "one data space at a time")
    one_line_error(regmap("frame", REMOTE_IO, "write", "--words", "--modicon", "10197=1"), "read-only")


def test_a_bare_number_stays_a_protocol_address_and_the_error_names_the_notations() -> None:
    # 40402 is protocol address 0x9DD2, where the iDM-RS has nothing; as a Modicon number it is Pr5.00.
    one_line_error(
        regmap("frame", IDM, "read", "40402"),
        "no register at 40402 = 0x9DD2",
        "as a Modicon number 40402 is holding register 401",
        "--modicon",
    )
    one_line_error(regmap("frame", IDM, "read", "402"), "no register at 402 = 0x0192", "mbpoll's -r 402 is address 401 (Pr5.00")


def test_the_readmes_addresses_print_what_it_says() -> None:
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    block = re.search(r"### Addresses\n.*?```sh\n(.*?)```", readme, re.S)
    assert block is not None, "README has no Addresses example"
    lines = block.group(1).splitlines()
    pairs = [(c, e) for c, e in itertools.pairwise(lines) if c.startswith("regmap ") and e.startswith("# ")]
    assert len(pairs) == 3
    for command, expected in pairs:
        argv = shlex.split(command.split("  #", 1)[0])
        assert regmap(*argv[1:]).stdout.strip() == expected[2:].strip(), command


# -- item 7: did you mean ----------------------------------------------------------------------


@pytest.mark.parametrize(("map_path", "typed", "first"), [(IDM, "Pr5.0", "Pr5.00"), (IDM, "pr5.2", "Pr5.02"), (C630S, "P12-2", "P12-02")])
def test_did_you_mean_offers_the_zero_padded_id_first(map_path: str, typed: str, first: str) -> None:
    line = one_line_error(regmap("frame", map_path, "read", typed), "did you mean")
    offered = line.split("did you mean ", 1)[1].rstrip("?)").split(" or ")
    assert offered[0] == first and len(offered) > 1, line


def _field_selectors() -> list[tuple[tuple[str, ...], str, str]]:
    """(arguments, field, label) for a register.field spelling: the map's first writable bitfield register, by name and by parameter id."""
    reg = next(r for r in load_map(ROOT / IDM).registers if r.bitfields and r.access.writable and r.param)
    first, last = reg.bitfields[0].name, reg.bitfields[-1].name
    return [
        (("write", IDM, "--tcp", "127.0.0.1:1", f"{reg.name}.{first}=1"), first, reg.label),  # refused before any connection
        (("write", IDM, "--tcp", "127.0.0.1:1", f"{reg.param}.{last}=1"), last, reg.label),
        (("frame", IDM, "read", f"{reg.name}.{first}"), first, reg.label),
    ]


@pytest.mark.parametrize(("args", "field", "label"), _field_selectors())
def test_a_dotted_field_says_how_regmap_names_it(args: tuple[str, ...], field: str, label: str) -> None:
    """REGISTER.FIELD (how a C struct or an ST variable spells a bitfield member) is no register: the error says
    the register's name and the field-write form, instead of 'did you mean' other registers."""
    name = label.split()[-1]
    line = one_line_error(regmap(*args), f"{field} is a field of {label}", f"{name}={field}:VALUE")
    assert "did you mean" not in line
