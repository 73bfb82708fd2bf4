"""regmap.render's code generator: templates read attributes and print text as Jinja's own code does, faster."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import jinja2
import pytest
from jinja2.compiler import CodeGenerator

from regmap import render


def _environment(generator: type[CodeGenerator] = render._CodeGenerator) -> jinja2.Environment:
    """An environment as `render.templates` makes one, without a loader or a cache: each test compiles its text."""
    env = jinja2.Environment(undefined=jinja2.StrictUndefined, **render._ENVIRONMENT_OPTIONS)
    env.code_generator_class = generator
    env.filters.update(render.FILTERS)
    return env


class _Record:
    title = "a title"
    nothing = None


def test_every_back_end_environment_compiles_with_the_code_generator() -> None:
    assert render.own_code_generator()  # this Jinja has every internal the generator builds on
    assert render.templates("regmap.backends.c.device").code_generator_class is render._CodeGenerator


def test_a_jinja_without_the_internals_renders_with_its_own_generator(monkeypatch: pytest.MonkeyPatch) -> None:
    """A later Jinja that renamed what `_CodeGenerator` overrides or calls must not break a run: its own generator serves."""
    monkeypatch.delattr(CodeGenerator, "_output_child_to_const")
    assert not render.own_code_generator()
    env = render.templates.__wrapped__("regmap.backends.c.device")  # a new environment, not the process's kept one
    assert env.code_generator_class is CodeGenerator
    template = env.from_string("{{ r.title }}, {{ r.nothing }}!")
    assert template.render(r=_Record()) == "a title, None!"


def test_an_attribute_is_read_and_an_item_is_the_fallback() -> None:
    text = "{{ r.title }}|{{ r.nothing }}|{{ d.key }}|{{ d.items is defined }}|{{ n.x.y }}"
    rendered = _environment().from_string(text).render(r=_Record(), d={"key": "item"}, n={"x": {"y": 3}})
    assert rendered == "a title|None|item|True|3"


def test_a_missing_attribute_is_undefined_and_strict() -> None:
    template = _environment().from_string("{{ r.absent }}")
    with pytest.raises(jinja2.UndefinedError, match="absent"):
        template.render(r=_Record())


def test_the_object_of_a_fallback_lookup_is_evaluated_once() -> None:
    calls: list[int] = []

    def made() -> dict[str, Any]:
        calls.append(1)
        return {"key": "item"}

    assert _environment().from_string("{{ made().key }}").render(made=made) == "item"
    assert len(calls) == 1


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("{{ x }}", "5"),  # one piece: printed as it is, not as a tuple of one
        ("a{{ x }}b{{ y }}c", "a5bNonec"),  # pieces that are no text are printed as str() prints them
        ("{% macro m(v) %}<{{ v }}|{{ v }}>{% endmacro %}{{ m(x) }}{{ m(y) }}", "<5|5><None|None>"),  # a buffer
        ("{% for i in [1, 2] %}{{ i }}-{{ x | hex2 }}\n{% endfor %}", "1-0x05\n2-0x05\n"),
    ],
)
def test_runs_of_text_and_values_print_as_jinja_prints_them(text: str, expected: str) -> None:
    assert _environment().from_string(text).render(x=5, y=None) == expected
    assert _environment(CodeGenerator).from_string(text).render(x=5, y=None) == expected  # Jinja's own code agrees


def test_compiled_templates_are_not_read_as_those_of_jinjas_own_generator(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("REGMAP_CACHE_DIR", str(tmp_path))
    monkeypatch.delenv(render.NO_TEMPLATE_CACHE_VARIABLE, raising=False)
    render.templates.cache_clear()
    try:
        cache = render.templates("regmap.backends.c.device").bytecode_cache
        assert isinstance(cache, render.TemplateCache)
        assert cache.pattern == render.compiled_names() != jinja2.FileSystemBytecodeCache().pattern
    finally:
        render.templates.cache_clear()
