"""Which column is which: headers recognised in English or Chinese, or named by a mapping file.

A mapping file (`--columns MAPPING.yaml`) is YAML:

    columns: {功能码: param, 名称: title_zh, 设定范围: range}   # header as printed -> field
    param_ids:                                                # addresses from parameter ids (C630S)
      - {regex: '^P(?P<group>[0-9A-F]{2})-(?P<index>[0-9]{2})$', format: 'P{group:02X}-{index:02d}', group_radix: 16, group_stride: 256}
    sheet: Sheet1                                             # optional, like --sheet
    addresses: modicon                                        # optional, like --addresses: modicon or plain

A "Gain" column divides (value = raw / gain); "Scale", "Multiplier" and "Resolution" multiply
(value = raw x scale). "Scale factor register" and "SF" (比例因子寄存器) name the s16 register whose raw
value sf scales the row's register (value = raw x 10^sf, SunSpec). A header that may mean either ("Factor", "Scale factor", "Coefficient") is
refused until the mapping names it: `columns: {Factor: gain}` or `{Factor: scale}`.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import yaml

from regmap.diagnostics import UsageError

FIELDS: dict[str, str] = {
    "name": "identifier (snake_case)",
    "param": "the manual's parameter id",
    "address": "register address (0x0191, 0191h or 401)",
    "address_hex": "register address in hex (the export's second address column)",
    "type": "u16 s16 u32 s32 u64 s64 f16 f32 f64 string bool (also uint16, int32, float16, float, double, 浮点数, 字符串 ...)",
    "words": "register count: a string's length, otherwise checked against type (1 or 2 gives u16/u32 without a type)",
    "word_order": "high_first or low_first",
    "paired": "iDM-RS pair (true/false)",
    "access": "r rw w",
    "unit": "unit, optionally with its step (0.1A)",
    "scale": "raw x scale = value (also multiplier, resolution)",
    "gain": "raw / gain = value (as vendors print a gain or a divisor)",
    "min": "raw minimum",
    "max": "raw maximum",
    "default": "raw default",
    "range": "the range as printed, in engineering units (0~655.35)",
    "min_value": "minimum in engineering units",
    "max_value": "maximum in engineering units",
    "default_value": "default in engineering units, as printed",
    "range_text": "the range text the map keeps",
    "enum": "name of an enum",
    "bitfields": "one field per line: BITS NAME [<ENUM>]: TITLE",
    "takes_effect": "立即生效 / 再次通电 / 停机生效 or immediately / after_restart / when_stopped",
    "settable": "运行设定 / 停机设定 / 显示 or always / when_stopped / display_only",
    "modes": "PST, PS, ALL, -",
    "group": "group id",
    "array": "array element (array[index].member); read-only information",
    "title": "English title",
    "title_zh": "Chinese title",
    "description": "text",
    "source": "manual section(s)",
    "errata": "erratum ids",
    "notes": "text",
    "space": "holding, input, coil, discrete_input (also 4x/3x/0x/1x, 保持寄存器, 输入寄存器, 线圈, 离散输入, or a read function code 03/04/01/02)",
    "byte_order": "high_first or low_first (also big/little endian, AB/BA, ABCD/CDAB/BADC/DCBA, 高字节在前/低字节在前)",
    "offset": "value = raw x scale + offset",
    "encoding": "a string's encoding: ascii, latin-1, utf-8, gbk",
    "padding": "what fills a string after its text: nul or space",
    "firmware_from": "first firmware version with the register (inclusive)",
    "firmware_until": "first firmware version without it (exclusive)",
    "poll": "static, fast, normal or slow (also 静态, 快, 普通, 慢)",
    "zone": "a timestamp's clock: utc or local (the table's own word; never guessed)",
    "na": "'not available' markers the device sends for no value: 0xFFFF, 0x7FFF, NaN (a float's), comma separated",
    "variants": "the models or options that have the register (device.variants), comma separated; empty: every one",
    "scale_from": "the name of the s16 scale-factor register (SunSpec's SF): value = raw x 10^sf, sf read from the device",
}

HEADERS: dict[str, str] = {
    # English (the export's own headers are the field names)
    **{f: f for f in FIELDS},
    "addr": "address",
    "reg": "address",
    "register": "address",
    "register address": "address",
    "modbus address": "address",
    "address (hex)": "address_hex",
    "hex": "address_hex",
    "parameter": "param",
    "param id": "param",
    "parameter id": "param",
    "identifier": "name",
    "data type": "type",
    "read/write": "access",
    "r/w": "access",
    "range": "range",
    "setting range": "range",
    "default": "default",
    "factory default": "default_value",
    "factory setting": "default_value",
    "takes effect": "takes_effect",
    "effective": "takes_effect",
    "modes": "modes",
    "related modes": "modes",
    "title (en)": "title",
    "title (zh)": "title_zh",
    "chinese title": "title_zh",
    "section": "source",
    "units": "unit",
    "multiplier": "scale",
    "resolution": "scale",
    "gain": "gain",
    "divisor": "gain",
    "增益": "gain",
    "quantity": "words",
    "length": "words",
    "words": "words",
    "number of registers": "words",
    "no. of registers": "words",
    "register count": "words",
    "remarks": "notes",
    "comments": "notes",
    # Chinese, as the manuals print them
    "地址": "address",
    "寄存器地址": "address",
    "通讯地址": "address",
    "通信地址": "address",
    "modbus地址": "address",
    "参数号": "param",
    "参数编号": "param",
    "功能码": "param",
    "参数代码": "param",
    "代码": "param",
    "名称": "title_zh",
    "参数名称": "title_zh",
    "中文名称": "title_zh",
    "英文名称": "title",
    "设定范围": "range",
    "范围": "range",
    "取值范围": "range",
    "出厂值": "default_value",
    "出厂设定": "default_value",
    "默认值": "default_value",
    "缺省值": "default_value",
    "单位": "unit",
    "生效方式": "takes_effect",
    "生效": "takes_effect",
    "设定方式": "settable",
    "相关模式": "modes",
    "读写": "access",
    "属性": "access",
    "数据类型": "type",
    "类型": "type",
    "枚举": "enum",
    "位定义": "bitfields",
    "章节": "source",
    "出处": "source",
    "说明": "description",
    "备注": "notes",
    "分组": "group",
    # spaces, orders, offsets, strings, firmware gates, poll classes
    "register type": "space",
    "table": "space",
    "modbus table": "space",
    "data area": "space",
    "function code": "space",
    "read function code": "space",
    "fc": "space",
    "寄存器类型": "space",
    "寄存器区": "space",
    "数据区": "space",
    "存储区": "space",
    "读功能码": "space",
    "byte order": "byte_order",
    "byte swap": "byte_order",
    "endianness": "byte_order",
    "字节序": "byte_order",
    "字节顺序": "byte_order",
    "value offset": "offset",
    "偏移量": "offset",
    "零点偏移": "offset",
    "字符编码": "encoding",
    "编码": "encoding",
    "填充": "padding",
    "字数": "words",
    "寄存器数量": "words",
    "寄存器个数": "words",
    "length (words)": "words",
    "firmware from": "firmware_from",
    "since firmware": "firmware_from",
    "min firmware": "firmware_from",
    "起始固件版本": "firmware_from",
    "最低固件版本": "firmware_from",
    "firmware until": "firmware_until",
    "until firmware": "firmware_until",
    "截止固件版本": "firmware_until",
    "poll class": "poll",
    "轮询": "poll",
    "轮询等级": "poll",
    "not available": "na",
    "n/a value": "na",
    "invalid value": "na",
    "无效值": "na",
    "zone": "zone",
    "time zone": "zone",
    "timezone": "zone",
    "时区": "zone",
    "variant": "variants",
    "models": "variants",
    "applicable models": "variants",
    "available on": "variants",
    "适用机型": "variants",
    "适用型号": "variants",
    # a register scaled by another (SunSpec's scale factors): the cell names that s16 register
    "scale factor register": "scale_from",
    "scale factor point": "scale_from",
    "sf register": "scale_from",
    "sf point": "scale_from",
    "sf": "scale_from",
    "scale from": "scale_from",
    "比例因子寄存器": "scale_from",
    "比例系数寄存器": "scale_from",
    "缩放因子寄存器": "scale_from",
    "倍率寄存器": "scale_from",
}


def normalise(header: str) -> str:
    """Headers are compared lower-case, without spaces, line breaks or a trailing colon."""
    return re.sub(r"[\s:：]+", "", header).lower()


_KNOWN = {normalise(k): v for k, v in HEADERS.items()}

AMBIGUOUS = {
    normalise(h): "raw x factor or raw / factor"
    for h in ("factor", "scale factor", "scaling factor", "scaling", "coefficient", "ratio", "倍率", "系数")
}
"""Headers that vendors print for a multiplier and for a divisor alike: refused until a mapping names them."""

ADDRESS_FORMS = ("modicon", "plain")


@dataclass
class Mapping:
    columns: dict[str, str] = field(default_factory=dict)  # normalised header -> field
    param_ids: list[dict[str, Any]] = field(default_factory=list)
    sheet: str | None = None
    addresses: str | None = None  # modicon or plain: how a decimal address column reads (None: see rows.address_form)


def load_mapping(path: str | Path) -> Mapping:
    try:
        data = yaml.safe_load(Path(path).read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, yaml.YAMLError) as exc:
        raise UsageError(f"{path}: cannot read the column mapping: {exc}") from None
    if not isinstance(data, dict) or not set(data) <= {"columns", "param_ids", "sheet", "addresses"}:
        raise UsageError(f"{path}: a column mapping has the keys columns, param_ids, sheet and addresses")
    addresses = data.get("addresses")
    if addresses is not None and addresses not in ADDRESS_FORMS:
        raise UsageError(f"{path}: addresses: expected modicon or plain, not {addresses!r}")
    columns = data.get("columns") or {}
    if not isinstance(columns, dict):
        raise UsageError(f"{path}: columns: expected a mapping of header -> field")
    out: dict[str, str] = {}
    for header, name in columns.items():
        if name not in FIELDS:
            raise UsageError(f"{path}: column {header!r}: unknown field {name!r} (fields: {', '.join(FIELDS)})")
        out[normalise(str(header))] = str(name)
    rules = data.get("param_ids") or []
    if not isinstance(rules, list) or not all(isinstance(r, dict) for r in rules):
        raise UsageError(f"{path}: param_ids: expected a list of rules as in a map")
    sheet = data.get("sheet")
    return Mapping(out, rules, None if sheet is None else str(sheet), addresses)


def recognise(header: list[str], mapping: Mapping) -> dict[int, str]:
    """Column index -> field for every header recognised; a field named twice keeps its first column.

    A vendor's "Default" beside a range is printed in engineering units, as the range is: it reads as
    `default_value` (the export's raw `default` comes with raw `min` and `max` columns)."""
    found: dict[int, str] = {}
    taken: set[str] = set()
    for i, cell in enumerate(header):
        key = normalise(cell)
        name = mapping.columns.get(key) or _KNOWN.get(key)
        if name and name not in taken:
            found[i] = name
            taken.add(name)
    printed = taken & {"range", "min_value", "max_value"}
    if printed and "default" in taken and not taken & {"min", "max", "default_value"}:
        column = next(i for i, n in found.items() if n == "default")
        if normalise(header[column]) not in mapping.columns:  # a mapping that says `default` is obeyed
            found[column] = "default_value"
    return found


def ignored(header: list[str], columns: dict[int, str], rows: list[list[str]]) -> dict[int, str]:
    """Column index -> why it is not read, for every column with a header or a value that no field takes."""
    out: dict[int, str] = {}
    width = max([len(header), *(len(r) for r in rows)], default=0)
    for i in range(width):
        if i in columns:
            continue
        text = header[i].strip() if i < len(header) else ""
        if text and normalise(text) in AMBIGUOUS:
            out[i] = "ambiguous"
        elif text and (mapping_field := _KNOWN.get(normalise(text))) in columns.values():
            out[i] = f"{mapping_field} already comes from another column"
        elif text:
            out[i] = "not a header regmap knows (name it with --columns MAPPING.yaml)"
        elif any(i < len(r) and r[i].strip() for r in rows):
            out[i] = "no header (name it with --columns MAPPING.yaml)"
    return out


def looks_like_header(cells: list[str], mapping: Mapping) -> bool:
    return len(recognise(cells, mapping)) >= 2
