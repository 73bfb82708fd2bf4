"""The device profile learned by a probe, and writing it so that it is never half there."""

from __future__ import annotations

import json
from pathlib import Path

from regmap.model import Device
from regmap.runtime_bridge import documented_addresses
from regmap.tools.output import write_output
from regmap_runtime.profile import DeviceProfile, ranges

from .limits import Limit
from .wordorder import WordOrder


def learned(device: Device, observed: set[int], limit: Limit | None, order: WordOrder | None) -> DeviceProfile:
    """Only what was seen: the undocumented addresses that answered reads, the read limit where
    the drive proved another one, the word order where the values decided it."""
    gaps = set() if device.transport.tolerates_gaps else observed - {address for _, address in documented_addresses(device)}
    decided = None if order is None else order.register_order or order.inferred
    return DeviceProfile(
        device=device.id,
        map_fingerprint=device.fingerprint,
        map_version=device.info.map_version,
        max_read_registers=None if limit is None else limit.profile_limit,
        readable_gaps=ranges(gaps),
        word_order=decided,
    )


def save(path: Path, profile: DeviceProfile) -> None:
    write_output(path, (json.dumps(profile.to_json(), indent=2) + "\n").encode("utf-8"), "--profile")
