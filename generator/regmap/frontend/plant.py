"""Plant file -> `Plant`: safe YAML, the plant JSON Schema, each device's map, then the bus rules.

Every problem is collected and raised together as one `MapError` (`file:line:col: message`), the
problems of a device's map at that map's own lines.
"""

from __future__ import annotations

import hashlib
from pathlib import Path as FsPath
from typing import Any

from regmap.diagnostics import Diagnostic, MapError
from regmap.frontend.load import decoded, load_map
from regmap.frontend.schema import _kind, _schema_problems
from regmap.frontend.yamlsource import Positions, YamlProblem, read_yaml
from regmap.keywords import C_KEYWORDS, CPP_KEYWORDS, IEC_KEYWORDS, PYTHON_KEYWORDS
from regmap.model import Device
from regmap.plant import PLANT_FORMAT, Bus, Plant, PlantDevice, SerialLine, TcpLine

SCHEMA_FILE = "plant.schema.json"
MODBUS_BROADCAST = 0  # a write to slave 0 reaches every device on a serial line, and none replies


def load_plant(path: str | FsPath, display_name: str | None = None) -> Plant:
    """Read and check one plant file and every map it names; raises MapError listing every problem."""
    name = display_name or str(path)
    try:
        data = FsPath(path).read_bytes()
    except OSError as exc:
        raise MapError([Diagnostic(name, 1, 1, f"cannot read the plant file: {exc.strerror or exc}")]) from None
    text = decoded(data, name, "plant file")
    try:
        raw, positions = read_yaml(text)
    except YamlProblem as exc:
        raise MapError([Diagnostic(name, exc.line, exc.column, exc.message)]) from None
    if not isinstance(raw, dict):
        line, col = positions.locate(())
        raise MapError([Diagnostic(name, line, col, f"the plant file must be a YAML mapping at the top level, not a {_kind(raw)}")])
    if raw.get("format") != PLANT_FORMAT:
        line, col = positions.locate(("format",))
        raise MapError([Diagnostic(name, line, col, f"format: expected {PLANT_FORMAT!r}, got {raw.get('format')!r}")])
    problems = _schema_problems(raw, positions, name, SCHEMA_FILE)
    if problems:
        raise MapError(problems)
    return _PlantChecker(raw, positions, name, FsPath(path).resolve().parent, data).plant()


class _PlantChecker:
    def __init__(self, raw: dict[str, Any], positions: Positions, name: str, base: FsPath, data: bytes) -> None:
        self.raw = raw
        self.positions = positions
        self.name = name
        self.base = base
        self.data = data
        self.problems: list[Diagnostic] = []
        self.maps: dict[FsPath, Device | None] = {}

    def add(self, path: tuple[str | int, ...], message: str) -> None:
        line, col = self.positions.locate(path)
        self.problems.append(Diagnostic(self.name, line, col, message))

    def plant(self) -> Plant:
        buses = []
        bus_names: dict[str, int] = {}
        device_names: dict[str, tuple[int, int]] = {}
        for i, bus_raw in enumerate(self.raw["buses"]):
            if bus_raw["name"] in bus_names:
                self.add(
                    ("buses", i, "name"), f"bus name {bus_raw['name']!r} is used twice (first at bus {bus_names[bus_raw['name']] + 1})"
                )
            bus_names.setdefault(bus_raw["name"], i)
            devices = []
            slaves: dict[int, str] = {}
            for j, dev_raw in enumerate(bus_raw["devices"]):
                at: tuple[str | int, ...] = ("buses", i, "devices", j)
                dev_name = dev_raw["name"]
                if dev_name in device_names:
                    self.add((*at, "name"), f"device name {dev_name!r} is used twice in the plant (it prefixes every generated name)")
                device_names.setdefault(dev_name, (i, j))
                self._reserved(dev_name, (*at, "name"))
                slave = dev_raw["slave"]
                if slave in slaves:
                    self.add((*at, "slave"), f"slave id {slave} is used twice on bus {bus_raw['name']!r} (also {slaves[slave]!r})")
                slaves.setdefault(slave, dev_name)
                device = self._map(dev_raw["map"], (*at, "map"))
                if device is None:
                    continue
                self._slave_rules(device, slave, (*at, "slave"))
                self._variant_rules(device, dev_raw.get("variant"), (*at, "variant"), dev_name)
                if "serial" in bus_raw:
                    self._line_rules(device, bus_raw["serial"], ("buses", i, "serial"), dev_name)
                devices.append(
                    PlantDevice(
                        name=dev_name,
                        title=dev_raw.get("title") or f"{device.info.vendor} {device.info.model}",
                        map_path=dev_raw["map"],
                        device=device,
                        slave=slave,
                        notes=dev_raw.get("notes", ""),
                        variant=dev_raw.get("variant"),
                        pos=self.positions.locate(at),
                    )
                )
            buses.append(self._bus(bus_raw, tuple(devices), ("buses", i)))
        if self.problems:
            raise MapError(self.problems)
        fingerprint = hashlib.sha256(self.data + "".join(d.fingerprint for d in self.maps.values() if d).encode()).hexdigest()[:16]
        return Plant(
            id=self.raw["plant"]["id"],
            title=self.raw["plant"]["title"],
            buses=tuple(buses),
            source_path=self.name,
            fingerprint=fingerprint,
            notes=self.raw["plant"].get("notes", ""),
        )

    def _bus(self, raw: dict[str, Any], devices: tuple[PlantDevice, ...], at: tuple[str | int, ...]) -> Bus:
        serial = raw.get("serial")
        tcp = raw.get("tcp")
        return Bus(
            name=raw["name"],
            devices=devices,
            serial=SerialLine(serial["port"], serial["baud"], serial["parity"], serial.get("data_bits", 8), serial.get("stop_bits", 1))
            if serial
            else None,
            tcp=TcpLine(tcp["host"], tcp.get("port", 502)) if tcp else None,
            notes=raw.get("notes", ""),
            pos=self.positions.locate(at),
        )

    def _map(self, written: str, at: tuple[str | int, ...]) -> Device | None:
        path = (self.base / written).resolve()
        if path not in self.maps:
            if not path.is_file():
                self.add(at, f"map {written!r} not found (looked for {path}; map paths are relative to the plant file)")
                self.maps[path] = None
            else:
                try:
                    self.maps[path] = load_map(path, display_name=_display(path))
                except MapError as exc:
                    self.add(at, f"map {written!r} is invalid ({len(exc.diagnostics)} problem(s), listed below)")
                    self.problems.extend(exc.diagnostics)
                    self.maps[path] = None
        return self.maps[path]

    def _slave_rules(self, device: Device, slave: int, at: tuple[str | int, ...]) -> None:
        t = device.transport
        if slave == MODBUS_BROADCAST or slave == t.broadcast_id:
            self.add(at, f"slave id {slave} is the broadcast address: every device would act on it and none would answer")
        elif not t.slave_min <= slave <= t.slave_max:
            self.add(at, f"slave id {slave} is outside {t.slave_min}..{t.slave_max}, the range the map {device.id} allows")

    def _variant_rules(self, device: Device, variant: str | None, at: tuple[str | int, ...], dev_name: str) -> None:
        if variant is None:
            return
        declared = [v.name for v in device.info.variants]
        if not declared:
            self.add(at, f"variant {variant!r}: device {dev_name!r} ({device.id}) declares no variants (device.variants)")
        elif variant not in declared:
            self.add(at, f"variant {variant!r}: device {dev_name!r} ({device.id}) declares {', '.join(declared)} only")

    def _line_rules(self, device: Device, line: dict[str, Any], at: tuple[str | int, ...], dev_name: str) -> None:
        t = device.transport
        bauds, parities = t.baud_rates or (t.baud,), t.parities or (t.parity,)  # the default alone when the map lists none
        if line["baud"] not in bauds:
            self.add(
                (*at, "baud"),
                f"baud {line['baud']}: device {dev_name!r} ({device.id}) can be set to {', '.join(map(str, bauds))} only",
            )
        if line["parity"] not in parities:
            self.add(
                (*at, "parity"),
                f"parity {line['parity']}: device {dev_name!r} ({device.id}) can be set to {', '.join(parities)} only",
            )
        if line.get("data_bits", 8) != t.data_bits:
            self.add((*at, "data_bits"), f"data bits {line.get('data_bits', 8)}: device {dev_name!r} ({device.id}) uses {t.data_bits}")

    def _reserved(self, name: str, at: tuple[str | int, ...]) -> None:
        for language, words, fold in (
            ("Python", PYTHON_KEYWORDS, False),
            ("C/C++", C_KEYWORDS | CPP_KEYWORDS, False),
            ("IEC 61131-3", IEC_KEYWORDS, True),
        ):
            if (name.casefold() in {w.casefold() for w in words}) if fold else name in words:
                self.add(at, f"device name {name!r} is a reserved word of {language}; choose another (e.g. {name}_1)")
                return


def _display(path: FsPath) -> str:
    """A map's name in messages: relative to the working directory when it is below it."""
    try:
        return str(path.relative_to(FsPath.cwd()))
    except ValueError:
        return str(path)
