"""`scale_from` registers in the generated plain-standard ST, run: matiec compiles the inverter fixture's ST, gcc
builds it with the driver of tests/support/st_exec.py, and each read block's decoder and each encoder answers as the
Python runtime does for the same words (regmap.core.decoding and regmap_runtime.scaling compute the expected values;
nothing typed in): value = raw x 10^sf as an LREAL, not available (never a number) where the point or its scale
factor reads its marker, a write refused where the sf is not known, the value is no whole multiple of 10^sf or the
raw value is out of range. The one deliberate difference: |sf| > 22, whose 10^sf is no LREAL exactly, is not
available in ST (the Python client computes it; SunSpec's factors are -10..10).

Without matiec or gcc the test skips (CI=true: fails).
"""

from __future__ import annotations

import math
import random
import re
from pathlib import Path
from typing import Any

import pytest

from regmap.backends.st.functions import Block
from regmap.core.decoding import DecodedValue, apply_scale_factors, decode_words
from regmap.frontend import load_map, load_map_text
from regmap.generate import render
from regmap.model import Device
from regmap.runtime_bridge import runtime_specs
from regmap_runtime.codec import RangeError, check_raw, raw_to_words
from regmap_runtime.scaling import unscaled

from conftest import ROOT
from support.st_exec import SENTINEL, Decode, Encode, Result, StProgram
from support.st_matiec import matiec_and_gcc

MAP = ROOT / "tests" / "maps" / "scaled_from" / "inverter.yaml"
NA_SF = 0x8000  # the fixture's scale factors' "not available" marker (SunSpec's)
BEYOND_EXACT = 23  # 10^23 is no LREAL exactly: ST reports no value, the Python client computes one


@pytest.fixture(scope="session")
def matiec() -> Path:
    return matiec_and_gcc()


def _sf(value: int) -> int:
    return value & 0xFFFF


def _measurement_words() -> dict[str, list[int]]:
    """Words of read block 0x0000 (a, a_sf, w, w_sf, wh (2 words, high first), wh_sf), by case."""
    cases = {
        "defaults": [1234, _sf(-2), 0xFA24, _sf(1), 0x0001, 0xE240, 0],
        "negative_sf": [1, _sf(-5), 3, _sf(-1), 0xFFFF, 0xFFFF, _sf(-2)],  # 3 x 10^-1 is 0.3 correctly rounded; u32 max
        "sf_na": [1234, NA_SF, 0xFA24, NA_SF, 0x0001, 0xE240, NA_SF],
        "value_na": [0xFFFF, _sf(-2), 0x8000, _sf(1), 0x8000, 0x0000, _sf(3)],  # wh has no marker: 2^31 x 10^3
        "sf_22": [65534, _sf(22), 0x7FFF, _sf(-22), 0x1234, 0x5678, _sf(21)],
        "zero": [0, _sf(-3), 0, _sf(5), 0, 0, _sf(-10)],
    }
    rng = random.Random(35)  # the number: the same words every run
    for k in range(12):
        words = [rng.randrange(0x10000) for _ in range(7)]
        for at in (1, 3, 6):
            words[at] = _sf(rng.randint(-10, 10))
        cases[f"random{k}"] = words
    return cases


def _python_values(device: Device, block: Block, words: list[int], among: list[DecodedValue] | None = None) -> dict[str, Any]:
    """The Python runtime's values of the block's registers (None: no value), scaled by the factors of the block
    and of `among` (the words of a bridged gap are read, but they are no register of the block's)."""
    ours = {r.name for r in block.registers}
    values = [v for v in decode_words(device, block.address, words, space=block.space) if v.register in ours]
    apply_scale_factors(device, values, [*(among or []), *values], "its scale factor {sf} was not read")
    return {str(v.register): v.value for v in values}


def _members(device: Device, block: Block) -> tuple[str, ...]:
    out: list[str] = []
    for reg in block.registers:
        out.append(reg.name.upper())
        if reg.has_na or reg.scale_from is not None or any(r.scale_from == reg.name for r in device.registers):
            out.append(f"{reg.name}_available".upper())
    return tuple(out)


def _compare(device: Device, case: str, expected: dict[str, Any], got: Result, beyond: frozenset[str] = frozenset()) -> list[str]:
    """Differences between the ST values struct and the Python values; `beyond`: points whose |sf| > 22."""
    problems = []
    if not got.ok:
        problems.append(f"{case}: the decoder returned FALSE (a value that is not available is no failure)")
    for reg in device.registers:
        if reg.name not in expected or reg.scale_from is None:
            continue
        value = expected[reg.name]
        available = got.values[f"{reg.name}_available".upper()] == "1"
        shown = float(got.values[reg.name.upper()])
        if reg.name in beyond:
            assert value is not None, "the divergence case must be one the Python client computes"
            if available:
                problems.append(f"{case} {reg.name}: |sf| > 22 showed {shown}; ST gives no value there")
        elif value is None:
            if available:
                problems.append(f"{case} {reg.name}: the Python client has no value; ST shows {shown}")
        elif not available or shown != float(value):
            problems.append(f"{case} {reg.name}: ST {'shows ' + repr(shown) if available else 'has no value'}, Python {float(value)!r}")
    return problems


def test_the_decoders_show_what_the_python_client_reads(matiec: Path, tmp_path: Path) -> None:
    device = load_map(MAP)
    program = StProgram(device)
    measurements, control = program.blocks
    assert [r.name for r in measurements.registers] == ["a", "a_sf", "w", "w_sf", "wh", "wh_sf"]
    cases: list[Decode] = []
    expected: dict[str, dict[str, Any]] = {}
    for name, words in _measurement_words().items():
        cases.append(Decode(name, measurements, tuple(words), _members(device, measurements)))
        expected[name] = _python_values(device, measurements, words)
    beyond = [1, _sf(BEYOND_EXACT), 2, _sf(-BEYOND_EXACT), 3, 0, _sf(0)]
    cases.append(Decode("beyond", measurements, tuple(beyond), _members(device, measurements)))
    for raw, sf in ((1000, _sf(-1)), (999, _sf(-3)), (0xFFFF, 2), (5, NA_SF), (7, _sf(1))):
        case = f"control_{raw}_{sf}"
        cases.append(Decode(case, control, (raw, sf), _members(device, control)))
        expected[case] = _python_values(device, control, [raw, sf])
    results = program.run(matiec, tmp_path, cases)
    problems = [p for case, values in expected.items() for p in _compare(device, case, values, results[case])]
    problems += _compare(device, "beyond", _python_values(device, measurements, beyond), results["beyond"], frozenset({"a", "w"}))
    assert not problems, "\n".join(problems)
    # the cases reach what they are named for: a value shown, each kind of "not available", a negative sf
    shown = {case: {k: v for k, v in values.items() if v is not None} for case, values in expected.items()}
    assert {"a", "w", "wh"} <= set(shown["defaults"]) and shown["negative_sf"]["w"] == 0.3
    assert shown["negative_sf"]["wh"] == 42949672.95
    assert {"a", "w", "wh"}.isdisjoint(shown["sf_na"]) and {"a", "w"}.isdisjoint(shown["value_na"]) and "wh" in shown["value_na"]
    assert results["beyond"].values["WH_AVAILABLE"] == "1"


def _split_map() -> Device:
    """The fixture with w_sf read at another rate than w: its own read block, decoded by another call."""
    text = MAP.read_text(encoding="utf-8")
    old = "default: 1, na: [0x8000], title: AC power scale factor}"
    assert text.count(old) == 1
    return load_map_text(text.replace(old, old[:-1] + ", poll: slow}"), "split.yaml")


def test_a_scale_factor_in_another_block_is_the_one_decoded_last(matiec: Path, tmp_path: Path) -> None:
    """w's block holds no w_sf: its decoder scales by the w_sf its own block's decoder stored (this poll's, when the
    plan reads it first); before any read of w_sf, or after one of its marker, w has no value."""
    device = _split_map()
    program = StProgram(device)
    sf_block = next(b for b in program.blocks if [r.name for r in b.registers] == ["w_sf"])
    point_block = next(b for b in program.blocks if "w" in {r.name for r in b.registers})
    assert sf_block is not point_block
    point_words = [0] * point_block.count
    point_words[2 - point_block.address] = 0xFA24  # w = -1500
    cases: list[Decode] = []
    expected: dict[str, dict[str, Any]] = {}
    for name, sf in (("sf_2", _sf(2)), ("sf_minus_3", _sf(-3)), ("sf_na", NA_SF)):
        cases.append(Decode(name, point_block, tuple(point_words), ("W", "W_AVAILABLE"), before=((sf_block, (sf,)),)))
        earlier = decode_words(device, sf_block.address, [sf], space=sf_block.space)
        expected[name] = _python_values(device, point_block, point_words, earlier)
    cases.append(Decode("unread", point_block, tuple(point_words), ("W", "W_AVAILABLE")))
    expected["unread"] = _python_values(device, point_block, point_words)
    results = program.run(matiec, tmp_path, cases)
    problems = [p for case, values in expected.items() for p in _compare(device, case, {"w": values["w"]}, results[case])]
    assert not problems, "\n".join(problems)
    assert expected["sf_2"]["w"] == -150000 and expected["unread"]["w"] is None and expected["sf_na"]["w"] is None


def test_a_factor_marker_within_the_exact_powers_is_no_value(matiec: Path, tmp_path: Path) -> None:
    """A map may mark an ordinary-looking factor as "not available" (here w_sf -5): no value, and no write, although
    10^-5 is an exact power (SunSpec's 0x8000 alone would be refused by |sf| > 22 anyway)."""
    text = MAP.read_text(encoding="utf-8")
    old = "default: 1, na: [0x8000], title: AC power scale factor}"
    device = load_map_text(text.replace(old, old.replace("[0x8000]", "[0x8000, -5]")), "marked.yaml")
    program = StProgram(device)
    block = program.blocks[0]
    cases, expected = [], {}
    for name, sf in (("marked", -5), ("unmarked", -4)):
        words = [1234, _sf(-2), 0xFA24, _sf(sf), 0, 7, 0]
        cases.append(Decode(name, block, tuple(words), _members(device, block)))
        expected[name] = _python_values(device, block, words)
    results = program.run(matiec, tmp_path, cases)
    problems = [p for case, values in expected.items() for p in _compare(device, case, values, results[case])]
    assert not problems, "\n".join(problems)
    assert expected["marked"]["w"] is None and expected["unmarked"]["w"] == -0.15


# (value, sf, sf available): the runtime's answer decides each; ST's must equal it
WRITES: tuple[tuple[float, int, bool], ...] = (
    (50.5, -1, True),
    (50.55, -1, True),  # no whole multiple of 0.1: refused
    (0.1 + 0.2, -1, True),  # 0.30000000000000004: refused, though within 0.001 of 0.3
    (0.3, -1, True),
    (100.1, -1, True),  # raw 1001 > max 1000: refused
    (-0.1, -1, True),  # raw -1 < min 0: refused
    (-0.0, -1, True),
    (1000.0, 0, True),
    (10.0, 1, True),
    (15.0, 1, True),  # no whole multiple of 10: refused
    (9.99, -2, True),
    (12.34, -2, True),  # raw 1234 > max: refused
    (5e-22, -22, True),
    (3.0, NA_SF - 0x10000, True),  # the sf's marker: refused
    (3.0, -1, False),  # the sf not read: refused
    (math.nan, 0, True),
    (math.inf, 0, True),
)


def _python_write(device: Device, value: float, sf: int, available: bool, name: str = "wmax_lim_pct") -> tuple[int, ...] | None:
    spec = next(s for s in runtime_specs(device) if s.name == name)
    factor = None if not available or device.register(f"{name}_sf").is_na(sf) else sf
    try:
        raw = unscaled(spec, value, factor)
        check_raw(spec, raw)
    except RangeError:
        return None
    return tuple(raw_to_words(spec, raw))


def test_the_encoder_sends_what_the_python_client_sends_and_refuses_what_it_refuses(matiec: Path, tmp_path: Path) -> None:
    device = load_map(MAP)
    program = StProgram(device)
    encoder = program.functions["F_SF_INVERTER_ENCODE_WMAX_LIM_PCT"]
    assert [m.name for m in encoder.inputs] == ["fValue", "nSf", "bSfAvailable"]
    cases = [Encode(f"e{i}", encoder, value, 1, scale_factor=(sf, ok)) for i, (value, sf, ok) in enumerate(WRITES)]
    cases.append(Encode("beyond", encoder, 5e-23, 1, scale_factor=(-BEYOND_EXACT, True)))
    expected = {f"e{i}": _python_write(device, *write) for i, write in enumerate(WRITES)}
    results = program.run(matiec, tmp_path, cases)
    problems = []
    for case_id, words in expected.items():
        got = results[case_id]
        if words is None and (got.ok or got.words != (SENTINEL,)):
            problems.append(f"{case_id} {WRITES[int(case_id[1:])]}: Python refuses; ST returned {got.ok} {got.words}")
        elif words is not None and (not got.ok or got.words != words):
            problems.append(f"{case_id} {WRITES[int(case_id[1:])]}: Python writes {words}; ST returned {got.ok} {got.words}")
    assert not problems, "\n".join(problems)
    assert _python_write(device, 5e-23, -BEYOND_EXACT, True) == (5,), "the divergence case must be one Python sends"
    assert not results["beyond"].ok and results["beyond"].words == (SENTINEL,)
    refused = sum(words is None for words in expected.values())
    assert 0 < refused < len(expected)  # the cases reach both answers
    for index in (1, 2, 4, 9, 13, 14):
        assert expected[f"e{index}"] is None, WRITES[index]


def test_the_st_lists_no_scaled_register_as_not_generated() -> None:
    files = render([load_map(MAP)], ["st"])["st"]
    assert files
    assert not any("Not generated" in text for text in files.values())
    functions = files["sf_inverter/iec/sf_inverter_functions.st"]
    for name in ("A", "W", "WH"):
        assert f"FUNCTION F_SF_INVERTER_SCALED_{name} : BOOL" in functions


def test_a_plant_polls_each_scaled_point_with_its_factor(tmp_path: Path) -> None:
    """The ST plant files take a scaled map: the bus's poll table reads the device's ST read plan, each point in the
    request that reads its scale factor."""
    from regmap.frontend.plant import load_plant
    from regmap.generate import render_plant

    plant_file = tmp_path / "sfplant.yaml"
    plant_file.write_text(
        "format: regmap-plant/1\nplant: {id: sfplant, title: Scaled plant}\nbuses:\n  - name: line1\n"
        "    serial: {port: /dev/ttyUSB0, baud: 9600, parity: none}\n    devices:\n"
        f"      - {{name: inverter, map: {MAP}, slave: 3}}\n",
        encoding="utf-8",
    )
    files = render_plant(load_plant(plant_file), ["st"])["st"]
    constants = files["sfplant_plant/sfplant_plant_constants.st"]
    rows = re.findall(r"\(DEVICE := \d+, SLAVE := 3, FUNCTION_CODE := 16#03, START_ADDR := 16#(\w+), COUNT := (\d+)\)", constants)
    device = load_map(MAP)
    blocks = {(b.address, b.count) for b in StProgram(device).blocks}
    assert {(int(address, 16), int(count)) for address, count in rows} == blocks
    for reg in device.registers:
        if reg.scale_from is not None:
            sf = device.register(reg.scale_from)
            assert any(a <= min(reg.address, sf.address) and max(reg.last_address, sf.address) < a + c for a, c in blocks), reg.name


def test_a_64_bit_point_is_exact_up_to_2_to_the_53(matiec: Path, tmp_path: Path) -> None:
    """wh as a writable s64 (SunSpec's acc64 counters are 64-bit): decoded and encoded as the Python client does while
    the raw value is an LREAL exactly; beyond 2^53 the value is within one unit in the last place, and a write refused
    (the raw integer would not be the one asked for)."""
    text = MAP.read_text(encoding="utf-8")
    old_wh, old_sf = "{name: wh, address: 0x0004, type: u32, access: r,", "address: 0x0006, type: s16, access: r, default: 0"
    assert text.count(old_wh) == 1 and text.count(old_sf) == 1
    text = text.replace(old_wh, "{name: wh, address: 0x0004, type: s64, access: rw,").replace(old_sf, old_sf.replace("0x0006", "0x0008"))
    device = load_map_text(text, "wide.yaml")
    program = StProgram(device)
    block = program.blocks[0]
    spec = next(s for s in runtime_specs(device) if s.name == "wh")
    raws = {"exact": (-123456789012, -3), "limit": (2**53, 2), "beyond": (2**60 + 1, -1)}
    cases: list[Decode | Encode] = []
    expected = {}
    for name, (raw, sf) in raws.items():
        words = [1234, _sf(-2), 0xFA24, _sf(1), *raw_to_words(spec, raw), _sf(sf)]
        cases.append(Decode(name, block, tuple(words), ("WH", "WH_AVAILABLE")))
        expected[name] = _python_values(device, block, words)["wh"]
    encoder = program.functions["F_SF_INVERTER_ENCODE_WH"]
    writes = {"w_exact": (-123456789.012, -3), "w_limit": (2.0**53, 0), "w_beyond": (2.0**60, 0), "w_half": (0.0005, -3)}
    cases += [Encode(name, encoder, value, 4, scale_factor=(sf, True)) for name, (value, sf) in writes.items()]
    results = program.run(matiec, tmp_path, cases)
    for name in ("exact", "limit"):
        assert results[name].values["WH_AVAILABLE"] == "1" and float(results[name].values["WH"]) == float(expected[name]), name
    beyond = float(results["beyond"].values["WH"])
    assert results["beyond"].values["WH_AVAILABLE"] == "1" and math.isclose(beyond, float(expected["beyond"]), rel_tol=2**-52)
    python = {name: _python_write(device, value, sf, True, "wh") for name, (value, sf) in writes.items()}
    assert results["w_exact"].ok and results["w_exact"].words == python["w_exact"]
    assert python["w_half"] is None and not results["w_half"].ok and results["w_half"].words == (SENTINEL,) * 4
    assert python["w_beyond"] is not None, "the divergence case must be one Python sends"
    assert not results["w_beyond"].ok and results["w_beyond"].words == (SENTINEL,) * 4
    assert python["w_limit"] is not None and not results["w_limit"].ok  # 2^53 itself: LREAL cannot tell it from 2^53 + 1
