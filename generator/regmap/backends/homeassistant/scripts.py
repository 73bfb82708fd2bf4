"""What Home Assistant's `modbus:` entities cannot show or do, as other parts of the same package:
`script:`s that send the map's commands (`modbus.write_register`), and `template:` entities over a
register's sensor: a binary sensor per bit flag, a sensor with the manual's labels per enum register.

Templates hold only entity ids (slugs: [a-z0-9_]) and integers; an enum label, being map text, goes in as
a Jinja string literal whose every character outside [A-Za-z0-9 ] is a `\\uXXXX` escape, so no label can
end the literal or the expression. HA names a sensor `sensor.<slug of its name>` when it first sees it
(`object_id`); the templates read that entity.

Retries: the hub hands pymodbus `retries=3, retry_on_empty=True` for every request, writes included
(homeassistant/components/modbus/modbus.py; 2024.3 deprecates the hub's `retries` option and ignores it,
later versions removed it): a command whose reply is lost may reach the device up to 4 times, and no
setting of the integration turns that off. The scripts run in `mode: single` (a second press while one
runs is dropped) and say so in their description.
"""

from __future__ import annotations

import re
from typing import Any

from regmap.homeauto.entities import Ids, flags, presses, reserved, too_many_presses
from regmap.homeauto.yamltext import Hex
from regmap.model import Command, Device, EnumMember, Register
from regmap.runtime_bridge import wire_specs
from regmap_runtime.codec import raw_to_words

RETRY_NOTE = (
    "Home Assistant's modbus hub retries a request without reply up to 3 times: if the reply is lost the command may be sent again."
)
_NOT_SLUG = re.compile(r"[^a-z0-9]+")


def object_id(name: str) -> str:
    """The object id HA gives an entity named `name` (its `slugify`, for ASCII text; the tests compare them)."""
    if name.isascii():  # NFKD leaves ASCII as it is: unicodedata (a shared library) is loaded only for other text
        text = name.lower()
    else:
        import unicodedata

        text = unicodedata.normalize("NFKD", name).encode("ascii", "ignore").decode().lower()
    # The quotes (' " ‘ ’) are dropped before slugging: the text is ASCII by now, so only ' and " can be left (a pattern
    # with the other two cost every cold run about 2.5M instructions to compile).
    return _NOT_SLUG.sub("_", text.replace("'", "").replace('"', "")).strip("_") or "unknown"


def jinja_text(text: str) -> str:
    """Map text as a Jinja string literal that cannot break out of itself."""
    return "'" + "".join(c if c.isascii() and (c.isalnum() or c == " ") else _escape(c) for c in text) + "'"


def _escape(c: str) -> str:
    return f"\\u{ord(c):04x}" if ord(c) <= 0xFFFF else f"\\U{ord(c):08x}"


def flag_sensor(reg: Register, source: str, name: str, unique_prefix: str, field_name: str, mask: int) -> dict[str, Any]:
    """A template binary sensor: the flag's bit of the register's sensor `source` (an entity id)."""
    return {
        "name": name,
        "unique_id": f"{unique_prefix}_{reg.name}_{field_name}",
        "state": f"{{{{ states('{source}') | int(0) | bitwise_and({mask}) != 0 }}}}",
        "availability": f"{{{{ has_value('{source}') }}}}",
    }


def label_sensor(reg: Register, source: str, name: str, unique_prefix: str) -> dict[str, Any]:
    """A template sensor showing the label of the value the register's sensor `source` reads (the value
    itself when the map lists no label for it). Members the device never reports are left out."""
    assert reg.enum is not None
    members: list[EnumMember] = [m for m in reg.enum.members if m.readable]
    labels = ", ".join(f"{m.value}: {jinja_text(' '.join(m.title.split()) or m.name)}" for m in members)
    return {
        "name": name,
        "unique_id": f"{unique_prefix}_{reg.name}_label",
        "state": f"{{{{ {{{labels}}}.get(states('{source}') | int(-1), states('{source}')) }}}}",
        "availability": f"{{{{ has_value('{source}') }}}}",
    }


def time_sensor(reg: Register, source: str, name: str, unique_prefix: str) -> dict[str, Any]:
    """A template sensor showing the time of a timestamp register's raw seconds (its sensor `source`): for a utc
    one a timestamp entity (`as_datetime` of the seconds is an aware UTC time); for a local one the wall-clock
    text, since Home Assistant's timestamp needs a zone the device does not state (none is guessed)."""
    entity: dict[str, Any] = {"name": name, "unique_id": f"{unique_prefix}_{reg.name}_time"}
    if reg.zone == "utc":
        entity["device_class"] = "timestamp"
        entity["state"] = f"{{{{ as_datetime(states('{source}')) }}}}"
    else:
        entity["state"] = f"{{{{ states('{source}') | int | timestamp_custom('%Y-%m-%dT%H:%M:%S', false) }}}}"
    entity["availability"] = f"{{{{ has_value('{source}') }}}}"
    return entity


def template_flags(reg: Register) -> list[tuple[str, str, int]]:
    """(field name, field title, mask) of the register's flags that have a meaning."""
    return [(f.name, f.title, f.mask) for f in flags(reg) if not reserved(f.title)]


class Scripts:
    """A script per command (per argument value, up to MAX_PRESSES_PER_COMMAND), named after it."""

    def __init__(self, device: Device, hub: str, slave: int, prefix: str, name_prefix: str = "") -> None:
        self.device = device
        self.hub = hub
        self.slave = slave
        self.prefix = prefix  # of every script id
        self.name_prefix = name_prefix  # of every alias
        self.ids = Ids()
        self.specs = {spec.name: spec for spec in wire_specs(device)}
        self.single_write = 0x06 in device.transport.function_codes
        self.scripts: dict[str, dict[str, Any]] = {}
        self.skipped: list[str] = []

    def add(self, command: Command) -> None:
        chosen = presses(command)
        if chosen is None:
            self.skipped.append(too_many_presses(command))
        for press in chosen or ():
            self._script(command, press.title, press.raw, press.key)

    def _write(self, reg: Register, raw: int) -> dict[str, Any]:
        data: dict[str, Any] = {"hub": self.hub, "slave": self.slave, "address": Hex(reg.address)}
        if reg.space == "coil":
            data["state"] = raw != 0
            return {"service": "modbus.write_coil", "data": data}
        words = raw_to_words(self.specs[reg.name], raw)
        data["value"] = Hex(words[0]) if len(words) == 1 and self.single_write else [Hex(w) for w in words]
        return {"service": "modbus.write_register", "data": data}

    def _script(self, command: Command, title: str, raw: int, key: tuple[str, ...]) -> None:
        script_id = self.ids.id(object_id("_".join((self.prefix, *key))))
        about = " ".join(command.description.split())
        script: dict[str, Any] = {"alias": self.name_prefix + " ".join(title.split()), "mode": "single"}
        sequence: list[dict[str, Any]] = []
        if command.destructive:
            # One deliberate step: pressing Run does nothing; a call must name the command in `confirm`.
            script["alias"] = "DESTRUCTIVE: " + script["alias"]
            about = f"Destructive. Sent only when called with confirm: {command.name}. {about}"
            script["fields"] = {
                "confirm": {"description": f"the command's name, {command.name}, to send it", "required": True, "selector": {"text": None}}
            }
            sequence.append({"condition": "template", "value_template": f"{{{{ confirm | default('') == '{command.name}' }}}}"})
        script["description"] = " ".join(part for part in (about, RETRY_NOTE) if part)
        sequence.append(self._write(command.register, raw))
        script["sequence"] = sequence
        self.scripts[script_id] = script
