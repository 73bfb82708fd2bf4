"""The device profile learned by a probe, and writing it so that it is never half there."""

from __future__ import annotations

import contextlib
import json
import os
import tempfile
from pathlib import Path

from regmap.model import Device
from regmap.runtime_bridge import documented_addresses
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


def write_atomically(path: Path, text: str) -> None:
    """Write beside the target and rename: a reader sees the old file or the new one, never a part."""
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}-", dir=path.parent)
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as handle:
            handle.write(text)
            handle.flush()
            os.fsync(handle.fileno())
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


def save(path: Path, profile: DeviceProfile) -> None:
    write_atomically(path, json.dumps(profile.to_json(), indent=2) + "\n")
