"""The cross-reference stage: uniqueness, overlaps, and what refers to registers (transport, commands, faults, errata,
examples), checked on the elaborated objects; its result is the one frozen `Device`."""

from __future__ import annotations

from dataclasses import replace
from typing import Any

from regmap.core.text import na_list
from regmap.frontend.copies import replaced
from regmap.frontend.stages import Elaborated, Problems
from regmap.frontend.transport import elaborate_transport
from regmap.frontend.values import _source
from regmap.frontend.yamlsource import Path
from regmap.model import (
    Command,
    CommandArgument,
    CommandEffect,
    DataType,
    Device,
    DeviceInfo,
    Erratum,
    Example,
    ExampleValue,
    Fault,
    FirmwareRegister,
    Reading,
    Register,
    Variant,
)
from regmap_runtime.rtu import FrameError, crc_bytes, crc_ok, parse_hex, to_hex


def check_references(elaborated: Elaborated) -> Device:
    """The frozen device, or a MapError with the elaboration's problems and these together."""
    return _CrossReferences(elaborated).run()


class _CrossReferences:
    def __init__(self, elaborated: Elaborated) -> None:
        self.elaborated = elaborated
        self.raw = elaborated.source.raw
        self.positions = elaborated.source.positions
        self.problems = Problems(elaborated.source, elaborated.problems)
        self.registers = list(elaborated.registers)  # errata are added to them here
        self.register_paths = elaborated.register_paths

    def run(self) -> Device:
        raw = self.raw
        self._check_unique_groups_and_arrays()
        self._check_unique_registers()
        self._check_overlaps()
        self._check_scale_from()
        errata = self._errata(raw.get("errata", []), self._selector_index())
        final = {r.name: r for r in self.registers}
        groups = tuple(replaced(g, registers=tuple(final[r.name] for r in g.registers)) for g in self.elaborated.groups)
        by_selector = self._selector_index()
        transport = elaborate_transport(self, raw["transport"], by_selector)
        commands = self._commands(raw.get("commands", []), by_selector)
        faults = self._faults(raw.get("faults", []))
        examples = self._examples(raw.get("examples", []), by_selector, {e.id for e in errata})
        self.problems.raise_any()
        info = replace(self._device_info(raw["device"]), firmware_register=self._firmware_register(raw["device"], by_selector))
        self.problems.raise_any()
        return Device(
            info=info,
            transport=transport,
            groups=groups,
            enums=tuple(self.elaborated.enums.values()),
            commands=commands,
            faults=faults,
            examples=examples,
            errata=errata,
            source_path=self.elaborated.source.name,
            fingerprint=self.elaborated.source.fingerprint,
            registers=tuple(sorted(self.registers, key=lambda r: (r.address, r.name))),
        )

    def _device_info(self, d: dict[str, Any]) -> DeviceInfo:
        manual = d["manual"]
        return DeviceInfo(
            id=d["id"],
            vendor=d["vendor"],
            vendor_zh=d.get("vendor_zh"),
            model=d["model"],
            description=d.get("description", ""),
            manual_title=manual["title"],
            manual_version=manual.get("version"),
            manual_file=manual["file"],
            manual_language=manual.get("language"),
            firmware=d.get("firmware"),
            map_version=d["map_version"],
            variants=tuple(Variant(v["name"], v["title"], v.get("description", "")) for v in d.get("variants", [])),
            id_pos=self.positions.locate(("device", "id")),
        )

    def _check_unique_groups_and_arrays(self) -> None:
        """Group ids and array names name things in generated code, so each must be unique."""
        first: dict[tuple[str, str], Path] = {}
        for gi, g in enumerate(self.raw["groups"]):
            keyed: list[tuple[str, str, Path]] = [("group id", g["id"], ("groups", gi, "id"))]
            for ri, entry in enumerate(g["registers"]):
                if "array" in entry:
                    keyed.append(("array name", entry["array"], ("groups", gi, "registers", ri, "array")))
            for what, value, path in keyed:
                seen = first.setdefault((what, value), path)
                if seen != path:
                    self.problems.add(path, f"duplicate {what} {value!r} (first declared on line {self.positions.locate(seen)[0]})")

    def _check_unique_registers(self) -> None:
        """Report each repeat where it is declared, naming the line of the first; an array member once, not per element."""
        names: dict[str, Path] = {}
        params: dict[str, tuple[Register, Path]] = {}
        reported: set[tuple[Path, Path]] = set()
        for reg, path in zip(self.registers, self.register_paths, strict=True):
            first = names.get(reg.name)
            if first is None:
                names[reg.name] = path
            elif (path, first) not in reported:
                reported.add((path, first))
                self.problems.add(path, f"duplicate register name {reg.name!r} (first declared on line {self.positions.locate(first)[0]})")
            if reg.param is not None:
                other, other_path = params.setdefault(reg.param, (reg, path))
                if other.name != reg.name and (path, other_path) not in reported:
                    reported.add((path, other_path))
                    self.problems.add(
                        (*path, "param"),
                        f"{reg.name}: parameter id {reg.param} is already used by {other.name} (line {self.positions.locate(other_path)[0]})",
                    )

    def _check_overlaps(self) -> None:
        """Report an overlap at the register that starts later (declared later, at equal starts), once per pair of
        declarations: two array members that collide do so in every element, which is one mistake."""
        owner: dict[tuple[str, int], tuple[Register, Path]] = {}
        reported: set[tuple[Path, Path]] = set()
        placed = sorted(enumerate(zip(self.registers, self.register_paths, strict=True)), key=lambda p: (p[1][0].first_address, p[0]))
        for _, (reg, path) in placed:
            for address in range(reg.first_address, reg.last_address + 1):
                other, other_path = owner.setdefault((reg.space, address), (reg, path))
                if other.name != reg.name and (other_path, path) not in reported:
                    reported.add((other_path, path))
                    self.problems.add(
                        (*path, "address"),
                        f"{reg.name} (0x{reg.first_address:04X}..0x{reg.last_address:04X}) overlaps {other.name} (0x{other.first_address:04X}..0x{other.last_address:04X}) at 0x{address:04X}",
                    )

    def _check_scale_from(self) -> None:
        """A `scale_from` names a readable s16 register (the sf, read as its signed raw value) that is no scaled point itself."""
        by_name = {reg.name: reg for reg in self.registers}
        reported: set[tuple[str | int, ...]] = set()  # an array member's factor is every element's: one mistake, said once
        for reg, path in zip(self.registers, self.register_paths, strict=True):
            if reg.scale_from is None or tuple(path) in reported:
                continue
            sf = by_name.get(reg.scale_from)
            where = (*path, "scale_from")
            name = reg.name if reg.array is None else f"array {reg.array.array} member {reg.array.member}"
            found = len(self.problems.found())
            if sf is None:
                self.problems.add(where, f"{name}: scale_from names unknown register {reg.scale_from!r}")
            elif sf.type is not DataType.S16:
                self.problems.add(where, f"{name}: scale_from {sf.name} is {sf.type.value}; a scale factor is an s16 register")
            elif not sf.access.readable:
                self.problems.add(where, f"{name}: scale_from {sf.name} is write-only; the scale factor is read from the device")
            elif sf.scale_from is not None:
                self.problems.add(where, f"{name}: scale_from {sf.name} is itself scaled by {sf.scale_from}; a scale factor is a plain s16")
            elif reg.array is not None and sf.array is not None and sf.array.array == reg.array.array:
                self.problems.add(
                    where,
                    f"{name}: scale_from {sf.name} is one element of array {sf.array.array}, yet every element would scale by it; "
                    "a member's factor is one register outside its array",
                )
            if len(self.problems.found()) > found:
                reported.add(tuple(path))

    def _selector_index(self) -> dict[str, Register]:
        index: dict[str, Register] = {}
        for reg in self.registers:
            if reg.param is not None:
                index.setdefault(reg.param, reg)
        for reg in self.registers:
            index[reg.name] = reg
        return index

    def _ref(self, selector: str, by_selector: dict[str, Register], path: Path, what: str) -> Register | None:
        reg = by_selector.get(selector)
        if reg is None:
            self.problems.add(path, f"{what}: unknown register {selector!r}")
        return reg

    def _firmware_register(self, d: dict[str, Any], by_selector: dict[str, Register]) -> FirmwareRegister | None:
        spec = d.get("firmware_register")
        if spec is None:
            return None
        path: Path = ("device", "firmware_register")
        reg = self._ref(spec["register"], by_selector, (*path, "register"), "firmware_register")
        if reg is None:
            return None
        form = spec["format"]
        if form == "string" and not reg.type.is_string:
            self.problems.add(
                (*path, "format"), f"firmware_register: format string needs a string register; {reg.name} is {reg.type.value}"
            )
        elif form != "string" and reg.type.kind != "int":
            self.problems.add(
                (*path, "format"), f"firmware_register: format {form} needs an integer register; {reg.name} is {reg.type.value}"
            )
        elif form == "major_minor" and reg.type.words != 1:
            self.problems.add(
                (*path, "format"), f"firmware_register: major_minor reads the two bytes of one word; {reg.name} is {reg.type.value}"
            )
        if "decimals" in spec and form != "decimal":
            self.problems.add((*path, "decimals"), f"firmware_register: decimals applies to format decimal, not {form}")
        if not reg.access.readable:
            self.problems.add((*path, "register"), f"firmware_register: {reg.name} is write-only")
        if reg.firmware is not None:
            self.problems.add((*path, "register"), f"firmware_register: {reg.name} is itself gated by firmware ({reg.firmware.text})")
        firmware = FirmwareRegister(register=reg, format=form, decimals=spec.get("decimals", 0), source=_source(spec.get("source")))
        self._check_gate_versions(firmware)
        return firmware

    def _check_gate_versions(self, firmware: FirmwareRegister) -> None:
        """A gate's version must be one the firmware register can report: with format decimal and 2
        decimals the register reports 2.05 as 205 and 2.50 as 250, so a gate `2.5` (= 2.05) is a slip."""
        if firmware.format == "string":
            return
        shown = f"the firmware register ({firmware.register.name}) reports"
        if firmware.format == "major_minor":
            parts, rule = 2, f"{shown} major.minor (0x0203 = 2.3)"
        elif firmware.decimals:
            scale = 10**firmware.decimals
            example = f"{2 * scale + 5} = 2.{5:0{firmware.decimals}d}"
            parts, rule = 2, f"{shown} versions with {firmware.decimals} decimals ({example})"
        else:
            parts, rule = 1, f"{shown} whole versions (format decimal without decimals)"
        reported: set[Path] = set()
        for reg, path in zip(self.registers, self.register_paths, strict=True):
            if reg.firmware is None:
                continue
            for key, version in (("from", reg.firmware.first), ("until", reg.firmware.until)):
                if version is None:
                    continue
                numbers = version.split(".")
                wrong = len(numbers) > parts or (
                    parts == 2 and firmware.decimals and len(numbers) == 2 and len(numbers[1]) != firmware.decimals
                )
                where = (*self._gate_owner(path), "firmware", key)
                if wrong and where not in reported:
                    reported.add(where)
                    hint = f"; a version has at most {parts} part{'s' if parts > 1 else ''}" if len(numbers) > parts else ""
                    if firmware.decimals and len(numbers) == 2 and len(numbers[1]) < firmware.decimals:
                        padded = numbers[1].ljust(firmware.decimals, "0")
                        hint = f"; write {numbers[0]}.{padded} (as written it means {numbers[0]}.{numbers[1].zfill(firmware.decimals)})"
                    self.problems.add(where, f"{reg.name}: firmware {key} {version}: {rule}{hint}")

    def _gate_owner(self, path: Path) -> Path:
        """Where a register's `firmware` is written: the register (or array member), its array, or its group (or the group's defaults)."""
        candidates: list[Path] = [path]
        if len(path) > 4:
            candidates.append(path[:4])  # the array a member belongs to
        candidates += [(*path[:2], "defaults"), path[:2]]
        for candidate in candidates:
            node: Any = self.raw
            for step in candidate:
                if isinstance(node, dict):
                    node = node.get(step)
                elif isinstance(node, list) and isinstance(step, int) and step < len(node):
                    node = node[step]
                else:
                    node = None
            if isinstance(node, dict) and "firmware" in node:
                return candidate
        return path

    # -- commands, faults, errata, examples ---------------------------------------------------

    def _commands(self, specs: list[dict[str, Any]], by_selector: dict[str, Register]) -> tuple[Command, ...]:
        commands = []
        names: set[str] = set()
        for i, c in enumerate(specs):
            path: Path = ("commands", i)
            if c["name"] in names:
                self.problems.add((*path, "name"), f"duplicate command name {c['name']!r}")
            names.add(c["name"])
            reg = self._ref(c["register"], by_selector, (*path, "register"), f"command {c['name']}")
            if reg is None:
                continue
            if not reg.access.writable:
                self.problems.add((*path, "register"), f"command {c['name']}: register {reg.name} is read-only")
            value = c["value"]
            if isinstance(value, str):
                if reg.enum is None:
                    self.problems.add(
                        (*path, "value"), f"command {c['name']}: register {reg.name} has no enum; give the value as an integer"
                    )
                    continue
                member = reg.enum.member(value)
                if member is None:
                    self.problems.add(
                        (*path, "value"), f"command {c['name']}: {value!r} is not a member of enum {reg.enum.name} (the enum of {reg.name})"
                    )
                    continue
                value = member.value
            argument = None
            if "argument" in c:
                arg = c["argument"]
                if arg["min"] > arg["max"]:
                    self.problems.add(
                        (*path, "argument"), f"command {c['name']}: argument min {arg['min']} is greater than max {arg['max']}"
                    )
                argument = CommandArgument(name=arg["name"], min=arg["min"], max=arg["max"], title=arg.get("title", ""))
            effect = self._effect(c, path, by_selector)
            top = value + (argument.max if argument else 0)
            reported = [m for m in (reg.enum.members if reg.enum else ()) if not m.writable and value <= m.value <= top]
            if reported:
                self.problems.add(
                    (*path, "value"),
                    f"command {c['name']}: {reported[0].name} ({reported[0].value:#06x}) is a state {reg.name} only reports (access: r); it is never written",
                )
            if not reg.type.raw_min <= value <= reg.type.raw_max or not reg.type.raw_min <= top <= reg.type.raw_max:
                self.problems.add(
                    (*path, "value"), f"command {c['name']}: value {value} does not fit register {reg.name} ({reg.type.value})"
                )
            commands.append(
                Command(
                    name=c["name"],
                    title=c["title"],
                    title_zh=c.get("title_zh"),
                    description=c.get("description", ""),
                    register=reg,
                    value=value,
                    argument=argument,
                    effect=effect,
                    destructive=c.get("destructive", effect is not None and effect.kind == "restore_defaults"),
                    source=_source(c["source"]),
                    pos=self.positions.locate(path),
                )
            )
        return tuple(commands)

    def _effect(self, c: dict[str, Any], path: Path, by_selector: dict[str, Register]) -> CommandEffect | None:
        spec = c.get("effect")
        if spec is None:
            return None
        target = None
        if "register" in spec:
            target = self._ref(spec["register"], by_selector, (*path, "effect", "register"), f"command {c['name']} effect")
        elif spec["kind"] == "clear":
            self.problems.add((*path, "effect"), f"command {c['name']}: a clear effect names the register it clears")
        return CommandEffect(kind=spec["kind"], register=target, value=spec.get("value", 0), after_read=spec.get("after_read"))

    def _faults(self, specs: list[dict[str, Any]]) -> tuple[Fault, ...]:
        faults = []
        names: set[str] = set()
        codes: set[str] = set()
        for i, f in enumerate(specs):
            path: Path = ("faults", i)
            if f["name"] in names:
                self.problems.add((*path, "name"), f"duplicate fault name {f['name']!r}")
            if f["code"] in codes:
                self.problems.add((*path, "code"), f"duplicate fault code {f['code']!r}")
            names.add(f["name"])
            codes.add(f["code"])
            faults.append(
                Fault(
                    code=f["code"],
                    value=f.get("value"),
                    name=f["name"],
                    title=f["title"],
                    title_zh=f.get("title_zh"),
                    kind=f["kind"],
                    resettable=f.get("resettable"),
                    description=f.get("description", ""),
                    source=_source(f["source"]),
                )
            )
        return tuple(faults)

    def _errata(self, specs: list[dict[str, Any]], by_selector: dict[str, Register]) -> tuple[Erratum, ...]:
        errata = []
        ids: set[str] = set()
        for i, e in enumerate(specs):
            path: Path = ("errata", i)
            if e["id"] in ids:
                self.problems.add((*path, "id"), f"duplicate erratum id {e['id']!r}")
            ids.add(e["id"])
            names = []
            for j, selector in enumerate(e.get("registers", [])):
                reg = self._ref(selector, by_selector, (*path, "registers", j), f"erratum {e['id']}")
                if reg is not None:
                    names.append(reg.name)
            errata.append(
                Erratum(
                    id=e["id"],
                    title=e["title"],
                    readings=tuple(Reading(source=_source(r["source"]), says=r["says"]) for r in e["readings"]),
                    choice=e["choice"],
                    reason=e["reason"],
                    registers=tuple(names),
                )
            )
        by_register: dict[str, list[str]] = {}
        for erratum in errata:
            for name in erratum.registers:
                by_register.setdefault(name, []).append(erratum.id)
        self.registers = [_with_errata(r, tuple(by_register.get(r.name, ()))) for r in self.registers]
        return tuple(errata)

    def _examples(self, specs: list[dict[str, Any]], by_selector: dict[str, Register], erratum_ids: set[str]) -> tuple[Example, ...]:
        examples: list[Example] = []
        ids: dict[str, str] = {}
        for i, x in enumerate(specs):
            path: Path = ("examples", i)
            if x["id"] in ids:
                self.problems.add((*path, "id"), f"duplicate example id {x['id']!r}")
            ids[x["id"]] = x["direction"]
        for i, x in enumerate(specs):
            path = ("examples", i)
            try:
                frame = parse_hex(x["frame"])
                corrected = parse_hex(x["corrected_frame"]) if "corrected_frame" in x else None
            except FrameError as exc:
                self.problems.add((*path, "frame"), f"example {x['id']}: {exc}")
                continue
            erratum = x.get("erratum")
            if erratum is not None and erratum not in erratum_ids:
                self.problems.add((*path, "erratum"), f"example {x['id']}: unknown erratum {erratum!r}")
            if len(frame) < 4:
                self.problems.add((*path, "frame"), f"example {x['id']}: a frame has at least 4 bytes")
            elif not crc_ok(frame) and erratum is None:
                self.problems.add(
                    (*path, "frame"),
                    f"example {x['id']}: CRC {to_hex(frame[-2:])} does not match the frame (expected {to_hex(crc_bytes(frame[:-2]))}); fix the transcription or declare an erratum",
                )
            if corrected is not None:
                if erratum is None:
                    self.problems.add(
                        (*path, "corrected_frame"), f"example {x['id']}: corrected_frame needs an erratum explaining the correction"
                    )
                if not crc_ok(corrected):
                    self.problems.add(
                        (*path, "corrected_frame"),
                        f"example {x['id']}: the corrected frame's CRC is wrong (expected {to_hex(crc_bytes(corrected[:-2]))})",
                    )
            request = x.get("request")
            if request is not None:
                if x["direction"] != "response":
                    self.problems.add((*path, "request"), f"example {x['id']}: only a response names the request it answers")
                elif request not in ids:
                    self.problems.add((*path, "request"), f"example {x['id']}: unknown request example {request!r}")
                elif ids[request] != "request":
                    self.problems.add((*path, "request"), f"example {x['id']}: {request!r} is a response, not a request example")
            values = []
            for j, v in enumerate(x.get("values", [])):
                reg = self._ref(v["register"], by_selector, (*path, "values", j, "register"), f"example {x['id']}")
                if reg is None:
                    continue
                raw = v.get("raw")
                words = tuple(raw) if isinstance(raw, list) else None
                if words is not None and len(words) > reg.words:
                    self.problems.add(
                        (*path, "values", j, "raw"), f"example {x['id']}: {len(words)} words for {reg.name}, which has {reg.words}"
                    )
                if isinstance(raw, bool):
                    raw = int(raw)
                not_available = "value" in v and v["value"] is None
                if not_available and (not reg.has_na or (raw is not None and words is None and not reg.is_na(raw))):
                    marks = f"its markers are {na_list(reg)}" if reg.has_na else "it has no `na` marker"
                    self.problems.add(
                        (*path, "values", j, "value"), f"example {x['id']}: value null says {reg.name} is not available, but {marks}"
                    )
                values.append(
                    ExampleValue(
                        register=reg,
                        raw=None if isinstance(raw, list) else raw,
                        words=words,
                        value=v.get("value"),
                        not_available=not_available,
                    )
                )
            examples.append(
                Example(
                    id=x["id"],
                    source=_source(x["source"]),
                    direction=x["direction"],
                    frame=frame,
                    request=request,
                    meaning=x["meaning"],
                    meaning_zh=x.get("meaning_zh"),
                    values=tuple(values),
                    erratum=erratum,
                    corrected_frame=corrected,
                    notes=x.get("notes", ""),
                )
            )
        return tuple(examples)


def _with_errata(reg: Register, errata: tuple[str, ...]) -> Register:
    return replaced(reg, errata=errata) if errata else reg
