"""`dataclass`: the standard library's, with the methods it compiles from text for each class built here instead:
`__repr__`, `__eq__`, `__hash__` (and with `order=True` the four comparisons) from the class's fields, a frozen
class's `__setattr__` and `__delattr__` as closures, and `__init__` from a code compiled once per number of fields.
Python 3.11 compiles each of those functions with an `exec` of its own text (about 0.9 ms a class; a `regmap generate`
makes some 90 classes at import). The methods answer as the generated ones do: the same text, comparisons, hashes, signature
and errors (tests/project/test_records.py compares them). mypy sees the standard decorator itself.

A class that writes one of these methods itself, or asks for another option than `frozen` and `order`, is left to
the standard decorator whole; one that needs what only the standard `__init__` does (`_standard_init`: a
`__post_init__`, a dataclass base, an `InitVar` ...) gets it, and the other methods from here.

`cached_property`: functools', without the lock Python 3.11 takes on each first read of a value.

`NamedTuple`: typing's, with each field's annotation kept as written. typing's makes a ForwardRef of each annotation
that is text (all of them, under `from __future__ import annotations`), compiling it: a fifth of the CPU of importing
the C, Markdown and ST back ends. Its class is collections.namedtuple's, whose `__new__` comes from a code compiled once
per number of fields too (namedtuple compiles a text per class). mypy sees typing's class itself.
"""

from __future__ import annotations

import abc
import collections
import dataclasses
import inspect
import keyword
import operator
import reprlib
import sys
import types
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

_BUILT_HERE = ("__repr__", "__eq__", "__hash__")
_ORDER = ("__lt__", "__le__", "__gt__", "__ge__")  # with `order=True`, as the standard decorator's: by the compared fields
_INIT_BUILT_HERE = ("__init__", "__setattr__", "__delattr__")

if TYPE_CHECKING:
    from dataclasses import dataclass as dataclass
    from functools import cached_property as cached_property
    from typing import NamedTuple as NamedTuple
else:

    class cached_property:
        """functools.cached_property without its lock: Python 3.11's takes an RLock on every first read (3.12 dropped
        it), and the back ends read thousands of register facts once each. A value computed twice by two threads is
        the same value."""

        def __init__(self, func: Callable[[Any], Any]) -> None:
            self.func = func
            self.attrname: str | None = None
            self.__doc__ = func.__doc__

        def __set_name__(self, owner: type, name: str) -> None:
            self.attrname = name

        def __get__(self, instance: Any, owner: type | None = None) -> Any:
            if instance is None:
                return self
            value = instance.__dict__[self.attrname] = self.func(instance)
            return value

    def dataclass(cls: type | None = None, /, **options: Any) -> Any:
        def made(cls: type) -> type:
            order = options.get("order", False)
            if set(options) - {"frozen", "order"} or any(name in cls.__dict__ for name in _BUILT_HERE + (_ORDER if order else ())):
                return dataclasses.dataclass(cls, **options)
            frozen = options.get("frozen", False)
            if _standard_init(cls):
                return _with_methods(dataclasses.dataclass(cls, repr=False, eq=False, frozen=frozen), frozen, order)
            return _with_methods(_with_init(cls, frozen), frozen, order)

        return made if cls is None else made(cls)


def _standard_init(cls: type) -> bool:
    """Whether the class needs what only the standard `__init__` does: a `__post_init__`, a dataclass base, an
    `InitVar` or a keyword-only field, a field named `self`; or keeps its fields other than in the instance's
    `__dict__` (slots, a base's `__setattr__`, a descriptor as a field's default); or writes one of the methods."""
    annotations = inspect.get_annotations(cls)
    own = cls.__dict__
    if (
        any(name in own for name in _INIT_BUILT_HERE)
        or "self" in annotations
        or hasattr(cls, "__post_init__")
        or any(hasattr(base, "__dataclass_fields__") or "__setattr__" in vars(base) for base in cls.__mro__[1:-1])
        or any("__slots__" in vars(klass) for klass in cls.__mro__[:-1])
    ):
        return True
    for name, kind in annotations.items():  # one pass over the fields: most classes have many
        text = str(kind)
        default = own.get(name)
        if isinstance(default, dataclasses.Field):
            if default.kw_only is True:
                return True
            default = default.default
        if "InitVar" in text or "KW_ONLY" in text or hasattr(type(default), "__set__"):
            return True
    return False


def _with_init(cls: type, frozen: bool) -> type:
    """The standard decorator's fields, defaults and `__match_args__`, with `__init__` (and a frozen class's
    `__setattr__`, `__delattr__`) built here."""
    documented = bool(cls.__doc__)
    if not documented:  # the standard decorator would word one from a signature without the `__init__` made below
        cls.__doc__ = cls.__name__
    if not (_MIRRORS_THIS_PYTHON and _with_fields(cls)):
        cls = dataclasses.dataclass(cls, init=False, repr=False, eq=False)
    fields = dataclasses.fields(cls)
    methods = {"__init__": _init(fields, cls.__module__)}
    if frozen:
        methods |= _frozen_methods(cls, frozenset(field.name for field in fields))
        vars(cls)["__dataclass_params__"].frozen = True  # what a subclass's decorator checks: frozen inherits frozen only
    for name, method in methods.items():
        method.__qualname__ = f"{cls.__qualname__}.{name}"
        setattr(cls, name, method)
    if not documented:
        cls.__doc__ = _doc(cls.__name__, methods["__init__"])
    return cls


# `_with_fields` and `_namedtuple_311` do what Python 3.11's dataclasses and collections.namedtuple do, with their
# private parts; another Python (3.12 gave `_DataclassParams` more fields, 3.13 dataclasses a `__replace__`) gets the
# standard library's own.
_MIRRORS_THIS_PYTHON = sys.version_info[:2] == (3, 11)
# What the standard decorator marks a field and a class with (Python 3.11's dataclasses, as `_with_fields` makes them).
_FIELD = vars(dataclasses)["_FIELD"]
_PARAMS: Callable[..., Any] = vars(dataclasses)["_DataclassParams"]


def _with_fields(cls: type) -> bool:
    """What `dataclasses.dataclass(cls, init=False, repr=False, eq=False)` does to a class that `_standard_init` leaves
    here (no dataclass base, no InitVar, no keyword-only field, no slots): its fields, their defaults as class
    attributes, `__match_args__`; done here without the standard decorator's three pattern matches a field. False,
    the class untouched, when a field may be a ClassVar: the standard decorator tells."""
    annotations = inspect.get_annotations(cls)
    if any("ClassVar" in str(kind) for kind in annotations.values()):
        return False
    fields: dict[str, dataclasses.Field[Any]] = {}
    for name, kind in annotations.items():
        default = getattr(cls, name, dataclasses.MISSING)
        made: Any = default if isinstance(default, dataclasses.Field) else dataclasses.field(default=default)
        made.name, made.type, made._field_type = name, kind, _FIELD
        if made.kw_only is dataclasses.MISSING:
            made.kw_only = False
        if made.default.__class__.__hash__ is None:
            raise ValueError(f"mutable default {type(made.default)} for field {name} is not allowed: use default_factory")
        fields[name] = made
    for name, kept in fields.items():
        if isinstance(getattr(cls, name, None), dataclasses.Field):
            if kept.default is dataclasses.MISSING:
                delattr(cls, name)
            else:
                setattr(cls, name, kept.default)
    for name, value in cls.__dict__.items():
        if isinstance(value, dataclasses.Field) and name not in annotations:
            raise TypeError(f"{name!r} is a field but has no type annotation")
    cls.__dataclass_params__ = _PARAMS(False, False, False, False, False, False)  # type: ignore[attr-defined]
    cls.__dataclass_fields__ = fields  # type: ignore[attr-defined]
    if "__match_args__" not in cls.__dict__:
        cls.__match_args__ = tuple(name for name, kept in fields.items() if kept.init)  # type: ignore[attr-defined, misc]
    abc.update_abstractmethods(cls)
    return True


def _doc(name: str, init: Callable[..., None]) -> str:
    """The text the standard decorator gives a class without a docstring, `Name(x: 'int', y: 'float' = 0.0)`: its
    name and the signature inspect prints for its `__init__`, worded here from the parameters' annotations and
    defaults (inspect.signature would first look for the callable the class stands for)."""
    annotations = {name: kind for name, kind in init.__annotations__.items() if name != "return"}
    defaults = init.__defaults__ or ()
    first_default = len(annotations) - len(defaults)
    parameters = [
        f"{parameter}: {inspect.formatannotation(kind)}" + (f" = {defaults[index - first_default]!r}" if index >= first_default else "")
        for index, (parameter, kind) in enumerate(annotations.items())
    ]
    return f"{name}({', '.join(parameters)})"


class _Factory:
    """The default an `__init__` parameter shows for a field with a default factory, as the standard one's does."""

    def __repr__(self) -> str:
        return "<factory>"


_FACTORY = _Factory()


def _init(fields: tuple[dataclasses.Field[Any], ...], module: str) -> Callable[..., None]:
    """`__init__(self, <the init fields>)`, its defaults the fields' own objects (in `__defaults__`, as the standard
    one's are), storing the fields in the instance's `__dict__` in their order, as the standard one's assignments
    do: compiled from a text that names each field twice, where the standard one's names it five times."""
    taken = [field for field in fields if field.init]
    defaults: list[Any] = []
    for field in taken:
        if field.default_factory is not dataclasses.MISSING:
            defaults.append(_FACTORY)
        elif field.default is not dataclasses.MISSING:
            defaults.append(field.default)
        elif defaults:
            raise TypeError(f"non-default argument {field.name!r} follows default argument")
    factories = {field.name: field.default_factory for field in fields if field.default_factory is not dataclasses.MISSING}
    names: dict[str, Any] = {"__name__": module, "__names": tuple(field.name for field in taken)}
    if factories:
        names["__fill"] = _filler(fields, names["__names"], factories)
    code = _renamed(_FILL if factories else _UPDATE, len(taken), ("self", *names["__names"]))
    init: Callable[..., None] = types.FunctionType(code, names)
    init.__defaults__ = tuple(defaults) or None
    init.__annotations__ = {field.name: field.type for field in taken} | {"return": None}
    return init


# The functions a class's fields name: `__init__` (storing its parameters, or handing them to the default factories'
# filler) and a named tuple's `__new__`. Each is compiled once per number of parameters, its parameters named _0, _1
# ..., then given the field names (`_renamed`): an `exec` of a text per class would compile it once per class.
_UPDATE = "def __init__(self, {0}):\n self.__dict__.update(zip(__names, ({0}{1})))"
_FILL = "def __init__(self, {0}):\n __fill(self, ({0}{1}))"
_NEW = "lambda _cls, {0}{1}: _tuple_new(_cls, ({0}{1}))"  # collections.namedtuple's
_COMPILED: dict[tuple[str, int], types.CodeType] = {}


def _renamed(text: str, count: int, parameters: tuple[str, ...]) -> types.CodeType:
    """The code of `text` (one of the texts above) for `count` parameters after the first, its parameters named
    `parameters`: the code the text with those names would compile to."""
    compiled = _COMPILED.get((text, count))
    if compiled is None:
        source = text.format(", ".join(f"_{index}" for index in range(count)), "," if count == 1 else "")
        module = compile(source, "<string>", "eval" if text.startswith("lambda") else "exec")
        compiled = _COMPILED[text, count] = next(const for const in module.co_consts if isinstance(const, types.CodeType))
    return compiled.replace(co_varnames=parameters)


def _filler(
    fields: tuple[dataclasses.Field[Any], ...], taken: tuple[str, ...], factories: dict[str, Callable[[], Any]]
) -> Callable[[Any, tuple[Any, ...]], None]:
    """What stores the fields of a class with default factories: each field not given (or not taken) made by its own."""
    stored = [field.name for field in fields if field.init or field.name in factories]

    def fill(record: Any, values: tuple[Any, ...]) -> None:
        given = dict(zip(taken, values, strict=True))
        made = {name: factories[name]() for name in factories if given.get(name, _FACTORY) is _FACTORY}
        record.__dict__.update({name: made[name] if name in made else given[name] for name in stored})

    return fill


def _frozen_methods(cls: type[Any], names: frozenset[str]) -> dict[str, Callable[..., None]]:
    """A frozen record's `__setattr__` and `__delattr__`: a field of it (or of a subclass that is no dataclass), or
    any attribute of an instance of the class itself, cannot be set or deleted."""

    def __setattr__(self: Any, name: str, value: Any) -> None:
        if type(self) is cls or name in names:
            raise dataclasses.FrozenInstanceError(f"cannot assign to field {name!r}")
        super(cls, self).__setattr__(name, value)

    def __delattr__(self: Any, name: str) -> None:
        if type(self) is cls or name in names:
            raise dataclasses.FrozenInstanceError(f"cannot delete field {name!r}")
        super(cls, self).__delattr__(name)

    return {"__setattr__": __setattr__, "__delattr__": __delattr__}


def _with_methods(cls: type, frozen: bool, order: bool) -> type:
    fields = dataclasses.fields(cls)
    compared = _values([field.name for field in fields if field.compare])
    hashed = _values([field.name for field in fields if (field.compare if field.hash is None else field.hash)])
    shown = [field.name for field in fields if field.repr]

    @reprlib.recursive_repr()
    def __repr__(self: Any) -> str:
        return f"{self.__class__.__qualname__}({', '.join(f'{name}={getattr(self, name)!r}' for name in shown)})"

    def __eq__(self: Any, other: Any) -> Any:
        if other.__class__ is self.__class__:
            return compared(self) == compared(other)
        return NotImplemented

    def __hash__(self: Any) -> int:
        return hash(hashed(self))

    # As the standard decorator does: a frozen class hashes its compared fields, a mutable one is unhashable.
    methods = {"__repr__": __repr__, "__eq__": __eq__, "__hash__": __hash__ if frozen else None}
    if order:
        methods |= {name: _comparison(compared, name) for name in _ORDER}
    for name, method in methods.items():
        if method is not None:
            method.__qualname__ = f"{cls.__qualname__}.{name}"
        setattr(cls, name, method)
    return cls


def _comparison(compared: Callable[[Any], tuple[Any, ...]], name: str) -> Callable[[Any, Any], Any]:
    """`__lt__` (`__le__` ...): the compared fields' tuples in that order, for two records of one class."""
    holds = getattr(operator, name)

    def compare(self: Any, other: Any) -> Any:
        if other.__class__ is self.__class__:
            return holds(compared(self), compared(other))
        return NotImplemented

    compare.__name__ = name
    return compare


def _values(names: list[str]) -> Callable[[Any], tuple[Any, ...]]:
    """The tuple of those attributes (the generated methods compare and hash tuples, even of one field or none)."""
    if len(names) >= 2:
        return operator.attrgetter(*names)
    if names:
        [name] = names
        return lambda record: (getattr(record, name),)
    return lambda record: ()


# What typing.NamedTuple refuses in a class body, and what it does not copy from it onto the class.
_TUPLE_PROHIBITED = frozenset(
    {"__new__", "__init__", "__slots__", "__getnewargs__", "_fields", "_field_defaults", "_make", "_replace", "_asdict", "_source"}
)
_TUPLE_SPECIAL = frozenset({"__module__", "__name__", "__annotations__"})


def _namedtuple_311(typename: str, field_names: list[str], *, defaults: list[Any], module: str) -> Any:
    """collections.namedtuple (Python 3.11's) without `rename`, its `__new__` not compiled from a text of its own."""
    for name in [typename, *field_names]:
        if not name.isidentifier():
            raise ValueError(f"Type names and field names must be valid identifiers: {name!r}")
        if keyword.iskeyword(name):
            raise ValueError(f"Type names and field names cannot be a keyword: {name!r}")
    seen: set[str] = set()
    for name in field_names:
        if name.startswith("_"):
            raise ValueError(f"Field names cannot start with an underscore: {name!r}")
        if name in seen:
            raise ValueError(f"Encountered duplicate field name: {name!r}")
        seen.add(name)
    typename = sys.intern(typename)
    fields = tuple(map(sys.intern, field_names))
    arguments = ", ".join(fields) + ("," if len(fields) == 1 else "")
    new = types.FunctionType(
        _renamed(_NEW, len(fields), ("_cls", *fields)),
        {"_tuple_new": tuple.__new__, "__builtins__": {}, "__name__": f"namedtuple_{typename}"},
    )
    new.__name__ = "__new__"
    new.__doc__ = f"Create new instance of {typename}({arguments})"
    new.__defaults__ = tuple(defaults)
    count, shown = len(fields), "(" + ", ".join(f"{name}=%r" for name in fields) + ")"

    def _make(cls: Any, iterable: Any) -> Any:
        result = tuple.__new__(cls, iterable)
        if len(result) != count:
            raise TypeError(f"Expected {count} arguments, got {len(result)}")
        return result

    _make.__doc__ = f"Make a new {typename} object from a sequence or iterable"

    def _replace(self: Any, /, **kwds: Any) -> Any:
        result = self._make(map(kwds.pop, fields, self))
        if kwds:
            raise ValueError(f"Got unexpected field names: {list(kwds)!r}")
        return result

    _replace.__doc__ = f"Return a new {typename} object replacing specified fields with new values"

    def __repr__(self: Any) -> Any:
        "Return a nicely formatted representation string"
        return self.__class__.__name__ + shown % self

    def _asdict(self: Any) -> dict[str, Any]:
        "Return a new dict which maps field names to their values."
        return dict(zip(self._fields, self, strict=False))

    def __getnewargs__(self: Any) -> tuple[Any, ...]:
        "Return self as a plain tuple.  Used by copy and pickle."
        return tuple(self)

    for method in (new, _make, _replace, __repr__, _asdict, __getnewargs__):
        method.__qualname__ = f"{typename}.{method.__name__}"
    namespace: dict[str, Any] = {
        "__doc__": f"{typename}({arguments})",
        "__slots__": (),
        "_fields": fields,
        "_field_defaults": dict(zip(fields[len(fields) - len(defaults) :], defaults, strict=True)),
        "__new__": new,
        "_make": classmethod(_make),
        "_replace": _replace,
        "__repr__": __repr__,
        "_asdict": _asdict,
        "__getnewargs__": __getnewargs__,
        "__match_args__": fields,
    }
    for index, name in enumerate(fields):
        namespace[name] = _tuple_getter(index, sys.intern(f"Alias for field number {index}"))
    result = type(typename, (tuple,), namespace)
    result.__module__ = module
    return result


_tuple_getter: Callable[[int, str], Any] = vars(collections)["_tuplegetter"]  # the field descriptor namedtuple's classes use
_namedtuple: Callable[..., Any] = _namedtuple_311 if _MIRRORS_THIS_PYTHON else collections.namedtuple


class _TupleMaker(type):
    """typing.NamedTupleMeta's work (typing 3.11), without Generic bases, the annotations kept as the body wrote them."""

    def __new__(cls, typename: str, bases: tuple[type, ...], namespace: dict[str, Any]) -> Any:
        if any(base is not NamedTuple for base in bases):
            raise TypeError("can only inherit from a NamedTuple type (regmap.records: not from Generic)")
        annotations: dict[str, Any] = namespace.get("__annotations__", {})
        default_names: list[str] = []
        for field_name in annotations:
            if field_name in namespace:
                default_names.append(field_name)
            elif default_names:
                raise TypeError(
                    f"Non-default namedtuple field {field_name} cannot follow default field"
                    f"{'s' if len(default_names) > 1 else ''} {', '.join(default_names)}"
                )
        defaults = [namespace[name] for name in default_names]
        made: Any = _namedtuple(typename, list(annotations), defaults=defaults, module=namespace["__module__"])
        made.__annotations__ = made.__new__.__annotations__ = dict(annotations)
        for key, value in namespace.items():
            if key in _TUPLE_PROHIBITED:
                raise AttributeError("Cannot overwrite NamedTuple attribute " + key)
            if key not in _TUPLE_SPECIAL and key not in made._fields:
                setattr(made, key, value)
        return made


if not TYPE_CHECKING:
    NamedTuple = type.__new__(_TupleMaker, "NamedTuple", (), {})  # the base a class names; itself never made by __new__
