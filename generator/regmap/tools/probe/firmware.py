"""Firmware version against the map's gates: the seam for the issue that adds firmware gates to maps.

The map format names no firmware-version register and no gates yet, so `firmware_register` finds
none and the probe says so. When the model gains them, `firmware_register` returns the register
and `check_firmware` compares the version read with the gates; the probe already calls both.
"""

from __future__ import annotations

from dataclasses import dataclass

from regmap.model import Device, Register


@dataclass(frozen=True)
class FirmwareCheck:
    register: str | None
    version: int | None
    agrees: bool
    text: str


def firmware_register(device: Device) -> Register | None:
    """The register holding the firmware version, where the map names one (none can yet)."""
    return None


def check_firmware(device: Device, register: Register | None, raw: int | None) -> FirmwareCheck:
    """The version read from `register`, checked against the map's firmware gates."""
    if register is None:
        return FirmwareCheck(None, None, True, "the map names no firmware register: the version was not read")
    if raw is None:
        return FirmwareCheck(register.name, None, True, f"{register.label} did not answer: the version is unknown")
    # No gates exist in the model yet: a version read is reported, never judged.
    return FirmwareCheck(register.name, raw, True, f"{register.label} = {raw} (the map has no firmware gates to check it against)")
