"""The back-end contract (docs/plugins.md): what a target declares and what the runner gives it.

A back end, built-in or a third party's, imports this module and nothing of the runner
(`regmap.generate`), and registers its `Target` under the `regmap.targets` entry points.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import field
from pathlib import Path
from typing import TYPE_CHECKING

from regmap.diagnostics import Diagnostic, at
from regmap.model import Device
from regmap.records import dataclass

if TYPE_CHECKING:  # only a plant's run imports the plant model (tests/project/test_generate_imports.py)
    from regmap.plant import Plant

Files = dict[str, str]  # relative path -> content
TargetOptions = Mapping[str, str]  # `regmap generate` target options (e.g. `--select`) -> their text

TARGET_GROUP = "regmap.targets"  # entry-point group: a third-party back end registers itself here, as the built-in ones do
PLUGIN_ORDER = 1000  # the default order: after every built-in target (10 ... 60), then by name


@dataclass(frozen=True)
class ReservedWords:
    """Names the target's output cannot give a device id (the id names its files, packages and
    prefixes): `language` names them in the refusal, e.g. "C/C++ keyword"."""

    language: str = ""
    words: frozenset[str] = frozenset()
    case_sensitive: bool = True  # IEC 61131-3 reads `program` and `PROGRAM` as one word

    def reserves(self, name: str) -> bool:
        if self.case_sensitive:
            return name in self.words
        return name.casefold() in {word.casefold() for word in self.words}


@dataclass(frozen=True)
class Target:
    name: str
    subdir: str
    per_device: Callable[[Device], Files]
    shared: Callable[[Sequence[Device]], Files]
    post: Callable[[Path], None] | None = None
    check: Callable[[Device], list[Diagnostic]] | None = None  # the back end's own rules, run by `regmap validate`
    # Target options: the names this target reads (`select`), and the target as given values make it.
    # A target that declares none never sees them; an option no chosen target reads is refused.
    options: tuple[str, ...] = ()
    configure: Callable[[TargetOptions], Target] | None = None
    order: int = PLUGIN_ORDER  # targets run and are listed by (order, name)
    reserved_words: ReservedWords = field(default_factory=ReservedWords)
    # A plant (several devices on buses, regmap.plant): the target's files for the whole plant, under `subdir`
    # of `regmap generate PLANT --out DIR`. A target without it is skipped for plants.
    plant: Callable[[Plant], Files] | None = None
    # The target shows `scale_from` registers (value = raw x 10^sf) as values; one that does not is given the
    # device without them (Device.without_scale_from: each listed in `Device.not_generated`), never their raw values.
    scale_from: bool = False

    def configured(self, options: TargetOptions) -> Target:
        """This target with the options it reads applied (itself when none of them was given)."""
        mine = {name: value for name, value in options.items() if name in self.options}
        return self.configure(mine) if mine and self.configure is not None else self


def reserved_id_problems(device: Device, targets: Sequence[Target]) -> list[Diagnostic]:
    """The device id, at its map line, if a chosen target reserves it (one problem naming every such target)."""
    device_id = device.id
    reserving = [t for t in targets if t.reserved_words.reserves(device_id)]
    if not reserving:
        return []
    named = [f"the {t.name} target ({t.reserved_words.language})" for t in reserving]
    owners = named[0] if len(named) == 1 else f"{', '.join(named[:-1])} and {named[-1]}"
    message = f"device id {device_id!r} is a reserved word of {owners}; choose another (e.g. {device_id}_drive)"
    return [at(device.source_path, device.info.id_pos, message)]
