"""Run with pysunspec2's own Python (the `sunspec` tool env): scan a SunSpec device over Modbus TCP as pysunspec2's
client does, and print what it found as JSON: the models (id, length) and a few points of each."""

from __future__ import annotations

import json
import sys

from sunspec2.modbus.client import SunSpecModbusClientDeviceTCP  # type: ignore[import-not-found]


def main() -> None:
    host, port, slave = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
    device = SunSpecModbusClientDeviceTCP(slave_id=slave, ipaddr=host, ipport=port, timeout=5)
    try:
        device.scan()
        found = []
        for mid in sorted(k for k in device.models if isinstance(k, int)):
            for model in device.models[mid]:
                groups = {name: len(g) if isinstance(g, list) else 1 for name, g in model.groups.items()}
                points = {k: p.value for k, p in model.points.items()}
                found.append({"id": mid, "len": model.len, "addr": model.model_addr, "points": points, "groups": groups})
        json.dump({"base": device.base_addr, "models": found}, sys.stdout, default=str)
    finally:
        device.close()


if __name__ == "__main__":
    main()
