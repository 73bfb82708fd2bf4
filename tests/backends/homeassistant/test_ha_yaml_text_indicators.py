"""The Home Assistant files' YAML writer (regmap.homeauto.yamltext) decides some strings without PyYAML's analysis: one
that starts with an indicator (a template's `{{`) and one that holds a `:` or `#`. Whatever else such a string holds
(a tab, a line break, a quote, a space before `#`), the file must be what PyYAML writes."""

from __future__ import annotations

import pytest

from regmap.homeauto.yamltext import pyyaml_text, yaml_text

TEXTS = [
    "{{ states('sensor.x') | int(0) }}",
    "{{ {1: 'On', 2: 'Off'}.get(states('sensor.x') | int(-1), states('sensor.x')) }}",
    "[a]b",
    "%",
    "!tag",
    "'quoted' start",
    "{\ttab}",
    "{line\nbreak}",
    "[trailing space ",
    "@at\u2028sep",
    "`tick\x85",
    "Run status: Fault",
    "ends with:",
    "a #comment",
    "a#b:c",
    "12:30",
    "yes: no",
    "x:\ty",
    "colon:\nbreak",
]


@pytest.mark.parametrize("text", TEXTS)
def test_a_string_decided_without_the_analysis_is_written_as_pyyaml_writes_it(text: str) -> None:
    data = {"key": text, "list": [text, {"name": text}]}
    assert yaml_text(data) == pyyaml_text(data)
