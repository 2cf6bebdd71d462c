# Two commands on a fresh machine: `make demo` and `make test`.
PYTHON ?= python3
VENV := .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.installed

.PHONY: venv demo test test-slow test-nonumba test-min test-min-core min-versions-banner bench docs browser clean

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

# Two pytest-xdist workers (the machines this runs on have two cores), a test file per
# worker (--dist loadfile): on a cold numba cache a file's kernels compile in one
# process, and its module fixtures are made once. (--dist loadgroup would also keep the
# XLA-compiling files on one worker, but with pytest 9 and xdist 3.8 it ignores its
# groups and splits every file.) `make test XDIST=` runs serially.
XDIST ?= -n 2 --dist loadfile

test: venv browser
	$(PY) -m ruff check src tests benchmarks
	$(PY) -m ruff format --check src tests benchmarks tools
	@# mypy (~1.5 min, one core, cold in CI) runs beside pytest, which leaves a core idle
	@# at times (subprocesses, servers, the last file of a worker); both must pass.
	( $(PY) -m mypy src/poinsot > $(VENV)/mypy.log 2>&1; echo $$? > $(VENV)/mypy.rc ) & \
	$(PY) -m pytest $(XDIST) --durations=30; rc=$$?; wait; \
	echo "mypy src/poinsot:"; cat $(VENV)/mypy.log; \
	test "$$(cat $(VENV)/mypy.rc)" = 0 && test $$rc = 0
	$(MAKE) test-nonumba

# Tests marked slow (minutes of XLA compiling each: the JAX exact free body's forward-
# and reverse-mode derivatives against central differences); not in `make test`, which
# must stay well under 20 minutes on 2 cores.
test-slow: venv
	$(PY) -m pytest -m slow tests

# The numerical core again without numba (issue 25): POINSOT_NUMBA=0 selects the NumPy
# executor of the same formula source (poinsot._jit); tests/test_nonumba.py also runs
# poinsot in a subprocess where `import numba` fails. Bit-identity of one rotation
# and a batch is numba's promise only (NumPy's SIMD trig differs by an ulp).
# Deselected: numba's own cache, and batch == single bit for bit.
NONUMBA_TESTS := tests/rotations tests/kinematics tests/test_nonumba.py tests/symbolic \
	tests/dynamics/test_free_body.py tests/dynamics/test_euler_rhs.py tests/dynamics/test_fused.py \
	tests/dynamics/test_elliptic.py tests/dynamics/test_lagrange_top.py \
	--ignore tests/rotations/test_single_batch_threads.py
test-nonumba: venv
	POINSOT_NUMBA=0 $(PY) -m pytest $(XDIST) -p no:cacheprovider $(NONUMBA_TESTS) \
		-k "not kernel_cache and not mixed_regimes_equals_single"

# The suite again with NumPy, SciPy and numba at the lowest versions pyproject.toml
# allows (tools/min_versions.py pins them), in a second venv `.venv-min`.
# `test-min-core` (run by CI after `test`): the numerical core (CORE_TESTS below).
# `test-min`: the whole suite (every extra installed at versions that fit the pins).
VENV_MIN := .venv-min
PY_MIN := $(VENV_MIN)/bin/python
STAMP_MIN_CORE := $(VENV_MIN)/.installed-core
STAMP_MIN := $(VENV_MIN)/.installed
# Every compiled kernel family and every version-sensitive API once (rotations, the
# fused DOP853 kernels and lanes, the exact free body and Lagrange top, the midpoint
# rule, SymPy -> numba code generation, the numba cache); the edge sweeps, interrupt and
# mpmath-heavy files run in `make test` (current versions) and `make test-min` (all).
CORE_TESTS := tests/rotations tests/kinematics tests/mass \
	tests/dynamics/test_fused.py tests/dynamics/test_fused_lanes.py \
	tests/dynamics/test_free_body.py tests/dynamics/test_euler_rhs.py \
	tests/dynamics/test_elliptic.py tests/dynamics/test_lagrange_top.py \
	tests/dynamics/test_heavy.py tests/dynamics/test_midpoint_compiled.py \
	tests/dynamics/test_simulate.py tests/symbolic/test_numeric.py \
	tests/peers/test_scipy_free_body.py tests/test_numba_helpers.py tests/test_numba_cache.py \
	tests/test_trajectory.py src/poinsot/rotations src/poinsot/dynamics

$(STAMP_MIN_CORE): pyproject.toml tools/min_versions.py
	test -x $(PY_MIN) || $(PYTHON) -m venv $(VENV_MIN)
	$(PY_MIN) -m pip install --quiet --upgrade pip
	$(PY_MIN) tools/min_versions.py > $(VENV_MIN)/constraints.txt
	$(PY_MIN) -m pip install --quiet -c $(VENV_MIN)/constraints.txt -e ".[test,symbolic]"
	touch $(STAMP_MIN_CORE)

$(STAMP_MIN): $(STAMP_MIN_CORE)
	$(PY_MIN) -m pip install --quiet -c $(VENV_MIN)/constraints.txt -e ".[all]"
	touch $(STAMP_MIN)

min-versions-banner:
	@$(PY_MIN) -c "import numpy, scipy, numba; print('minimum versions: numpy', numpy.__version__, 'scipy', scipy.__version__, 'numba', numba.__version__)"

# numba's cache of its own, apart from the one `make test` fills with the current numba
# in the source tree's __pycache__ (docs/testing.md).
NUMBA_CACHE_MIN := $(CURDIR)/$(VENV_MIN)/numba-cache

# The SIMD lanes compile per torque kind (about 7 s each, cold): at the minimum versions,
# the free body, gravity and the gyrostat (diagonal, pinned, time-reading kinds); the
# other kinds' torque formulas are the one-body kernel's, checked by `make test`.
LANES := tests/dynamics/test_fused_lanes.py
CORE_DESELECT := --deselect "$(LANES)::test_bit_identical_to_one_body_kernel[body]" \
	--deselect "$(LANES)::test_bit_identical_to_one_body_kernel[space]" \
	--deselect "$(LANES)::test_bit_identical_to_one_body_kernel[gravity-gradient]" \
	--deselect "$(LANES)::test_bit_identical_with_full_inertia_tensors[gyrostat]"

test-min-core: $(STAMP_MIN_CORE) min-versions-banner
	NUMBA_CACHE_DIR=$(NUMBA_CACHE_MIN) $(PY_MIN) -m pytest $(XDIST) $(CORE_TESTS) $(CORE_DESELECT)

test-min: $(STAMP_MIN) browser min-versions-banner
	NUMBA_CACHE_DIR=$(NUMBA_CACHE_MIN) $(PY_MIN) -m pytest

bench: venv
	$(PY) -m pip install --quiet -e ".[bench]" || echo "peer libraries unavailable; benchmarking against SciPy only"
	$(PY) benchmarks/run.py

docs: venv
	$(PY) -m sphinx -W -b html docs docs/_build/html

clean:
	rm -rf $(VENV) $(VENV_MIN) build dist docs/_build src/*.egg-info
