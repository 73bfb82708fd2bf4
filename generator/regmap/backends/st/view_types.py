"""The view objects of one device's Structured Text, which the templates print: constants, struct members,
enums, structs and functions. What a dialect writes its own way (an enum value, a text type) is a
`MemberConst` / `TextConst` / `TextMember` until `spelled` with that dialect's `Notation`."""

from __future__ import annotations

from dataclasses import dataclass

from regmap.backends.st.codec import Notation


@dataclass(frozen=True)
class Const:
    name: str
    type: str
    value: str
    comment: str = ""  # plain text; the template escapes it

    def spelled(self, notation: Notation) -> Const:
        return self


@dataclass(frozen=True)
class MemberConst:
    """A constant whose value is a member of the enum `type`: `E_X.R` (CODESYS) or `E_X#R` (plain IEC)."""

    name: str
    type: str
    member: str

    def spelled(self, notation: Notation) -> Const:
        return Const(self.name, self.type, notation.member(self.type, self.member))


@dataclass(frozen=True)
class TextConst:
    """A constant of `size` text bytes: typed `STRING(size)` (CODESYS) or `STRING` (plain IEC)."""

    name: str
    size: int
    value: str
    comment: str = ""

    def spelled(self, notation: Notation) -> Const:
        return Const(self.name, notation.string(self.size), self.value, self.comment)


@dataclass(frozen=True)
class Member:
    name: str
    type: str
    comment: str = ""

    def spelled(self, notation: Notation) -> Member:
        return self


@dataclass(frozen=True)
class TextMember:
    """A struct member of `size` text bytes: `STRING(size)` (CODESYS) or `STRING` (plain IEC)."""

    name: str
    size: int
    comment: str = ""

    def spelled(self, notation: Notation) -> Member:
        return Member(self.name, notation.string(self.size), self.comment)


@dataclass(frozen=True)
class EnumValue:
    name: str
    value: str
    comment: str


@dataclass(frozen=True)
class EnumView:
    type_name: str
    base: str
    comment: str
    members: tuple[EnumValue, ...]


@dataclass(frozen=True)
class StructView:
    type_name: str
    comment: str
    members: tuple[Member, ...]


@dataclass(frozen=True)
class FunctionView:
    name: str
    returns: str
    comment: str
    inputs: tuple[Member, ...]
    in_outs: tuple[Member, ...]
    locals: tuple[Member, ...]
    body: tuple[str, ...]  # ST statements, indented by the template


@dataclass(frozen=True)
class Section:
    comment: str
    consts: tuple[Const, ...]


@dataclass(frozen=True)
class SectionToSpell:
    """A section some of whose constants each dialect writes its own way."""

    comment: str
    consts: tuple[Const | MemberConst | TextConst, ...]

    def spelled(self, notation: Notation) -> Section:
        return Section(self.comment, tuple(c.spelled(notation) for c in self.consts))
