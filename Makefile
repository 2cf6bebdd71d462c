# Two commands on a fresh machine: `make demo` and `make test`.
PYTHON ?= python3
VENV := .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.installed

.PHONY: venv demo test test-min bench docs browser clean

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

# The suite again with NumPy, SciPy and numba at the lowest versions pyproject.toml
# allows (tools/min_versions.py pins them), in a second venv `.venv-min`.
VENV_MIN := .venv-min
PY_MIN := $(VENV_MIN)/bin/python
STAMP_MIN := $(VENV_MIN)/.installed

$(STAMP_MIN): pyproject.toml tools/min_versions.py
	test -x $(PY_MIN) || $(PYTHON) -m venv $(VENV_MIN)
	$(PY_MIN) -m pip install --quiet --upgrade pip
	$(PY_MIN) tools/min_versions.py > $(VENV_MIN)/constraints.txt
	$(PY_MIN) -m pip install --quiet -c $(VENV_MIN)/constraints.txt -e ".[all]"
	touch $(STAMP_MIN)

test-min: $(STAMP_MIN) browser
	$(PY_MIN) -c "import numpy, scipy, numba; print('minimum versions: numpy', numpy.__version__, 'scipy', scipy.__version__, 'numba', numba.__version__)"
	$(PY_MIN) -m pytest

bench: venv
	$(PY) -m pip install --quiet -e ".[bench]" || echo "peer libraries unavailable; benchmarking against SciPy only"
	$(PY) benchmarks/run.py

docs: venv
	$(PY) -m sphinx -W -b html docs docs/_build/html

clean:
	rm -rf $(VENV) $(VENV_MIN) build dist docs/_build src/*.egg-info
