"""Firmware version against the map's gates: the version the firmware register reports, and whether
the registers gated by firmware (`firmware: {from, until}`) answer as that version says they should."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from regmap.model import Device, Register
from regmap.runtime_bridge import runtime_device
from regmap_runtime.spec import Raw

if TYPE_CHECKING:
    from .registers import RegisterRead


@dataclass(frozen=True)
class FirmwareCheck:
    register: str | None
    version: str | None
    agrees: bool
    text: str
    disagreements: tuple[str, ...] = field(default=())


def firmware_register(device: Device) -> Register | None:
    """The register holding the firmware version, where the map names one (`device.firmware_register`)."""
    named = device.info.firmware_register
    return named.register if named is not None else None


def check_firmware(
    device: Device, register: Register | None, raw: Raw | None, reads: Mapping[str, RegisterRead] | None = None
) -> FirmwareCheck:
    """The version read from `register`, and every gated register whose answer disagrees with it: one
    the version should lack that answered, or one it should have that was refused."""
    if register is None:
        return FirmwareCheck(None, None, True, "the map names no firmware register: the version was not read")
    if raw is None:
        return FirmwareCheck(register.name, None, True, f"{register.label} did not answer: the version is unknown")
    spec = runtime_device(device)
    try:
        version = spec.firmware_version(raw)
    except ValueError as exc:
        return FirmwareCheck(register.name, None, False, f"{register.label} = {raw!r}: not a version ({exc})")
    shown = spec.firmware_text(raw)  # as the device's documents write it: 1.05, not 1.5
    gated = [r for r in device.registers if r.firmware is not None and r.access.readable]
    if not gated:
        return FirmwareCheck(register.name, shown, True, f"firmware {shown} ({register.label}); the map gates no register by firmware")
    disagreements = []
    for reg in gated:
        assert reg.firmware is not None
        read = (reads or {}).get(reg.name)
        if read is None or read.answer is None:
            continue
        expected = reg.firmware.admits(version)
        answered = read.answer.ok
        if expected != answered:
            what = "answered" if answered else f"was refused ({read.answer.text})"
            disagreements.append(f"{reg.label} ({reg.firmware.text}) {what}")
    if disagreements:
        text = f"firmware {shown} ({register.label}), but " + "; ".join(disagreements)
        return FirmwareCheck(register.name, shown, False, text, tuple(disagreements))
    present = sum(1 for r in gated if r.firmware is not None and r.firmware.admits(version))
    text = f"firmware {shown} ({register.label}): {present} of {len(gated)} gated registers exist in it, and they answer as their gates say"
    return FirmwareCheck(register.name, shown, True, text)
