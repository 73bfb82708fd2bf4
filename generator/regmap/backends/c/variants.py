"""The C spelling of device variants (models or options whose registers differ): a bit per declared
variant, and for a register only some variants have, the mask of those bits and a helper that asks it."""

from __future__ import annotations

from regmap.backends.c.names import CIdentifier, Context, Define, Macro
from regmap.core.text import titled
from regmap.model import Device, Register
from regmap.records import NamedTuple

VARIANT_BITS = 32  # a variant is a bit of a uint32_t


class VariantView(NamedTuple):
    """Whether a device variant has the register (its `variants`)."""

    function: str
    mask: str  # the register's VARIANTS macro
    bits: str  # the macros' prefix, as the comment names them
    text: str  # the variants that have it


def too_many_variants(device: Device) -> str:
    """Why the C header cannot give each variant a bit ("" when it can)."""
    count = len(device.info.variants)
    return f"{count} variants: the C header gives each one bit of a uint32_t (at most {VARIANT_BITS})" if count > VARIANT_BITS else ""


def variant_bit(ctx: Context, name: str) -> str:
    return CIdentifier(ctx.prefix, "VARIANT", name)


def variant_macros(ctx: Context) -> list[Macro]:
    """A bit per declared variant, in the map's order (eight digits: the type of the literal that holds bit 31 too)."""
    return [
        Macro(ctx.const("VARIANT", v.name, what=f"variant {v.name}"), f"0x{1 << i:08X}u", titled(v.title, None))
        for i, v in enumerate(ctx.device.info.variants)
    ]


def variants_macro(ctx: Context, reg: Register, owner: str) -> list[Define]:
    """The mask of the variants that have the register (none for a register every variant has)."""
    if not reg.variants:
        return []
    bits = " | ".join(variant_bit(ctx, name) for name in reg.variants)
    return [(ctx.const(owner, "VARIANTS"), f"({bits})" if len(reg.variants) > 1 else bits)]


def variant_view(ctx: Context, reg: Register, owner: str) -> VariantView | None:
    if not reg.variants:
        return None
    return VariantView(
        function=ctx.symbol(owner, "on_variant"),
        mask=ctx.member_const(reg, "VARIANTS"),
        bits=CIdentifier(ctx.prefix, "VARIANT"),
        text=", ".join(reg.variants),
    )
