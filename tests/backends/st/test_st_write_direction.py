"""The ST encoders refuse a state the device only reports (an enum member with `access: r`).

Each encoder of an enum register (and of a register whose bitfield takes an enum) refuses exactly the
members the model says are not writable, in both dialects; the compiled ST's answers on them are checked
in tests/backends/st/test_st_executed.py.
"""

from __future__ import annotations

import re

import pytest

from regmap.frontend import load_map
from regmap.model import Device, EnumType

from conftest import FIXTURE_MAPS, MAPS, ROOT
from support.st_matiec import st_files

REFUSAL = re.compile(
    r"^    CASE (\w+) OF\n((?:        [\w#.]+[,:]\n)+)            (\w+) := FALSE; \(\* a state the device only reports \*\)$", re.M
)
FUNCTION = re.compile(r"^FUNCTION (\w+) : BOOL\n(.*?)^END_FUNCTION$", re.M | re.S)


def _device(name: str) -> Device:
    path = next(p for p in [*MAPS, *FIXTURE_MAPS] if p.stem == name)
    return load_map(path, display_name=path.relative_to(ROOT).as_posix())


def refused(functions: str) -> dict[str, set[str]]:
    """encoder name -> the enum values (as printed) it refuses as reported states."""
    out: dict[str, set[str]] = {}
    for function in FUNCTION.finditer(functions):
        for case in REFUSAL.finditer(function[2]):
            assert case[3] == function[1], case[0]
            out.setdefault(function[1], set()).update(label.strip().rstrip(",:") for label in case[2].splitlines())
    return out


def _reported(device: Device, enum: EnumType, qualifier: str) -> set[str]:
    return {f"E_{device.id.upper()}_{enum.name.upper()}{qualifier}{m.name.upper()}" for m in enum.members if not m.writable}


@pytest.mark.parametrize("dialect", ["iec", "codesys"])
@pytest.mark.parametrize("name", [p.stem for p in [*MAPS, *FIXTURE_MAPS]])
def test_each_encoder_refuses_exactly_the_reported_members(name: str, dialect: str) -> None:
    device = _device(name)
    qualifier = "#" if dialect == "iec" else "."
    expected: dict[str, set[str]] = {}
    for reg in device.registers:
        if not reg.access.writable:
            continue
        label = f"{reg.array.array}_{reg.array.member}" if reg.array else reg.name
        encoder = f"F_{device.id.upper()}_ENCODE_{label.upper()}"
        enums = [reg.enum] if reg.enum is not None and not reg.bitfields else [b.enum for b in reg.bitfields if b.enum]
        for enum in enums:
            if reported := _reported(device, enum, qualifier):
                expected.setdefault(encoder, set()).update(reported)
    assert refused(st_files(device, dialect)["functions"]) == expected


def test_idm_rs_pr_trigger_refuses_done_path_5_and_takes_start_path_5() -> None:
    encoders = refused(st_files(_device("idm_rs"))["functions"])
    assert "E_IDM_RS_PR_TRIGGER#DONE_PATH_5" in encoders["F_IDM_RS_ENCODE_PR_TRIGGER"]
    assert "E_IDM_RS_PR_TRIGGER#START_PATH_5" not in encoders["F_IDM_RS_ENCODE_PR_TRIGGER"]
