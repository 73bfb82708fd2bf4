"""The C630S manual's chapter 7 parameter tables as a CSV, the way a vendor's sheet would give them.

Rows are copied cell for cell from ../shared/manuals/c630s.txt (tab-separated in the text); only the
section number is added as a column (章节), so that the draft cites its source. Nothing is corrected:
what the manual prints wrongly or splits across lines stays so, and the import must report it.

    python tests/support/c630s_table.py write OUT.csv   # write the table
    python tests/support/c630s_table.py report          # import it into a draft; the agreement with maps/c630s.yaml
"""

from __future__ import annotations

import csv
import os
import re
import sys
from pathlib import Path

# ../shared beside the repository, or where REGMAP_SHARED_DIR says (as tests/conftest.py and tool_envs.py read it)
MANUAL = Path(os.environ.get("REGMAP_SHARED_DIR") or Path(__file__).resolve().parents[2].parent / "shared") / "manuals" / "c630s.txt"
HEADER = ["功能码", "名称", "设定范围", "单位", "出厂设定", "生效方式", "设定方式", "相关模式", "章节"]
MAPPING = """\
# C630S chapter 7: no address column; the address of PXX-YY is XX << 8 | YY (YY decimal), as in maps/c630s.yaml.
param_ids:
  - {regex: '^P(?P<group>[0-9A-F]{2})-(?P<index>[0-9]{2})$', format: 'P{group:02X}-{index:02d}', group_radix: 16, group_stride: 256}
"""


class ManualAbsent(Exception):
    """The manual's text is beside the repository only in the shared layout (../shared/manuals)."""


def manual_path() -> Path:
    if not MANUAL.is_file():
        raise ManualAbsent(f"{MANUAL} is absent: the manuals are beside the repository only in the shared layout")
    return MANUAL


def chapter7_rows(text: str) -> list[list[str]]:
    """Every parameter row of chapter 7 (7.1 ... 7.18), its section appended."""
    body = text[
        text.index("第七章 参数说明", text.index("第七章 参数说明") + 1) : text.index("第八章 故障处理", text.rindex("第七章 参数说明"))
    ]
    rows, section = [], ""
    for line in body.splitlines():
        heading = re.match(r"^(7\.[0-9]+) ", line)
        if heading:
            section = heading.group(1)
            continue
        if re.match(r"^P[0-9A-FO]{2}-[0-9]{2}\t", line):
            cells = line.split("\t")[:8]
            rows.append(cells + [""] * (8 - len(cells)) + [section])
    return rows


def write_table(out: Path) -> int:
    rows = chapter7_rows(manual_path().read_text(encoding="utf-8"))
    with out.open("w", encoding="utf-8-sig", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(HEADER)
        writer.writerows(rows)
    return len(rows)


FIELDS = ("address", "range", "default", "unit", "scale")


def agreement(draft_text: str, map_path: Path) -> dict[str, object]:
    """How many of the map's registers the draft reproduces, field by field (matched by parameter id)."""
    from fractions import Fraction

    import yaml

    from regmap.frontend import load_map

    device = load_map(map_path)
    draft = yaml.safe_load(draft_text)
    drafted = {r["param"]: r for g in draft["groups"] for r in g["registers"] if r.get("param")}
    result: dict[str, object] = {"map_registers": len(device.registers)}
    counts = dict.fromkeys(FIELDS, 0)
    differ: dict[str, list[str]] = {f: [] for f in FIELDS}
    missing = []
    for reg in device.registers:
        got = drafted.get(reg.param or "")
        if got is None:
            missing.append(reg.param or reg.name)
            continue
        pairs = {
            "address": (reg.address, got["address"]),
            "range": ((reg.min, reg.max), (got.get("min"), got.get("max"))),
            "default": (reg.default, got.get("default")),
            "unit": (reg.unit, got.get("unit")),
            "scale": (reg.scale, Fraction(str(got.get("scale", 1)))),
        }
        for name, (want, have) in pairs.items():
            if want == have:
                counts[name] += 1
            else:
                differ[name].append(f"{reg.param}: map {want} table {have}")
    result.update(in_table=len(device.registers) - len(missing), not_in_table=missing, agree=counts, differ=differ)
    return result


def report(out_dir: Path) -> str:
    """Write the table, import it into a new draft, and say how far it agrees with maps/c630s.yaml."""
    import subprocess

    root = Path(__file__).resolve().parents[2]
    table, mapping, draft = out_dir / "c630s-ch7.csv", out_dir / "c630s-columns.yaml", out_dir / "c630s_draft.yaml"
    rows = write_table(table)
    mapping.write_text(MAPPING, encoding="utf-8")
    regmap = Path(sys.executable).with_name("regmap")
    run = subprocess.run(
        [str(regmap), "import", str(table), "--columns", str(mapping), "--into", str(draft)], capture_output=True, text=True, check=False
    )
    result = agreement(draft.read_text(encoding="utf-8"), root / "maps" / "c630s.yaml")
    agree = result["agree"]
    assert isinstance(agree, dict)
    unread = [line for line in run.stderr.splitlines() if line.startswith(str(table))]
    lines = [
        f"{rows} table rows; import exit status {run.returncode}; {len(unread)} cell(s) it could not read",
        f"{result['map_registers']} registers in maps/c630s.yaml, {result['in_table']} of them in the table",
        "agree: " + ", ".join(f"{k} {v}/{result['in_table']}" for k, v in agree.items()),
    ]
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    import argparse
    import tempfile

    parser = argparse.ArgumentParser(prog="tests/support/c630s_table.py", description=__doc__.split("\n\n")[0])
    actions = parser.add_subparsers(dest="action", required=True)
    write = actions.add_parser("write", help="write chapter 7 as a CSV")
    write.add_argument("out", type=Path, metavar="OUT.csv")
    actions.add_parser("report", help="import the table into a draft and say how far it agrees with maps/c630s.yaml")
    args = parser.parse_args(argv)
    try:
        if args.action == "write":
            print(write_table(args.out), "rows")
        else:
            with tempfile.TemporaryDirectory() as tmp:
                print(report(Path(tmp)))
    except ManualAbsent as exc:
        print(f"tests/support/c630s_table.py: {exc}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
