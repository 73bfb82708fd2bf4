"""The PLCopen XML project of one device (TC6 XML v2.01, which TwinCAT 3 and CODESYS import): the same
enums, structs, constants and functions as the ST files, as `dataType`s, `pou`s of type function with
ST bodies, and one constant `globalVars` list in a configuration.

The text is CODESYS' (enum values with a base type, `E_X.MEMBER`, STRING lengths), except the float
helpers, which rebuild the value with exact LREAL arithmetic as the plain-standard ones do: TC6 XML has
no UNION. Every element type is computed here from the ST type the views give; the template prints.
"""

from __future__ import annotations

import functools
import re
from typing import Any

from regmap.backends.st.view_types import Const, FunctionView, Member, Section
from regmap.records import NamedTuple

ELEMENTARY = frozenset(
    [
        "BOOL",
        "BYTE",
        "WORD",
        "DWORD",
        "LWORD",
        "SINT",
        "INT",
        "DINT",
        "LINT",
        "USINT",
        "UINT",
        "UDINT",
        "ULINT",
        "REAL",
        "LREAL",
        "TIME",
        "DATE",
        "DT",
        "TOD",
    ]
)
_ARRAY = re.compile(r"^ARRAY\[(\d+)\.\.(\d+)\] OF (\w+)$")
_STRING = re.compile(r"^STRING(?:\((\d+)\))?$")


@functools.cache  # a few dozen types, asked for by every member, variable and constant
def xml_type(st_type: str) -> str:
    """The TC6 `dataType` element of an ST type the views use (elementary, STRING(n), ARRAY, a named type)."""
    if st_type in ELEMENTARY:
        return f"<{st_type}/>"
    string = _STRING.match(st_type)
    if string:
        return f'<string length="{string[1]}"/>' if string[1] else "<string/>"
    array = _ARRAY.match(st_type)
    if array:
        return f'<array><dimension lower="{array[1]}" upper="{array[2]}"/><baseType>{xml_type(array[3])}</baseType></array>'
    if not re.fullmatch(r"[A-Z_][A-Z0-9_]*", st_type):
        raise ValueError(f"no PLCopen type for {st_type!r}")
    return f'<derived name="{st_type}"/>'


class Variable(NamedTuple):  # thousands per device: a named tuple is cheap to make
    name: str
    type: str  # a TC6 dataType element
    initial: str | None  # an ST literal, for simpleValue
    comment: str  # plain text; the template escapes it


class Pou(NamedTuple):
    name: str
    returns: str
    comment: str
    lists: tuple[tuple[str, tuple[Variable, ...]], ...]  # (inputVars | inOutVars | localVars, variables)
    body_xml: str  # ST statements, one per line, escaped as XML character data


def _variables(members: tuple[Member, ...]) -> tuple[Variable, ...]:
    return tuple(Variable(m.name, xml_type(m.type), None, m.comment) for m in members)


def _pou(f: FunctionView) -> Pou:
    lists = [(tag, _variables(members)) for tag, members in (("inputVars", f.inputs), ("inOutVars", f.in_outs), ("localVars", f.locals))]
    return Pou(f.name, xml_type(f.returns), f.comment, tuple((tag, v) for tag, v in lists if v), f.xml_body)


def _constants(context: dict[str, Any]) -> list[Variable]:
    sections: list[Section] = [
        context["device_consts"],
        Section("The read plan.", (context["plan_len"], *(c for b in context["plan"] for c in b.consts))),
        *context["registers"],
        *context["arrays"],
        *context["bitfields"],
        *context["commands"],
    ]
    consts: list[Const] = [c for s in sections for c in s.consts]
    return [Variable(c.name, xml_type(c.type), c.value, c.comment) for c in consts]


def plcopen_context(context: dict[str, Any]) -> dict[str, Any]:
    """The template context of `<device>/plcopen/<device>.xml`, from the views in the PLCopen dialect."""
    device = context["device"]
    structs = [*(b.struct for b in context["plan"]), context["values"]]
    return {
        "header": context["header"],
        "device": device,
        "enums": [
            {
                "name": e.type_name,
                "comment": e.comment,
                "base": xml_type(e.base),
                "members": e.members,
            }
            for e in context["enums"]
        ],
        "structs": [{"name": s.type_name, "comment": s.comment, "members": _variables(s.members)} for s in structs],
        "pous": [_pou(f) for f in context["functions"]],
        "configuration": f"C_{device.id.upper()}",
        "global_list": f"GVL_{device.id.upper()}",
        "constants": _constants(context),
    }
