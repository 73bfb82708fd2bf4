"""Structured Text back end (IEC 61131-3): per map, `st/<device>/codesys/` (CODESYS / TwinCAT 3) and
`st/<device>/iec/` (plain standard, for OpenPLC / matiec), each with the enums and raw read-plan
blocks (`<device>_types.st`), the constants (`<device>_constants.st`) and the functions
(`<device>_functions.st`), plus `st/<device>/plcopen/<device>.xml` (the same as one PLCopen TC6 XML
project), the poller per runtime (`st/<device>/codesys/<device>_poll.st` on CODESYS' ModbusFB,
`st/<device>/twincat/<device>_poll.st` on TwinCAT's Tc2_ModbusRTU: poller.py, with the write request of
writes.py) and a README with the import steps per runtime.

As in the C back end, `views` computes every name, literal and statement and the templates only
print, escaping map text with `st_comment`; `names` holds the identifier rules (IEC keywords, no
double or trailing underscore, 64 characters, names that differ only by case collide).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

from regmap.backends.st.codec import DIALECTS, PLCOPEN
from regmap.backends.st.device import DeviceViews, device_views
from regmap.backends.st.names import StIdentifier, st_string
from regmap.backends.st.plcopen import plcopen_context
from regmap.backends.st.poller import RUNTIMES, VENDOR, poller, serial_settings
from regmap.diagnostics import Diagnostic, UsageError
from regmap.keywords import IEC_KEYWORDS
from regmap.model import Device
from regmap.render import templates
from regmap.target import Files, ReservedWords, Target

if TYPE_CHECKING:
    from regmap.plant import Plant

FILES = ("types", "constants", "functions")


def _contexts(device: Device) -> tuple[DeviceViews, dict[str, dict[str, Any]], list[Diagnostic]]:
    """The device's views (shared by the dialects, the PLCopen XML's included), each dialect's context and the problems."""
    problems: list[Diagnostic] = []
    shared = DeviceViews(device, problems)
    out = {dialect.name: shared.context(dialect) for dialect in DIALECTS}
    return shared, out, sorted(set(problems))


def contexts(device: Device) -> tuple[dict[str, dict[str, Any]], list[Diagnostic]]:
    """Each dialect's template context, and every name problem of the map (found in either dialect)."""
    return _contexts(device)[1:]


def check(device: Device) -> list[Diagnostic]:
    return contexts(device)[1]


def render_device(device: Device) -> Files:
    shared, views, problems = _contexts(device)
    if problems:
        raise UsageError("\n".join(str(p) for p in problems))
    env = templates(__name__)
    files: Files = {}
    for dialect, context in views.items():
        for name in FILES:
            files[f"{device.id}/{dialect}/{device.id}_{name}.st"] = env.get_template(f"{name}.st.jinja").render(**context)
    polls = {runtime.name: poller(views["codesys"], runtime, VENDOR) for runtime in RUNTIMES}  # the README shows the first
    for runtime in RUNTIMES:
        files[f"{device.id}/{runtime.name}/{device.id}_poll.st"] = env.get_template("poll.st.jinja").render(
            **views["codesys"], runtime=runtime, poller=polls[runtime.name]
        )
    files[f"{device.id}/plcopen/{device.id}.xml"] = env.get_template("plcopen.xml.jinja").render(**plcopen_context(shared.context(PLCOPEN)))
    codesys = views["codesys"]
    plain = [f for f in codesys["write_functions"][1:] if not any(m.name in ("nIndex", "nSf") for m in f.inputs)]
    example = {"function": plain[0].name, "input": plain[0].inputs[0].name} if plain else None
    files[f"{device.id}/README.md"] = env.get_template("README.md.jinja").render(
        **codesys,
        iec=views["iec"],
        files=FILES,
        poll=polls[RUNTIMES[0].name],
        serial=serial_settings(device),
        write_example=example,
    )
    return files


def render_shared(devices: Sequence[Device]) -> Files:
    ids: dict[str, str] = {}
    for device in devices:
        key = device.id.upper()
        if key in ids:
            raise UsageError(
                f"{device.source_path} and {ids[key]} have device ids that ST reads as one ({device.id!r}): their names would collide"
            )
        ids[key] = device.source_path
    return {}


# The device id prefixes the ST names; ST reads every name case-insensitively.
RESERVED_WORDS = ReservedWords("an IEC 61131-3 or CODESYS reserved word", IEC_KEYWORDS, case_sensitive=False)


def render_plant(plant: Plant) -> Files:
    """The plant's files (backends/st/plant.py): imported only when a plant is rendered."""
    from regmap.backends.st.plant import render_plant as render

    return render(plant)


TARGET = Target(
    name="st",
    subdir="st",
    per_device=render_device,
    shared=render_shared,
    check=check,
    order=40,
    reserved_words=RESERVED_WORDS,
    plant=render_plant,
    scale_from=True,  # F_<DEV>_SCALED_<R> and the encoders take the scale factor (scaling.py)
)

__all__ = ["DIALECTS", "TARGET", "StIdentifier", "check", "contexts", "device_views", "render_device", "render_shared", "st_string"]
