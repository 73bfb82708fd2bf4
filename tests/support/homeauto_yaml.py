"""Reading the ESPHome and Home Assistant outputs back, and what the model says each entity must be,
written here apart from the back ends (tests/backends/*/test_*_write_safety.py use it)."""

from __future__ import annotations

import re
import subprocess
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import yaml

from regmap.model import Command, Device, PollClass, Register
from regmap.runtime_bridge import runtime_specs
from regmap_runtime.codec import raw_to_words


@dataclass(frozen=True)
class Tagged:
    """A node with an ESPHome/HA tag (`!lambda`, `!secret`, `!include`, `!extend`): kept as data."""

    tag: str
    value: Any


class _Loader(yaml.SafeLoader):
    pass


def _tagged(loader: yaml.SafeLoader, suffix: str, node: yaml.Node) -> Tagged:
    if isinstance(node, yaml.MappingNode):
        return Tagged("!" + suffix, loader.construct_mapping(node))
    if isinstance(node, yaml.SequenceNode):
        return Tagged("!" + suffix, loader.construct_sequence(node))
    return Tagged("!" + suffix, loader.construct_scalar(node))  # type: ignore[arg-type]


_Loader.add_multi_constructor("!", _tagged)


def load(text: str) -> Any:
    return yaml.load(text, Loader=_Loader)


ESPHOME_MAIN = "esphome:\n  name: regmap-check\nesp32:\n  board: esp32dev\n  framework:\n    type: esp-idf\npackages:\n  device: !include device.yaml\n"


def esphome_config(esphome: Path, work: Path, package: str) -> str:
    """`esphome config` on an ESP32 config that includes `package`: it must be valid with no warning.
    Returns what ESPHome prints on stdout: the configuration as it validated it."""
    (work / "device.yaml").write_text(package, encoding="utf-8")
    (work / "main.yaml").write_text(ESPHOME_MAIN, encoding="utf-8")
    result = subprocess.run([str(esphome), "config", "main.yaml"], cwd=work, capture_output=True, text=True, timeout=300, check=False)
    out = result.stdout + result.stderr
    assert result.returncode == 0, out[-4000:]
    assert "Configuration is valid!" in out
    assert "WARNING" not in out.replace("WARNING 💡", ""), [line for line in out.splitlines() if "WARNING" in line]
    return result.stdout


def ha_slug(name: str) -> str:
    """The object id HA gives an entity with an ASCII name (homeassistant.util.slugify), written apart from the back end."""
    return re.sub(r"[^a-z0-9]+", "_", name.lower().replace("'", "")).strip("_")


SUB = re.compile(r"\$\{(\w+)\}")


def resolve(value: str, subs: dict[str, str]) -> str:
    """`value` after ESPHome's substitution of `${name}`."""
    return SUB.sub(lambda m: str(subs[m.group(1)]), value)


ENERGY = {"Wh", "kWh", "MWh"}
COUNTS = {"Wh", "kWh", "MWh", "varh", "kvarh"}


def is_running_total(device: Device, reg: Register) -> bool:
    """The model's running totals: energy, and a duration or plain count whose title says total/since/running."""
    if reg.access.writable or reg.enum is not None or reg.bitfields:
        return False
    if reg.unit in COUNTS:
        return True
    words = {"total", "since", "running", "count", "counter", "cumulative", "accumulated", "operating", "power-on"}
    titled = bool(words & set(re.findall(r"[a-z-]+", reg.title.lower())))
    plain_count = reg.unit is None and not reg.type.is_float and not reg.scaled
    return titled and not reg.signed and (reg.unit in {"s", "ms", "min", "h"} or plain_count)


def expected_state_class(device: Device, reg: Register) -> str | None:
    """No statistics of settings, states, codes and identity; totals accumulate; quantities are measurements."""
    firmware = device.info.firmware_register
    identity = reg.type.is_string or reg.poll is PollClass.STATIC or (firmware is not None and firmware.register.name == reg.name)
    if reg.access.writable or identity or reg.enum is not None or reg.bitfields or reg.type.is_bool:
        return None
    if is_running_total(device, reg):
        return "total" if reg.signed else "total_increasing"
    if reg.unit is None and not reg.type.is_float and not reg.scaled and reg.offset == 0:
        return None  # a status word, a fault code, a version word: a code, not a quantity
    return "measurement"


def command_writes(device: Device, command: Command) -> list[tuple[int, tuple[int, ...]]]:
    """(register address, wire words) of each write the command can make (one per argument value)."""
    spec = next(s for s in runtime_specs(device) if s.name == command.register.name)
    arg = command.argument
    values = [command.raw_value()] if arg is None else [command.raw_value(v) for v in range(arg.min, arg.max + 1)]
    return [(command.register.address, tuple(raw_to_words(spec, v))) for v in values]


def reserved_title(title: str) -> bool:
    return title.strip().lower().startswith("reserved") or "no meaning" in title.lower()
