# Two commands on a fresh machine: `make demo` and `make test`.
PYTHON ?= python3
VENV := .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.installed

.PHONY: venv demo test bench docs browser clean

venv: $(STAMP)

$(STAMP): pyproject.toml
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e ".[all]"
	touch $(STAMP)

demo: venv
	$(VENV)/bin/poinsot demo

# Debian's chromium for the end-to-end report test (skipped loudly if it cannot be had).
browser:
	bash tools/install_browser.sh

test: venv browser
	$(PY) -m ruff check src tests benchmarks
	$(PY) -m pytest

bench: venv
	$(PY) -m pip install --quiet -e ".[bench]" || echo "peer libraries unavailable; benchmarking against SciPy only"
	$(PY) benchmarks/run.py

docs: venv
	$(PY) -m sphinx -W -b html docs docs/_build/html

clean:
	rm -rf $(VENV) build dist docs/_build src/*.egg-info
