"""The one Jinja environment every back end renders with, and the escaping filters it offers.

Templates print; they do not compute. Anything that came from a map reaches a template either as a
validated identifier or through one of the escaping filters below.
"""

from __future__ import annotations

import functools
import hashlib
import json
import os
import re
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

import jinja2
import jinja2.bccache
from jinja2 import nodes
from jinja2.compiler import CodeGenerator, Frame, optimizeconst

from regmap.model import Device

if TYPE_CHECKING:  # only a plant's run imports the plant model (tests/project/test_generate_imports.py)
    from regmap.plant import Plant

# How many texts each escaping cache keeps: a run over three maps meets about 5,000; a process that generates for
# hours (a build server, a test run) keeps no more than this.
TEXT_CACHE_SIZE = 1 << 15


def py_str(text: str | None) -> str:
    """A Python string literal (repr escapes quotes, backslashes, newlines and control characters)."""
    return repr(text or "")


def py_doc(text: str | None) -> str:
    """Text safe inside a triple-quoted docstring: no closing quotes, no escapes, no stray newlines."""
    cleaned = " ".join((text or "").split())
    return cleaned.replace("\\", "\\\\").replace('"""', '\\"\\"\\"').rstrip('"')


def c_comment(text: str | None) -> str:
    """Text safe inside a /* */ comment on one line: no comment terminators, no line breaks,
    no trigraph-like sequences or backslash-newline splices."""
    cleaned = " ".join((text or "").split())
    return cleaned.replace("*/", "* /").replace("/*", "/ *").replace("\\", "/").replace("??", "?\u200b?")


def c_str(text: str | None) -> str:
    """A C string literal (UTF-8 bytes outside printable ASCII as octal escapes)."""
    out = []
    for byte in (text or "").encode("utf-8"):
        char = chr(byte)
        if char in '"\\':
            out.append("\\" + char)
        elif 0x20 <= byte < 0x7F and char != "?":
            out.append(char)
        else:
            out.append(f"\\{byte:03o}")
    return '"' + "".join(out) + '"'


@functools.lru_cache(maxsize=TEXT_CACHE_SIZE)  # the dialects print the same comments: each text is escaped once
def st_comment(text: str | None) -> str:
    """Text safe inside a Structured Text (* *) comment on one line: CODESYS nests comments, so an
    opener must not reach it either; IEC 61131-3 edition 3's /* */ and // are broken up too."""
    cleaned = " ".join((text or "").split())
    if "*" not in cleaned:  # every token below has one; most text has none
        return cleaned
    for token, broken in (("(*", "( *"), ("*)", "* )"), ("/*", "/ *"), ("*/", "* /")):
        while token in cleaned:
            cleaned = cleaned.replace(token, broken)
    return cleaned


_MD_ESCAPES = str.maketrans(
    {
        "\\": "\\\\",
        "&": "&amp;",
        "~": "&#126;",  # GitHub reads 0~22 ... 0~80 as strikethrough
        "|": "\\|",
        "<": "&lt;",
        ">": "&gt;",
        "`": "\\`",
        "*": "\\*",
        "_": "\\_",
        "[": "\\[",
        "]": "\\]",
    }
)


# Text md_text leaves as it is: single spaces between words of characters that need no escape. Most map text is
# such, and a match costs far less than a split, a join and a translate.
_MD_PLAIN = re.compile(r"[^\s\\&~|<>`*_\[\]]+(?: [^\s\\&~|<>`*_\[\]]+)*")


# `_MD_ESCAPES` as replacements one after the other, `\\` first and `&` second: the later escapes bring in those two and
# no other character escaped here, so each character is escaped once, as by `translate`. A `replace` copies; `translate`
# through a table looks each character up (a KeyError for each one left as it is).
_MD_IN_ORDER = tuple((chr(code), escaped) for code, escaped in _MD_ESCAPES.items())


def md_text(text: str | None) -> str:
    """Inline Markdown text: table pipes, HTML and line breaks neutralised (one pass: no escape is escaped again)."""
    if not text:
        return ""
    if _MD_PLAIN.fullmatch(text):
        return text
    cleaned = " ".join(text.split())
    for char, escaped in _MD_IN_ORDER:
        if char in cleaned:
            cleaned = cleaned.replace(char, escaped)
    return cleaned


# Markup characters as entities; the control characters XML 1.0 cannot carry at all as U+FFFD.
_XML_ESCAPES = str.maketrans(
    {"&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;", **{chr(c): "\ufffd" for c in range(0x20) if chr(c) not in "\t\n\r"}}
)


# The control characters `_XML_ESCAPES` replaces: text almost never has one. The markup characters are replaced one
# by one instead, `&` first: a `replace` per character costs a fraction of a `translate` through a table (an ST body
# has `<` and `>` on most lines).
_XML_CONTROL = re.compile("[" + re.escape("".join(chr(c) for c in range(0x20) if chr(c) not in "\t\n\r")) + "]")
_XML_MARKUP = (("&", "&amp;"), ("<", "&lt;"), (">", "&gt;"), ('"', "&quot;"))


def _printable(text: str) -> bool:
    """True when `text` has no control character but tabs and line breaks (False may still have none): a character
    class searched for costs several times Python's own test of each character."""
    return text.isprintable() or text.replace("\n", "").replace("\t", "").replace("\r", "").isprintable()


@functools.lru_cache(maxsize=TEXT_CACHE_SIZE)  # the PLCopen XML repeats values and comments: each text is escaped once
def xml_text(text: str | None) -> str:
    """XML character data or an attribute value: markup characters as entities, and the control
    characters XML 1.0 cannot carry at all as U+FFFD."""
    text = text or ""
    if not _printable(text) and _XML_CONTROL.search(text):
        return text.translate(_XML_ESCAPES)
    for char, entity in _XML_MARKUP:
        if char in text:
            text = text.replace(char, entity)
    return text


def xml_comment(text: str | None) -> str:
    """Text safe inside an XML <!-- --> comment on one line: no `--`, no `-` at its end."""
    cleaned = xml_text(" ".join((text or "").split()))
    while "--" in cleaned:
        cleaned = cleaned.replace("--", "- -")
    return cleaned + " " if cleaned.endswith("-") else cleaned


def hex4(value: int) -> str:
    return f"0x{value:04X}"


def hex2(value: int) -> str:
    return f"0x{value:02X}"


FILTERS: dict[str, Callable[..., Any]] = {
    "py_str": py_str,
    "py_doc": py_doc,
    "c_comment": c_comment,
    "c_str": c_str,
    "st_comment": st_comment,
    "md": md_text,
    "xml": xml_text,
    "xml_comment": xml_comment,
    "hex4": hex4,
    "hex2": hex2,
    "json": lambda v: json.dumps(v, ensure_ascii=False),
}


# How every template is compiled: part of the template cache's key, as the compiled code depends on it.
_ENVIRONMENT_OPTIONS: dict[str, Any] = {"trim_blocks": True, "lstrip_blocks": True, "keep_trailing_newline": True, "autoescape": False}
NO_TEMPLATE_CACHE_VARIABLE = "REGMAP_NO_TEMPLATE_CACHE"


class TemplateCache(jinja2.FileSystemBytecodeCache):
    """Compiled templates on disk, as Python keeps its bytecode: a template is compiled once per change, not once per
    run. Jinja rejects an entry whose template source changed (its checksum) or whose Jinja/Python made it (its magic);
    the directory name holds regmap's version and the environment's options. An entry that cannot be read or written
    costs the run its compile time, nothing else."""

    def load_bytecode(self, bucket: jinja2.bccache.Bucket) -> None:
        try:
            super().load_bytecode(bucket)
        except Exception:  # a truncated or foreign file: compile the template as if there were no entry
            bucket.reset()

    def dump_bytecode(self, bucket: jinja2.bccache.Bucket) -> None:
        try:
            Path(self.directory).mkdir(parents=True, exist_ok=True)
            super().dump_bytecode(bucket)
        except OSError:
            return


def template_cache_dir() -> Path | None:
    """Where compiled templates live (`$REGMAP_CACHE_DIR/templates`, else `$XDG_CACHE_HOME/regmap/templates`, else
    `~/.cache/regmap/templates`), one directory per regmap version, Jinja version and environment options; None when
    `REGMAP_NO_TEMPLATE_CACHE=1`. `REGMAP_NO_CACHE` (the output cache) leaves it on, as Python's bytecode stays on."""
    from regmap import __version__

    if os.environ.get(NO_TEMPLATE_CACHE_VARIABLE, "") not in ("", "0"):
        return None
    explicit = os.environ.get("REGMAP_CACHE_DIR")
    base = Path(explicit) if explicit else Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "regmap"
    options = hashlib.sha256(json.dumps(_ENVIRONMENT_OPTIONS, sort_keys=True).encode()).hexdigest()[:12]
    return base / "templates" / f"regmap-{__version__}-jinja-{jinja2.__version__}-{options}"


class _CodeGenerator(CodeGenerator):
    """Jinja's code generator, but `x.name` asks Python's `getattr` first, inline: Jinja's `environment.getattr` is a
    Python call per attribute (about 90,000 in a run over three maps). Only when Python finds no such attribute does it
    call `environment.getattr`, which looks for an item and otherwise makes the undefined value, as Jinja does."""

    @optimizeconst
    def visit_Getattr(self, node: nodes.Getattr, frame: Frame) -> None:
        if self.environment.is_async:
            super().visit_Getattr(node, frame)
            return
        # The object is evaluated once: the fallback gets it from `_rm_o`, bound just before Python's lookup.
        self.write("(_rm_v if (_rm_v := getattr((_rm_o := ")
        self.visit(node.node, frame)
        self.write(f"), {node.attr!r}, missing)) is not missing else environment.getattr(_rm_o, {node.attr!r}))")

    def visit_Output(self, node: nodes.Output, frame: Frame) -> None:
        """Jinja 3.1's, but a run of text and `{{ }}` outside a buffer is one `yield` of the pieces joined, not a
        `yield` per piece: each yield is a turn of the generator that the render's join drives (hundreds of
        thousands in a run). The pieces are the same, made by Jinja's own code in the same order."""
        if frame.require_output_check:
            if self.has_known_extends:
                return
            self.writeline("if parent_template is None:")
            self.indent()
        finalize = self._make_finalize()
        body: list[list[Any] | nodes.Expr] = []
        for child in node.nodes:
            try:
                if not (finalize.const or isinstance(child, nodes.TemplateData)):
                    raise nodes.Impossible()
                const = self._output_child_to_const(child, frame, finalize)
            except Exception:  # Jinja's: not constant (Impossible) or failing, left to run time
                body.append(child)
                continue
            if body and isinstance(body[-1], list):
                body[-1].append(const)
            else:
                body.append([const])
        single = len(body) == 1
        if frame.buffer is not None:
            self.writeline(f"{frame.buffer}.append(" if single else f"{frame.buffer}.extend((")
        else:
            self.writeline("yield (" if single else "yield ''.join((")
        after = "" if single and frame.buffer is None else ","  # `yield (x,)` would yield a tuple
        self.indent()
        for item in body:
            if isinstance(item, list):
                self.writeline(self._output_const_repr(item) + after)
            else:
                self.newline(item)
                self._output_child_pre(item, frame, finalize)
                self.visit(item, frame)
                self._output_child_post(item, frame, finalize)
                self.write(after)
        self.outdent()
        self.writeline(")" if single else "))")
        if frame.require_output_check:
            self.outdent()


# The Jinja internals `_CodeGenerator` builds on (Jinja 3.1's). A Jinja without them renders with its own code generator:
# slower, the same text (tests/frontend/test_render_codegen.py fails first, so the change is seen).
JINJA_HOOKS = (
    "visit_Getattr",
    "visit_Output",
    "_make_finalize",
    "_output_child_to_const",
    "_output_const_repr",
    "_output_child_pre",
    "_output_child_post",
)


def own_code_generator() -> bool:
    """Whether this Jinja has what `_CodeGenerator` overrides and calls."""
    return all(callable(getattr(CodeGenerator, name, None)) for name in JINJA_HOOKS)


@functools.cache
def compiled_names() -> str:
    """The file names of compiled templates (`%s`: Jinja's key of the template), named by this module's text: the code
    `_CodeGenerator` writes differs from Jinja's and changes with it, so an entry compiled by Jinja's own generator or
    by another version of this one is never read (Jinja's checksum covers the template's text only)."""
    try:
        code = hashlib.sha256(Path(__file__).read_bytes()).hexdigest()[:12]
    except OSError:  # no file to read (an import from a zip): the regmap version in the directory's name still tells
        code = "unread"
    return f"__regmap_{code}_%s.cache"


class _Template(jinja2.Template):
    """Jinja's template, whose `render` also undoes the cycle a macro makes: the macro's function holds the render's
    context, whose variables hold the macro. Left alone, each render that defines a macro keeps its context, and the
    views it was given, until the cyclic collector runs, which a generate run asks for rarely (cli/generate.py)."""

    def render(self, *args: Any, **kwargs: Any) -> str:
        context = self.new_context(dict(*args, **kwargs))
        try:
            return self.environment.concat(self.root_render_func(context))
        except Exception:
            self.environment.handle_exception()
        finally:
            context.vars.clear()


@functools.cache
def templates(module: str) -> jinja2.Environment:
    """The environment of the back end that `module` (a module's `__name__`) belongs to: the templates in
    the `templates/` folder beside that module, so a back end is one folder. Built once per process, so
    each template is compiled once, not once per device (and, with the template cache, once per change)."""
    where = template_cache_dir()
    env = jinja2.Environment(
        loader=jinja2.PackageLoader(module, "templates"),
        undefined=jinja2.StrictUndefined,
        auto_reload=False,  # a run never edits its templates: no stat of the file at every include
        cache_size=-1,  # a plain dict of the folder's few templates: no LRU bookkeeping under a lock at every include
        bytecode_cache=TemplateCache(str(where), compiled_names()) if where is not None else None,
        **_ENVIRONMENT_OPTIONS,
    )
    env.template_class = _Template
    if own_code_generator():
        env.code_generator_class = _CodeGenerator
    env.filters.update(FILTERS)
    return env


def header_lines(device: Device, generator: str) -> list[str]:
    """The do-not-edit header every generated file starts with (without comment markers)."""
    return [
        f"Generated by regmap from {device.source_path} - do not edit.",
        f"Map version {device.info.map_version}, fingerprint {device.fingerprint}; regenerate with `{generator}`.",
        *(f"Not generated: {item}" for item in device.not_generated),
    ]


def plant_header_lines(plant: Plant, generator: str) -> list[str]:
    """The do-not-edit header of a plant's generated files (without comment markers)."""
    return [
        f"Generated by regmap from {plant.source_path} (plant {plant.id}) - do not edit.",
        f"Plant fingerprint {plant.fingerprint}; regenerate with `{generator}`.",
    ]
