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

from regmap.backends.st.view_types import Const, EnumView, FunctionView, Member, StructView
from regmap.render import TEXT_CACHE_SIZE, xml_text

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


# The elements are joined here, not looped over in the template: a device has thousands of constants and members,
# and a template's loop costs several times the line it prints.


def _enum(e: EnumView) -> str:
    values = "".join([f'              <value name="{name}" value="{value}"/>\n' for name, value, _ in e.members])
    return (
        f'      <dataType name="{e.type_name}">\n        <baseType>\n          <enum>\n            <values>\n{values}'
        f"            </values>\n            <baseType>{xml_type(e.base)}</baseType>\n          </enum>\n        </baseType>\n"
        f"        <documentation><xhtml:p>{xml_text(e.comment)}</xhtml:p></documentation>\n      </dataType>\n"
    )


def _struct(s: StructView) -> str:
    head, tail = "              <documentation><xhtml:p>", "</xhtml:p></documentation>\n"  # a member's, where it has a comment
    members = "".join(
        [
            f'            <variable name="{name}">\n              <type>{xml_type(kind)}</type>\n'
            + (f"{head}{xml_text(comment)}{tail}" if comment else "")
            + "            </variable>\n"
            for name, kind, comment in s.members
        ]
    )
    return (
        f'      <dataType name="{s.type_name}">\n        <baseType>\n          <struct>\n{members}          </struct>\n'
        f"        </baseType>\n        <documentation><xhtml:p>{xml_text(s.comment)}</xhtml:p></documentation>\n      </dataType>\n"
    )


@functools.lru_cache(maxsize=TEXT_CACHE_SIZE)  # functions share parameter lists (a FROM_RAW's nRaw, eValue ...): each made once
def _variables(tag: str, members: tuple[Member, ...]) -> str:
    if not members:
        return ""
    lines = [
        f'            <variable name="{name}"><type>{xml_type(kind)}</type>'
        + (f"<documentation><xhtml:p>{xml_text(comment)}</xhtml:p></documentation>" if comment else "")
        + "</variable>\n"
        for name, kind, comment in members
    ]
    return f"          <{tag}>\n{''.join(lines)}          </{tag}>\n"


def _pou(f: FunctionView) -> str:
    return (
        f'      <pou name="{f.name}" pouType="function">\n        <interface>\n          <returnType>{xml_type(f.returns)}</returnType>\n'
        f"{_variables('inputVars', f.inputs)}{_variables('inOutVars', f.in_outs)}{_variables('localVars', f.locals)}"
        f'        </interface>\n        <body>\n          <ST><xhtml:p xml:space="preserve">{f.xml_body}</xhtml:p></ST>\n        </body>\n'
        f"        <documentation><xhtml:p>{xml_text(f.comment)}</xhtml:p></documentation>\n      </pou>\n"
    )


def _constants(context: dict[str, Any]) -> str:
    notation = context["dialect"].notation
    consts = [*context["device_consts"].consts, context["plan_len"]]
    for block in context["plan"]:
        consts += block.consts
    consts += [c if type(c) is Const else c.spelled(notation) for s in context["const_sections"] for c in s.consts]
    head, tail = "            <documentation><xhtml:p>", "</xhtml:p></documentation>\n          </variable>\n"
    return "".join(
        [
            f'          <variable name="{name}">\n            <type>{xml_type(kind)}</type>\n'
            f'            <initialValue><simpleValue value="{xml_text(value)}"/></initialValue>\n'
            + (f"{head}{xml_text(comment)}{tail}" if comment else "          </variable>\n")
            for name, kind, value, comment in consts
        ]
    )


def plcopen_context(context: dict[str, Any]) -> dict[str, Any]:
    """The template context of `<device>/plcopen/<device>.xml`, from the views in the PLCopen dialect: each list of
    elements as its XML text."""
    device = context["device"]
    structs = [*(b.struct for b in context["plan"]), context["values"]]
    return {
        "header": context["header"],
        "device": device,
        "data_types": "".join([*(_enum(e) for e in context["enums"]), *(_struct(s) for s in structs)]),
        "pous": "".join([_pou(f) for f in context["functions"]]),
        "configuration": f"C_{device.id.upper()}",
        "global_list": f"GVL_{device.id.upper()}",
        "constants": _constants(context),
    }
