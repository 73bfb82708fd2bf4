"""Base class of the typed bitfield values generated for bitfield registers."""

from __future__ import annotations

import dataclasses
import enum
from typing import Any, ClassVar, TypeVar

from .spec import BitfieldSpec

B = TypeVar("B", bound="BitfieldValue")


@dataclasses.dataclass(frozen=True)
class BitfieldValue:
    """A register value split into named fields.

    `raw` is the whole word as it was read: `to_raw()` keeps the bits no field describes, so
    read -> `dataclasses.replace(value, flag=...)` -> write changes only the field the caller
    changed. A value built from fields alone (raw=0) sets every undescribed bit to 0.
    """

    FIELDS: ClassVar[tuple[BitfieldSpec, ...]] = ()
    raw: int = dataclasses.field(default=0, kw_only=True)

    @classmethod
    def from_raw(cls: type[B], raw: int) -> B:
        values: dict[str, Any] = {}
        for spec in cls.FIELDS:
            value = (raw & spec.mask) >> spec.lsb
            if spec.enum is not None:
                try:
                    values[spec.name] = spec.enum(value)
                except ValueError:
                    values[spec.name] = value
            elif spec.width == 1:
                values[spec.name] = bool(value)
            else:
                values[spec.name] = value
        return cls(**values, raw=raw)

    @classmethod
    def described_mask(cls) -> int:
        """The bits some field describes."""
        mask = 0
        for spec in cls.FIELDS:
            mask |= spec.mask
        return mask

    def to_raw(self) -> int:
        raw = self.raw & ~self.described_mask()
        for spec in self.FIELDS:
            value = int(getattr(self, spec.name))
            if not 0 <= value < (1 << spec.width):
                raise ValueError(f"{type(self).__name__}.{spec.name}: {value} does not fit in {spec.width} bit(s)")
            raw |= value << spec.lsb
        return raw

    def describe(self) -> dict[str, object]:
        """Field values for display: enum members by name, flags as booleans."""
        out: dict[str, object] = {}
        for spec in self.FIELDS:
            value = getattr(self, spec.name)
            out[spec.name] = value.name if isinstance(value, enum.Enum) else value
        return out
