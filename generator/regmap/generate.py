"""`regmap generate`: run the back ends and swap their output into place atomically."""

from __future__ import annotations

import contextlib
import functools
import os
import shutil
import tempfile
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, Protocol

from regmap import entrypoints
from regmap.diagnostics import Diagnostic, MapError, OutputError, UsageError
from regmap.model import Device
from regmap.outputcache import OutputCache, Source, entry_key

# The contract lives in regmap.target; these names stay importable from here for the runner's users.
from regmap.target import TARGET_GROUP, reserved_id_problems
from regmap.target import Files as Files
from regmap.target import Target as Target
from regmap.target import TargetOptions as TargetOptions
from regmap.tools.output import write_all

if TYPE_CHECKING:  # only a plant's run imports the plant model (tests/project/test_generate_imports.py)
    from regmap.plant import Plant


def check(devices: Sequence[Device], targets: Sequence[str] | None = None) -> list[Diagnostic]:
    """Every target's own checks on every device: what `generate` would refuse, found by `validate`."""
    known = _targets()
    problems = reserved_ids(devices, targets)
    for name in targets or list(known):
        target = known[name]
        if target.check is not None:
            for device in devices:
                problems.extend(target.check(device))
    return problems


def reserved_ids(devices: Sequence[Device], targets: Sequence[str] | None = None) -> list[Diagnostic]:
    """Each device id that a chosen target (by default: any target) reserves, at its map line."""
    known = _targets()
    chosen = [known[name] for name in targets or list(known)]
    return [problem for device in devices for problem in reserved_id_problems(device, chosen)]


def _targets() -> dict[str, Target]:
    """Every back end registered under the `regmap.targets` entry points, in the order each declares (then by name)."""
    found: dict[str, Target] = {}
    for point in _entry_points():
        try:
            target = point.load()
        except Exception as exc:  # a broken plugin must not take the built-in back ends down with it
            raise UsageError(f"back end {point.name!r} ({point.value}) cannot be loaded: {type(exc).__name__}: {exc}") from None
        if not isinstance(target, Target) or target.name != point.name:
            raise UsageError(f"entry point {point.name!r} ({point.value}) is not a regmap Target named {point.name!r}")
        found[point.name] = target
    return {name: found[name] for name in sorted(found, key=lambda name: (found[name].order, name))}


class _EntryPoint(Protocol):
    name: str
    value: str

    def load(self) -> Any: ...


@functools.cache  # the installed packages do not change while regmap runs, and reading their metadata is slow
def _entry_points() -> tuple[_EntryPoint, ...]:
    found = entrypoints.read(TARGET_GROUP)
    if found is not None:
        return tuple(found)
    from importlib.metadata import entry_points  # a layout only it reads (a zip on sys.path, another finder)

    return tuple(entry_points(group=TARGET_GROUP))


def target_names() -> list[str]:
    return list(_targets())


def target(name: str) -> Target:
    """The registered back end of that name (the tools find a target here, never by importing it)."""
    return _targets()[name]


def check_options(targets: Sequence[str], options: TargetOptions) -> None:
    """Refuse a target option that none of the chosen targets reads (it would silently do nothing)."""
    known = _targets()
    for option in options:
        if not any(option in known[name].options for name in targets):
            readers = [name for name, target in known.items() if option in target.options]
            raise UsageError(f"--{option} is read by the target(s) {', '.join(readers) or '(none)'}, none of which is chosen")


def render(devices: Sequence[Device], targets: Sequence[str], options: TargetOptions | None = None) -> dict[str, Files]:
    """Every file each target produces, in memory, keyed by target subdir."""
    known = _targets()
    problems = reserved_ids(devices, targets)
    if problems:
        raise MapError(problems)
    out: dict[str, Files] = {}
    for name in targets:
        target = known[name].configured(options or {})
        shown = devices if target.scale_from else [device.without_scale_from() for device in devices]
        files: Files = dict(target.shared(shown))
        for device in shown:
            files.update(target.per_device(device))
        out[name] = files
    return out


def plant_target_names() -> list[str]:
    """The targets that render plants, in their order."""
    return [name for name, target in _targets().items() if target.plant is not None]


PLANT_MARKER = "regmap-plant.txt"  # marks a directory `regmap generate PLANT` wrote: only such a directory is replaced


def render_plant(plant: Plant, targets: Sequence[str]) -> dict[str, Files]:
    """Every file each plant-rendering target produces for `plant`, in memory, keyed by target name."""
    known = _targets()
    problems = reserved_ids(plant.maps, targets)
    if problems:
        raise MapError(problems)
    out: dict[str, Files] = {}
    for name in targets:
        render_whole = known[name].plant
        if render_whole is None:
            raise UsageError(f"--target {name}: this target does not render plants (plant targets: {', '.join(plant_target_names())})")
        scaled = sorted({f"{device.id}.{reg.name}" for device in plant.maps for reg in device.registers if reg.scale_from is not None})
        if scaled and not known[name].scale_from:
            raise UsageError(
                f"--target {name}: a plant's {name} files cannot scale by another register yet (scale_from: {', '.join(scaled)})"
            )
        out[name] = dict(render_whole(plant))
    return out


def generate_plant(plant: Plant, out_dir: Path, targets: Sequence[str]) -> list[Path]:
    """Write a plant's files under `out_dir`, each target's subdirectory replaced whole. A non-empty `out_dir`
    that an earlier plant run did not write (no marker file) is refused: it is not ours to replace."""
    if out_dir.is_dir() and any(out_dir.iterdir()) and not (out_dir / PLANT_MARKER).is_file():
        raise UsageError(f"--out {out_dir}: holds files that `regmap generate PLANT` did not write; choose a new or empty directory")
    marker = f"generated from {plant.source_path} (plant {plant.id}) by regmap — do not edit; this directory is replaced on each run\n"
    return generate(list(plant.maps), out_dir, targets, complete=True, extra={PLANT_MARKER: marker}, rendered=render_plant(plant, targets))


class CachedOutputs:
    """The targets whose finished files the output cache holds for these maps, and where to store the others'."""

    def __init__(self, cache: OutputCache, sources: Sequence[Source], targets: Sequence[str]) -> None:
        known = _targets()
        self.cache = cache
        # A third party's target may read more than the maps and regmap's own files: never cached.
        self.keys = {name: entry_key(name, sources) for name in targets if known[name].per_device.__module__.startswith("regmap.")}
        self.found: dict[str, Files] = {}
        for name, key in self.keys.items():
            files = cache.get(key)
            if files is not None:
                self.found[name] = files

    def complete(self, targets: Sequence[str]) -> bool:
        return all(name in self.found for name in targets)

    def store(self, name: str, files: Files) -> None:
        if name in self.keys:
            self.cache.put(self.keys[name], files)


def generate(
    devices: Sequence[Device],
    out_dir: Path,
    targets: Sequence[str],
    *,
    complete: bool,
    extra: Files | None = None,
    options: TargetOptions | None = None,
    rendered: dict[str, Files] | None = None,
    cached: CachedOutputs | None = None,
) -> list[Path]:
    """Write the targets' files under `out_dir`. With `complete` (all maps in scope) each target's
    subdirectory is replaced whole, so files of removed maps disappear; otherwise files are added or
    overwritten. `extra` (path relative to `out_dir` -> content, e.g. the `--since` changelog pages)
    is written last, into the same staged tree. Nothing under `out_dir` changes unless every target
    rendered and post-processed. A target `cached` holds is written from the cache (post-processed
    already); the others are rendered from `devices`, and `cached` stores their finished files."""
    known = _targets()
    found = cached.found if cached is not None else {}
    if rendered is None:
        fresh = render(devices, [t for t in targets if t not in found], options)
        rendered = {name: found[name] if name in found else fresh[name] for name in targets}
    given = out_dir
    out_dir = out_dir.resolve()  # a symlink is followed: its target is swapped, the link stays
    with _writing(given):
        out_dir.parent.mkdir(parents=True, exist_ok=True)
        recover(out_dir)
        staging = Path(tempfile.mkdtemp(prefix=f"{STAGING_PREFIX}{os.getpid()}-", dir=out_dir.parent))
    try:
        tree = staging / "tree"
        replaced = {os.path.join(out_dir, known[name].subdir) for name in rendered} if complete else set()
        with _writing(given):
            if out_dir.exists():
                shutil.copytree(out_dir, tree, symlinks=True, ignore=functools.partial(_replaced_dirs, replaced))
            else:
                tree.mkdir()
        written: list[Path] = []
        for name, files in rendered.items():
            target = known[name]
            sub = tree / target.subdir
            with _writing(given):
                if complete and sub.exists():
                    shutil.rmtree(sub)
                _write(sub, files)
                written.extend(out_dir / target.subdir / rel for rel in sorted(files))
            if name in found:
                continue
            if target.post is not None:
                target.post(sub)
            if cached is not None:
                with _writing(given):
                    cached.store(name, {rel: (sub / rel).read_bytes().decode("utf-8") for rel in files})
        with _writing(given):
            _write(tree, extra or {})
            written.extend(out_dir / rel for rel in sorted(extra or {}))
            _swap(tree, out_dir, staging)
        return written
    finally:
        shutil.rmtree(staging, ignore_errors=True)


def _replaced_dirs(replaced: set[str], directory: str, names: list[str]) -> list[str]:
    """The target subdirectories a complete run removes anyway: copying the old output into staging would be wasted."""
    return [
        name for name in names if (path := os.path.join(directory, name)) in replaced and os.path.isdir(path) and not os.path.islink(path)
    ]


@contextlib.contextmanager
def _writing(out_dir: Path) -> Iterator[None]:
    """A full disk or a read-only directory is the user's situation (one line, exit 74), not a bug in regmap."""
    try:
        yield
    except OSError as exc:
        raise OutputError(f"cannot write {out_dir}: {exc.strerror or exc}") from None


def _write(root: Path, files: Files) -> None:
    """Each directory is made once, not once per file it holds (a made one costs a failed mkdir call each time). Each
    file is written as its UTF-8 bytes through the bare descriptor: no path objects or text layer for 93 files."""
    paths = {rel: os.path.join(root, rel) for rel in files}
    for directory in sorted({os.path.dirname(path) for path in paths.values()}):
        os.makedirs(directory, exist_ok=True)
    for rel, content in sorted(files.items()):
        _write_bytes(paths[rel], utf8(content))


# A text with one character beyond Latin-1 (a CJK description) is stored two bytes a character, and UTF-8 encodes such a
# text character by character, at several times the cost of copying ASCII. Cut into slices, each slice without such a
# character is stored one byte a character again, and its encoding is a copy; the bytes are the same.
UTF8_SLICE = 4096


def utf8(text: str) -> bytes:
    """`text.encode("utf-8")`, by slices when that is cheaper (a code point is never cut: a str slices by code points)."""
    if text.isascii() or len(text) <= UTF8_SLICE:
        return text.encode("utf-8")
    return b"".join([text[start : start + UTF8_SLICE].encode("utf-8") for start in range(0, len(text), UTF8_SLICE)])


def _write_bytes(path: str, data: bytes) -> None:
    write_all(os.open(path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o666), data)  # as open(path, "w") makes it


STAGING_PREFIX = ".regmap-staging-"


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def recover(out_dir: Path) -> None:
    """Clean up after a run that was killed: put the previous output back if the kill came
    between the two renames of the swap, and remove staging directories of dead runs."""
    for staging in sorted(out_dir.parent.glob(STAGING_PREFIX + "*")):
        pid_text = staging.name[len(STAGING_PREFIX) :].split("-", 1)[0]
        if not pid_text.isdigit() or _alive(int(pid_text)):
            continue
        previous = staging / "previous"
        if not out_dir.exists() and previous.is_dir():
            os.rename(previous, out_dir)
        shutil.rmtree(staging, ignore_errors=True)


def _swap(new: Path, out_dir: Path, staging: Path) -> None:
    old = staging / "previous"
    if out_dir.exists():
        os.rename(out_dir, old)
    try:
        os.rename(new, out_dir)
    except OSError:
        if old.exists():
            os.rename(old, out_dir)
        raise
