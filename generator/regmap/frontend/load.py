"""Map file -> `Device`: safe YAML, JSON Schema, semantic checks, elaboration.

Every problem in a file is collected (errors are values here) and raised together as one
`MapError`, each as `file:line:col: message`.
"""

from __future__ import annotations

import difflib
import hashlib
import json
import keyword
import re
import string
from collections.abc import Iterable
from dataclasses import dataclass, replace
from decimal import Decimal
from fractions import Fraction
from importlib import resources
from pathlib import Path as FsPath
from typing import Any

import jsonschema

from regmap.diagnostics import Diagnostic, MapError
from regmap.frontend.yamlsource import Path, Positions, YamlProblem, read_yaml
from regmap.keywords import C_KEYWORDS, CPP_KEYWORDS
from regmap.model import (
    Access,
    ArrayDef,
    ArrayMember,
    ArrayRef,
    BadCrc,
    Bitfield,
    Command,
    CommandArgument,
    CommandEffect,
    DataType,
    Device,
    DeviceInfo,
    EnumMember,
    EnumType,
    Erratum,
    Example,
    ExampleValue,
    Fault,
    Group,
    ModbusException,
    Reading,
    Register,
    TimingRow,
    Transport,
    WordOrder,
    WordOrderRegister,
)
from regmap_runtime.rtu import FrameError, crc_bytes, crc_ok, parse_hex, to_hex

MAX_MAP_BYTES = 8 * 1024 * 1024

RESERVED_IDS = frozenset({"regmap", "regmap_runtime", "regmap_rtu", "pymodbus", "test", "tests"})


def _schema() -> dict[str, Any]:
    text = resources.files("regmap").joinpath("schema/map.schema.json").read_text(encoding="utf-8")
    schema: dict[str, Any] = json.loads(text)
    return schema


_VALIDATOR: jsonschema.protocols.Validator | None = None


def _validator() -> jsonschema.protocols.Validator:
    global _VALIDATOR
    if _VALIDATOR is None:
        _VALIDATOR = jsonschema.Draft202012Validator(_schema())
    return _VALIDATOR


def load_map(path: str | FsPath, display_name: str | None = None) -> Device:
    """Read, check and elaborate one map file; raises MapError listing every problem."""
    name = display_name or str(path)
    try:
        data = FsPath(path).read_bytes()
    except OSError as exc:
        raise MapError([Diagnostic(name, 1, 1, f"cannot read the map: {exc.strerror or exc}")]) from None
    return load_map_bytes(data, name)


def load_map_bytes(data: bytes, name: str) -> Device:
    if len(data) > MAX_MAP_BYTES:
        raise MapError([Diagnostic(name, 1, 1, f"the map is {len(data)} bytes; maps larger than {MAX_MAP_BYTES} bytes are refused")])
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = data[: exc.start].count(b"\n") + 1
        column = exc.start - (data.rfind(b"\n", 0, exc.start) + 1) + 1
        raise MapError(
            [Diagnostic(name, line, column, f"the map is not valid UTF-8 (byte 0x{data[exc.start]:02X}); save it as UTF-8")]
        ) from None
    if text.startswith("\ufeff"):
        text = text[1:]
    return load_map_text(text, name, fingerprint=hashlib.sha256(data).hexdigest()[:16])


def load_map_text(text: str, name: str, fingerprint: str | None = None) -> Device:
    if fingerprint is None:
        fingerprint = hashlib.sha256(text.encode("utf-8")).hexdigest()[:16]
    try:
        raw, positions = read_yaml(text)
    except YamlProblem as exc:
        raise MapError([Diagnostic(name, exc.line, exc.column, exc.message)]) from None
    if not isinstance(raw, dict):
        line, col = positions.locate(())
        raise MapError([Diagnostic(name, line, col, f"the map must be a YAML mapping at the top level, not a {_kind(raw)}")])
    problems = _schema_problems(raw, positions, name)
    if problems:
        raise MapError(problems)
    return _Elaborator(raw, positions, name, fingerprint).run()


def _kind(value: Any) -> str:
    return {list: "list", str: "string", int: "number", float: "number", bool: "boolean"}.get(type(value), type(value).__name__)


def _dotted(path: Iterable[str | int]) -> str:
    out = ""
    for part in path:
        out += f"[{part}]" if isinstance(part, int) else (f".{part}" if out else str(part))
    return out or "(top level)"


def _schema_problems(raw: dict[str, Any], positions: Positions, name: str) -> list[Diagnostic]:
    problems = []
    for umbrella in _validator().iter_errors(raw):
        error, message = _pick(umbrella)
        path = tuple(error.absolute_path)
        instance: Any = error.instance
        if error.validator == "additionalProperties":
            # One line per unknown key, at the key itself.
            known = sorted(error.schema.get("properties", {})) if isinstance(error.schema, dict) else []
            for key in sorted(set(instance) - set(known)):
                line, col = positions.locate_key((*path, key))
                close = difflib.get_close_matches(key, known, n=1)
                hint = f" (did you mean {close[0]!r}?)" if close else ""
                problems.append(Diagnostic(name, line, col, f"{_dotted(path)}: unknown key {key!r}{hint}"))
            continue
        if "propertyNames" in error.schema_path:
            line, col = positions.locate_key((*path, instance))
        else:
            line, col = positions.locate(path)
        message = message if len(message) <= 200 else message[:197] + "..."
        problems.append(Diagnostic(name, line, col, f"{_dotted(path)}: {message}"))
    return problems


def _pick(error: jsonschema.ValidationError) -> tuple[jsonschema.ValidationError, str]:
    """The error to report for a oneOf/anyOf failure, and its message.

    The branch that takes the value's type explains best (a string that misses a pattern, not "is not an
    integer"); when no branch takes it, the message names every type that would do.
    """
    while error.context:
        typed = [e for e in error.context if not (e.validator == "type" and not e.relative_path)]
        if not typed:
            types = [t for e in error.context for t in _as_list(e.validator_value)]
            return error, _type_message(error.instance, types)
        error = jsonschema.exceptions.best_match(typed)
    return error, _schema_message(error)


# What the schema's patterns mean, for messages a person can act on.
_PATTERNS = {
    "^[a-z][a-z0-9_]*$": "a snake_case identifier (lowercase letters, digits and _, starting with a letter)",
    r"^(0|[1-9][0-9]*)\.(0|[1-9][0-9]*)\.(0|[1-9][0-9]*)$": "a semantic version such as 1.0.0",
    "^[0-9A-Fa-f]{2}( ?[0-9A-Fa-f]{2})*$": "hex bytes such as '01 03 00 01'",
    "^[0-9]{1,2}-[0-9]{1,2}$": "a bit number or an inclusive bit range low-high such as '8-10'",
    "^E[0-9]+$": "an erratum id such as E1",
}
# YAML 1.1 reads 1e-3 (no dot, unsigned exponent) as text, where JSON and YAML 1.2 read a number.
_FLOAT_AS_TEXT = re.compile(r"^[-+]?([0-9]+\.?[0-9]*|\.[0-9]+)[eE][-+]?[0-9]+$")


_TYPE_NAMES = {
    "object": "a mapping",
    "array": "a list",
    "string": "a string",
    "integer": "an integer",
    "number": "a number",
    "boolean": "true or false",
    "null": "null",
}


def _schema_message(error: jsonschema.ValidationError) -> str:
    """jsonschema's message, reworded where it would show Python spellings (None, True) or a bare regex."""
    value: Any = error.validator_value
    if error.validator == "required":
        return error.message.replace("is a required property", "is required")
    if error.validator == "pattern" and value in _PATTERNS:
        return f"{error.instance!r} is not {_PATTERNS[value]}"
    if error.validator == "type":
        return _type_message(error.instance, _as_list(value))
    if error.validator == "enum":
        return f"{_show(error.instance)} is not one of {', '.join(_show(v) for v in value)}"
    if error.validator == "const":
        return f"expected {_show(value)}, got {_show(error.instance)}"
    if error.validator == "exclusiveMinimum":
        return f"{_show(error.instance)} must be greater than {value}"
    return error.message


def _type_message(instance: Any, types: list[Any]) -> str:
    wanted = " or ".join(dict.fromkeys(_TYPE_NAMES.get(t, str(t)) for t in types))
    message = f"expected {wanted}, got {_describe(instance)}"
    if isinstance(instance, str) and _FLOAT_AS_TEXT.match(instance) and {"number", "integer"} & set(types):
        message += f"; YAML reads {instance} as text: write a number with a dot and a signed exponent, such as 1.0e-3"
    return message


def _as_list(value: Any) -> list[Any]:
    return value if isinstance(value, list) else [value]


def _show(value: Any) -> str:
    """A value as YAML spells it (null, true), strings quoted and cut short."""
    if isinstance(value, str):
        return repr(value if len(value) <= 60 else value[:57] + "...")
    if isinstance(value, dict | list):
        return _describe(value)
    return json.dumps(value)


def _describe(value: Any) -> str:
    if isinstance(value, dict):
        return "a mapping"
    if isinstance(value, list):
        return "a list"
    if isinstance(value, str):
        return f"the string {_show(value)}"
    if isinstance(value, bool) or value is None:
        return _show(value)
    return f"the {'integer' if isinstance(value, int) else 'number'} {value}"


def _source(value: Any) -> tuple[str, ...]:
    if value is None:
        return ()
    return (value,) if isinstance(value, str) else tuple(value)


def _scale(value: Any) -> Fraction:
    # Decimal(str()) keeps 0.1 as 1/10 instead of the binary float's 3602879701896397/36028797018963968.
    return Fraction(Decimal(str(value)))


def _bits(spec: int | str) -> tuple[int, int]:
    if isinstance(spec, int):
        return spec, spec
    low, high = (int(p) for p in spec.split("-"))
    return low, high


@dataclass(frozen=True)
class _ParamRule:
    regex: re.Pattern[str]
    format: str
    base: int
    group_stride: int
    index_stride: int
    group_radix: int
    index_radix: int

    def address_of(self, param: str) -> int | None:
        """The address this rule gives `param`, or None when the regex does not match.

        Raises ValueError when the regex matches but a group is not a number in its radix.
        """
        match = self.regex.fullmatch(param)
        if not match:
            return None
        index = _number(match.group("index"), self.index_radix, "index")
        group = _number(match.group("group"), self.group_radix, "group") if "group" in match.groupdict() and match.group("group") else 0
        return self.base + group * self.group_stride + index * self.index_stride

    def param_of(self, address: int) -> str | None:
        offset = address - self.base
        if offset < 0:
            return None
        group = offset // self.group_stride if self.group_stride else 0
        rest = offset - group * self.group_stride
        if rest % self.index_stride:
            return None
        text = self.format.format(group=group, index=rest // self.index_stride)
        try:
            return text if self.address_of(text) == address else None
        except ValueError:
            return None


_FORMAT_SPEC = re.compile(r"^(:0?[1-9]?[dxX]?)?$")


def _number(text: str | None, radix: int, what: str) -> int:
    try:
        return int(text or "", radix)
    except ValueError:
        raise ValueError(f"its {what} {text!r} is not a base-{radix} number") from None


class _Elaborator:
    """Semantic checks and model building in one walk; problems accumulate in `self.problems`."""

    def __init__(self, raw: dict[str, Any], positions: Positions, name: str, fingerprint: str) -> None:
        self.raw = raw
        self.positions = positions
        self.name = name
        self.fingerprint = fingerprint
        self.problems: list[Diagnostic] = []
        self.enums: dict[str, EnumType] = {}
        self.rules: list[_ParamRule] = []
        self.registers: list[Register] = []
        self.register_paths: list[Path] = []  # where each of self.registers is declared, in step with it

    def problem(self, path: Path, message: str) -> None:
        line, col = self.positions.locate(path)
        self.problems.append(Diagnostic(self.name, line, col, message))

    # -- top level -------------------------------------------------------------------------

    def run(self) -> Device:
        raw = self.raw
        self._param_rules(raw.get("param_ids", []))
        self._enums(raw.get("enums", {}))
        word_order = WordOrder(raw["transport"]["word_order"])
        groups = [self._group(g, ("groups", i), word_order) for i, g in enumerate(raw["groups"])]
        self._check_unique_groups_and_arrays()
        self._check_unique_registers()
        self._check_overlaps()
        errata = self._errata(raw.get("errata", []), self._selector_index())
        final = {r.name: r for r in self.registers}
        groups = [replace(g, registers=tuple(final[r.name] for r in g.registers)) for g in groups]
        by_selector = self._selector_index()
        transport = self._transport(raw["transport"], by_selector)
        commands = self._commands(raw.get("commands", []), by_selector)
        faults = self._faults(raw.get("faults", []))
        examples = self._examples(raw.get("examples", []), by_selector, {e.id for e in errata})
        self._check_device_id(raw["device"]["id"])
        if self.problems:
            raise MapError(self.problems)
        info = self._device_info(raw["device"])
        return Device(
            info=info,
            transport=transport,
            groups=tuple(groups),
            enums=tuple(self.enums.values()),
            commands=commands,
            faults=faults,
            examples=examples,
            errata=errata,
            source_path=self.name,
            fingerprint=self.fingerprint,
            registers=tuple(sorted(self.registers, key=lambda r: (r.address, r.name))),
        )

    def _check_device_id(self, device_id: str) -> None:
        """The id names a Python package and prefixes every C name: it must be usable as both."""
        if (
            keyword.iskeyword(device_id)
            or keyword.issoftkeyword(device_id)
            or device_id in C_KEYWORDS
            or device_id in CPP_KEYWORDS
            or device_id in RESERVED_IDS
        ):
            self.problem(
                ("device", "id"),
                f"device id {device_id!r} is a reserved word in Python, C or regmap; choose another (e.g. {device_id}_drive)",
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
        )

    # -- parameter-id rules ----------------------------------------------------------------

    def _param_rules(self, rules: list[dict[str, Any]]) -> None:
        for i, rule in enumerate(rules):
            path: Path = ("param_ids", i)
            try:
                regex = re.compile(rule["regex"])
            except re.error as exc:
                self.problem((*path, "regex"), f"invalid regular expression: {exc}")
                continue
            if "index" not in regex.groupindex:
                self.problem((*path, "regex"), "the regex needs a named group `index`")
                continue
            fields = set()
            specs = set()
            try:
                for _, field_name, spec, conversion in string.Formatter().parse(rule["format"]):
                    if field_name is not None:
                        fields.add(field_name)
                        specs.add(f"{'!' + conversion if conversion else ''}{':' + spec if spec else ''}")
            except ValueError as exc:
                self.problem((*path, "format"), f"invalid format pattern: {exc}")
                continue
            bad_field = next((f for f in sorted(fields) if f not in ("group", "index")), None)
            if bad_field is not None:
                self.problem((*path, "format"), f"format field {{{bad_field}}} is not allowed; use only {{group}} and {{index}}")
                continue
            if "index" not in fields:
                self.problem((*path, "format"), "the format must use the field {index}")
                continue
            bad_spec = next((spec for spec in sorted(specs) if not _FORMAT_SPEC.match(spec)), None)
            if bad_spec is not None:
                # Only a width and a base: anything else could pad a parameter id to gigabytes.
                self.problem(
                    (*path, "format"),
                    f"format spec {bad_spec!r} is not supported; use a width of at most 9 and d, x or X, as in {{index:02d}}",
                )
                continue
            try:
                rule["format"].format(group=0, index=0)
            except (ValueError, KeyError, IndexError) as exc:
                self.problem((*path, "format"), f"invalid format pattern: {exc}")
                continue
            self.rules.append(
                _ParamRule(
                    regex=regex,
                    format=rule["format"],
                    base=rule.get("base", 0),
                    group_stride=rule.get("group_stride", 0),
                    index_stride=rule.get("index_stride", 1),
                    group_radix=rule.get("group_radix", 10),
                    index_radix=rule.get("index_radix", 10),
                )
            )

    def _rule_address(self, param: str) -> int | None:
        for rule in self.rules:
            address = rule.address_of(param)
            if address is not None:
                return address
        return None

    def _rule_param(self, address: int) -> str | None:
        for rule in self.rules:
            param = rule.param_of(address)
            if param is not None:
                return param
        return None

    # -- enums -----------------------------------------------------------------------------

    def _enums(self, enums: dict[str, Any]) -> None:
        for enum_name, spec in enums.items():
            path: Path = ("enums", enum_name)
            members = []
            seen_names: set[str] = set()
            seen_values: dict[int, str] = {}
            for j, v in enumerate(spec["values"]):
                vpath: Path = (*path, "values", j)
                if v["name"] in seen_names:
                    self.problem((*vpath, "name"), f"enum {enum_name}: duplicate member name {v['name']!r}")
                if v["value"] in seen_values:
                    self.problem((*vpath, "value"), f"enum {enum_name}: value {v['value']} is already used by {seen_values[v['value']]!r}")
                seen_names.add(v["name"])
                seen_values.setdefault(v["value"], v["name"])
                members.append(
                    EnumMember(
                        value=v["value"],
                        name=v["name"],
                        title=v["title"],
                        title_zh=v.get("title_zh"),
                        symbol=v.get("symbol"),
                        description=v.get("description", ""),
                        source=_source(v.get("source")),
                    )
                )
            self.enums[enum_name] = EnumType(
                name=enum_name,
                title=spec["title"],
                title_zh=spec.get("title_zh"),
                description=spec.get("description", ""),
                source=_source(spec.get("source")),
                members=tuple(members),
                pos=self.positions.locate(path),
            )

    def _enum_ref(self, name: str | None, path: Path, owner: str) -> EnumType | None:
        if name is None:
            return None
        found = self.enums.get(name)
        if found is None:
            self.problem(path, f"{owner}: unknown enum {name!r}" + (f" (known: {', '.join(sorted(self.enums))})" if self.enums else ""))
        return found

    # -- groups, registers, arrays -----------------------------------------------------------

    def _group(self, g: dict[str, Any], path: Path, word_order: WordOrder) -> Group:
        defaults = dict(g.get("defaults", {}))
        if "source" not in defaults and "source" in g:
            defaults["source"] = g["source"]
        registers: list[Register] = []
        arrays: list[ArrayDef] = []
        for i, entry in enumerate(g["registers"]):
            epath: Path = (*path, "registers", i)
            if "array" in entry:
                array, expanded = self._array(entry, epath, defaults, g["id"], word_order)
                arrays.append(array)
                for element, member_path in expanded:
                    registers.append(element)
                    self.register_paths.append(member_path)
            else:
                reg = self._register({**defaults, **entry}, epath, g["id"], word_order)
                if reg is not None:
                    self._check_param(reg, epath)
                    registers.append(reg)
                    self.register_paths.append(epath)
        self.registers.extend(registers)
        return Group(
            id=g["id"],
            title=g["title"],
            title_zh=g.get("title_zh"),
            description=g.get("description", ""),
            source=_source(g.get("source")),
            registers=tuple(registers),
            arrays=tuple(arrays),
        )

    def _register(
        self,
        r: dict[str, Any],
        path: Path,
        group: str,
        word_order: WordOrder,
        *,
        name: str | None = None,
        address: int | None = None,
        param: str | None = None,
        array: ArrayRef | None = None,
    ) -> Register | None:
        name = name or r["name"]
        address = r["address"] if address is None else address
        dtype = DataType(r.get("type", "u16"))
        if "words" in r and r["words"] != dtype.words:
            self.problem(
                (*path, "words"),
                f"{name}: words {r['words']} does not match type {dtype.value} ({dtype.words} word{'s' if dtype.words > 1 else ''})",
            )
        if address + dtype.words - 1 > 0xFFFF:
            self.problem((*path, "address"), f"{name}: a {dtype.words}-word register at 0x{address:04X} runs past address 0xFFFF")
        paired = bool(r.get("paired", False))
        if paired and dtype.words != 1:
            self.problem(
                (*path, "paired"),
                f"{name}: `paired` describes a 16-bit value in the low word of a 32-bit pair; type {dtype.value} is already 32-bit",
            )
        if paired and address == 0:
            self.problem((*path, "address"), f"{name}: a paired register needs its high word at address-1, but the address is 0")
        if "word_order" in r and dtype.words == 1 and "word_order" not in self._defaults_keys(path):
            self.problem((*path, "word_order"), f"{name}: word_order applies only to 32-bit registers; type is {dtype.value}")
        order = WordOrder(r["word_order"]) if "word_order" in r and dtype.wide else word_order
        enum_type = self._enum_ref(r.get("enum"), (*path, "enum"), name)
        bitfields = self._bitfields(r.get("bitfields", []), (*path, "bitfields"), dtype, name)
        low, high, default = r.get("min"), r.get("max"), r.get("default")
        for key, value in (("min", low), ("max", high), ("default", default)):
            if value is not None and not dtype.raw_min <= value <= dtype.raw_max:
                self.problem(
                    (*path, key), f"{name}: {key} {value} is outside the range of {dtype.value} ({dtype.raw_min}..{dtype.raw_max})"
                )
        if low is not None and high is not None and low > high:
            self.problem((*path, "min"), f"{name}: min {low} is greater than max {high}")
        if default is not None:
            if (low is not None and default < low) or (high is not None and default > high):
                self.problem((*path, "default"), f"{name}: default {default} is outside min..max ({low}..{high})")
            if enum_type is not None and enum_type.by_value(default) is None:
                self.problem((*path, "default"), f"{name}: default {default} is not a value of enum {enum_type.name}")
        if enum_type is not None:
            for member in enum_type.members:
                if not dtype.raw_min <= member.value <= dtype.raw_max:
                    self.problem(
                        (*path, "enum"), f"{name}: enum {enum_type.name} member {member.name} = {member.value} does not fit {dtype.value}"
                    )
        if not r.get("source"):
            self.problem(path, f"{name}: no source; give the manual section it was read from (on the register or in the group)")
        access = Access(r.get("access", "rw"))
        return Register(
            name=name,
            param=param if param is not None else r.get("param"),
            address=address,
            type=dtype,
            word_order=order,
            word_order_fixed="word_order" in r and dtype.wide,
            access=access,
            unit=r.get("unit"),
            scale=_scale(r.get("scale", 1)),
            min=low,
            max=high,
            default=default,
            enum=enum_type,
            bitfields=bitfields,
            takes_effect=r.get("takes_effect"),
            settable=r.get("settable"),
            modes=tuple(r.get("modes", ())),
            paired=paired,
            title=r["title"],
            title_zh=r.get("title_zh"),
            description=r.get("description", ""),
            range_text=r.get("range_text"),
            source=_source(r.get("source")),
            notes=r.get("notes", ""),
            group=group,
            array=array,
            pos=self.positions.locate(path),
        )

    def _defaults_keys(self, path: Path) -> set[str]:
        group_path = path[:2]
        group = self.raw["groups"][group_path[1]] if len(group_path) == 2 else {}
        return set(group.get("defaults", {}))

    def _bitfields(self, specs: list[dict[str, Any]], path: Path, dtype: DataType, name: str) -> tuple[Bitfield, ...]:
        fields: list[Bitfield] = []
        used: dict[int, str] = {}
        names: set[str] = set()
        for i, spec in enumerate(specs):
            fpath: Path = (*path, i)
            lsb, msb = _bits(spec["bits"])
            if lsb > msb:
                self.problem((*fpath, "bits"), f"{name}.{spec['name']}: bit range {spec['bits']} runs backwards; write low-high")
                continue
            if msb >= dtype.bits:
                self.problem((*fpath, "bits"), f"{name}.{spec['name']}: bits {spec['bits']} lie beyond the {dtype.bits}-bit register")
                continue
            if spec["name"] in names:
                self.problem((*fpath, "name"), f"{name}: duplicate bitfield name {spec['name']!r}")
            names.add(spec["name"])
            for bit in range(lsb, msb + 1):
                if bit in used:
                    self.problem((*fpath, "bits"), f"{name}.{spec['name']}: bit {bit} overlaps bitfield {used[bit]}")
                    break
                used[bit] = spec["name"]
            enum_type = self._enum_ref(spec.get("enum"), (*fpath, "enum"), f"{name}.{spec['name']}")
            if enum_type is not None:
                for member in enum_type.members:
                    if not 0 <= member.value < (1 << (msb - lsb + 1)):
                        self.problem(
                            (*fpath, "enum"),
                            f"{name}.{spec['name']}: enum {enum_type.name} member {member.name} = {member.value} does not fit in {msb - lsb + 1} bit(s)",
                        )
                        break
            fields.append(
                Bitfield(
                    name=spec["name"],
                    lsb=lsb,
                    msb=msb,
                    title=spec["title"],
                    title_zh=spec.get("title_zh"),
                    description=spec.get("description", ""),
                    enum=enum_type,
                    pos=self.positions.locate(fpath),
                )
            )
        return tuple(sorted(fields, key=lambda f: f.lsb))

    def _array(
        self, a: dict[str, Any], path: Path, defaults: dict[str, Any], group: str, word_order: WordOrder
    ) -> tuple[ArrayDef, list[tuple[Register, Path]]]:
        """The array and its expanded registers, each with the path of the member it comes from."""
        index_base = a.get("index_base", 0)
        members: list[ArrayMember] = []
        expanded: list[tuple[Register, Path]] = []
        member_names: set[str] = set()
        repeated: set[int] = set()  # not expanded, so the repeat is reported once, not again as duplicate registers
        for j, m in enumerate(a["members"]):
            mpath: Path = (*path, "members", j)
            if m["name"] in member_names:
                self.problem((*mpath, "name"), f"array {a['array']}: duplicate member {m['name']!r}")
                repeated.add(j)
            member_names.add(m["name"])
            words = DataType(m.get("type", defaults.get("type", "u16"))).words
            if m["offset"] + words > a["stride"]:
                self.problem(
                    (*mpath, "offset"),
                    f"array {a['array']}: member {m['name']} (offset {m['offset']}, {words} words) does not fit in the stride {a['stride']}",
                )
            members.append(ArrayMember(name=m["name"], offset=m["offset"], words=words, title=m["title"]))
        array = ArrayDef(
            name=a["array"],
            title=a["title"],
            title_zh=a.get("title_zh"),
            description=a.get("description", ""),
            element_title=a.get("element_title", a["title"] + " {n}"),
            count=a["count"],
            index_base=index_base,
            base=a["base"],
            stride=a["stride"],
            members=tuple(members),
            group=group,
            source=_source(a.get("source")),
            notes=a.get("notes", ""),
        )
        last = array.base + (array.count - 1) * array.stride + max((m.offset + m.words for m in members), default=1) - 1
        if last > 0xFFFF:
            self.problem((*path, "count"), f"array {array.name}: its last element ends at 0x{last:X}, past address 0xFFFF")
            return array, []
        inherited = {**defaults, "source": a.get("source", defaults.get("source"))}
        for j, spec in enumerate(a["members"]):
            if isinstance(spec.get("default"), list) and len(spec["default"]) != array.count:
                self.problem(
                    (*path, "members", j, "default"),
                    f"array {array.name}: member {spec['name']} lists {len(spec['default'])} defaults for {array.count} elements",
                )
        for i in range(array.count):
            index = index_base + i
            for j, (member, spec) in enumerate(zip(members, a["members"], strict=True)):
                if j in repeated:
                    continue
                address = array.element_address(index, member)
                if isinstance(spec.get("default"), list):
                    spec = {**spec, "default": spec["default"][i] if i < len(spec["default"]) else None}
                reg = self._register(
                    {**inherited, **spec},
                    (*path, "members", j),
                    group,
                    word_order,
                    name=f"{array.name}_{index}_{member.name}",
                    address=address,
                    param=self._rule_param(address),
                    array=ArrayRef(array=array.name, index=index, member=member.name),
                )
                if reg is not None:
                    expanded.append((reg, (*path, "members", j)))
        # Report per-member problems once, not once per element.
        self.problems = list(dict.fromkeys(self.problems))
        return array, expanded

    def _check_param(self, reg: Register, path: Path) -> None:
        if reg.param is None:
            return
        try:
            expected = self._rule_address(reg.param)
        except ValueError as exc:
            self.problem((*path, "param"), f"{reg.name}: parameter {reg.param} matches a param_ids regex, but {exc}")
            return
        if expected is not None and expected != reg.address:
            self.problem(
                (*path, "address"),
                f"{reg.name}: parameter {reg.param} is at 0x{expected:04X} by the param_ids rule, but the address is 0x{reg.address:04X}",
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
                    self.problem(path, f"duplicate {what} {value!r} (first declared on line {self.positions.locate(seen)[0]})")

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
                self.problem(path, f"duplicate register name {reg.name!r} (first declared on line {self.positions.locate(first)[0]})")
            if reg.param is not None:
                other, other_path = params.setdefault(reg.param, (reg, path))
                if other.name != reg.name and (path, other_path) not in reported:
                    reported.add((path, other_path))
                    self.problem(
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
                    self.problem(
                        (*path, "address"),
                        f"{reg.name} (0x{reg.first_address:04X}..0x{reg.last_address:04X}) overlaps {other.name} (0x{other.first_address:04X}..0x{other.last_address:04X}) at 0x{address:04X}",
                    )

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
            self.problem(path, f"{what}: unknown register {selector!r}")
        return reg

    # -- transport ---------------------------------------------------------------------------

    def _transport(self, t: dict[str, Any], by_selector: dict[str, Register]) -> Transport:
        path: Path = ("transport",)
        serial = t["serial"]
        rates = tuple(serial.get("baud_rates", ()))
        if rates and serial["baud"] not in rates:
            self.problem((*path, "serial", "baud"), f"default baud {serial['baud']} is not among baud_rates {list(rates)}")
        ids = t["slave_ids"]
        if ids["min"] > ids["max"]:
            self.problem((*path, "slave_ids", "min"), f"slave id min {ids['min']} is greater than max {ids['max']}")
        word_order_register = None
        if "word_order_register" in t:
            w = t["word_order_register"]
            reg = self._ref(w["register"], by_selector, (*path, "word_order_register", "register"), "word_order_register")
            if reg is not None:
                word_order_register = WordOrderRegister(register=reg, high_first=w["high_first"], low_first=w["low_first"])
                if reg.default is not None and reg.default not in (w["high_first"], w["low_first"]):
                    self.problem(
                        (*path, "word_order_register"),
                        f"word_order_register: the default {reg.default} of {reg.name} is neither the high_first value {w['high_first']} nor the low_first value {w['low_first']}",
                    )
                elif reg.default is not None:
                    configured = "high_first" if reg.default == w["high_first"] else "low_first"
                    if configured != t["word_order"]:
                        self.problem(
                            (*path, "word_order"),
                            f"word_order {t['word_order']} disagrees with the default of {reg.name} ({reg.default} = {configured})",
                        )
        max_bytes = t.get("max_message_bytes")
        if max_bytes is not None:
            if 5 + 2 * t["max_read_registers"] > max_bytes:
                self.problem(
                    (*path, "max_read_registers"),
                    f"a read response of {t['max_read_registers']} registers is {5 + 2 * t['max_read_registers']} bytes, more than max_message_bytes {max_bytes}",
                )
            if 9 + 2 * t["max_write_registers"] > max_bytes:
                self.problem(
                    (*path, "max_write_registers"),
                    f"a write request of {t['max_write_registers']} registers is {9 + 2 * t['max_write_registers']} bytes, more than max_message_bytes {max_bytes}",
                )
        codes = [e["code"] for e in t.get("exceptions", [])]
        for i, code in enumerate(codes):
            if code in codes[:i]:
                self.problem((*path, "exceptions", i, "code"), f"duplicate exception code 0x{code:02X}")
        crc = t.get("bad_crc", {"reply": "silent"})
        if crc["reply"] == "exception" and crc["code"] not in codes:
            listed = ", ".join(f"0x{c:02X}" for c in codes) or "none"
            self.problem(
                (*path, "bad_crc", "code"),
                f"bad_crc answers exception 0x{crc['code']:02X}, which transport.exceptions does not list (listed: {listed})",
            )
        bad_crc = BadCrc(reply=crc["reply"], code=crc.get("code"), source=_source(crc.get("source")), notes=crc.get("notes", ""))
        return Transport(
            baud=serial["baud"],
            baud_rates=rates,
            parity=serial["parity"],
            data_bits=serial["data_bits"],
            stop_bits=serial["stop_bits"],
            slave_min=ids["min"],
            slave_max=ids["max"],
            broadcast_id=t.get("broadcast_id"),
            function_codes=tuple(t["function_codes"]),
            max_read_registers=t["max_read_registers"],
            max_write_registers=t["max_write_registers"],
            max_message_bytes=max_bytes,
            word_order=WordOrder(t["word_order"]),
            word_order_register=word_order_register,
            crc_byte_order=t.get("crc_byte_order", "low_first"),
            undocumented_addresses=t.get("undocumented_addresses", "reject"),
            bad_crc=bad_crc,
            response_delay_ms=t.get("response_delay_ms"),
            timing=tuple(TimingRow(**row) for row in t.get("timing", [])),
            exceptions=tuple(
                ModbusException(
                    code=e["code"], name=e["name"], title=e["title"], title_zh=e.get("title_zh"), source=_source(e.get("source"))
                )
                for e in t.get("exceptions", [])
            ),
            source=_source(t.get("source")) + _source(serial.get("source")),
            notes="\n".join(x for x in (t.get("notes", ""), serial.get("notes", "")) if x),
        )

    # -- commands, faults, errata, examples ---------------------------------------------------

    def _commands(self, specs: list[dict[str, Any]], by_selector: dict[str, Register]) -> tuple[Command, ...]:
        commands = []
        names: set[str] = set()
        for i, c in enumerate(specs):
            path: Path = ("commands", i)
            if c["name"] in names:
                self.problem((*path, "name"), f"duplicate command name {c['name']!r}")
            names.add(c["name"])
            reg = self._ref(c["register"], by_selector, (*path, "register"), f"command {c['name']}")
            if reg is None:
                continue
            if not reg.access.writable:
                self.problem((*path, "register"), f"command {c['name']}: register {reg.name} is read-only")
            value = c["value"]
            if isinstance(value, str):
                if reg.enum is None:
                    self.problem((*path, "value"), f"command {c['name']}: register {reg.name} has no enum; give the value as an integer")
                    continue
                member = reg.enum.member(value)
                if member is None:
                    self.problem(
                        (*path, "value"), f"command {c['name']}: {value!r} is not a member of enum {reg.enum.name} (the enum of {reg.name})"
                    )
                    continue
                value = member.value
            argument = None
            if "argument" in c:
                arg = c["argument"]
                if arg["min"] > arg["max"]:
                    self.problem((*path, "argument"), f"command {c['name']}: argument min {arg['min']} is greater than max {arg['max']}")
                argument = CommandArgument(name=arg["name"], min=arg["min"], max=arg["max"], title=arg.get("title", ""))
            effect = self._effect(c, path, by_selector)
            top = value + (argument.max if argument else 0)
            if not reg.type.raw_min <= value <= reg.type.raw_max or not reg.type.raw_min <= top <= reg.type.raw_max:
                self.problem((*path, "value"), f"command {c['name']}: value {value} does not fit register {reg.name} ({reg.type.value})")
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
            self.problem((*path, "effect"), f"command {c['name']}: a clear effect names the register it clears")
        return CommandEffect(kind=spec["kind"], register=target, value=spec.get("value", 0), after_read=spec.get("after_read"))

    def _faults(self, specs: list[dict[str, Any]]) -> tuple[Fault, ...]:
        faults = []
        names: set[str] = set()
        codes: set[str] = set()
        for i, f in enumerate(specs):
            path: Path = ("faults", i)
            if f["name"] in names:
                self.problem((*path, "name"), f"duplicate fault name {f['name']!r}")
            if f["code"] in codes:
                self.problem((*path, "code"), f"duplicate fault code {f['code']!r}")
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
                self.problem((*path, "id"), f"duplicate erratum id {e['id']!r}")
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
                self.problem((*path, "id"), f"duplicate example id {x['id']!r}")
            ids[x["id"]] = x["direction"]
        for i, x in enumerate(specs):
            path = ("examples", i)
            try:
                frame = parse_hex(x["frame"])
                corrected = parse_hex(x["corrected_frame"]) if "corrected_frame" in x else None
            except FrameError as exc:
                self.problem((*path, "frame"), f"example {x['id']}: {exc}")
                continue
            erratum = x.get("erratum")
            if erratum is not None and erratum not in erratum_ids:
                self.problem((*path, "erratum"), f"example {x['id']}: unknown erratum {erratum!r}")
            if len(frame) < 4:
                self.problem((*path, "frame"), f"example {x['id']}: a frame has at least 4 bytes")
            elif not crc_ok(frame) and erratum is None:
                self.problem(
                    (*path, "frame"),
                    f"example {x['id']}: CRC {to_hex(frame[-2:])} does not match the frame (expected {to_hex(crc_bytes(frame[:-2]))}); fix the transcription or declare an erratum",
                )
            if corrected is not None:
                if erratum is None:
                    self.problem(
                        (*path, "corrected_frame"), f"example {x['id']}: corrected_frame needs an erratum explaining the correction"
                    )
                if not crc_ok(corrected):
                    self.problem(
                        (*path, "corrected_frame"),
                        f"example {x['id']}: the corrected frame's CRC is wrong (expected {to_hex(crc_bytes(corrected[:-2]))})",
                    )
            request = x.get("request")
            if request is not None:
                if x["direction"] != "response":
                    self.problem((*path, "request"), f"example {x['id']}: only a response names the request it answers")
                elif request not in ids:
                    self.problem((*path, "request"), f"example {x['id']}: unknown request example {request!r}")
                elif ids[request] != "request":
                    self.problem((*path, "request"), f"example {x['id']}: {request!r} is a response, not a request example")
            values = []
            for j, v in enumerate(x.get("values", [])):
                reg = self._ref(v["register"], by_selector, (*path, "values", j, "register"), f"example {x['id']}")
                if reg is None:
                    continue
                raw = v.get("raw")
                words = tuple(raw) if isinstance(raw, list) else None
                if words is not None and len(words) > reg.words:
                    self.problem(
                        (*path, "values", j, "raw"), f"example {x['id']}: {len(words)} words for {reg.name}, which has {reg.words}"
                    )
                values.append(ExampleValue(register=reg, raw=raw if isinstance(raw, int) else None, words=words, value=v.get("value")))
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
    return replace(reg, errata=errata) if errata else reg
