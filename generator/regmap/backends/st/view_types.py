"""The view objects of one device's Structured Text, which the templates print: constants, struct members,
enums, structs and functions. What a dialect writes its own way (an enum value, a text type) is a
`MemberConst` / `TextConst` / `TextMember` until `spelled` with that dialect's `Notation`.

A device has thousands of constants and members: they are named tuples, which cost far less to make than
frozen dataclasses; their text (`Section.lines`, a function's `text`, a struct's members) is joined here in
Python, once, and the templates print it."""

from __future__ import annotations

import functools
from collections.abc import Callable, Sequence

from regmap.backends.st.codec import Notation
from regmap.records import NamedTuple, cached_property, dataclass
from regmap.render import st_comment, xml_text


class Const(NamedTuple):
    name: str
    type: str
    value: str
    comment: str = ""  # plain text; the template escapes it

    def spelled(self, notation: Notation) -> Const:
        return self


# A Const through namedtuple's `__new__` costs a Python call; the thousands of register constants are made with tuple's own.
new_const: Callable[[tuple[str, str, str, str]], Const] = functools.partial(tuple.__new__, Const)


class MemberConst(NamedTuple):
    """A constant whose value is a member of the enum `type`: `E_X.R` (CODESYS) or `E_X#R` (plain IEC)."""

    name: str
    type: str
    member: str

    def spelled(self, notation: Notation) -> Const:
        return Const(self.name, self.type, notation.member(self.type, self.member))

    def line(self, notation: Notation) -> str:
        """`const_line` of the spelled constant, made in one step (every register has one): the value as
        `Notation.member` writes it, and no comment."""
        name, kind, member = self
        return f"    {name} : {kind} := {kind}{notation.qualifier}{member};\n"


class TextConst(NamedTuple):
    """A constant of `size` text bytes: typed `STRING(size)` (CODESYS) or `STRING` (plain IEC)."""

    name: str
    size: int
    value: str
    comment: str = ""

    def spelled(self, notation: Notation) -> Const:
        return Const(self.name, notation.string(self.size), self.value, self.comment)

    def line(self, notation: Notation) -> str:
        return const_line(self.spelled(notation))


class Member(NamedTuple):
    name: str
    type: str
    comment: str = ""

    def spelled(self, notation: Notation) -> Member:
        return self


class TextMember(NamedTuple):
    """A struct member of `size` text bytes: `STRING(size)` (CODESYS) or `STRING` (plain IEC)."""

    name: str
    size: int
    comment: str = ""

    def spelled(self, notation: Notation) -> Member:
        return Member(self.name, notation.string(self.size), self.comment)


class EnumValue(NamedTuple):
    name: str
    value: str
    comment: str


@dataclass(frozen=True)
class EnumView:
    type_name: str
    base: str  # "" in a notation without enum base types (plain IEC), which gives the members no values either
    comment: str
    members: tuple[EnumValue, ...]

    # The member lines an ST file prints, made here as a function's are: joined in a template they cost several times more.
    @cached_property
    def st_members(self) -> str:
        """The members, one a line, the last without a comma; each with its value where the notation has a base type."""
        last = len(self.members) - 1
        return "".join(
            [
                f"    {name}{f' := {value}' if self.base else ''}{',' if i != last else ''} (* {st_comment(comment)} *)\n"
                for i, (name, value, comment) in enumerate(self.members)
            ]
        )


@dataclass(frozen=True)
class StructView:
    type_name: str
    comment: str
    members: tuple[Member, ...]

    @cached_property
    def st_members(self) -> str:
        """The members as an ST STRUCT declares them, one a line (the dialects share the read blocks' structs)."""
        return "".join([f"    {name} : {kind}; (* {st_comment(comment)} *)\n" for name, kind, comment in self.members])


@dataclass(frozen=True)
class FunctionView:
    name: str
    returns: str
    comment: str
    inputs: tuple[Member, ...]
    in_outs: tuple[Member, ...]
    locals: tuple[Member, ...]
    body: tuple[str, ...]  # ST statements

    # The body's text, joined once per function: the dialects and the XML share most functions' views.
    @cached_property
    def indented_body(self) -> str:
        """The statements, one a line, each indented by four spaces and ended by a newline (the ST files)."""
        return "    " + "\n    ".join(self.body) + "\n" if self.body else ""

    @cached_property
    def st_text(self) -> str:
        """The whole function as an ST file prints it, from the blank line before its comment to END_FUNCTION: made
        once here (the dialects share most functions), since a template's loops cost several times the lines."""
        return self._text(declare_empty=False)

    @cached_property
    def poll_text(self) -> str:
        """The same as the poller's file prints it (both runtimes share it), VAR_INPUT and VAR_IN_OUT even when empty."""
        return self._text(declare_empty=True)

    def _text(self, declare_empty: bool) -> str:
        lines = [f"\n(* {st_comment(self.comment)} *)\n", f"FUNCTION {self.name} : {self.returns}\n"]
        if self.inputs or declare_empty:
            lines.append("VAR_INPUT\n")
            lines += [
                f"    {name} : {kind}; (* {st_comment(comment)} *)\n" if comment else f"    {name} : {kind};\n"
                for name, kind, comment in self.inputs
            ]
            lines.append("END_VAR\n")
        if self.in_outs or declare_empty:
            lines.append("VAR_IN_OUT\n")
            lines += [f"    {m.name} : {m.type};\n" for m in self.in_outs]
            lines.append("END_VAR\n")
        if self.locals:
            lines.append("VAR\n")
            lines += [f"    {m.name} : {m.type};\n" for m in self.locals]
            lines.append("END_VAR\n")
        lines.append(self.indented_body)
        lines.append("END_FUNCTION\n")
        return "".join(lines)

    @cached_property
    def xml_body(self) -> str:
        """The statements, one a line, as XML character data (the PLCopen POU's ST body)."""
        return xml_text("\n".join(self.body))


class Section(NamedTuple):
    comment: str
    consts: tuple[Const, ...]

    @property
    def text(self) -> str:
        """The section as an ST file's VAR_GLOBAL CONSTANT prints it: a blank line, its comment, its constants."""
        return f"\n    (* {st_comment(self.comment)} *)\n{self.lines}"

    @property
    def lines(self) -> str:
        """The constants' declarations, one a line, each ended by a newline (an ST file's VAR_GLOBAL CONSTANT): made
        here, as the functions' bodies are, since a template's loop costs several times the line it prints."""
        return "".join(
            [
                f"    {name} : {kind} := {value}; (* {st_comment(comment)} *)\n" if comment else f"    {name} : {kind} := {value};\n"
                for name, kind, value, comment in self.consts
            ]
        )


def const_line(const: Const) -> str:
    """One constant's declaration in an ST file's VAR_GLOBAL CONSTANT (as `Section.lines` prints each)."""
    name, kind, value, comment = const
    return f"    {name} : {kind} := {value}; (* {st_comment(comment)} *)\n" if comment else f"    {name} : {kind} := {value};\n"


class SpelledText:
    """The text of sections whose constants every notation prints alike but a few (an enum value, a text type): the
    runs printed alike are joined once, and `text` spells and prints only the few, so the second notation costs a
    fraction of the first (every register has one such constant among its ten or so)."""

    __slots__ = ("pieces",)

    def __init__(self, sections: Sequence[Section | SectionToSpell]) -> None:
        pieces: list[str | MemberConst | TextConst] = []
        run: list[str] = []
        for section in sections:
            run.append(f"\n    (* {st_comment(section.comment)} *)\n")
            for c in section.consts:
                if isinstance(c, Const):
                    name, kind, value, comment = c
                    # const_line's text, without a call for each of the thousands of constants
                    run.append(
                        f"    {name} : {kind} := {value}; (* {st_comment(comment)} *)\n"
                        if comment
                        else f"    {name} : {kind} := {value};\n"
                    )
                else:
                    pieces += ["".join(run), c]
                    run = []
        pieces.append("".join(run))
        self.pieces = pieces

    def text(self, notation: Notation) -> str:
        """What the sections' `Section.text` would print, one after another, in `notation`."""
        return "".join([p if isinstance(p, str) else p.line(notation) for p in self.pieces])


class SectionToSpell(NamedTuple):
    """A section some of whose constants each dialect writes its own way."""

    comment: str
    consts: tuple[Const | MemberConst | TextConst, ...]

    def spelled(self, notation: Notation) -> Section:
        return Section(self.comment, tuple([c if type(c) is Const else c.spelled(notation) for c in self.consts]))  # most are plain
