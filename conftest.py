"""pytest configuration for the whole tree."""

import importlib.util

# poinsot.jax needs the extra poinsot[jax]: without JAX its doctests cannot be collected
collect_ignore = [] if importlib.util.find_spec("jax") else ["src/poinsot/jax.py"]

import os  # noqa: E402

# The suite tests the compiled kernels and their compilation (notices, Ctrl-C, the
# cache): a first call compiles as it did before issue 40, and no background build is
# started; tests/test_cold_start.py turns interpreting on where it tests it.
os.environ.setdefault("POINSOT_INTERPRET_FIRST", "0")
os.environ.setdefault("POINSOT_BACKGROUND_BUILD", "0")

import pytest  # noqa: E402

# The longest files (minutes of XLA compiling each): under pytest-xdist (`make test`:
# `-n 2 --dist loadfile`, a file per worker in the order collected) they go first, so
# that the run does not end with one worker compiling while the other waits.
_LONGEST_FIRST = ("src/poinsot/jax.py", "tests/test_jax_free_body.py")


@pytest.hookimpl(tryfirst=True)
def pytest_collection_modifyitems(config, items):
    """On an xdist worker (whose collection the scheduler hands out), the files of
    :data:`_LONGEST_FIRST` first; the order within a file is kept."""
    if os.environ.get("PYTEST_XDIST_WORKER"):
        items.sort(key=lambda item: item.nodeid.split("::")[0] not in _LONGEST_FIRST)
