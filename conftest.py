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

# The files whose tests compile with XLA (poinsot.jax): one worker runs them all, since
# two XLA compiles at once have taken most of the machine's memory.
_XLA_FILES = {
    "src/poinsot/jax.py",
    "tests/test_jax.py",
    "tests/test_jax_free_body.py",
    "tests/test_formulas.py",
    "tests/test_docs_examples.py",
}


@pytest.hookimpl(tryfirst=True)
def pytest_collection_modifyitems(config, items):
    """Under pytest-xdist (`make test` runs `-n 2 --dist loadgroup`): the tests of one
    file run on one worker, so the numba kernels a file needs compile once, in one
    process (not once in each worker on a cold cache), and the XLA files share one
    worker. The XLA group is moved to the front: it is the longest (minutes of XLA
    compiling), and a group is given to a worker in the order of the collection, so it
    starts first and the other worker takes the rest. Without xdist the marks change
    nothing."""
    if config.pluginmanager.hasplugin("xdist") and getattr(config.option, "numprocesses", None):
        items.sort(key=lambda item: item.nodeid.split("::")[0] not in _XLA_FILES)
    for item in items:
        path = item.nodeid.split("::")[0]
        group = "xla" if path in _XLA_FILES else path
        item.add_marker(pytest.mark.xdist_group(group))
