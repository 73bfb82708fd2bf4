"""A device profile: what `regmap probe` observed a drive doing, for clients that should use it.

A small JSON document tied to one map by its fingerprint. It can only say what was seen: the
largest read the drive answered (or the smaller one it refused beyond), the undocumented
addresses it answered reads of, and its 32-bit word order. Applied to a `DeviceSpec` it lowers or
raises `max_read_registers` to the observed limit and widens the readable addresses by exactly the
observed ones, so a plan made with it never spans an address that was not seen answering.
"""

from __future__ import annotations

import dataclasses
import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from .spaces import DEFAULT_SPACE
from .spec import HIGH_FIRST, LOW_FIRST, DeviceSpec

FORMAT = "regmap-device-profile/1"
SPEC_MAX_READ = 125  # Modbus application protocol §6.3


class ProfileError(ValueError):
    """A profile that is not one, or that belongs to another map."""


def ranges(addresses: frozenset[int] | set[int]) -> tuple[tuple[int, int], ...]:
    """Sorted addresses as inclusive (first, last) runs."""
    out: list[tuple[int, int]] = []
    for address in sorted(addresses):
        if out and out[-1][1] + 1 == address:
            out[-1] = (out[-1][0], address)
        else:
            out.append((address, address))
    return tuple(out)


@dataclass(frozen=True)
class DeviceProfile:
    device: str
    map_fingerprint: str
    map_version: str = ""
    max_read_registers: int | None = None  # None: the map's limit stands
    readable_gaps: tuple[tuple[int, int], ...] = ()  # undocumented addresses seen answering reads, as inclusive runs
    word_order: str | None = None  # None: not decided from the values

    @property
    def gap_addresses(self) -> frozenset[int]:
        return frozenset(a for first, last in self.readable_gaps for a in range(first, last + 1))

    def check(self, device_id: str, fingerprint: str) -> None:
        if device_id != self.device:
            raise ProfileError(f"the profile is for device {self.device!r}, not {device_id!r}")
        if fingerprint != self.map_fingerprint:
            raise ProfileError(
                f"the profile was learned with another version of the {device_id} map (fingerprint {self.map_fingerprint}, "
                f"this map is {fingerprint}): probe the drive again with this map"
            )

    def plan_limits(self, max_read: int, documented: frozenset[tuple[str, int]] | None) -> tuple[int, frozenset[tuple[str, int]] | None]:
        """The read plan's limits with what was observed: the register count, and the (space, address) a request may span."""
        limit = self.max_read_registers if self.max_read_registers is not None else max_read
        return limit, None if documented is None else documented | self.gap_keys

    @property
    def gap_keys(self) -> frozenset[tuple[str, int]]:
        """The observed gaps as (space, address): holding registers, the one space a profile covers so far."""
        return frozenset((DEFAULT_SPACE, a) for a in self.gap_addresses)

    def apply(self, device: DeviceSpec) -> DeviceSpec:
        """The device as observed (checked to be the map the profile was learned with)."""
        self.check(device.id, device.fingerprint)
        limit = self.max_read_registers if self.max_read_registers is not None else device.max_read_registers
        return dataclasses.replace(device, max_read_registers=limit, also_readable=device.also_readable | self.gap_keys)

    def to_json(self) -> dict[str, Any]:
        return {
            "format": FORMAT,
            "device": self.device,
            "map_fingerprint": self.map_fingerprint,
            "map_version": self.map_version,
            "observed": {
                "max_read_registers": self.max_read_registers,
                "readable_gaps": [list(r) for r in self.readable_gaps],
                "word_order": self.word_order,
            },
        }

    @classmethod
    def from_json(cls, data: Any) -> DeviceProfile:
        try:
            if data["format"] != FORMAT:
                raise ProfileError(f"format {data['format']!r} is not {FORMAT}")
            observed = data["observed"]
            limit = observed.get("max_read_registers")
            if limit is not None and (not isinstance(limit, int) or not 1 <= limit <= SPEC_MAX_READ):
                raise ProfileError(f"max_read_registers {limit!r} is outside 1..{SPEC_MAX_READ}")
            gaps = tuple((int(first), int(last)) for first, last in observed.get("readable_gaps", []))
            if any(not 0 <= first <= last <= 0xFFFF for first, last in gaps):
                raise ProfileError("readable_gaps holds a run outside 0x0000..0xFFFF")
            order = observed.get("word_order")
            if order not in (None, HIGH_FIRST, LOW_FIRST):
                raise ProfileError(f"word_order {order!r} is neither {HIGH_FIRST} nor {LOW_FIRST}")
            return cls(str(data["device"]), str(data["map_fingerprint"]), str(data.get("map_version", "")), limit, gaps, order)
        except (KeyError, TypeError, ValueError) as exc:
            if isinstance(exc, ProfileError):
                raise
            raise ProfileError(f"not a regmap device profile ({type(exc).__name__}: {exc})") from None


def load_profile(path: str | Path, device: DeviceSpec | None = None) -> DeviceProfile:
    """Read a profile; with `device`, refuse one learned with another map."""
    try:
        data = json.loads(Path(path).read_text(encoding="utf-8"))
    except OSError as exc:
        raise ProfileError(f"{path}: {exc.strerror or exc}") from None
    except ValueError as exc:
        raise ProfileError(f"{path}: not JSON ({exc})") from None
    try:
        profile = DeviceProfile.from_json(data)
        if device is not None:
            profile.check(device.id, device.fingerprint)
    except ProfileError as exc:
        raise ProfileError(f"{path}: {exc}") from None
    return profile
