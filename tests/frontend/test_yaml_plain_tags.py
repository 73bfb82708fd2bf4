"""The fast YAML reader gives a plain text the tag PyYAML's resolver gives it, reading no pattern where the resolver
lists none for the text's first character, and asking the resolver for every text once a pattern is listed for
every text (a library may add one to PyYAML's shared resolver)."""

from __future__ import annotations

import re

import pytest
import yaml

from regmap.frontend.yamlsource import YamlProblem, read_yaml

DOCUMENT = "name: zz top\ncount: 12\nflag: yes\nempty:\n"


def test_texts_read_as_pyyaml_reads_them() -> None:
    data, _ = read_yaml(DOCUMENT)
    assert data == yaml.safe_load(DOCUMENT) == {"name": "zz top", "count": 12, "flag": True, "empty": None}


def test_a_pattern_for_every_text_is_asked_of_every_text(monkeypatch: pytest.MonkeyPatch) -> None:
    every = (yaml.resolver.BaseResolver.DEFAULT_SCALAR_TAG.replace("str", "bool"), re.compile(r"^zz"))
    table = {**yaml.resolver.Resolver.yaml_implicit_resolvers, None: [every]}
    monkeypatch.setattr(yaml.resolver.Resolver, "yaml_implicit_resolvers", table)
    with pytest.raises(YamlProblem, match="'zz top' is not a valid YAML bool"):  # `zz top` now reads as a boolean
        read_yaml(DOCUMENT)
