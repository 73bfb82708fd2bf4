"""Scale factors (`scale_from`, SunSpec's sunssf): value = raw x 10^sf, sf the signed raw value of another
register the device reports (and may change at run time). A point's value needs its sf read with it; a write
needs a fresh read of the sf, never a guess."""

from __future__ import annotations

from decimal import Decimal, InvalidOperation
from typing import Any

from .codec import RangeError
from .spec import RegisterSpec


def scaled(raw: int | None, sf: int | None) -> int | float | None:
    """The value of a point read as `raw` with scale factor `sf`; None when either is not available (their `na`).
    A negative sf divides (raw / 10^-sf is correctly rounded: 1234 with sf -1 is 123.4, not 123.40000000000001)."""
    if raw is None or sf is None:
        return None
    value: int | float = raw * 10**sf if sf >= 0 else raw / 10**-sf
    return value


def unscaled(spec: RegisterSpec[Any], value: object, sf: int | None) -> int:
    """The raw integer that carries `value` at scale factor `sf`: refused (RangeError, nothing sent) when the sf is
    not available or `value` is no whole multiple of 10^sf; the caller checks the raw range (codec.check_raw)."""
    if sf is None:
        raise RangeError(
            f"{spec.label}: its scale factor {spec.scale_from} reads 'not available'; no value can be written: nothing was sent"
        )
    if isinstance(value, bool) or not isinstance(value, int | float | str | Decimal):
        raise RangeError(f"{spec.label}: {value!r} is not a number")
    try:
        exact = Decimal(repr(value) if isinstance(value, float) else str(value).strip())
    except InvalidOperation:
        raise RangeError(f"{spec.label}: {value!r} is not a number") from None
    if not exact.is_finite():
        raise RangeError(f"{spec.label}: {value!r} is not a number")
    raw = exact.scaleb(-sf)
    if raw != raw.to_integral_value():
        raise RangeError(
            f"{spec.label}: {value} is not a whole multiple of 10^{sf} (its scale factor {spec.scale_from} reads {sf}): nothing was sent"
        )
    return int(raw)
