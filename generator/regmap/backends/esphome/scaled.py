"""`scale_from` points in the ESPHome package (value = raw x 10^sf, sf the signed raw value of another s16 register).

The scale factor is a sensor of its own (internal when the selection does not show it), so ESPHome reads it and the
point's read plan holds it beside the point. The point is a `modbus_controller` sensor (a `number` when writable)
whose lambda assembles the raw value from the response and scales it:

- sf read in the same ESPHome range as the point: the lambda takes the sf from the same response (`data`), so a
  point and its factor are always one reading. `id(sf).state` would not do: ESPHome publishes a range's items in
  address order, so a factor after its point would still hold the previous read's sf (or none at the first).
- sf read in another range (another poll class or firmware gate, or a gap ESPHome cannot bridge): the lambda
  takes `id(sf).state`, the factor as last read (NaN until then).

The point's or the factor's "not available" marker, or a factor not yet read, give NaN (unknown), never a number.
A write takes the factor as last read, as ESPHome holds no fresher one, and sends nothing (it logs why) when that
is unknown, when the value is no whole multiple of 10^sf (the float nearest raw x 10^sf is what a value must be),
when the raw value is outside the register's range or its marker, or when a float cannot carry it exactly.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from regmap.backends.esphome.lambdas import wire_bytes
from regmap.backends.esphome.text import esp_unit, num
from regmap.homeauto.entities import MAX_DECIMALS, device_class, entity_category, reserved, state_class, swapped, unit_text
from regmap.homeauto.yamltext import Lambda
from regmap.model import Device, Register

if TYPE_CHECKING:
    from regmap.backends.esphome.package import DevicePackage

SF_MIN = -32768  # an s16 factor's lowest raw value: a map that narrows it gives a lower bound of the decimals
FLOAT_EXACT = 1 << 24  # every integer up to this is exact in a float (ESPHome's number sends a float, llroundf)
_SIGNED = {16: "int16_t", 32: "int32_t", 64: "int64_t"}
_UNSIGNED = {16: "uint16_t", 32: "uint32_t", 64: "uint64_t"}


def with_factors(device: Device, registers: tuple[Register, ...]) -> tuple[Register, ...]:
    """`registers` and, after them in map order, the scale factors their `scale_from` points need and they lack."""
    names = {r.name for r in registers}
    wanted = {r.scale_from for r in registers if r.scale_from is not None and r.access.readable}
    return registers + tuple(r for r in device.registers if r.name in wanted - names)


def factor_problem(sf: Register) -> str | None:
    """Why a factor's entity cannot give its raw value (None: it can): its state must be the s16 it reads."""
    if reserved(sf.title):
        return "it is reserved"
    if sf.scaled or sf.offset_set or sf.enum is not None or sf.bitfields:
        return "its entity shows no plain raw value"
    return None


def decimals(sf: Register) -> int:
    """The digits a value shows: 10^-digits is the finest step the factor's declared lowest value (else its default) allows."""
    lowest = sf.raw_min if sf.raw_min > SF_MIN else sf.default if isinstance(sf.default, int) else -MAX_DECIMALS
    return max(0, min(MAX_DECIMALS, -int(lowest)))


def add_point(pkg: DevicePackage, reg: Register) -> None:
    """The point's sensor (number when writable), its lambdas written by `finish` once the factor's entity exists."""
    sf = pkg.device.register(reg.scale_from or "")
    problem = factor_problem(sf)
    if problem is not None:
        pkg.skipped.append(f"{reg.name} (scale_from {sf.name}: {problem})")
        return
    from regmap.backends.esphome.package import NUMBER_LIMIT  # here: the package module imports this one

    entity: dict[str, Any] = {"platform": "modbus_controller", "name": pkg._name(reg.title, reg.name)}
    entity.update(pkg._item(reg, value_type=pkg._value_type(reg)))
    digits = decimals(sf)
    writable = reg.access.writable and reg.raw_min < reg.raw_max and reg.name not in pkg.widened
    if writable and swapped(reg):  # ESPHome's number writes its value_type's words: bytes in the order it reads them
        pkg.skipped.append(f"writes of {reg.name} (byte-swapped: ESPHome's number would send its bytes unswapped; its sensor reads it)")
        writable = False
    if writable:
        # The value's sign is the raw value's (10^sf > 0); its bounds depend on sf: the write lambda checks the raw range.
        low = -NUMBER_LIMIT if reg.raw_min < 0 else 0
        high = NUMBER_LIMIT if reg.raw_max > 0 else 0
        entity.update({"min_value": low, "max_value": high, "step": num(10.0**-digits), "mode": "box"})
        if reg.words == 1 and not pkg.single_write:
            entity["use_write_multiple"] = True
    else:
        entity["accuracy_decimals"] = digits
        if device_class(reg) is not None:
            entity["device_class"] = device_class(reg)
        if state_class(pkg.device, reg) is not None:
            entity["state_class"] = state_class(pkg.device, reg)
    if reg.unit:
        entity["unit_of_measurement"] = unit_text(esp_unit(reg.unit))
    platform = "number" if writable else "sensor"
    pkg.add(platform, entity, reg.name, category=entity_category(pkg.device, reg))
    pkg.scaled_points.append((reg, pkg.made[(reg.name,)][1], platform))  # `add` made the entity anew


def finish(pkg: DevicePackage) -> None:
    """Each point's lambdas (they name the factor's entity id), the added factors made internal, and a point whose
    factor got no entity left out."""
    ranges = _ranges(pkg)
    kept = []
    for reg, entity, platform in pkg.scaled_points:
        sf = pkg.device.register(reg.scale_from or "")
        made = pkg.made.get((sf.name,))
        if made is None or made[0] not in ("sensor", "number"):  # e.g. a writable factor an aligned device reads widened
            pkg.entities[platform].remove(entity)
            if not pkg.entities[platform]:
                del pkg.entities[platform]
            pkg.skipped.append(f"{reg.name} (scale_from {sf.name}: ESPHome has no entity that reads it)")
            continue
        kept.append((reg, entity, platform))
        same = ranges.get(reg.name) is not None and ranges.get(reg.name) == ranges.get(sf.name)
        entity["lambda"] = Lambda(read_lambda(reg, sf, made[1]["id"], 2 * (sf.address - reg.address) if same else None))
        if platform == "number":
            entity["write_lambda"] = Lambda(write_lambda(reg, sf, made[1]["id"]))
    pkg.scaled_points = kept
    for name in pkg.added_factors:
        if (name,) in pkg.made:
            pkg.made[(name,)][1]["internal"] = True


def notes(pkg: DevicePackage) -> list[str]:
    """The header's word on the scaled points (none without them)."""
    if not pkg.scaled_points:
        return []
    added = f" ({', '.join(pkg.added_factors)}: internal, the selection does not show them)" if pkg.added_factors else ""
    return [
        "Points scaled by a factor register (`scale_from`): value = raw x 10^sf, the factor a sensor of its own"
        f"{added}, taken from the same response where one request reads both, else its last state;"
        " unknown (NaN) when the point or its factor reads 'not available' or the factor is not read yet.",
        "Their writes use the factor as last read and send nothing (a warning in the log) while it is unknown, for a value"
        " that is no whole multiple of 10^sf, and for a raw value outside the register's range.",
    ]


def _ranges(pkg: DevicePackage) -> dict[str, int]:
    """Per register with an entity, the ESPHome range that reads it: its plan block's run of words that entities cover
    without a gap (ESPHome joins only items at contiguous addresses into one read); a `force_new_range` register
    (a block's first where the block before ends) is a range of its own, as ESPHome reads it alone."""
    shown = {key[0] for key in pkg.made}
    out: dict[str, int] = {}
    run = 0
    for block, _, _ in pkg.blocks:
        run, end = run + 1, None
        for spec in sorted(block.registers, key=lambda s: pkg.widened.get(s.name, (s.address, s.words))[0]):
            if spec.name not in shown:
                continue
            start, count = pkg.widened.get(spec.name, (spec.address, spec.words))
            alone = bool(pkg.item_keys[spec.name].get("force_new_range"))
            if end is not None and (start > end or alone):
                run += 1
            out[spec.name] = run
            end = max(end or 0, start + count)
            if alone:
                run, end = run + 1, None
    return out


def _point(reg: Register) -> list[str]:
    """Lines that set `const double point` to the register's raw value from its wire bytes, or return NaN."""
    size, bits = 2 * reg.words, 16 * reg.words
    lines = ["const std::size_t o = item->offset;", f"if (data.size() < o + {size}) return NAN;", "uint64_t raw = 0;"]
    lines += [f"raw = (raw << 8) | data[o + {i}];" for i in wire_bytes(reg)]
    lines += [f"if (raw == 0x{pattern:X}u) return NAN;  // the point's 'not available' marker" for pattern in reg.na_bits]
    if reg.type.signed:
        lines += [
            f"const {_UNSIGNED[bits]} u = static_cast<{_UNSIGNED[bits]}>(raw);",
            f"{_SIGNED[bits]} s;",
            "std::memcpy(&s, &u, sizeof s);",
            "const double point = static_cast<double>(s);",
        ]
    else:
        lines.append("const double point = static_cast<double>(raw);")
    return lines


def _factor_from_data(sf: Register, delta: int) -> list[str]:
    """Lines that set `int sf` from the factor's bytes `delta` bytes from the point's in the same response."""
    where = f"o + {delta}" if delta >= 0 else f"o - {-delta}"
    guard = f"data.size() < o + {delta + 2}" if delta >= 0 else f"o < {-delta} || data.size() < o - {-delta} + 2"
    high, low = (f"data[{where} + {i}]" for i in wire_bytes(sf))
    lines = [f"if ({guard}) return NAN;", f"const uint16_t sf_bits = static_cast<uint16_t>(({high} << 8) | {low});"]
    lines += [f"if (sf_bits == 0x{pattern:X}u) return NAN;  // the factor's 'not available' marker" for pattern in sf.na_bits]
    return [*lines, "int16_t sf16;", "std::memcpy(&sf16, &sf_bits, sizeof sf16);", "const int sf = sf16;"]


def _factor_from_state(sf: Register, sf_id: str, refuse: str) -> list[str]:
    """Lines that set `int sf` from the factor's entity, `refuse` (a statement) when it is unknown or its marker."""
    marks = "".join(f" || sf_state == {float(mark)!r}f" for mark in sf.na)
    return [
        f"const float sf_state = id({sf_id}).state;  // the factor as last read: NaN until then",
        f"if (std::isnan(sf_state){marks}) {refuse}",
        "const int sf = static_cast<int>(sf_state);",
    ]


# 10^|sf| by multiplication (exact to 10^22, as the C back end's); beyond a double's range a value is 0 or infinite anyway.
_POWER = ["double scale = 1.0;", "for (int n = sf < 0 ? -sf : sf; n > 0 && scale < 1e300; n--) scale *= 10.0;"]


def read_lambda(reg: Register, sf: Register, sf_id: str, delta: int | None) -> str:
    """The point's value: its raw value x 10^sf as the Python client computes it (raw / 10^-sf correctly rounded,
    then the nearest float); `delta`: the factor's byte offset from the point in the same response, or None to
    take the factor's entity state."""
    factor = _factor_from_data(sf, delta) if delta is not None else _factor_from_state(sf, sf_id, "return NAN;")
    tail = "return static_cast<float>(sf < 0 ? point / scale : point * scale);"
    return "\n".join([*_point(reg), *factor, *_POWER, tail])


def write_lambda(reg: Register, sf: Register, sf_id: str) -> str:
    """The raw value ESPHome should send for x (it sends llroundf of what the lambda returns), or nothing (`{}`)."""
    tag = f'"regmap.{reg.name}"'

    def refuse(why: str, *args: str) -> str:
        extra = "".join(f", {a}" for a in args)
        return f'{{ ESP_LOGW({tag}, "{why}: nothing sent"{extra}); return {{}}; }}'

    low, high = float(max(reg.raw_min, -FLOAT_EXACT)), float(min(reg.raw_max, FLOAT_EXACT))
    lines = _factor_from_state(sf, sf_id, refuse("scale factor unknown (not read yet or not available)"))
    lines += [f"if (!std::isfinite(x)) {refuse('not a number')}", *_POWER]
    lines += [
        "const double raw = std::nearbyint(sf < 0 ? static_cast<double>(x) * scale : static_cast<double>(x) / scale);",
        f"if (static_cast<float>(sf < 0 ? raw / scale : raw * scale) != x) {refuse('%g is not a whole multiple of 10^%d', 'x', 'sf')}",
        f"if (raw < {low!r} || raw > {high!r}) {refuse(f'raw %.0f is outside {num(low)}..{num(high)}', 'raw')}",
    ]
    lines += [f"if (raw == {float(mark)!r}) {refuse('raw %.0f is the not-available marker', 'raw')}" for mark in reg.na]
    return "\n".join([*lines, "return static_cast<float>(raw);"])
