"""The Markdown back end and the docs site: every register on its page at its address, a diagram
for every bitfield register, a strict mkdocs build, and a headless Chromium screenshot of a page."""

from __future__ import annotations

import importlib.util
import os
import random
import re
import shutil
import struct
import subprocess
import sys
import xml.etree.ElementTree as ET
import zlib
from pathlib import Path
from typing import NoReturn

import pytest

from regmap.backends.markdown import diagram_path
from regmap.backends.markdown.text import DocId
from regmap.diagnostics import UsageError
from regmap.frontend import load_map, load_map_text
from regmap.generate import generate, render
from regmap.model import Device, Register
from regmap.render import md_text

from conftest import ROOT

MAP_FILES = sorted((ROOT / "maps").glob("*.yaml")) + sorted((ROOT / "tests" / "maps" / "small").glob("*.yaml"))
SMALL_MAP = ROOT / "tests" / "maps" / "small" / "idm_rs_small.yaml"
CHROMIUM_NAMES = ("chromium", "chromium-browser", "google-chrome")


def _name(path: Path) -> str:
    """A map's name as `regmap generate` run at the top of the repository prints it."""
    return path.relative_to(ROOT).as_posix()


def _device(devices: list[Device], map_file: Path) -> Device:
    return next(d for d in devices if d.source_path == _name(map_file))


def _missing_tool(message: str) -> NoReturn:
    """Skip on a developer's machine; on CI (CI=true) a missing tool is a failure."""
    if os.environ.get("CI") == "true":
        pytest.fail(f"{message} (CI installs it; see .ci/run)")
    pytest.skip(message)


@pytest.fixture(scope="module")
def devices() -> list[Device]:
    loaded = [load_map(path, _name(path)) for path in MAP_FILES]
    ids = [d.id for d in loaded]
    assert len(ids) == len(set(ids)), f"two maps share a device id: {ids}"
    return loaded


@pytest.fixture(scope="module")
def docs(devices: list[Device], tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("generated")
    generate(devices, out, ["markdown"], complete=True)
    return out / "docs"


@pytest.fixture(scope="module")
def site(docs: Path, tmp_path_factory: pytest.TempPathFactory) -> Path:
    if importlib.util.find_spec("mkdocs") is None:
        _missing_tool("mkdocs is not installed (pip install -e '.[dev]')")
    site_dir = tmp_path_factory.mktemp("site")
    result = subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "-f", str(ROOT / "mkdocs.yml"), "-d", str(site_dir)],
        env={**os.environ, "REGMAP_DOCS_DIR": str(docs)},
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
    )
    output = result.stdout + result.stderr
    assert result.returncode == 0, f"mkdocs build --strict failed:\n{output}"
    assert "WARNING" not in output, output
    return site_dir


def _section(page: str, anchor: str) -> str:
    """The text from an anchor's heading to the next heading of the same or a higher level."""
    start = page.index(f'<a id="{anchor}"></a>')
    line_start = page.rfind("\n", 0, start) + 1
    level = len(page[line_start:start].strip())
    ends = [page.find("\n" + "#" * n + " ", start) for n in range(2, level + 1)]
    ends = [e for e in ends if e != -1]
    return page[line_start : min(ends) if ends else len(page)]


def _hex(address: int) -> str:
    return f"`0x{address:04X}`"


def _plain(device: Device) -> list[Register]:
    return [r for r in device.registers if r.array is None]


def _page(docs: Path, device: Device) -> str:
    return (docs / f"{device.id}.md").read_text(encoding="utf-8")


@pytest.mark.parametrize("map_file", MAP_FILES, ids=lambda p: p.stem)
def test_every_register_on_its_page_at_its_address(map_file: Path, devices: list[Device], docs: Path) -> None:
    device = _device(devices, map_file)
    page = _page(docs, device)
    quick_reference = _section(page, "quick-reference")
    for reg in _plain(device):
        section = _section(page, reg.name)
        assert f"`{reg.name}`" in section.splitlines()[0], f"{reg.name}: heading"
        assert _hex(reg.address) in section, f"{reg.name}: address {_hex(reg.address)} missing from its section"
        quick = [line for line in quick_reference.splitlines() if f"(#{reg.name})" in line and line.startswith("| ")]
        assert quick and _hex(reg.address) in quick[0], f"{reg.name}: quick-reference row"
    for array in device.arrays:
        section = _section(page, f"array-{array.name}")
        table = section[section.index("Element addresses:") :].split("\n\n")[1]
        rows = {line.split("|")[1].strip(): line for line in table.splitlines()[2:]}
        for member in array.members:
            first = device.register(f"{array.name}_{array.first_index}_{member.name}")
            assert f"`0x{first.address:04X} + " in section, f"{array.name}.{member.name}: address formula"
        for reg in device.registers:
            if reg.array is not None and reg.array.array == array.name:
                row = rows.get(str(reg.array.index))
                assert row is not None and _hex(reg.address) in row, f"{reg.name}: element table row"
        assert page.count(f'<a id="array-{array.name}"></a>') == 1, f"{array.name} is shown once"


@pytest.mark.parametrize("map_file", MAP_FILES, ids=lambda p: p.stem)
def test_every_register_shows_its_own_value_table(map_file: Path, devices: list[Device], docs: Path) -> None:
    """A register with an enum lists that enum's members (the view of a value table is built once and shared)."""
    device = _device(devices, map_file)
    page = _page(docs, device)
    for reg in _plain(device):
        if reg.enum is not None:
            table = _section(page, reg.name).split("Values:", 1)[1].split("\nSource: ", 1)[0]
            rows = [line for line in table.splitlines() if line.startswith("| ") and line.split("|")[1].strip().lstrip("-").isdigit()]
            assert [row.split("|")[3].strip() for row in rows] == [f"`{m.name}`" for m in reg.enum.members], reg.name


@pytest.mark.parametrize("map_file", MAP_FILES, ids=lambda p: p.stem)
def test_every_bitfield_register_has_a_diagram(map_file: Path, devices: list[Device], docs: Path) -> None:
    device = _device(devices, map_file)
    page = _page(docs, device)
    for reg in device.registers:
        if not reg.bitfields:
            continue
        path = diagram_path(device, reg)
        owner = f"array-{reg.array.array}" if reg.array else reg.name
        assert f"]({path})" in _section(page, owner), f"{reg.name}: diagram {path} not referenced from its section"
        root = ET.parse(docs / path).getroot()
        assert root.tag.endswith("svg"), path
        text = "".join(t for t in root.itertext())
        for b in reg.bitfields:
            assert b.name in text.replace("\n", ""), f"{path}: field {b.name} not drawn"


@pytest.mark.parametrize("map_file", MAP_FILES, ids=lambda p: p.stem)
def test_every_example_annotated(map_file: Path, devices: list[Device], docs: Path) -> None:
    device = _device(devices, map_file)
    page = _page(docs, device)
    for ex in device.examples:
        section = _section(page, f"example-{ex.id}")
        assert " ".join(f"{b:02X}" for b in ex.frame) in section
        crc_rows = [line for line in section.splitlines() if "| CRC |" in line]
        assert crc_rows and ("valid" in crc_rows[0]) != ("**wrong**" in crc_rows[0]), f"{ex.id}: CRC row"
        for value in ex.values:
            assert f"`{value.register.name}`" in section, f"{ex.id}: {value.register.name} not decoded"
    for erratum in device.errata:
        section = _section(page, f"erratum-{erratum.id}")
        rows = [line for line in section.splitlines() if line.startswith("| ")]
        assert len(rows) == len(erratum.readings) + 1, f"{erratum.id}: a header and one row per reading"
        assert "**The map's choice:**" in section


def test_output_is_deterministic(devices: list[Device]) -> None:
    first, second = render(devices, ["markdown"]), render(devices, ["markdown"])
    assert first == second
    for name, text in first["markdown"].items():
        assert not re.search(r"\b20\d\d-\d\d-\d\d\b", text), f"{name} carries a date"
        assert "do not edit" in text, f"{name} has no do-not-edit header"


def test_map_text_cannot_inject_markup() -> None:
    text = SMALL_MAP.read_text(encoding="utf-8")
    evil = 'Peak <script>alert(1)</script> | {: onclick="x"} [a](http://evil) `x` *y*'
    text = text.replace("title: Peak current,", f"title: '{evil}', description: '# not a heading -->',")
    assert evil in text
    device = load_map_text(text, "maps/evil-->.yaml")
    page = render([device], ["markdown"])["markdown"][f"{device.id}.md"]
    assert "<script>" not in page and "&lt;script&gt;" in page
    assert not re.search(r"(?<!\\)\]\(http://evil\)", page), "a title must not make a link"
    assert "evil-->" not in page, "the source path must not end the header comment"
    row = next(line for line in page.splitlines() if "(#peak_current)" in line and line.startswith("| "))
    assert len(re.findall(r"(?<!\\)\|", row)) == 12, "a pipe in a title must not add a table column"
    assert "\n\\# not a heading" in page


def test_md_text_folds_whitespace_and_escapes_markup() -> None:
    """Plain text passes as it is; any other whitespace run becomes one space, and markup is escaped."""
    assert md_text("Outdoor temperature 外温") == "Outdoor temperature 外温"
    assert md_text("  two\tspaces  and\nlines ") == "two spaces and lines"
    assert md_text("full\u3000width") == "full width"
    assert md_text("a_b | <c>") == "a\\_b \\| &lt;c&gt;"
    assert md_text(None) == md_text("") == ""


def test_doc_ids_are_letters_digits_and_underscores() -> None:
    assert DocId("peak_current2") == "peak_current2"
    for bad in ("_peak", "2peak", "peak-current", "peak current", "", "peak\u00e9"):
        with pytest.raises(UsageError, match="cannot name an anchor"):
            DocId(bad)


def test_site_builds_strict(site: Path, devices: list[Device]) -> None:
    for device in devices:
        html = (site / f"{device.id}.html").read_text(encoding="utf-8")
        assert 'id="device-overview"' in html
    assert (site / "index.html").exists()
    assert (site / "map-format.html").exists(), "docs/map-format.md is part of the site"


def _png_pixels(data: bytes) -> tuple[int, int, list[bytes]]:
    """Width, height and rows of pixels of an 8-bit RGB or RGBA PNG (the kind Chromium writes)."""
    assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
    pos, idat, header = 8, b"", b""
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos : pos + 8])
        chunk = data[pos + 8 : pos + 8 + length]
        if kind == b"IHDR":
            header = chunk
        elif kind == b"IDAT":
            idat += chunk
        pos += 12 + length
    width, height, depth, colour, _, _, interlace = struct.unpack(">IIBBBBB", header)
    assert depth == 8 and colour in (2, 6) and interlace == 0, f"unexpected PNG format {depth=} {colour=}"
    bpp = 3 if colour == 2 else 4
    raw = zlib.decompress(idat)
    stride = width * bpp
    rows: list[bytes] = []
    previous = bytearray(stride)
    for y in range(height):
        kind = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1 : (y + 1) * (stride + 1)])
        if kind == 1:
            for i in range(bpp, stride):
                line[i] = (line[i] + line[i - bpp]) & 0xFF
        elif kind == 2:
            line = bytearray((a + b) & 0xFF for a, b in zip(line, previous, strict=True))
        elif kind == 3:
            for i in range(stride):
                left = line[i - bpp] if i >= bpp else 0
                line[i] = (line[i] + ((left + previous[i]) >> 1)) & 0xFF
        elif kind == 4:
            for i in range(stride):
                a = line[i - bpp] if i >= bpp else 0
                b = previous[i]
                c = previous[i - bpp] if i >= bpp else 0
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 0xFF
        rows.append(bytes(line))
        previous = line
    return width, height, [bytes(r[i : i + 3]) for r in rows[::4] for i in range(0, stride, bpp * 4)]


def test_device_page_renders_in_chromium(site: Path, devices: list[Device], tmp_path: Path) -> None:
    chromium = next((found for name in CHROMIUM_NAMES if (found := shutil.which(name))), None)
    if chromium is None:
        _missing_tool("headless Chromium is not installed (apt-get install chromium)")
    device = next((d for d in devices if d.id == "idm_rs"), devices[0])
    png = tmp_path / "page.png"
    result = subprocess.run(
        [
            chromium,
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-quic",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--hide-scrollbars",
            f"--user-data-dir={tmp_path / 'profile'}",
            f"--screenshot={png}",
            "--window-size=1280,2000",
            (site / f"{device.id}.html").as_uri(),
        ],
        capture_output=True,
        text=True,
        timeout=180,
        check=False,
    )
    assert png.exists(), f"Chromium wrote no screenshot:\n{result.stdout}{result.stderr}"
    assert png.stat().st_size > 20_000, "the screenshot is suspiciously small"
    width, height, pixels = _png_pixels(png.read_bytes())
    assert (width, height) == (1280, 2000)
    colours = set(pixels)
    ink = sum(1 for p in pixels if p != b"\xff\xff\xff") / len(pixels)
    assert len(colours) > 64, f"only {len(colours)} colours: the page looks blank"
    assert 0.05 < ink < 0.98, f"{ink:.0%} of the page is not white"


def test_md_text_and_xml_text_escape_as_their_tables_do() -> None:
    """md_text escapes by replacements one after the other and xml_text looks for control characters only in text
    Python does not call printable: both answer as one pass through their tables, on text made of every character
    they treat, whitespace of each kind and wide characters."""
    from regmap.render import _MD_ESCAPES, _XML_ESCAPES, xml_text

    pieces = ["\\", "&", "~", "|", "<", ">", "`", "*", "_", "[", "]", '"', " ", "  ", "\t", "\n", "\r", "\x0b", "\x01"]
    pieces += ["\x1f", "\x7f", "\x85", "\xa0", "\u3000", "\u200b", "外温", "a", "b1", "&amp;", "\\*"]
    generator = random.Random(36)
    texts = ["".join(generator.choice(pieces) for _ in range(generator.randrange(1, 12))) for _ in range(3000)]
    assert [md_text(text) for text in texts] == [" ".join(text.split()).translate(_MD_ESCAPES) for text in texts]
    markup = str.maketrans({"&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;"})
    assert [xml_text(text) for text in texts] == [
        text.translate(_XML_ESCAPES) if any(c in text for c in "\x01\x0b\x1f") else text.translate(markup) for text in texts
    ]
