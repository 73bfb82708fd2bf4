"""The comparison of two `Device` models; docs/diff.md gives the matching and classification rules."""

from __future__ import annotations

import json
from collections.abc import Callable
from typing import Any

from regmap.core.contract import na_json
from regmap.core.text import na_list
from regmap.model import ArrayDef, ArrayMember, Command, Device, EnumType, FirmwareGate, FirmwareRegister, Register
from regmap.render import hex4
from regmap.tools.diff.documentation import documentation_changes
from regmap.tools.diff.kinds import _KIND_ORDER, MAJOR, MINOR, PATCH, Change, Changes, Report
from regmap.tools.diff.match import _match
from regmap.tools.diff.text import (
    ACCESS,
    _array_summary,
    _effect,
    _fields,
    _fraction,
    _gate,
    _indices,
    _layout,
    _natural,
    _plain,
    _range,
    _register_summary,
    _show,
    _val,
)
from regmap.tools.diff.transport import transport_changes
from regmap_runtime.spec import parse_version

ELEMENT = "\0"  # stands for an array index in subjects until identical element changes are merged


class _Diff:
    def __init__(self, old: Device, new: Device) -> None:
        self.old, self.new = old, new
        self.changes = Changes()
        self.enum_names: dict[str, str] = {}  # old enum name -> new
        self.register_names: dict[str, str] = {}  # old register name -> new (elements included)

    def run(self) -> tuple[Change, ...]:
        # Enums and registers first: later steps compare references through their pairings.
        self._enums()
        self._registers()
        self._arrays()
        self._device()
        self.changes += transport_changes(self.old.transport, self.new.transport, self._register_name)
        self._commands()
        self._faults()
        self.changes += documentation_changes(self.old, self.new, self._register_name)
        return tuple(sorted(self.changes, key=lambda c: (not c.breaking, _KIND_ORDER[c.kind], _natural(c.subject), c.before)))

    def _enum_name(self, e: EnumType | None) -> str | None:
        return None if e is None else self.enum_names.get(e.name, f"(removed) {e.name}")

    def _register_name(self, name: str) -> str:
        return self.register_names.get(name, name)

    # -- device

    def _device(self) -> None:
        o, n = self.old.info, self.new.info
        if o.id != n.id:
            self.changes.add("device_id_changed", "id", MAJOR, o.id, n.id, o.id, n.id)
        for f in (
            "vendor",
            "vendor_zh",
            "model",
            "description",
            "manual_title",
            "manual_version",
            "manual_file",
            "manual_language",
            "firmware",
        ):
            a, b = getattr(o, f), getattr(n, f)
            if a != b:
                self.changes.add("device_changed", f, PATCH, _show(a), _show(b), a, b)
        a_fw, b_fw = _firmware_register(o.firmware_register, self._register_name), _firmware_register(n.firmware_register, str)
        if a_fw != b_fw:
            bump = MINOR if a_fw is None else MAJOR
            note = "" if a_fw is None else "removed" if b_fw is None else "an old client reads the version another way"
            self.changes.add(
                "firmware_register_changed", "firmware_register", bump, _firmware_text(a_fw), _firmware_text(b_fw), a_fw, b_fw, note
            )

    def _enums(self) -> None:
        def members(e: EnumType) -> frozenset[tuple[int, str]]:
            return frozenset((m.value, m.name) for m in e.members)

        pairs, removed, added = _match(self.old.enums, self.new.enums, [lambda e: e.name, members])
        users_old, users_new = _enum_users(self.old), _enum_users(self.new)
        for e in removed:
            self.changes.add("enum_removed", e.name, MAJOR, f"{len(e.members)} values", "", e.name, None, users_old.get(e.name, ""))
        for e in added:
            self.changes.add("enum_added", e.name, MINOR, "", f"{len(e.members)} values", None, e.name, users_new.get(e.name, ""))
        for o, n, _ in pairs:
            self.enum_names[o.name] = n.name
            if o.name != n.name:
                self.changes.add("enum_renamed", o.name, MAJOR, o.name, n.name, o.name, n.name, users_new.get(n.name, ""))
            self.changes.doc("enum_doc_changed", n.name, o, n, ("title", "title_zh", "description", "source"))
            self._enum_members(o, n, users_old.get(o.name, ""), users_new.get(n.name, ""))

    def _enum_members(self, o: EnumType, n: EnumType, used_old: str, used_new: str) -> None:
        pairs, removed, added = _match(o.members, n.members, [lambda m: m.name, lambda m: m.value])
        for m in removed:
            self.changes.add("enum_value_removed", f"{n.name}.{m.name}", MAJOR, _val(m.value), "", m.value, None, used_old)
        for m in added:
            self.changes.add("enum_value_added", f"{n.name}.{m.name}", MINOR, "", _val(m.value), None, m.value, used_new)
        for a, b, _ in pairs:
            if a.value != b.value:
                self.changes.add(
                    "enum_value_renumbered", f"{n.name}.{b.name}", MAJOR, _val(a.value), _val(b.value), a.value, b.value, used_new
                )
            if a.name != b.name:
                self.changes.add("enum_value_renamed", f"{n.name}.{a.name}", MAJOR, a.name, b.name, a.name, b.name, used_new)
            self.changes.doc("enum_doc_changed", f"{n.name}.{b.name}", a, b, _MEMBER_DOC)

    # -- registers outside arrays

    def _registers(self) -> None:
        old = [r for r in self.old.registers if r.array is None]
        new = [r for r in self.new.registers if r.array is None]
        pairs, removed, added = _match(
            old,
            new,
            [lambda r: r.name, lambda r: r.param, lambda r: (r.space, r.address)],
            accept=lambda a, b: not (a.param and b.param and a.param != b.param),
        )
        for r in removed:
            self.changes.add("register_removed", r.name, MAJOR, _register_summary(r), "", r.name, None)
        for r in added:
            self.changes.add("register_added", r.name, MINOR, "", _register_summary(r), None, r.name)
        for o, n, how in pairs:
            self.register_names[o.name] = n.name
            if o.name != n.name:
                note = ("matched by parameter id" if how == 1 else "matched by address") if how else ""
                self.changes.add("register_renamed", o.name, MAJOR, o.name, n.name, o.name, n.name, note)
            if o.address != n.address:
                params = o.param != n.param
                before = hex4(o.address) + (f" ({o.param})" if params and o.param else "")
                after = hex4(n.address) + (f" ({n.param})" if params and n.param else "")
                self.changes.add("register_moved", n.name, MAJOR, before, after, o.address, n.address)
            elif o.param != n.param:
                self.changes.add("register_param_changed", n.name, PATCH, _show(o.param), _show(n.param), o.param, n.param)
            self.changes.extend(self._register_attributes(o, n, n.name))

    def _register_attributes(self, o: Register, n: Register, subject: str) -> list[Change]:
        """Changes of one register's type, access, unit ..., bitfields and text; name and address are the caller's."""
        out = Changes()
        add = out.add
        if o.space != n.space:
            add("register_space_changed", subject, MAJOR, o.space, n.space, o.space, n.space, _codes(o, n))
        if o.type != n.type:
            if o.type.kind != n.type.kind:
                note = f"{o.type.kind} -> {n.type.kind}"
            elif o.words != n.words:
                note = f"{o.words} -> {n.words} words"
            elif o.type.is_timestamp or n.type.is_timestamp:
                note = "a read gives a datetime" if n.type.is_timestamp else "a read gives a number, not a datetime"
            else:
                note = "signedness" if o.signed != n.signed else ""
            add("register_type_changed", subject, MAJOR, o.type.value, n.type.value, o.type, n.type, note)
        elif o.type.is_string:
            out += _string_changes(o, n, subject)
        # A register that follows the device's word (byte) order is reported once, as the transport change.
        device_orders = self.old.transport.word_order, self.new.transport.word_order
        follows = device_orders[0] != device_orders[1] and (o.word_order, n.word_order) == device_orders
        if o.wide and n.wide and o.word_order != n.word_order and not follows:
            add("register_word_order_changed", subject, MAJOR, o.word_order.value, n.word_order.value, o.word_order, n.word_order)
        device_bytes = self.old.transport.byte_order, self.new.transport.byte_order
        follows = device_bytes[0] != device_bytes[1] and (o.byte_order, n.byte_order) == device_bytes
        has_bytes = o.type.info.has_byte_order and n.type.info.has_byte_order
        if has_bytes and o.byte_order != n.byte_order and not follows:
            add("register_byte_order_changed", subject, MAJOR, o.byte_order.value, n.byte_order.value, o.byte_order, n.byte_order)
        if o.paired != n.paired:
            add(
                "register_paired_changed",
                subject,
                MAJOR,
                "paired" if o.paired else "single",
                "paired" if n.paired else "single",
                o.paired,
                n.paired,
            )
        if o.access != n.access:
            lost = (o.access.readable and not n.access.readable) or (o.access.writable and not n.access.writable)
            add("register_access_changed", subject, MAJOR if lost else MINOR, ACCESS[o.access], ACCESS[n.access], o.access, n.access)
        if o.unit != n.unit:
            add("register_unit_changed", subject, PATCH if o.unit is None else MAJOR, _show(o.unit), _show(n.unit), o.unit, n.unit)
        if (o.scale, o.scale_from) != (n.scale, n.scale_from):  # a scale read from the device (scale_from) is 10^<its register>
            old_scale, new_scale = (f"10^{r.scale_from}" if r.scale_from else r.scale for r in (o, n))
            old_text, new_text = (s if isinstance(s, str) else _fraction(s) for s in (old_scale, new_scale))
            add("register_scale_changed", subject, MAJOR, old_text, new_text, old_scale, new_scale)
        if o.offset != n.offset:
            add("register_offset_changed", subject, MAJOR, _fraction(o.offset), _fraction(n.offset), o.offset, n.offset)
        if (o.min, o.max) != (n.min, n.max):
            narrowed = n.raw_min > o.raw_min or n.raw_max < o.raw_max
            widened = n.raw_min < o.raw_min or n.raw_max > o.raw_max
            bump, note = (MAJOR, "narrowed") if narrowed else (MINOR, "widened") if widened else (PATCH, "same effective range")
            add("register_range_changed", subject, bump, _range(o.min, o.max), _range(n.min, n.max), [o.min, o.max], [n.min, n.max], note)
        if o.default != n.default:
            add("register_default_changed", subject, PATCH, _show(o.default), _show(n.default), o.default, n.default)
        a_enum, b_enum = self._enum_name(o.enum), n.enum.name if n.enum else None
        if a_enum != b_enum:
            add(
                "register_enum_changed",
                subject,
                MAJOR,
                _show(o.enum.name if o.enum else None),
                _show(b_enum),
                o.enum.name if o.enum else None,
                b_enum,
            )
        if o.firmware != n.firmware:
            taken, given = _gate_change(o.firmware, n.firmware)
            note = "; ".join(p for p in (taken, given) if p)
            add(
                "register_firmware_changed",
                subject,
                MAJOR if taken else MINOR,
                _gate(o.firmware),
                _gate(n.firmware),
                _gate_json(o.firmware),
                _gate_json(n.firmware),
                note,
            )
        if (o.na, o.na_nan) != (n.na, n.na_nan):
            add("register_na_changed", subject, MAJOR, _show(na_list(o) or None), _show(na_list(n) or None), na_json(o), na_json(n))
        if o.type == n.type and o.zone != n.zone:
            add("register_zone_changed", subject, MAJOR, _show(o.zone), _show(n.zone), o.zone, n.zone)
        if o.poll != n.poll:
            add("register_poll_changed", subject, PATCH, o.poll.value, n.poll.value, o.poll, n.poll)
        out += self._bitfields(o, n, subject)
        out.doc("register_doc_changed", subject, o, n, _REGISTER_DOC)
        return out

    def _bitfields(self, o: Register, n: Register, subject: str) -> list[Change]:
        out = Changes()
        add = out.add
        pairs, removed, added = _match(o.bitfields, n.bitfields, [lambda b: b.name, lambda b: (b.lsb, b.msb)])
        for b in removed:
            add("bitfield_removed", f"{subject}.{b.name}", MAJOR, f"bits {b.bits_text}", "", b.bits_text, None)
        for b in added:
            first = not o.bitfields
            note = "the register had no bitfields: its value type changes" if first else ""
            add("bitfield_added", f"{subject}.{b.name}", MAJOR if first else MINOR, "", f"bits {b.bits_text}", None, b.bits_text, note)
        for a, b, _ in pairs:
            if a.name != b.name:
                add("bitfield_renamed", f"{subject}.{a.name}", MAJOR, a.name, b.name, a.name, b.name)
            if a.width != b.width:
                add(
                    "bitfield_resized", f"{subject}.{b.name}", MAJOR, f"bits {a.bits_text}", f"bits {b.bits_text}", a.bits_text, b.bits_text
                )
            elif a.lsb != b.lsb:
                add("bitfield_moved", f"{subject}.{b.name}", MAJOR, f"bits {a.bits_text}", f"bits {b.bits_text}", a.bits_text, b.bits_text)
            if self._enum_name(a.enum) != (b.enum.name if b.enum else None):
                a_name, b_name = (a.enum.name if a.enum else None), (b.enum.name if b.enum else None)
                add("bitfield_enum_changed", f"{subject}.{b.name}", MAJOR, _show(a_name), _show(b_name), a_name, b_name)
            out.doc("bitfield_doc_changed", f"{subject}.{b.name}", a, b, ("title", "title_zh", "description"))
        return out

    # -- arrays

    def _arrays(self) -> None:
        old_space, new_space = _array_spaces(self.old), _array_spaces(self.new)
        pairs, removed, added = _match(
            [(a, old_space[a.name]) for a in self.old.arrays],
            [(a, new_space[a.name]) for a in self.new.arrays],
            [lambda p: p[0].name, lambda p: (p[1], p[0].base, p[0].stride)],
        )
        self._array_pairs([a for a, _ in removed], [a for a, _ in added], [(o, n) for (o, _), (n, _), _ in pairs])

    def _array_pairs(self, removed: list[ArrayDef], added: list[ArrayDef], pairs: list[tuple[ArrayDef, ArrayDef]]) -> None:
        for a in removed:
            self.changes.add("array_removed", a.name, MAJOR, _array_summary(a), "", a.name, None)
        for a in added:
            self.changes.add("array_added", a.name, MINOR, "", _array_summary(a), None, a.name)
        old_elements = _elements(self.old)
        new_elements = _elements(self.new)
        for o, n in pairs:
            if o.name != n.name:
                self.changes.add("array_renamed", o.name, MAJOR, o.name, n.name, o.name, n.name)
            layout = [(f, getattr(o, f), getattr(n, f)) for f in ("base", "stride", "index_base") if getattr(o, f) != getattr(n, f)]
            if layout:
                self.changes.add(
                    "array_layout_changed",
                    n.name,
                    MAJOR,
                    ", ".join(_layout(f, a) for f, a, _ in layout),
                    ", ".join(_layout(f, b) for f, _, b in layout),
                    {f: a for f, a, _ in layout},
                    {f: b for f, _, b in layout},
                    "every element moves",
                )
            if o.count != n.count:
                fewer = n.count < o.count
                self.changes.add(
                    "array_count_changed",
                    n.name,
                    MAJOR if fewer else MINOR,
                    str(o.count),
                    str(n.count),
                    o.count,
                    n.count,
                    "fewer elements" if fewer else "more elements",
                )
            self.changes.doc(
                "array_doc_changed", n.name, o, n, ("title", "title_zh", "element_title", "description", "group", "source", "notes")
            )
            member_pairs, gone, new_members = _match(o.members, n.members, [lambda m: m.name, lambda m: m.offset])
            for m in gone:
                self.changes.add("array_member_removed", f"{n.name}.{m.name}", MAJOR, f"offset {m.offset}", "", m.name, None)
            for m in new_members:
                first = new_elements[(n.name, n.first_index, m.name)]
                self.changes.add(
                    "array_member_added", f"{n.name}.{m.name}", MINOR, "", f"offset {m.offset}, {_register_summary(first)}", None, m.name
                )
            common = range(max(o.first_index, n.first_index), min(o.last_index, n.last_index) + 1)
            for om, nm, _ in member_pairs:
                self._array_member(o, n, om, nm, common, old_elements, new_elements)

    def _array_member(
        self,
        o: ArrayDef,
        n: ArrayDef,
        om: ArrayMember,
        nm: ArrayMember,
        common: range,
        old_elements: dict[tuple[str, int, str], Register],
        new_elements: dict[tuple[str, int, str], Register],
    ) -> None:
        if om.name != nm.name:
            self.changes.add("array_member_renamed", f"{n.name}.{om.name}", MAJOR, om.name, nm.name, om.name, nm.name)
        if om.offset != nm.offset:
            self.changes.add(
                "array_layout_changed",
                f"{n.name}.{nm.name}",
                MAJOR,
                f"offset {om.offset}",
                f"offset {nm.offset}",
                om.offset,
                nm.offset,
                "every element moves",
            )
        # Element registers change together; one row per distinct change, naming the elements it covers.
        merged: dict[tuple[Any, ...], tuple[Change, list[int]]] = {}
        template = f"{n.name}[{ELEMENT}].{nm.name}"
        for i in common:
            a, b = old_elements[(o.name, i, om.name)], new_elements[(n.name, i, nm.name)]
            self.register_names[a.name] = b.name
            for c in self._register_attributes(a, b, template):
                key = (c.kind, c.subject, c.bump, c.before, c.after, c.note, json.dumps(c.old), json.dumps(c.new))
                merged.setdefault(key, (c, []))[1].append(i)
        for c, indices in merged.values():
            subject = c.subject.replace(ELEMENT, _indices(indices))
            self.changes.append(Change(c.kind, subject, c.bump, c.before, c.after, c.old, c.new, c.note, len(indices)))

    # -- commands and faults

    def _commands(self) -> None:
        def target(c: Command, old: bool) -> tuple[str, int]:
            return (self._register_name(c.register.name) if old else c.register.name, c.value)

        pairs, removed, added = _match(
            [(c, True) for c in self.old.commands],
            [(c, False) for c in self.new.commands],
            [lambda p: p[0].name, lambda p: target(*p)],
        )

        def what(c: Command) -> str:
            arg = f" + {c.argument.name} {c.argument.min}..{c.argument.max}" if c.argument else ""
            return f"{c.register.name} = {_val(c.value)}{arg}"

        for c, _ in removed:
            self.changes.add("command_removed", c.name, MAJOR, what(c), "", c.name, None)
        for c, _ in added:
            self.changes.add("command_added", c.name, MINOR, "", what(c), None, c.name)
        for (o, _), (n, _), _ in pairs:
            if o.name != n.name:
                self.changes.add("command_renamed", o.name, MAJOR, o.name, n.name, o.name, n.name)
            a_arg = None if o.argument is None else (o.argument.name, o.argument.min, o.argument.max)
            b_arg = None if n.argument is None else (n.argument.name, n.argument.min, n.argument.max)
            if target(o, True) != target(n, False) or a_arg != b_arg:
                self.changes.add(
                    "command_changed",
                    n.name,
                    MAJOR,
                    what(o),
                    what(n),
                    {"register": o.register.name, "value": o.value, "argument": a_arg},
                    {"register": n.register.name, "value": n.value, "argument": b_arg},
                )
            a_eff = (
                None
                if o.effect is None
                else (
                    o.effect.kind,
                    self._register_name(o.effect.register.name) if o.effect.register else None,
                    o.effect.value,
                    o.effect.after_read,
                )
            )
            b_eff = (
                None
                if n.effect is None
                else (n.effect.kind, n.effect.register.name if n.effect.register else None, n.effect.value, n.effect.after_read)
            )
            if a_eff != b_eff:
                self.changes.add("command_effect_changed", n.name, PATCH, _effect(a_eff), _effect(b_eff), a_eff, b_eff)
            self.changes.doc("command_doc_changed", n.name, o, n, ("title", "title_zh", "description", "source"))

    def _faults(self) -> None:
        pairs, removed, added = _match(self.old.faults, self.new.faults, [lambda f: f.name, lambda f: f.code])
        for f in removed:
            self.changes.add("fault_removed", f.name, MAJOR, f"{_plain(f.code)} ({f.kind})", "", f.name, None)
        for f in added:
            self.changes.add("fault_added", f.name, MINOR, "", f"{_plain(f.code)} ({f.kind})", None, f.name)
        for o, n, _ in pairs:
            fields = [
                (k, getattr(o, k), getattr(n, k)) for k in ("name", "code", "value", "kind", "resettable") if getattr(o, k) != getattr(n, k)
            ]
            if fields:
                bump = MAJOR if any(k in ("name", "code", "value") for k, _, _ in fields) else PATCH
                self.changes.add(
                    "fault_changed",
                    o.name,
                    bump,
                    *_fields(fields),
                    {k: a for k, a, _ in fields},
                    {k: b for k, _, b in fields},
                )
            self.changes.doc("fault_doc_changed", n.name, o, n, ("title", "title_zh", "description", "source"))


_REGISTER_DOC = ("title", "title_zh", "description", "range_text", "takes_effect", "settable", "modes", "group", "source", "notes")
_MEMBER_DOC = ("title", "title_zh", "symbol", "description", "source")


def _codes(o: Register, n: Register) -> str:
    """`read 0x03 -> 0x04`: what a client sends for it now."""
    return f"read 0x{o.space_info.read:02X} -> 0x{n.space_info.read:02X}"


def _string_changes(o: Register, n: Register, subject: str) -> Changes:
    """A string register's length, encoding or padding: one row listing what differs."""
    out = Changes()
    diffs = [(f, getattr(o, f), getattr(n, f)) for f in ("string_words", "encoding", "padding") if getattr(o, f) != getattr(n, f)]
    if diffs:
        before = "; ".join(f"{'words' if f == 'string_words' else f} {a}" for f, a, _ in diffs)
        after = "; ".join(f"{'words' if f == 'string_words' else f} {b}" for f, _, b in diffs)
        key = {"string_words": "words"}
        old = {key.get(f, f): a for f, a, _ in diffs}
        new = {key.get(f, f): b for f, _, b in diffs}
        out.add("register_string_changed", subject, MAJOR, before, after, old, new)
    return out


def _gate_change(o: FirmwareGate | None, n: FirmwareGate | None) -> tuple[str, str]:
    """What a gate change takes from and gives to firmware versions, as (lost, gained) notes. No gate
    admits every version; `from` is inclusive, `until` exclusive."""
    low, high = (float("-inf"),), (float("inf"),)

    def first(g: FirmwareGate | None) -> tuple[float, ...]:
        return low if g is None or g.first is None else tuple(map(float, parse_version(g.first)))

    def until(g: FirmwareGate | None) -> tuple[float, ...]:
        return high if g is None or g.until is None else tuple(map(float, parse_version(g.until)))

    lost, gained = [], []
    if first(n) > first(o):
        lost.append(f"firmware before {n.first if n else ''} loses it")
    elif first(n) < first(o):
        gained.append(f"firmware before {o.first if o else ''} gains it")
    if until(n) < until(o):
        lost.append(f"firmware {n.until if n else ''} and later loses it")
    elif until(n) > until(o):
        gained.append(f"firmware {o.until if o else ''} and later gains it")
    return ", ".join(lost), ", ".join(gained)


def _gate_json(gate: FirmwareGate | None) -> dict[str, str | None] | None:
    return None if gate is None else {"from": gate.first, "until": gate.until}


def _firmware_register(fw: FirmwareRegister | None, rename: Callable[[str], str]) -> dict[str, Any] | None:
    return None if fw is None else {"register": rename(fw.register.name), "format": fw.format, "decimals": fw.decimals}


def _firmware_text(fw: dict[str, Any] | None) -> str:
    if fw is None:
        return "none"
    decimals = f", {fw['decimals']} decimals" if fw["format"] == "decimal" and fw["decimals"] else ""
    return f"{fw['register']} ({fw['format']}{decimals})"


def _array_spaces(device: Device) -> dict[str, str]:
    """Array name -> the space of its elements (an array's members share its group's space)."""
    return {r.array.array: r.space for r in device.registers if r.array is not None}


def _elements(device: Device) -> dict[tuple[str, int, str], Register]:
    return {(r.array.array, r.array.index, r.array.member): r for r in device.registers if r.array is not None}


def _enum_users(device: Device, limit: int = 3) -> dict[str, str]:
    """enum name -> "used by a, b, c and 4 more" (array elements named once per member)."""
    users: dict[str, list[str]] = {}

    def use(e: EnumType | None, who: str) -> None:
        if e is not None and who not in users.setdefault(e.name, []):
            users[e.name].append(who)

    for r in device.registers:
        label = f"{r.array.array}[].{r.array.member}" if r.array else r.name
        use(r.enum, label)
        for b in r.bitfields:
            use(b.enum, f"{label}.{b.name}")
    out = {}
    for name, who in users.items():
        more = f" and {len(who) - limit} more" if len(who) > limit else ""
        out[name] = "used by " + ", ".join(who[:limit]) + more
    return out


def compare(old: Device, new: Device) -> Report:
    """Every difference between two maps, classified, breaking first."""
    return Report(old, new, _Diff(old, new).run())
