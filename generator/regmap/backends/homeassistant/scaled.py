"""Registers scaled by another (`scale_from`, SunSpec's sunssf: value = raw x 10^sf, sf the raw s16 value of
another register) in a Home Assistant package. HA's modbus sensor scales by a constant only, so the package
reads the point and its sf as raw modbus sensors and shows the value in a template sensor.

- The raw sensor of the point is named "<title> (raw)" and has no unit, device class or state class, so it
  enters neither statistics nor the energy dashboard; HA's modbus sensor takes no `entity_category` nor
  `entity_registry_visible_default` (2024.3's schema), so it cannot be hidden from here (its unique_id lets
  the user hide it). The sf is its own register's sensor (added when the selection lacks it).
- The template sensor (`<title>`, the register's unit and classes) is unavailable whenever either sensor has no
  value or reads one of its `na` markers (all of them: HA's `nan_value` takes one): never a number for n/a.
  A negative sf divides (raw / 10^-sf is correctly rounded), as the Python client does.
- A writable point gets a script `<prefix>_set_<register>` with a `value` field: it reads the sf afresh
  (`homeassistant.update_entity`), computes the raw value and sends it only when the sf is known (not n/a),
  the value is a whole multiple of 10^sf, and the raw value is inside the register's range and no `na`
  marker; otherwise it stops before the write (the rule of the runtime's `unscaled` and `check_raw`).

The templates hold entity ids, integers computed here, and the variable names below; HA computes the power
of ten at run time because the sf is only known then.
"""

from __future__ import annotations

from typing import Any

from regmap.model import ByteOrder, Register, WordOrder

RAW_VARIABLE = "regmap_raw"  # the script variable holding the raw value to send ('' when refused)
MAX_WRITE_WORDS = 2  # HA's templates compute in floating point: wider raw values are not written exactly


def _ints(values: tuple[int | float, ...]) -> str:
    return "[" + ", ".join(str(int(v)) for v in values) + "]"


def availability(raw_source: str, raw_na: tuple[int | float, ...], sf_source: str, sf_na: tuple[int | float, ...]) -> str:
    """True when both sensors have a value and neither reads one of its `na` markers."""
    parts = [f"has_value('{raw_source}')", f"has_value('{sf_source}')"]
    parts += [f"states('{raw_source}') | int(none) not in {_ints(raw_na)}"] if raw_na else []
    parts += [f"states('{sf_source}') | int(none) not in {_ints(sf_na)}"] if sf_na else []
    return "{{ " + " and ".join(parts) + " }}"


def state(raw_source: str, sf_source: str) -> str:
    """raw x 10^sf; a negative sf divides by 10^-sf (correctly rounded, as the Python client's `scaled`)."""
    return (
        f"{{% set raw = states('{raw_source}') | int(none) %}}{{% set sf = states('{sf_source}') | int(none) %}}"
        "{% if raw is integer and sf is integer %}{{ raw * 10 ** sf if sf >= 0 else raw / 10 ** -sf }}{% endif %}"
    )


def scaled_sensor(reg: Register, raw_source: str, sf: Register, sf_source: str, entity: dict[str, Any]) -> dict[str, Any]:
    """The template sensor of `reg` (`entity`: its name, unique_id, unit and classes) over its raw sensor and its sf's."""
    return entity | {"state": state(raw_source, sf_source), "availability": availability(raw_source, reg.na, sf_source, sf.na)}


def raw_to_send(reg: Register, sf: Register, sf_source: str) -> str:
    """The raw integer carrying the script's `value` at the sf the sensor `sf_source` reads, or '' (nothing to
    send) when the sf is unknown or n/a, the value is not a number, not a whole multiple of 10^sf, outside the
    register's raw range or one of its `na` markers."""
    known_sf = f"sf is integer{f' and sf not in {_ints(sf.na)}' if sf.na else ''}"
    fits = f"{int(reg.raw_min)} <= raw <= {int(reg.raw_max)}" + (f" and raw not in {_ints(reg.na)}" if reg.na else "")
    return (
        f"{{% set sf = states('{sf_source}') | int(none) if has_value('{sf_source}') else none %}}"
        "{% set v = none if value is boolean else value | float(none) %}"
        f"{{% if {known_sf} and v is not none and -1e300 < v < 1e300 %}}"
        "{% set raw = (v * 10 ** -sf if sf <= 0 else v / 10 ** sf) | round(0) | int %}"
        "{% set back = raw * 10 ** sf if sf >= 0 else raw / 10 ** -sf %}"
        f"{{% if back == v and {fits} %}}{{{{ raw }}}}{{% endif %}}{{% endif %}}"
    )


def word_expressions(reg: Register) -> list[str]:
    """The wire words of the raw value in `RAW_VARIABLE` as Jinja expressions, in the order sent (the register's
    word order, each word's bytes exchanged for a low-first byte order): the runtime's `raw_to_words`."""
    words = [f"({RAW_VARIABLE} // {1 << 16 * i} % 65536)" if i else f"({RAW_VARIABLE} % 65536)" for i in reversed(range(reg.words))]
    if reg.word_order is WordOrder.LOW_FIRST:
        words.reverse()
    if reg.byte_order is ByteOrder.LOW_FIRST:
        words = [f"({w} % 256 * 256 + {w} // 256)" for w in words]
    return words


SCALED_NOTE = (
    "Registers scaled by another (value = raw x 10^sf): a raw sensor '<title> (raw)' and the sf's sensor, the value a"
    " template sensor, unavailable while either reads 'not available'; a writable one a script <device>_set_<register>"
    " that reads the sf afresh and sends nothing that is not exactly raw x 10^sf inside the register's range."
)


def unwritable(reg: Register) -> str | None:
    """Why no set script is generated for the writable point (None: one is)."""
    if reg.words > MAX_WRITE_WORDS:
        return f"writing {reg.name} (a {16 * reg.words}-bit value: HA's templates compute in floating point, not exactly)"
    if reg.paired:
        return f"writing {reg.name} (a paired register: its unused high word is not written by this script)"
    return None


def set_script(
    reg: Register, sf: Register, sf_source: str, alias: str, write: dict[str, Any], single_write: bool, note: str
) -> dict[str, Any]:
    """The script writing a value to `reg`: `write` holds the hub, slave and address; one word goes with function
    0x06 when the device has it (`single_write`), else as a list (0x10), as the command scripts do."""
    words = word_expressions(reg)
    value = words[0] if len(words) == 1 and single_write else "[" + ", ".join(words) + "]"
    data = write | {"value": "{{ " + value + " }}"}
    refused = f"{{{{ {RAW_VARIABLE} is integer }}}}"
    about = (
        f"Writes value = raw x 10^{sf.name} to {reg.name}: reads {sf.name} first, and sends nothing when it is unknown or"
        f" 'not available', or the value is no whole multiple of 10^{sf.name}, or the raw value is outside"
        f" {int(reg.raw_min)}..{int(reg.raw_max)}" + (" or its 'not available' marker" if reg.na else "") + f". {note}"
    )
    return {
        "alias": alias,
        "mode": "single",
        "description": about,
        "fields": {
            "value": {
                "description": f"the value to write ({reg.unit or 'no unit'})",
                "required": True,
                "selector": {"number": {"mode": "box", "step": "any"}},
            }
        },
        "sequence": [
            {"service": "homeassistant.update_entity", "target": {"entity_id": [sf_source]}},
            {"variables": {RAW_VARIABLE: raw_to_send(reg, sf, sf_source)}},
            {"condition": "template", "value_template": refused},
            {"service": "modbus.write_register", "data": data},
        ],
    }
