"""Validate PLCopen XML files against the TC6 XML schema; run inside the plcopen tool venv (lxml).

Usage: validate_plcopen.py SCHEMA.xsd FILE...; prints one JSON list of problems ("file:line: message").
"""

from __future__ import annotations

import json
import sys

from lxml import etree  # type: ignore[import-untyped, unused-ignore]


def main(argv: list[str]) -> int:
    schema = etree.XMLSchema(etree.parse(argv[0]))
    problems = []
    for path in argv[1:]:
        try:
            document = etree.parse(path)
        except etree.XMLSyntaxError as exc:
            problems.append(f"{path}:{exc.lineno}: not well-formed: {exc.msg}")
            continue
        if not schema.validate(document):
            problems += [f"{path}:{error.line}: {error.message}" for error in schema.error_log]
    print(json.dumps(problems))
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
