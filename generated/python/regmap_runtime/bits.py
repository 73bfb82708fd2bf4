# Copied by regmap from generator/regmap_runtime/bits.py - do not edit; regenerate with `regmap generate`.
"""Base class of the typed bitfield values generated for bitfield registers."""

from __future__ import annotations

import dataclasses
import enum
from typing import Any, ClassVar, TypeVar

from regmap_runtime.spec import BitfieldSpec

B = TypeVar("B", bound="BitfieldValue")


@dataclasses.dataclass(frozen=True)
class BitfieldValue:
    """A register value split into named fields. `raw` keeps bits no field describes."""

    FIELDS: ClassVar[tuple[BitfieldSpec, ...]] = ()

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
        return cls(**values)

    def to_raw(self) -> int:
        raw = 0
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
