"""The fixture maps' clients, two flavours of each: built from the map at run time (`regmap_runtime`,
as `regmap read` builds it) and the generated module (its vendored runtime); reads and writes
through either, and a recorder of the frames they send."""

from __future__ import annotations

import importlib
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path
from types import ModuleType
from typing import Any

from pymodbus.client import AsyncModbusTcpClient, ModbusTcpClient

import regmap_runtime.errors as runtime_errors
from regmap.frontend import load_map
from regmap.model import Device
from regmap.runtime_bridge import runtime_device
from regmap_runtime.client import AsyncClient, SyncClient
from regmap_runtime.spec import DeviceSpec, RegisterSpec

from conftest import FIXTURE_MAPS

DEVICES: dict[str, Device] = {load_map(p).id: load_map(p) for p in FIXTURE_MAPS}
POWER, REMOTE, SWAPPED = "fixture_power_meter", "fixture_remote_io", "fixture_swapped_drive"
FLAVOURS = ("runtime", "generated")

_GENERATED: list[Path] = []


def generated_python() -> Path:
    """The Python clients of the fixture maps (only the python target), generated once per run into a temporary directory."""
    if not _GENERATED:
        from regmap.generate import generate

        out = Path(tempfile.mkdtemp(prefix="regmap-fixture-clients-")) / "generated"
        generate(list(DEVICES.values()), out, ["python"], complete=True)
        _GENERATED.append(out / "python")
        sys.path.append(str(out / "python"))
    return _GENERATED[0]


def camel(name: str) -> str:
    return "".join(part.capitalize() for part in name.split("_"))


# -- clients -----------------------------------------------------------------------------------


class Recorder:
    """pymodbus's packet hook: every frame sent, every frame received (a LineWatch's attributes too)."""

    def __init__(self) -> None:
        self.rtu_framing = False
        self.received = b""
        self.sent: list[bytes] = []

    def __call__(self, sending: bool, data: bytes) -> bytes:
        if sending:
            self.sent.append(bytes(data))
            self.received = b""
        else:
            self.received = bytes(data[-260:])
        return data

    def pdus(self) -> list[bytes]:
        """The PDUs sent (Modbus TCP: after the 7-byte MBAP header)."""
        return [frame[7:] for frame in self.sent]


@dataclass
class Flavour:
    """One way of getting a client for a map: from the map at run time, or the generated module."""

    name: str
    device: Device
    module: ModuleType | None  # the generated module
    errors: Any  # the errors module the client raises from
    sync_class: type[Any]
    async_class: type[Any]

    @property
    def spec_device(self) -> DeviceSpec:
        spec: DeviceSpec = self.sync_class.DEVICE
        return spec

    def spec(self, name: str) -> RegisterSpec[Any]:
        return next(r for r in self.spec_device.registers if r.name == name)

    def client(self, port: int, *, device: DeviceSpec | None = None, **options: Any) -> tuple[Any, Recorder]:
        """A blocking client on the libmodbus server at `port`, its frames recorded; `device` replaces the map's DeviceSpec."""
        recorder = Recorder()
        modbus = ModbusTcpClient("127.0.0.1", port=port, timeout=3, retries=0, trace_packet=recorder)
        cls = self.sync_class if device is None else type("Changed", (self.sync_class,), {"DEVICE": device})
        return cls(modbus, 1, line=recorder, **options), recorder

    def async_client(self, port: int, **options: Any) -> tuple[Any, Recorder]:
        recorder = Recorder()
        modbus = AsyncModbusTcpClient("127.0.0.1", port=port, timeout=3, retries=0, trace_packet=recorder)
        return self.async_class(modbus, 1, line=recorder, **options), recorder


def flavour(name: str, device_id: str) -> Flavour:
    device = DEVICES[device_id]
    if name == "runtime":
        spec = runtime_device(device)
        sync_class = type(f"{device.id}_live", (SyncClient,), {"DEVICE": spec})
        async_class = type(f"{device.id}_live_async", (AsyncClient,), {"DEVICE": spec})
        return Flavour(name, device, None, runtime_errors, sync_class, async_class)
    generated_python()
    module = importlib.import_module(device.id)
    errors = importlib.import_module(module.SyncClient.__module__.rsplit(".", 1)[0] + ".errors")
    return Flavour(name, device, module, errors, getattr(module, camel(device.id)), getattr(module, "Async" + camel(device.id)))


def read(f: Flavour, client: Any, name: str) -> Any:
    """Read one register: the generated `read_<name>()` accessor, or `client.read(spec)`."""
    if f.module is not None:
        reg = f.device.register(name)
        if reg.array is not None:
            return getattr(getattr(client, reg.array.array)(reg.array.index), f"read_{reg.array.member}")()
        return getattr(client, f"read_{name}")()
    return client.read(f.spec(name))


def write(f: Flavour, client: Any, name: str, value: Any) -> None:
    if f.module is not None:
        reg = f.device.register(name)
        if reg.array is not None:
            getattr(getattr(client, reg.array.array)(reg.array.index), f"write_{reg.array.member}")(value)
            return
        getattr(client, f"write_{name}")(value)
        return
    client.write(f.spec(name), value)
