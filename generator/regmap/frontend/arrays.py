"""Bit fields and arrays of a map, elaborated into model objects for the elaboration stage."""

from __future__ import annotations

from typing import Any, Protocol

from regmap.frontend.copies import replaced
from regmap.frontend.stages import Problems
from regmap.frontend.values import DATA_TYPES, _bits, _source
from regmap.frontend.yamlsource import Path, Positions
from regmap.model import ArrayDef, ArrayMember, ArrayRef, Bitfield, DataType, EnumType, Register, WordOrder
from regmap_runtime.spaces import DEFAULT_SPACE, SPACES


class ElaborationHost(Protocol):
    """What the elaboration stage lends these functions: its problems, positions and register builder."""

    problems: Problems
    positions: Positions

    def _enum_ref(self, name: str | None, path: Path, owner: str) -> EnumType | None: ...

    def _rule_param(self, address: int) -> str | None: ...

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
    ) -> Register | None: ...


def elaborate_bitfields(host: ElaborationHost, specs: list[dict[str, Any]], path: Path, dtype: DataType, name: str) -> tuple[Bitfield, ...]:
    if dtype.kind != "int" or not specs:
        return ()  # another type's bitfields: reported by _check_type_in_space
    fields: list[Bitfield] = []
    used: dict[int, str] = {}
    names: set[str] = set()
    for i, spec in enumerate(specs):
        fpath: Path = (*path, i)
        lsb, msb = _bits(spec["bits"])
        if lsb > msb:
            host.problems.add((*fpath, "bits"), f"{name}.{spec['name']}: bit range {spec['bits']} runs backwards; write low-high")
            continue
        if msb >= dtype.bits:
            host.problems.add((*fpath, "bits"), f"{name}.{spec['name']}: bits {spec['bits']} lie beyond the {dtype.bits}-bit register")
            continue
        if spec["name"] in names:
            host.problems.add((*fpath, "name"), f"{name}: duplicate bitfield name {spec['name']!r}")
        names.add(spec["name"])
        for bit in range(lsb, msb + 1):
            if bit in used:
                host.problems.add((*fpath, "bits"), f"{name}.{spec['name']}: bit {bit} overlaps bitfield {used[bit]}")
                break
            used[bit] = spec["name"]
        enum_type = host._enum_ref(spec.get("enum"), (*fpath, "enum"), f"{name}.{spec['name']}")
        if enum_type is not None:
            for member in enum_type.members:
                if not 0 <= member.value < (1 << (msb - lsb + 1)):
                    host.problems.add(
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
                pos=host.positions.locate(fpath),
            )
        )
    return tuple(sorted(fields, key=lambda f: f.lsb))


def elaborate_array(
    host: ElaborationHost, a: dict[str, Any], path: Path, defaults: dict[str, Any], group: str, word_order: WordOrder
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
            host.problems.add((*mpath, "name"), f"array {a['array']}: duplicate member {m['name']!r}")
            repeated.add(j)
        member_names.add(m["name"])
        member_space = SPACES[m.get("space", defaults.get("space", DEFAULT_SPACE))]
        member_type = DATA_TYPES[m.get("type", defaults.get("type", "bool" if member_space.bits else "u16"))]
        words = m.get("words", 1) if member_type.is_string else member_type.words
        if "word_offset" not in m:
            moved = "offset" in m and isinstance(m["offset"], int) and "scale" not in m
            hint = "; `offset` is now the value offset beside `scale`, so rename this member's `offset` to `word_offset`" if moved else ""
            host.problems.add(mpath, f"array {a['array']}: member {m['name']} needs `word_offset` (its position in the element){hint}")
            repeated.add(j)
            members.append(ArrayMember(name=m["name"], offset=0, words=words, title=m["title"]))
            continue
        if m["word_offset"] + words > a["stride"]:
            host.problems.add(
                (*mpath, "word_offset"),
                f"array {a['array']}: member {m['name']} (word_offset {m['word_offset']}, {words} words) does not fit in the stride {a['stride']}",
            )
        members.append(ArrayMember(name=m["name"], offset=m["word_offset"], words=words, title=m["title"]))
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
        host.problems.add((*path, "count"), f"array {array.name}: its last element ends at 0x{last:X}, past address 0xFFFF")
        return array, []
    inherited = {**defaults, "source": a.get("source", defaults.get("source"))}
    for j, spec in enumerate(a["members"]):
        if isinstance(spec.get("default"), list) and len(spec["default"]) != array.count:
            host.problems.add(
                (*path, "members", j, "default"),
                f"array {array.name}: member {spec['name']} lists {len(spec['default'])} defaults for {array.count} elements",
            )
    clean: dict[int, Register] = {}  # a member's first element, where building it found no problem
    for i in range(array.count):
        index = index_base + i
        for j, (member, spec) in enumerate(zip(members, a["members"], strict=True)):
            if j in repeated:
                continue
            address = array.element_address(index, member)
            name = f"{array.name}_{index}_{member.name}"
            param = host._rule_param(address)
            ref = ArrayRef(array=array.name, index=index, member=member.name)
            first = clean.get(j)
            if first is not None and address + first.words - 1 <= 0xFFFF and not (first.paired and address == 0):
                # The other elements of a clean member differ only in what names and places them (the register's
                # checks read the name only to word their messages, the address only in the two tests above).
                reg: Register | None = replaced(
                    first,
                    name=name,
                    address=address,
                    param=param if param is not None else spec.get("param", inherited.get("param")),
                    array=ref,
                )
            else:
                per_element = isinstance(spec.get("default"), list)
                if per_element:
                    spec = {**spec, "default": spec["default"][i] if i < len(spec["default"]) else None}
                found = host.problems.count()
                reg = host._register(
                    {**inherited, **{k: v for k, v in spec.items() if k != "word_offset"}},
                    (*path, "members", j),
                    group,
                    word_order,
                    name=name,
                    address=address,
                    param=param,
                    array=ref,
                )
                if reg is not None and not per_element and host.problems.count() == found:
                    clean[j] = reg
            if reg is not None:
                expanded.append((reg, (*path, "members", j)))
    # Report per-member problems once, not once per element.
    host.problems.forget_repeats()
    return array, expanded
