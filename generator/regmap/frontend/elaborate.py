"""The elaboration stage: groups, registers, arrays and enums into model objects, checked as they are built."""

from __future__ import annotations

import re
import string
from typing import Any

from regmap.core.text import article
from regmap.frontend.arrays import elaborate_array, elaborate_bitfields
from regmap.frontend.stages import Elaborated, MapSource, Problems
from regmap.frontend.timestamps import timestamp_facts
from regmap.frontend.values import (
    _FORMAT_SPEC,
    ACCESSES,
    BYTE_ORDERS,
    DATA_TYPES,
    POLL_CLASSES,
    WORD_ORDERS,
    _ParamRule,
    _scale,
    _source,
    na_markers,
)
from regmap.frontend.yamlsource import Path
from regmap.model import (
    ArrayDef,
    ArrayRef,
    ByteOrder,
    DataType,
    EnumMember,
    EnumType,
    FirmwareGate,
    Group,
    Register,
    WordOrder,
)
from regmap_runtime.spaces import DEFAULT_SPACE, SPACES, Space
from regmap_runtime.spec import na_marks, parse_version

GROUP_KEYS = ("space", "firmware", "poll", "variants")  # a group's own keys that its registers inherit
# The keys a type refuses: (key, whether the type refuses it, what the key needs), in the order problems are reported.
_NEEDS = (
    ("scale", lambda t: not t.numeric, "a number"),
    ("offset", lambda t: not t.numeric, "a number"),
    ("unit", lambda t: t.is_bool, "a number or text"),
    ("bitfields", lambda t: t.kind != "int", "an integer"),
    ("enum", lambda t: t.kind not in ("int", "float"), "a number"),
    ("byte_order", lambda t: not t.info.has_byte_order, "a value in register words"),
    ("encoding", lambda t: not t.is_string, "a string"),
    ("padding", lambda t: not t.is_string, "a string"),
    ("min", lambda t: not t.numeric, "a number"),
    ("max", lambda t: not t.numeric, "a number"),
    ("na", lambda t: not t.numeric, "a number"),
)


def elaborate(source: MapSource) -> Elaborated:
    """The map's enums, groups, registers and arrays as model objects, each checked on its own."""
    return _Elaboration(source).run()


class _Elaboration:
    """One walk over the map's declarations; what refers to what is the cross-reference stage's."""

    def __init__(self, source: MapSource) -> None:
        self.raw = source.raw
        self.positions = source.positions
        self.source = source
        self.problems = Problems(source)
        self.enums: dict[str, EnumType] = {}
        self.rules: list[_ParamRule] = []
        self.registers: list[Register] = []
        self.register_paths: list[Path] = []  # where each of self.registers is declared, in step with it
        self.defaults_keys: dict[Path, set[str]] = {}  # _defaults_keys by group path

    def run(self) -> Elaborated:
        raw = self.raw
        self._param_rules(raw.get("param_ids", []))
        self._enums(raw.get("enums", {}))
        names = [v["name"] for v in raw["device"].get("variants", [])]
        for i, name in enumerate(names):
            if name in names[:i]:
                self.problems.add(("device", "variants", i, "name"), f"variant {name!r} is declared twice")
        word_order = WordOrder(raw["transport"]["word_order"])
        groups = [self._group(g, ("groups", i), word_order) for i, g in enumerate(raw["groups"])]
        return Elaborated(
            source=self.source,
            enums=self.enums,
            groups=tuple(groups),
            registers=tuple(self.registers),
            register_paths=tuple(self.register_paths),
            problems=self.problems.found(),
        )

    # -- parameter-id rules ----------------------------------------------------------------

    def _param_rules(self, rules: list[dict[str, Any]]) -> None:
        for i, rule in enumerate(rules):
            path: Path = ("param_ids", i)
            try:
                regex = re.compile(rule["regex"])
            except re.error as exc:
                self.problems.add((*path, "regex"), f"invalid regular expression: {exc}")
                continue
            if "index" not in regex.groupindex:
                self.problems.add((*path, "regex"), "the regex needs a named group `index`")
                continue
            fields = set()
            specs = set()
            try:
                for _, field_name, spec, conversion in string.Formatter().parse(rule["format"]):
                    if field_name is not None:
                        fields.add(field_name)
                        specs.add(f"{'!' + conversion if conversion else ''}{':' + spec if spec else ''}")
            except ValueError as exc:
                self.problems.add((*path, "format"), f"invalid format pattern: {exc}")
                continue
            bad_field = next((f for f in sorted(fields) if f not in ("group", "index")), None)
            if bad_field is not None:
                self.problems.add((*path, "format"), f"format field {{{bad_field}}} is not allowed; use only {{group}} and {{index}}")
                continue
            if "index" not in fields:
                self.problems.add((*path, "format"), "the format must use the field {index}")
                continue
            bad_spec = next((spec for spec in sorted(specs) if not _FORMAT_SPEC.match(spec)), None)
            if bad_spec is not None:
                # Only a width and a base: anything else could pad a parameter id to gigabytes.
                self.problems.add(
                    (*path, "format"),
                    f"format spec {bad_spec!r} is not supported; use a width of at most 9 and d, x or X, as in {{index:02d}}",
                )
                continue
            try:
                rule["format"].format(group=0, index=0)
            except (ValueError, KeyError, IndexError) as exc:
                self.problems.add((*path, "format"), f"invalid format pattern: {exc}")
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
                    self.problems.add((*vpath, "name"), f"enum {enum_name}: duplicate member name {v['name']!r}")
                if v["value"] in seen_values:
                    self.problems.add(
                        (*vpath, "value"), f"enum {enum_name}: value {v['value']} is already used by {seen_values[v['value']]!r}"
                    )
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
                        access=ACCESSES[v.get("access", "rw")],
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
            self.problems.add(
                path, f"{owner}: unknown enum {name!r}" + (f" (known: {', '.join(sorted(self.enums))})" if self.enums else "")
            )
        return found

    # -- groups, registers, arrays -----------------------------------------------------------

    def _group(self, g: dict[str, Any], path: Path, word_order: WordOrder) -> Group:
        defaults = {key: g[key] for key in GROUP_KEYS if key in g} | dict(g.get("defaults", {}))
        if "source" not in defaults and "source" in g:
            defaults["source"] = g["source"]
        registers: list[Register] = []
        arrays: list[ArrayDef] = []
        for i, entry in enumerate(g["registers"]):
            epath: Path = (*path, "registers", i)
            if "array" in entry:
                array, expanded = elaborate_array(self, entry, epath, defaults, g["id"], word_order)
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
        space = SPACES[r.get("space", DEFAULT_SPACE)]
        dtype = DATA_TYPES[r.get("type", "bool" if space.bits else "u16")]
        self._check_type_in_space(r, path, name, dtype, space)
        words = self._words(r, path, name, dtype)
        if address + words - 1 > 0xFFFF:
            self.problems.add((*path, "address"), f"{name}: a {words}-word register at 0x{address:04X} runs past address 0xFFFF")
        paired = bool(r.get("paired", False))
        if paired and (dtype.words != 1 or not dtype.numeric or dtype.is_float):
            self.problems.add(
                (*path, "paired"),
                f"{name}: `paired` describes a 16-bit value in the low word of a 32-bit pair; type {dtype.value} is not a 16-bit integer",
            )
        if paired and address == 0:
            self.problems.add((*path, "address"), f"{name}: a paired register needs its high word at address-1, but the address is 0")
        if "word_order" in r and not dtype.wide and "word_order" not in self._defaults_keys(path):
            self.problems.add((*path, "word_order"), f"{name}: word_order applies only to values wider than 16 bits; type is {dtype.value}")
        order = WORD_ORDERS[r["word_order"]] if "word_order" in r and dtype.wide else word_order
        byte_order = BYTE_ORDERS[r.get("byte_order", self.raw["transport"].get("byte_order", "high_first"))]
        if not dtype.info.has_byte_order:
            byte_order = ByteOrder.HIGH_FIRST
        enum_type = self._enum_ref(r.get("enum"), (*path, "enum"), name)
        bitfields = elaborate_bitfields(self, r.get("bitfields", []), (*path, "bitfields"), dtype, name)
        low, high = r.get("min"), r.get("max")
        problem = lambda key, message: self.problems.add((*path, key), f"{name}: {message}")  # noqa: E731
        zone, default = timestamp_facts(r, dtype, self._defaults_keys(path), problem)
        self._check_values(path, name, dtype, low, high, default, r)
        if enum_type is not None:
            self._check_members_fit(enum_type, dtype, path, name)
        if not r.get("source"):
            self.problems.add(path, f"{name}: no source; give the manual section it was read from (on the register or in the group)")
        access = ACCESSES[r.get("access", "rw" if space.writable else "r")]
        if access.writable and not space.writable:
            self.problems.add(
                (*path, "access"),
                f"{name}: {space.title} are read-only (function 0x{space.read:02X}); access {access.value} is not possible",
            )
        if isinstance(default, bool) and dtype.is_bool:
            default = int(default)
        na, na_nan = self._na(r, path, name, dtype, bool(bitfields), default)
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
            offset=_scale(r.get("offset", 0)),
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
            space=space.name,
            byte_order=byte_order,
            string_words=words if dtype.is_string else 0,
            encoding=r.get("encoding", "ascii"),
            padding=r.get("padding", "nul"),
            firmware=self._firmware_gate(r.get("firmware"), (*path, "firmware"), name),
            poll=POLL_CLASSES[r.get("poll", "normal")],
            trigger=bool(r.get("trigger", False)),
            na=na,
            na_nan=na_nan,
            variants=self._variants(r.get("variants", ()), (*path, "variants"), name),
            zone=zone,
            scale_from=self._scale_from(r, path, name, dtype),
            pos=self.positions.locate(path),
        )

    def _check_type_in_space(self, r: dict[str, Any], path: Path, name: str, dtype: DataType, space: Space) -> None:
        """A coil or discrete input is one bit (bool) and nothing else; every other type lives in register words."""
        if space.bits and not dtype.is_bool:
            self.problems.add(
                (*path, "type"), f"{name}: a {space.name.replace('_', ' ')} is one bit, so its type is bool, not {dtype.value}"
            )
        if dtype.is_bool and not space.bits:
            self.problems.add(
                (*path, "type"),
                f"{name}: bool is the type of coils and discrete inputs; {space.title} hold numbers (a u16 with a bitfield for flags, or `space: coil`)",
            )
        inherited = self._defaults_keys(path)
        for key, refused, needs in _NEEDS:
            if key in r and r[key] is not None and key not in inherited and refused(dtype):
                what = f"a {space.name.replace('_', ' ')}" if space.bits else article(f"{dtype.value} register")
                self.problems.add((*path, key), f"{name}: `{key}` needs {needs}; {what} has none")

    def _scale_from(self, r: dict[str, Any], path: Path, name: str, dtype: DataType) -> str | None:
        """`scale_from` (value = raw x 10^sf) scales a plain integer: no scale or offset of its own, no enum or flags;
        the sf register itself is checked against the rest of the map (crossrefs)."""
        sf: str | None = r.get("scale_from")
        if sf is None:
            return None
        if dtype.kind != "int" or dtype.is_timestamp:
            self.problems.add((*path, "scale_from"), f"{name}: `scale_from` scales an integer register (u16..s64), not {dtype.value}")
        for key, plain in (("scale", 1), ("offset", 0)):
            if key in r and r[key] != plain:
                self.problems.add((*path, key), f"{name}: a register with `scale_from` has no {key} of its own (value = raw x 10^{sf})")
        for key in ("enum", "bitfields"):
            if r.get(key):
                self.problems.add((*path, key), f"{name}: a register with `scale_from` is a number; it has no {key}")
        return sf

    def _words(self, r: dict[str, Any], path: Path, name: str, dtype: DataType) -> int:
        if dtype.is_string:
            if "words" not in r:
                self.problems.add(path, f"{name}: a string register needs `words` (its length in registers, two characters each)")
                return 1
            words: int = r["words"]
            return words
        if "words" in r and r["words"] != dtype.words:
            self.problems.add(
                (*path, "words"),
                f"{name}: words {r['words']} does not match type {dtype.value} ({dtype.words} word{'s' if dtype.words > 1 else ''})",
            )
        return dtype.words

    def _check_values(self, path: Path, name: str, dtype: DataType, low: Any, high: Any, default: Any, r: dict[str, Any]) -> None:
        """min/max/default are raw values of the register's type: integers, floats, text or true/false."""
        for key, value in (("min", low), ("max", high), ("default", default)):
            if value is None:
                continue
            if dtype.is_string:
                if key == "default":
                    self._check_string_default(path, name, value, r)
                continue
            if dtype.is_bool:
                if key == "default" and not isinstance(value, bool):
                    self.problems.add((*path, key), f"{name}: the default of a bit is true or false, not {value!r}")
                continue
            if isinstance(value, bool | str) or (dtype.kind == "int" and not isinstance(value, int)):
                kind = "an integer" if dtype.kind == "int" else "a number"
                self.problems.add((*path, key), f"{name}: {key} of a {dtype.value} register is {kind} (a raw value), not {value!r}")
                continue
            if not dtype.raw_min <= value <= dtype.raw_max:
                self.problems.add(
                    (*path, key), f"{name}: {key} {value} is outside the range of {dtype.value} ({dtype.raw_min:g}..{dtype.raw_max:g})"
                )
        if not dtype.numeric or any(isinstance(v, bool | str) for v in (low, high, default)):
            return
        if low is not None and high is not None and low > high:
            self.problems.add((*path, "min"), f"{name}: min {low} is greater than max {high}")
        if default is not None:
            if (low is not None and default < low) or (high is not None and default > high):
                self.problems.add((*path, "default"), f"{name}: default {default} is outside min..max ({low}..{high})")
            enum_type = self.enums.get(r.get("enum", ""))
            if enum_type is not None and enum_type.by_value(default) is None:
                self.problems.add((*path, "default"), f"{name}: default {default} is not a value of enum {enum_type.name}")

    def _variants(self, names: Any, path: Path, name: str) -> tuple[str, ...]:
        """The device variants that have the register: each one `device.variants` declares."""
        if not names:
            return ()
        known = [v["name"] for v in self.raw["device"].get("variants", [])]
        for i, variant in enumerate(names):
            if variant not in known:
                listed = f"device.variants declares {', '.join(known)}" if known else "device.variants declares none"
                self.problems.add((*path, i), f"{name}: unknown variant {variant!r} ({listed})")
        return tuple(names)

    def _check_members_fit(self, enum_type: EnumType, dtype: DataType, path: Path, name: str) -> None:
        """Each member of an integer register's enum fits its type; of a float's (a setting coded as a float: a baud
        code 0-4 as an f32), each is a value the float holds exactly."""
        for member in enum_type.members:
            inside = dtype.raw_min <= member.value <= dtype.raw_max
            if dtype.is_float and (not inside or dtype.info.from_words(dtype.info.to_words(member.value)) != member.value):
                self.problems.add(
                    (*path, "enum"), f"{name}: enum {enum_type.name} member {member.name} = {member.value} is no exact {dtype.value} value"
                )
            elif dtype.kind == "int" and not inside:
                self.problems.add(
                    (*path, "enum"), f"{name}: enum {enum_type.name} member {member.name} = {member.value} does not fit {dtype.value}"
                )

    def _na(
        self, r: dict[str, Any], path: Path, name: str, dtype: DataType, bitfields: bool, default: Any
    ) -> tuple[tuple[int | float, ...], bool]:
        """The "not available" markers as raw values of the register's type (`values.na_markers`); never its default."""
        if not dtype.numeric:
            return (), False  # reported by _check_type_in_space
        na, nan = na_markers(r.get("na") or (), dtype, lambda i, message: self.problems.add((*path, "na", i), f"{name}: {message}"))
        if default is not None and na_marks(na, nan, default):
            self.problems.add((*path, "default"), f"{name}: default {default} is the 'not available' marker (na); a default is a value")
        if bitfields and (na or nan):
            self.problems.add((*path, "na"), f"{name}: `na` marks a whole value as not available; a bitfield register has no one value")
        return na, nan

    def _check_string_default(self, path: Path, name: str, value: Any, r: dict[str, Any]) -> None:
        if not isinstance(value, str):
            self.problems.add((*path, "default"), f"{name}: the default of a string register is text, not {value!r}")
            return
        encoding = r.get("encoding", "ascii")
        try:
            size = len(value.encode(encoding))
        except UnicodeEncodeError:
            self.problems.add((*path, "default"), f"{name}: the default {value!r} cannot be written in {encoding}")
            return
        if isinstance(r.get("words"), int) and size > 2 * r["words"]:
            self.problems.add(
                (*path, "default"), f"{name}: the default {value!r} is {size} bytes; {r['words']} words hold {2 * r['words']}"
            )

    def _firmware_gate(self, spec: dict[str, str] | None, path: Path, name: str) -> FirmwareGate | None:
        if spec is None:
            return None
        gate = FirmwareGate(first=spec.get("from"), until=spec.get("until"))
        if gate.first is not None and gate.until is not None and parse_version(gate.first) >= parse_version(gate.until):
            self.problems.add(
                (*path, "until"), f"{name}: firmware from {gate.first} until {gate.until} is empty; `until` is the first version without it"
            )
        return gate

    def _defaults_keys(self, path: Path) -> set[str]:
        """The keys the register at `path` takes from its group's `defaults` (asked several times of each register)."""
        group_path = path[:2]
        keys = self.defaults_keys.get(group_path)
        if keys is None:
            group = self.raw["groups"][group_path[1]] if len(group_path) == 2 else {}
            keys = self.defaults_keys[group_path] = set(group.get("defaults", {}))
        return keys

    def _check_param(self, reg: Register, path: Path) -> None:
        if reg.param is None:
            return
        try:
            expected = self._rule_address(reg.param)
        except ValueError as exc:
            self.problems.add((*path, "param"), f"{reg.name}: parameter {reg.param} matches a param_ids regex, but {exc}")
            return
        if expected is not None and expected != reg.address:
            self.problems.add(
                (*path, "address"),
                f"{reg.name}: parameter {reg.param} is at 0x{expected:04X} by the param_ids rule, but the address is 0x{reg.address:04X}",
            )
