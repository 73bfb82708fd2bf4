# regmap — `make` installs into .venv and generates everything; `make test` runs the tests.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed

.PHONY: all install tools generate regen test lint format typecheck check docs bench bench-sim mutate clean

all: generate

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/pip install --quiet --upgrade pip
	$(BIN)/pip install --quiet -e '.[dev]'
	touch $(STAMP)

install: $(STAMP)

# The third-party judges of the generated output (ESPHome, Home Assistant, the ST parsers, matiec), each in
# its own environment under ~/.cache/regmap/tools, rebuilt only when its pins change (tests/support/tool_envs.py).
# A tool that cannot be built here is reported and its tests skip; under CI=true that fails.
tools: $(STAMP)
	$(BIN)/python tests/support/tool_envs.py install

generate: $(STAMP)
	$(BIN)/regmap generate
	for plant in examples/plants/*.yaml; do $(BIN)/regmap generate $$plant || exit 1; done  # into generated/plants/<plant id>/

# Rewrite every committed golden output (generated/ and the expected error texts of invalid maps).
regen: generate
	$(BIN)/python tests/support/regen.py
	$(BIN)/regmap diff tests/maps/diff/idm_rs_small_v1.yaml tests/maps/diff/idm_rs_small_v2.yaml --format markdown > docs/changelog-example.md; status=$$?; test $$status -eq 6 -o $$status -eq 7

test: $(STAMP) tools
	$(BIN)/python -m pytest -q

lint: $(STAMP)
	$(BIN)/ruff check generator tests bench
	$(BIN)/ruff format --check generator tests bench
	$(BIN)/mypy
	$(BIN)/mypy --strict tests bench

format: $(STAMP)
	$(BIN)/ruff format generator tests bench
	$(BIN)/ruff check --fix generator tests bench

typecheck: $(STAMP)
	$(BIN)/mypy

check: lint test

# Benchmarks (bench/): bus time, read-plan optimality, generation speed, client overhead, C helpers -> docs/benchmarks.md.
bench-sim: $(STAMP)
	$(BIN)/python -m bench.simload

bench: $(STAMP)
	$(BIN)/python -m bench

docs: $(STAMP)
	$(BIN)/regmap generate --target markdown
	$(BIN)/mkdocs build --strict

clean:
	rm -rf $(VENV) build *.egg-info generator/*.egg-info .pytest_cache .mypy_cache .ruff_cache

# Curated mutants (tests/mutation/mutants.yaml) against the behavioural tests; not part of `make test`.
mutate: $(STAMP)
	$(BIN)/python tests/mutation/run.py
