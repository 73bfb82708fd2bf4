"""Parse generated Structured Text; run inside the ST tools' own venv (blark, tree-sitter-iec61131-3-st).

Usage: parse_st.py blark|tree-sitter FILE...; prints one JSON list of problems ("file:line: ...").

tree-sitter parses every file whole. blark's Earley parser reads ~100 lines a second, too slow for the
60,000 generated lines, so each file is cut into its top-level declarations (and a constant list into
its lines, each one declaration) and blark parses, verbatim, declarations until every distinct line
shape (a line with identifiers, numbers, strings and comments blanked out) has been parsed in at least
one of them: lines of one shape differ only in tokens the grammar treats alike, and every name is
checked by the generator. tree-sitter still reads everything.
"""

from __future__ import annotations

import json
import re
import sys

COMMENT = re.compile(r"\(\*.*?\*\)")
STRING = re.compile(r"'(?:\$.|[^'$])*'")
NUMBER = re.compile(r"\b(?:16#[0-9A-Fa-f_]+|\d+(?:\.\d+)?(?:[eE][-+]?\d+)?)\b")
WORD = re.compile(r"\b[A-Za-z_][A-Za-z0-9_]*\b")
CONVERSION = re.compile(r"^[A-Z]+_TO_[A-Z]+$")
KEYWORDS = set(
    [
        "TYPE",
        "END_TYPE",
        "STRUCT",
        "END_STRUCT",
        "ARRAY",
        "OF",
        "VAR_GLOBAL",
        "CONSTANT",
        "END_VAR",
        "VAR",
        "VAR_INPUT",
        "VAR_IN_OUT",
        "FUNCTION",
        "END_FUNCTION",
        "IF",
        "THEN",
        "ELSE",
        "ELSIF",
        "END_IF",
        "CASE",
        "END_CASE",
        "RETURN",
        "NOT",
        "AND",
        "OR",
        "TRUE",
        "FALSE",
        "BOOL",
        "WORD",
        "DWORD",
        "UINT",
        "INT",
        "UDINT",
        "DINT",
        "LINT",
        "USINT",
        "REAL",
        "LREAL",
        "STRING",
        "SHL",
        "SHR",
        "ABS",
        "attribute",
    ]
)


def _shapes(text: str) -> set[str]:
    """The distinct lines of a declaration with identifiers, numbers, strings and comments blanked out."""
    text = STRING.sub("'s'", COMMENT.sub("", text))
    text = NUMBER.sub("1", text)
    text = WORD.sub(lambda m: m[0] if m[0] in KEYWORDS or CONVERSION.match(m[0]) else "X", text)
    return {line.strip() for line in text.splitlines() if line.strip()}


def _declarations(text: str) -> list[tuple[int, str]]:
    """(first line, text) of each top-level declaration; each line of a VAR_GLOBAL list is one."""
    out: list[tuple[int, str]] = []
    lines = text.splitlines()
    start = 0
    in_globals = False
    for i, line in enumerate([*lines, ""]):
        if line.startswith("VAR_GLOBAL"):
            in_globals = True
        elif in_globals:
            if line == "END_VAR":
                in_globals = False
            elif line.strip() and not COMMENT.fullmatch(line.strip()):
                out.append((i + 1, f"VAR_GLOBAL CONSTANT\n{line}\nEND_VAR\n"))
            start = i + 1
            continue
        if line.strip():
            continue
        chunk = lines[start:i]
        if any(not COMMENT.fullmatch(x.strip()) for x in chunk):
            out.append((start + 1, "\n".join(chunk) + "\n"))
        start = i + 1
    return out


def blark_problems(paths: list[str]) -> list[str]:
    from blark.parse import parse_source_code  # type: ignore[import-not-found]

    covered: set[str] = set()
    chosen: list[tuple[str, int, str]] = []
    for path in paths:
        with open(path, encoding="utf-8") as f:
            for line, decl in _declarations(f.read()):
                shapes = _shapes(decl)
                if not shapes <= covered:
                    covered |= shapes
                    chosen.append((path, line, decl))
    problems = []
    for path, line, decl in chosen:
        result = parse_source_code(decl, fn=path)
        if result.exception is not None:
            problems.append(f"{path}:{line}: blark: {str(result.exception)[:400]}")
    return problems


def tree_sitter_problems(paths: list[str]) -> list[str]:
    import tree_sitter  # type: ignore[import-not-found]
    import tree_sitter_iec61131_3_st  # type: ignore[import-not-found]

    parser = tree_sitter.Parser(tree_sitter.Language(tree_sitter_iec61131_3_st.language()))
    problems = []
    for path in paths:
        with open(path, "rb") as f:
            tree = parser.parse(f.read())
        stack = [tree.root_node]
        while stack:
            node = stack.pop()
            if node.is_error or node.is_missing:
                problems.append(f"{path}:{node.start_point[0] + 1}: tree-sitter: {node.type} at {node.text[:60]!r}")
            elif node.has_error:
                stack.extend(node.children)
    return problems


if __name__ == "__main__":
    tool, files = sys.argv[1], sys.argv[2:]
    print(json.dumps(blark_problems(files) if tool == "blark" else tree_sitter_problems(files)))
