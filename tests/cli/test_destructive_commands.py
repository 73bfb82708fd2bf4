"""A destructive command (the map marks it: factory defaults, initialisation, encoder reset ...) is one
deliberate step away on every path that reaches a drive: the CLI wants its name repeated (--confirm), the
Python client a `confirm=` keyword with its name, the C helper its name as a string; a plain write of the
value it writes is refused everywhere (it is sent only as that command)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from regmap.frontend import load_map

from conftest import ROOT, SimulatorFactory, require_tool
from support.clients import client_module

IDM = ROOT / "maps" / "idm_rs.yaml"
DEVICE = load_map(IDM)
RESTORE = next(c for c in DEVICE.commands if c.name == "restore_factory_defaults")
WRITE_RESTORE = (
    f"06 {RESTORE.register.address >> 8:02X} {RESTORE.register.address & 0xFF:02X} {RESTORE.value >> 8:02X} {RESTORE.value & 0xFF:02X}"
)


def regmap(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "regmap", *args], cwd=ROOT, capture_output=True, text=True, timeout=60, check=False)


def test_the_maps_mark_the_commands_that_lose_data() -> None:
    assert RESTORE.destructive and {c.name for c in DEVICE.commands if c.destructive} >= {"init_parameters", "force_enable_on"}


@pytest.mark.parametrize(
    ("args", "message"),
    [
        ((), "restore_factory_defaults is destructive"),
        (("--confirm", "save_all_parameters"), "--confirm save_all_parameters does not name the command sent (restore_factory_defaults)"),
    ],
)
def test_the_cli_sends_a_destructive_command_only_with_its_name_repeated(
    simulator: SimulatorFactory, tmp_path: Path, args: tuple[str, ...], message: str
) -> None:
    log = tmp_path / "requests.log"
    sim = simulator(IDM, "--log", str(log))
    result = regmap("command", str(IDM), "restore_factory_defaults", *args, "--tcp", f"127.0.0.1:{sim.port}")
    assert result.returncode == 2 and message in result.stderr and result.stderr.count("\n") == 1, result.stderr
    assert "Traceback" not in result.stderr
    sent = regmap(
        "command", str(IDM), "restore_factory_defaults", "--confirm", "restore_factory_defaults", "--tcp", f"127.0.0.1:{sim.port}"
    )
    assert sent.returncode == 0, sent.stderr
    sim.stop()
    assert log.read_text(encoding="utf-8").count(f"PDU {WRITE_RESTORE}") == 2  # the confirmed request and its answer only


def test_a_plain_write_of_a_destructive_value_is_refused_before_the_port_is_opened() -> None:
    for args in (
        ("write", str(IDM), "control_word=restore_factory_defaults", "--tcp", "127.0.0.1:9"),
        ("frame", str(IDM), "write", "control_word=0x2233", "--raw"),
    ):
        result = regmap(*args)
        assert result.returncode == 2 and "restore_factory_defaults is destructive" in result.stderr, result.stderr
        assert result.stdout == ""
    assert regmap("frame", str(IDM), "command", "restore_factory_defaults").returncode == 2
    framed = regmap("frame", str(IDM), "command", "restore_factory_defaults", "--confirm", "restore_factory_defaults")
    assert framed.returncode == 0 and framed.stdout.startswith("01 " + WRITE_RESTORE)


def test_the_python_client_wants_the_name_as_its_confirm_keyword(simulator: SimulatorFactory, tmp_path: Path) -> None:
    idm = client_module("idm_rs")
    log = tmp_path / "requests.log"
    sim = simulator(IDM, "--log", str(log))
    with idm.IdmRs.tcp("127.0.0.1", sim.port, timeout=2) as drive:
        with pytest.raises(TypeError):
            drive.restore_factory_defaults()
        with pytest.raises(ValueError, match="restore_factory_defaults is destructive"):  # the runtime's DestructiveWriteError
            drive.restore_factory_defaults(confirm="restore")
        with pytest.raises(ValueError, match="is destructive"):
            drive.write_control_word(idm.ControlWord.RESTORE_FACTORY_DEFAULTS)
        drive.restore_factory_defaults(confirm="restore_factory_defaults")
    sim.stop()
    assert log.read_text(encoding="utf-8").count(f"PDU {WRITE_RESTORE}") == 2


C_PROGRAM = r"""
#define IDM_RS_IMPLEMENTATION
#include "idm_rs.h"
#include <stdio.h>
int main(void) {
    uint8_t buf[16];
    uint16_t word = 0u;
    printf("%u %u %u\n", (unsigned)idm_rs_build_restore_factory_defaults(buf, sizeof buf, 1u, NULL),
           (unsigned)idm_rs_build_restore_factory_defaults(buf, sizeof buf, 1u, "restore"),
           (unsigned)idm_rs_build_restore_factory_defaults(buf, sizeof buf, 1u, "restore_factory_defaults"));
    printf("%d %d\n", (int)idm_rs_control_word_encode(IDM_RS_CONTROL_WORD_RESTORE_FACTORY_DEFAULTS, &word),
           (int)idm_rs_control_word_encode(IDM_RS_CONTROL_WORD_SAVE_ALL_PARAMETERS, &word));
    return 0;
}
"""


def test_the_c_helper_builds_a_destructive_frame_only_for_its_name(tmp_path: Path) -> None:
    gcc = require_tool("gcc")
    (tmp_path / "main.c").write_text(C_PROGRAM)
    flags = ["-std=c99", "-Wall", "-Wextra", "-Wpedantic", "-Werror", "-I", str(ROOT / "generated" / "c")]
    subprocess.run([gcc, *flags, "-o", str(tmp_path / "main"), str(tmp_path / "main.c")], check=True)
    out = subprocess.run([str(tmp_path / "main")], capture_output=True, text=True, check=True).stdout.split()
    assert out == ["0", "0", "8", "0", "1"]  # nothing, nothing, the 8-byte 0x06 frame; the plain encoder refuses it
