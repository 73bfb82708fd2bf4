"""Python back end: a typed client package per map on pymodbus, plus a copy of `regmap_runtime`.

The views below compute every identifier, literal and docstring line; the template only prints.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from regmap.backends.python.docs import method_docs, register_doc, sources
from regmap.backends.python.package import RUNTIME_MODULES, post, render_shared, runtime_package
from regmap.core.text import titled
from regmap.diagnostics import Diagnostic, MapError, UsageError, at
from regmap.keywords import PYTHON_KEYWORDS
from regmap.model import Access, ArrayDef, Bitfield, Command, Device, EnumType, Register
from regmap.records import NamedTuple
from regmap.render import header_lines, py_doc, py_str, templates
from regmap.runtime_bridge import device_extras, read_plan, register_extras
from regmap.target import Files, ReservedWords, Target
from regmap_runtime import errors
from regmap_runtime.spaces import DEFAULT_SPACE

if TYPE_CHECKING:  # only a plant's run imports the plant model (tests/project/test_generate_imports.py)
    from regmap.plant import Plant
__all__ = ["RUNTIME_MODULES", "TARGET", "PythonIdentifier", "check", "device_context", "render_device", "render_shared", "runtime_package"]


class PythonIdentifier(str):
    """A snake_case identifier that is valid in Python and not a keyword."""

    def __new__(cls, name: str) -> PythonIdentifier:
        if not name.isidentifier():
            raise UsageError(f"{name!r} is not a valid Python identifier")
        if name in PYTHON_KEYWORDS:  # soft keywords as of Python 3.11: the names do not change with the interpreter
            name = name + "_"
        return super().__new__(cls, name)


def camel(name: str) -> str:
    return "".join(part[:1].upper() + part[1:] for part in name.split("_") if part)


def const(name: str) -> str:
    return name.upper()


def _int_literal(value: int) -> str:
    """Hex for codes (the manuals print them so), decimal for small counts and negatives."""
    return f"0x{value:02X}" if value >= 0x10 else str(value)


class EnumView(NamedTuple):
    class_name: str
    doc: str
    members: tuple[tuple[str, str, str], ...]  # (NAME, literal value, docstring)


class BitfieldView(NamedTuple):
    attr: str
    name_literal: str
    lsb: int
    width: int
    enum_class: str | None
    annotation: str
    default: str  # literal for the dataclass field: False for a flag, 0 otherwise


class BitsClassView(NamedTuple):
    class_name: str
    doc: str
    fields: tuple[BitfieldView, ...]


class RegisterView(NamedTuple):
    const: str
    attr: str  # method suffix / bundle attribute
    spec_class: str  # ReadOnly / ReadWrite / WriteOnly
    value_type: str
    write_type: str
    readable: bool
    writable: bool
    arguments: str  # the constructor's keyword arguments, already literals: one `    key=value,` a line
    doc: str  # the register's documentation, written once: under its constant
    read_doc: str  # the methods' one line: the constant they use and the register's title
    write_doc: str


class ArrayView(NamedTuple):
    name: str
    bundle_class: str
    element_class: str
    async_element_class: str
    const: str
    first: int
    last: int
    doc: str
    members: tuple[RegisterView, ...]  # one view per member (element 0's), for method signatures
    elements: tuple[tuple[int, tuple[tuple[str, str], ...]], ...]  # (index, ((attr, CONST), ...))


class SnapshotView(NamedTuple):
    """The TypedDict read_all() and read_many() return: each readable register's name and value type."""

    name: str
    name_literal: str
    doc: str
    fields: tuple[tuple[str, str], ...]  # (the name as a literal, the value type)


def snapshot_name(device: Device) -> str:
    return camel(device.id) + "Values"


def _snapshot_view(device: Device, views: list[RegisterView]) -> SnapshotView:
    """`views`: each register's, whose value type the snapshot gives a readable one."""
    name = snapshot_name(device)
    doc = (
        "What read_all() and read_many() return: register name -> value, typed per register; a register"
        " not read (another poll class, absent in the firmware, not asked for) is not there."
    )
    fields = tuple((py_str(r.name), view.value_type) for r, view in zip(device.registers, views, strict=True) if view.readable)
    return SnapshotView(name=name, name_literal=py_str(name), doc=py_doc(doc), fields=fields)


class CommandView(NamedTuple):
    method: str
    const: str
    raw: str
    argument: str | None
    arg_min: int
    arg_max: int
    doc: str
    confirm_param: str = ""  # a destructive command's required keyword: its own name, typed as a Literal
    confirm_arg: str = ""  # and what send_command is told of it


def _enum_view(e: EnumType) -> EnumView:
    members = tuple(
        (
            const(PythonIdentifier(m.name)),
            _int_literal(m.value),
            py_doc(f"{m.title}" + (f" ({m.title_zh})" if m.title_zh else "") + (f" [{m.symbol}]" if m.symbol else "")),
        )
        for m in e.members
    )
    return EnumView(class_name=camel(e.name), doc=py_doc(titled(e.title, e.title_zh) + sources(e.source)), members=members)


def _bits_class_name(reg: Register) -> str:
    owner = f"{reg.array.array}_{reg.array.member}" if reg.array else reg.name
    return camel(owner) + "Bits"


def _bitfield_view(b: Bitfield) -> BitfieldView:
    enum_class = camel(b.enum.name) if b.enum else None
    flag = b.width == 1 and enum_class is None
    annotation = f"{enum_class} | int" if enum_class else ("bool" if flag else "int")
    return BitfieldView(
        attr=PythonIdentifier(b.name),
        name_literal=py_str(b.name),
        lsb=b.lsb,
        width=b.width,
        enum_class=enum_class,
        annotation=annotation,
        default="False" if flag else "0",
    )


def _read_type(reg: Register) -> str:
    """What a read returns: the bitfield class, the enum (or the number, for a value the manual does not
    list), text for a string, a bool for a coil or discrete input, a float for a float or a scaled or
    offset value, else an int (the register's view adds `| None` where the device may send its "not
    available" marker, `na`, or the value waits for its scale factor)."""
    if reg.bitfields:
        return _bits_class_name(reg)
    if reg.enum is not None:  # a float enum register also reads a value no member can be (2.5) as the float
        return f"{camel(reg.enum.name)} | Unlisted" + (" | float" if reg.type.is_float else "")
    return _plain_type(reg)


def _enum_write_type(e: EnumType) -> str:
    """What an enum register's write takes: a member, or a member's name as the map spells it; only the
    writable ones. Where some member is a state the device only reports, the members are listed too,
    so mypy refuses a state as it refuses its name."""
    cls = camel(e.name)
    writable = [m for m in e.members if m.writable]
    names = ", ".join(py_str(m.name) for m in writable)
    if len(writable) == len(e.members):
        return f"{cls} | Literal[{names}]"
    if not writable:
        return cls  # nothing may be written: the runtime refuses every member
    members = ", ".join(f"{cls}.{const(PythonIdentifier(m.name))}" for m in writable)
    return f"Literal[{members}, {names}]"


def _plain_type(reg: Register) -> str:
    if reg.type.is_string or reg.type.is_bool or reg.type.is_timestamp:  # a timestamp's datetime: aware (UTC) or naive (local)
        return {"string": "str", "bool": "bool", "timestamp": "datetime"}[reg.type.value]
    return "float" if reg.type.is_float or reg.scaled or reg.offset_set or reg.scale_from else "int"


def _writable(reg: Register) -> bool:
    """A write_ accessor exists only where both the register's access and its space allow writing."""
    return reg.access.writable and reg.space_info.writable


def _literal(value: object) -> str:
    return py_str(value) if isinstance(value, str) else str(value)


_SPEC_CLASSES = {"r": "ReadOnly", "rw": "ReadWrite", "w": "WriteOnly"}  # by the access's value: an enum hashes in Python


def _register_view(
    reg: Register, own: dict[str, Any], commands: dict[str, Any] | None = None, *, attr: str | None = None, constant: str | None = None
) -> RegisterView:
    """`own`, `commands`: the register's `register_extras` (spec fields beyond the basic ones; trigger and destructive
    values); `attr` and `constant` for an array member: its attribute and how an element's method reaches its constant."""
    writable = _writable(reg)
    readable = reg.access.readable
    access = reg.access if writable or not readable else Access.READ
    constant_name = reg.name.upper()  # const()
    # The constructor's keyword arguments, one `    key=value,` a line (repr: py_str of a text that is never empty).
    lines = [
        f"    name={reg.name!r},\n    address=0x{reg.address:04X},\n    data_type={reg.type._value_!r},\n    access={reg.access._value_!r},"
    ]  # _value_: an enum's .value is a Python-level property in 3.11
    if reg.space != DEFAULT_SPACE:
        lines.append(f"    space={reg.space!r},")
    if reg.wide:
        lines.append(f"    word_order={reg.word_order._value_!r},")
        if reg.word_order_fixed:
            lines.append("    follows_device_order=False,")
    if reg.paired:
        lines.append("    paired=True,")
    if reg.scaled:
        lines.append(f"    scale_num={reg.scale.numerator},\n    scale_den={reg.scale.denominator},")
    if reg.min is not None:
        lines.append(f"    min={reg.min},")
    if reg.max is not None:
        lines.append(f"    max={reg.max},")
    if reg.unit:
        lines.append(f"    unit={reg.unit!r},")
    if reg.param:
        lines.append(f"    param={reg.param!r},")
    if reg.enum is not None:
        lines.append(f"    enum={camel(reg.enum.name)},")
    read_type = _read_type(reg)
    if reg.bitfields:
        lines.append(f"    bitfields={read_type}.FIELDS,\n    bitfield_type={read_type},")  # the read type: the bits class
    # The wider types, spaces and gates: only where they differ from the defaults (seed output unchanged).
    lines += [f"    {key}={_literal(value)}," for key, value in (own | commands if commands else own).items()]
    methods = reg.array is None or attr is not None  # an array element's are its member's: no method text of its own
    read_doc, write_doc = method_docs(reg, constant or constant_name) if methods else ("", "")
    return RegisterView(
        const=constant_name,
        attr=PythonIdentifier(attr or reg.name),
        spec_class=_SPEC_CLASSES[access._value_],
        value_type=read_type + " | None" if reg.has_na or reg.scale_from else read_type,
        write_type=(_enum_write_type(reg.enum) if reg.enum is not None and not reg.bitfields else read_type) if methods else "",
        readable=readable,
        writable=writable,
        arguments="\n".join(lines),
        doc=register_doc(reg),
        read_doc=read_doc,
        write_doc=write_doc,
    )


def _array_view(by_name: dict[str, Register], array: ArrayDef, extras: dict[str, tuple[dict[str, Any], dict[str, Any]]]) -> ArrayView:
    elements = []
    members: dict[str, RegisterView] = {}
    for index in range(array.first_index, array.last_index + 1):
        pairs = []
        for member in array.members:
            reg = by_name[f"{array.name}_{index}_{member.name}"]
            pairs.append((str(PythonIdentifier(member.name)), const(reg.name)))
            if member.name not in members:
                attr = PythonIdentifier(member.name)
                members[member.name] = _register_view(reg, extras[reg.name][0], attr=attr, constant=f"{const(array.name)}[n].{attr}")
        elements.append((index, tuple(pairs)))
    doc = (
        titled(array.title, array.title_zh)
        + f": {array.count} elements {array.first_index}..{array.last_index}, element n at 0x{array.base:04X} + {array.stride} x {'n' if array.index_base == 0 else f'(n - {array.index_base})'}"
        + sources(array.source)
    )
    return ArrayView(
        name=PythonIdentifier(array.name),
        bundle_class=camel(array.name) + "Registers",
        element_class=camel(array.name) + "Element",
        async_element_class="Async" + camel(array.name) + "Element",
        const=const(array.name),
        first=array.first_index,
        last=array.last_index,
        doc=py_doc(doc),
        members=tuple(members.values()),
        elements=tuple(elements),
    )


def _command_view(cmd: Command) -> CommandView:
    doc = (
        titled(cmd.title, cmd.title_zh)
        + f": writes 0x{cmd.value:04X}"
        + (f" + {cmd.argument.name}" if cmd.argument else "")
        + f" to {cmd.register.label} (0x{cmd.register.address:04X})"
        + sources(cmd.source)
    )
    if cmd.description:
        doc += " " + cmd.description
    confirm_param = confirm_arg = ""
    if cmd.destructive:
        doc += f" Destructive (it loses data or state): nothing is sent without confirm={cmd.name!r}."
        confirm_param = f", *, confirm: Literal[{py_str(cmd.name)}]"
        confirm_arg = f", confirmed=confirm == {py_str(cmd.name)}"
    return CommandView(
        confirm_param=confirm_param,
        confirm_arg=confirm_arg,
        method=PythonIdentifier(cmd.name),
        const=const(cmd.register.name),
        raw=f"0x{cmd.value:04X}",
        argument=PythonIdentifier(cmd.argument.name) if cmd.argument else None,
        arg_min=cmd.argument.min if cmd.argument else 0,
        arg_max=cmd.argument.max if cmd.argument else 0,
        doc=py_doc(doc),
    )


CLIENT_METHODS = frozenset(
    {
        "read",
        "write",
        "update",
        "read_many",
        "write_many",
        "read_all",
        "read_raw",
        "write_raw",
        "send_command",
        "connect",
        "close",
        "rtu",
        "tcp",
    }
    | {
        "plan_reads",
        "plan_writes",
        "readable",
        "encode",
        "encode_raw",
        "decode",
        "values_of",
        "effective",
        "broadcast",
        "transport_error",
        "check_response",
    }
    | {"read_words", "slave", "word_order", "requests_sent", "line", "modbus", "DEVICE"}
    | {"check_writable", "check_exists", "writer", "reader", "write_args", "profile", "masked", "retries"}
    | {"check_firmware", "firmware", "firmware_text", "firmware_pending", "firmware_block", "learn_firmware", "detect_firmware"}
    | {"echo", "echoed", "report_server_id", "read_identification", "identification_code", "write_and_read", "read_write_arguments"}
    | {"read_write_plan", "check_listed", "where", "check_aligned", "set_word_order", "word_order_write"}
)
# Every error the runtime raises, re-exported by every generated module: `except drive.AccessError` must work
# whichever map the module came from (a map without a firmware register still raises FirmwareError on request).
RUNTIME_ERRORS = tuple(sorted(name for name, obj in vars(errors).items() if isinstance(obj, type) and issubclass(obj, errors.RegmapError)))


def module_errors(device: Device) -> tuple[str, ...]:
    """The runtime's errors a generated module re-exports: all of them."""
    return RUNTIME_ERRORS


BITFIELD_RESERVED = frozenset({"raw", "FIELDS", "from_raw", "to_raw", "described_mask", "describe"})


def check(device: Device) -> list[Diagnostic]:
    """Names the generated module would use twice or that would shadow the runtime's own, at the
    map line that declares them (run by `regmap validate` as by `regmap generate`)."""
    file = device.source_path
    problems: list[Diagnostic] = []
    taken: dict[str, str] = {}

    def claim(name: str, what: str, pos: tuple[int, int] | None) -> None:
        if name in taken and taken[name] != what:
            problems.append(
                at(file, pos, f"generated Python name {name!r} is used by both {taken[name]} and {what}; rename one in the map")
            )
        taken.setdefault(name, what)

    client_class = camel(device.id)
    for name in ("BitfieldValue", "Unlisted", *module_errors(device)):
        claim(name, f"the runtime's {name}, which the module re-exports", None)
    claim(client_class, "the client class", None)
    claim(snapshot_name(device), "the values read_all() returns", None)
    claim("Async" + client_class, "the async client class", None)
    for e in device.enums:
        claim(camel(e.name), f"enum {e.name}", e.pos)
    for reg in device.registers:
        if reg.bitfields:
            claim(_bits_class_name(reg), f"the bitfield class of {reg.array.array if reg.array else reg.name}", reg.pos)
            for b in reg.bitfields:
                if b.name in BITFIELD_RESERVED:
                    problems.append(
                        at(file, b.pos, f"{reg.name}.{b.name}: bitfield name {b.name!r} would shadow BitfieldValue.{b.name}; rename it")
                    )
    for a in device.arrays:
        owner = f"array {a.name}"
        for cls in (camel(a.name) + "Registers", camel(a.name) + "Element", "Async" + camel(a.name) + "Element"):
            claim(cls, owner, None)
    taken.clear()
    methods: list[tuple[str, str, tuple[int, int] | None]] = []
    for reg in device.registers:
        if reg.array is None:
            attr = PythonIdentifier(reg.name)
            if reg.access.readable:
                methods.append((f"read_{attr}", f"register {reg.name}", reg.pos))
            if _writable(reg):
                methods.append((f"write_{attr}", f"register {reg.name}", reg.pos))
    first_element = {r.array.array: r for r in device.registers if r.array is not None}
    methods += [
        (PythonIdentifier(a.name), f"array {a.name}", first_element[a.name].pos if a.name in first_element else None) for a in device.arrays
    ]
    methods += [(PythonIdentifier(c.name), f"command {c.name}", c.pos) for c in device.commands]
    for name, what, pos in methods:
        if name in CLIENT_METHODS:
            problems.append(
                at(file, pos, f"{what}: the generated method {name!r} would shadow the client's own {name}(); rename it in the map")
            )
        claim(name, what, pos)
    return problems


def _firmware_note(device: Device) -> str:
    """The class docstring's word on check_firmware, for a map that names its firmware register."""
    named = device.info.firmware_register
    if named is None:
        return ""
    gated = sum(1 for r in device.registers if r.firmware is not None)
    return py_doc(
        f"With `check_firmware=True` the client reads {named.register.name} on connect (the version is then"
        f" `client.firmware`) and refuses, with FirmwareError, the registers that firmware lacks ({gated} of the map's"
        " registers exist only in some versions); read_all() leaves those out."
    )


def device_context(device: Device) -> dict[str, Any]:
    enums = [_enum_view(e) for e in device.enums]
    bits_classes: dict[str, BitsClassView] = {}
    for reg in device.registers:
        if reg.bitfields:
            name = _bits_class_name(reg)
            if name not in bits_classes:
                title = reg.title if reg.array is None else f"{reg.title} of a {reg.array.array} element"
                bits_classes[name] = BitsClassView(
                    class_name=name, doc=py_doc(f"Fields of {title}."), fields=tuple(_bitfield_view(b) for b in reg.bitfields)
                )
    # One lookup table and one view per register: Device.register() scans, which made array-heavy maps quadratic.
    by_name: dict[str, Register] = {}
    for reg in device.registers:
        by_name.setdefault(reg.name, reg)
    extras = register_extras(device)
    arrays = [_array_view(by_name, a, extras) for a in device.arrays]
    all_regs = [_register_view(r, *extras[r.name]) for r in device.registers]
    plain = [view for view, r in zip(all_regs, device.registers, strict=True) if r.array is None]
    client_class = camel(device.id)
    problems = check(device)
    if problems:
        raise MapError(problems)
    t = device.transport
    blocks = read_plan(device)
    return {
        "header": header_lines(device, "regmap generate"),
        "device": device,
        "title": py_doc(f"{device.info.vendor} {device.info.model} client"),
        "client_class": client_class,
        "enums": enums,
        "bits_classes": list(bits_classes.values()),
        "registers": all_regs,
        "plain": plain,
        "arrays": arrays,
        "commands": [_command_view(c) for c in device.commands],
        "snapshot": _snapshot_view(device, all_regs),
        "exceptions": [(e.code, py_str(e.name), py_str(e.title)) for e in t.exceptions],
        "device_kwargs": [(key, _literal(value)) for key, value in device_extras(device).items()],
        "errors": module_errors(device),
        "has_time": any(r.type.is_timestamp for r in device.registers),
        "firmware_note": _firmware_note(device),
        "read_plan_requests": len(blocks),
        "runtime": runtime_package(),
        "py_str": py_str,
    }


def render_device(device: Device) -> Files:
    env = templates(__name__)
    context = device_context(device)
    package = device.id
    return {
        f"{package}/__init__.py": env.get_template("client.py.jinja").render(**context),
        f"{package}/py.typed": "",
    }


def render_plant(plant: Plant) -> Files:
    """The plant module with the device packages and the runtime it imports (backends/python/plant.py)."""
    from regmap.backends.python.plant import render_plant as render  # that module uses this package's views

    return render(plant)


# A device id names the generated package: one of these would shadow a package its client imports (or the stdlib's `test`).
SHADOWED_PACKAGES = frozenset({"regmap", "regmap_runtime", "pymodbus", "test", "tests"})

TARGET = Target(
    name="python",
    subdir="python",
    per_device=render_device,
    shared=render_shared,
    post=post,
    check=check,
    order=10,
    scale_from=True,
    reserved_words=ReservedWords("a Python keyword or a package the client would shadow", PYTHON_KEYWORDS | SHADOWED_PACKAGES),
    plant=render_plant,
)
