"""The YAML text of the ESPHome and Home Assistant files, written directly for the shapes their views build.

PyYAML's emitter walks every scalar through events and a character-by-character analysis in pure Python: a third
of `regmap generate`'s time went into it (issue #36). `yaml_text` writes what `yaml.dump` with `_Dumper` writes,
byte for byte, for block mappings with string keys, sequences, strings, integers, `Hex`, booleans, None, floats and
`Lambda`s; anything else (a string PyYAML would double-quote, a multi-line one, an unknown type) it leaves to
`yaml.dump` itself. Every style decision is PyYAML's: a string is written plain only when PyYAML's own resolver
reads it back as a string and PyYAML's own `analyze_scalar` allows plain (a cheap pattern stands in for the
analysis where it cannot differ), else single-quoted; so map text stays data (a `!secret`, `*alias`, `yes`,
`0x10` or `- x` is quoted exactly as PyYAML quotes it). The property tests compare the two on generated data.
"""

from __future__ import annotations

import functools
import io
import re
from typing import Any

import yaml
from yaml.emitter import Emitter

from regmap.records import dataclass

WIDTH = 120  # the line width the files are folded at (PyYAML folds a scalar at a space once past it)
INDENT = 2
MAX_SIMPLE_KEY = 128 - len("!!str")  # PyYAML writes a longer key as a complex `? key` (it counts the unwritten tag)


class Hex(int):
    """An integer written in hex (addresses, masks); YAML 1.1 reads `0x0010` back as 16."""

    digits: int

    def __new__(cls, value: int, digits: int = 4) -> Hex:
        made = super().__new__(cls, value)
        made.digits = digits
        return made


@dataclass(frozen=True)
class Lambda:
    """An ESPHome `!lambda` whose code the back end wrote from integers and identifiers, never from map text."""

    code: str


class _Dumper(yaml.SafeDumper):
    def ignore_aliases(self, data: Any) -> bool:
        return True  # no anchors/aliases: repeated values are written out


def _hex(dumper: yaml.SafeDumper, value: Hex) -> yaml.Node:
    return dumper.represent_scalar("tag:yaml.org,2002:int", _hex_text(value))


def _hex_text(value: Hex) -> str:
    return f"0x{int(value):0{value.digits}X}"


def _lambda(dumper: yaml.SafeDumper, value: Lambda) -> yaml.Node:
    return dumper.represent_scalar("!lambda", value.code, style="|")


_Dumper.add_representer(Hex, _hex)
_Dumper.add_representer(Lambda, _lambda)


def pyyaml_text(data: Any) -> str:
    """What PyYAML writes for `data`: the reference `yaml_text` matches, and its fallback."""
    return yaml.dump(data, Dumper=_Dumper, sort_keys=False, allow_unicode=True, width=WIDTH, default_flow_style=False)


def yaml_text(data: Any) -> str:
    """`data` as YAML, byte for byte `pyyaml_text(data)`: written directly when every node is of a supported shape."""
    direct = direct_text(data)
    return pyyaml_text(data) if direct is None else direct


def direct_text(data: Any) -> str | None:
    """`pyyaml_text(data)` written without PyYAML, or None when a node is of a shape this writer leaves to PyYAML."""
    if type(data) is not dict or not data:
        return None
    out: list[str] = []
    try:
        _Writer(out).mapping(data, 0, inline=True)
    except _Unsupported:
        return None
    out.append("\n")
    return "".join(out)


class _Unsupported(Exception):
    """A node this writer leaves to PyYAML."""


_STR = "tag:yaml.org,2002:str"
_INT = "tag:yaml.org,2002:int"
_FLOAT = "tag:yaml.org,2002:float"
_RESOLVER = yaml.resolver.Resolver()
_ANALYZER = Emitter(io.StringIO(), allow_unicode=True)  # only its analysis of a scalar is used: it writes nothing

# A string whose every character PyYAML's analysis treats as ordinary text: printable (unicode allowed, no BOM), no
# line break, tab, `#` or `:`; not starting with an indicator, a space or `.` (`...`), not ending with a space. For
# such a string the analysis allows plain style, so only the resolver decides (`yes`, `12`, `~` are quoted).
# The pattern excludes only ASCII (a class reaching past U+FFFF cost a cold run about 3M instructions to compile, and
# the allowed ranges spelled out 10-20 ms each: issue #36); `_ordinary` checks each other character in Python.
_ORDINARY_ASCII = re.compile(r"(?![\s#,\[\]{}&*!|>'\"%@`?:.-])[^\x00-\x1f#:\x7f]+(?<! )")
_FIRST_INDICATORS = frozenset("#,[]{}&*!|>'\"%@`")  # PyYAML's analysis: as a first character, a flow and block indicator


def _ordinary_char(c: str) -> bool:
    """A character beyond ASCII that PyYAML's analysis takes for ordinary text: not C1, a line or paragraph separator,
    a surrogate, the BOM, or U+FFFE and above."""
    code = ord(c)
    return code > 0x9F and code not in (0x2028, 0x2029, 0xFEFF) and not 0xD800 <= code <= 0xDFFF and code < 0xFFFE


def _ordinary(text: str) -> bool:
    """Whether `text` is ordinary text (above). Most text is ASCII, which the pattern alone decides; in other text each
    character beyond ASCII is spelled as one the pattern allows (`a`) or refuses (NUL): a first one that is whitespace
    (`\\s` matches Unicode whitespace, as str.isspace) is refused, as the pattern's look-ahead refuses it."""
    if not text.isascii():
        if not text[0].isascii() and text[0].isspace():
            return False
        text = "".join([c if c.isascii() else "a" if _ordinary_char(c) else "\x00" for c in text])
    return _ORDINARY_ASCII.fullmatch(text) is not None


def _special(code: str) -> bool:
    """Whether `code` holds a character PyYAML escapes, or a line break other than `\\n`: in ASCII a control other than
    `\\n` (what str.isprintable refuses there), beyond it the pattern's (compiled only for such code: about 2M
    instructions, and a lambda's code is ASCII)."""
    if code.isascii():
        return not code.replace("\n", " ").isprintable()
    return _special_pattern().search(code) is not None


@functools.cache
def _special_pattern() -> re.Pattern[str]:
    return re.compile("[\x00-\x09\x0b-\x1f\x7f-\x9f\u2028\u2029\ud800-\udfff\ufeff\ufffe-\U0010ffff]")


_SINGLE_SPACE = re.compile(r"(?<! ) (?! )")  # where PyYAML may fold: a space that is not part of a run


def _resolves(text: str) -> str:
    """The tag PyYAML's resolver gives `text` written plain."""
    tag: str = _RESOLVER.resolve(yaml.ScalarNode, text, (True, False))  # type: ignore[no-untyped-call]
    return tag


@functools.lru_cache(maxsize=4096)
def _plain(text: str) -> bool:
    """PyYAML writes the string plain (else single-quoted: double-quoted and multi-line strings are unsupported)."""
    if _ordinary(text):
        return _resolves(text) == _STR
    # Ordinary but for a `:` or `#` after the first character (`Run status: Fault`): PyYAML's analysis, about 3.5 ms of a
    # run over these, finds a block indicator exactly at `: `, a final `:` or ` #` (the only whitespace allowed is the
    # space), and nothing else that could stop plain or single-quoted style.
    marked = text.replace(":", "a").replace("#", "a")
    if marked != text and text[0] not in "#:" and _ordinary(marked):
        return not (": " in text or text.endswith(":") or " #" in text) and _resolves(text) == _STR
    # An indicator first (a Home Assistant template's `{{`), the rest ordinary: the analysis forbids plain, allows quotes.
    if text[:1] in _FIRST_INDICATORS and _ordinary("a" + marked[1:]):
        return False
    analysis = _ANALYZER.analyze_scalar(text)
    if analysis.multiline or not analysis.allow_single_quoted:
        raise _Unsupported(text)
    return bool(analysis.allow_block_plain) and _resolves(text) == _STR


class _Writer:
    """PyYAML's block emitter for the supported shapes; `column` is where the next character goes, as PyYAML counts it."""

    def __init__(self, out: list[str]) -> None:
        self.out = out
        self.column = 0

    def write(self, text: str) -> None:
        self.out.append(text)
        self.column += len(text)

    def newline(self, indent: int) -> None:
        self.out.append("\n" + " " * indent)
        self.column = indent

    def mapping(self, data: dict[Any, Any], indent: int, inline: bool) -> None:
        """A block mapping whose keys start at `indent`; `inline`: its first key follows a `- ` (or starts the file)."""
        for key, value in data.items():
            if inline:
                self.write(" " * (indent - self.column))
            else:
                self.newline(indent)
            inline = False
            if type(key) is not str or not key or len(key) >= MAX_SIMPLE_KEY:
                raise _Unsupported(key)
            self.write((key if _plain(key) else "'" + key.replace("'", "''") + "'") + ":")  # a key is never folded
            self.node(value, indent, in_mapping=True)

    def sequence(self, data: list[Any], indent: int, inline: bool) -> None:
        for item in data:
            if inline:
                self.write(" " * (indent - self.column) + "-")
            else:
                self.newline(indent)
                self.write("-")
            inline = False
            self.node(item, indent, in_mapping=False)

    def node(self, value: Any, indent: int, in_mapping: bool) -> None:
        """`value` after `key:` of a mapping at `indent` or after `-` of a sequence at `indent`."""
        kind = type(value)
        if kind is dict or kind is list:
            if not value:
                self.write(" {}" if kind is dict else " []")
            elif kind is dict:
                self.mapping(value, indent + INDENT, inline=not in_mapping)
            elif in_mapping:
                self.sequence(value, indent, inline=False)  # PyYAML does not indent a sequence under a key
            else:
                self.sequence(value, indent + INDENT, inline=True)
        elif kind is str:
            self.string(value, indent + INDENT)
        elif kind is Lambda:
            self.literal(value.code, indent + INDENT)
        else:
            self.write(" " + _scalar_text(value))

    def string(self, text: str, indent: int) -> None:
        """A string value, plain or single-quoted, folded at a single space once past WIDTH as PyYAML folds it."""
        quoted = not _plain(text)
        lead = " '" if quoted else " "
        if self.column + len(lead) + len(text) <= WIDTH and "'" not in text:  # most strings: one piece, nothing folded
            self.write(lead + text + "'" if quoted else lead + text)
            return
        self.write(lead)
        self._folded(text.replace("'", "''") if quoted else text, indent, quoted)  # a doubled quote: two columns

    def _folded(self, text: str, indent: int, quoted: bool) -> None:
        """`text` (its quotes doubled if `quoted`) folded at each single space where the column has passed WIDTH, but not
        at a quoted text's first or last character; found by jumping to the first single space past WIDTH rather than
        writing space by space: most of a long text is not near a fold."""
        start = 0  # the first character not yet written
        after = 0  # where the next single space may be
        while (match := _SINGLE_SPACE.search(text, max(after, start + WIDTH - self.column + 1))) is not None:
            space = match.start()
            after = space + 1
            if quoted and not 0 < space < len(text) - 1:  # a quoted text's first and last space are kept
                continue
            self.write(text[start:space])
            self.newline(indent)
            start = space + 1
        self.write(text[start:])
        if quoted:
            self.write("'")

    def literal(self, code: str, indent: int) -> None:
        """A `!lambda |-` block: code without a leading space, trailing spaces, trailing line break or special characters."""
        if not code or code[0] in " \n" or code[-1] in " \n" or " \n" in code or _special(code):
            raise _Unsupported(code)
        self.write(" !lambda |-")
        for line in code.split("\n"):
            self.out.append("\n" + (" " * indent + line if line else ""))
        self.column = indent + len(line) if line else 0


def _scalar_text(value: Any) -> str:
    """A non-string scalar as PyYAML's safe representer writes it, when it reads back as that type written plain."""
    kind = type(value)
    if kind is bool:
        return "true" if value else "false"
    if value is None:
        return "null"
    if kind is int:
        return str(value)
    if kind is Hex:
        text = _hex_text(value)
        if _resolves(text) == _INT:
            return text
    elif kind is float and value == value and value not in (float("inf"), float("-inf")):
        text = repr(value).lower()
        if "." not in text and "e" in text:
            text = text.replace("e", ".0e", 1)
        if _resolves(text) == _FLOAT:
            return text
    raise _Unsupported(value)
