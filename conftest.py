"""pytest configuration for the whole tree."""

import importlib.util
import tempfile

# poinsot.jax needs the extra poinsot[jax]: without JAX its doctests cannot be collected
collect_ignore = [] if importlib.util.find_spec("jax") else ["src/poinsot/jax.py"]

import os  # noqa: E402

# The suite tests the compiled kernels and their compilation (notices, Ctrl-C, the
# cache): a first call compiles as it did before issue 40, and no background build is
# started; tests/test_cold_start.py turns interpreting on where it tests it.
os.environ.setdefault("POINSOT_INTERPRET_FIRST", "0")
os.environ.setdefault("POINSOT_BACKGROUND_BUILD", "0")

# poinsot.jax's exact free body is a large XLA program (its bounded loops unrolled):
# compiling it at LLVM -O0 takes ~2/3 of the time at the default -O2 (measured 142 s
# against 218 s for one `.attitude`), and the persistent compilation cache lets the
# doctests and tests of every xdist worker share a compile of the same shapes (a single
# body's setup is one program for all of them) instead of compiling it once each. The
# results are compared with tolerances, not bit for bit, so the optimisation level does
# not change what the tests check. Set either variable to override.
os.environ.setdefault("XLA_FLAGS", "--xla_backend_optimization_level=0")
os.environ.setdefault(
    "JAX_COMPILATION_CACHE_DIR",
    os.path.join(tempfile.gettempdir(), f"poinsot-tests-jax-cache-{os.getuid()}"),
)

import sys  # noqa: E402

import pytest  # noqa: E402


@pytest.fixture(autouse=True)
def _close_pyplot_figures():
    """Close the pyplot figures a test or doctest opened: a worker that runs many
    plotting doctests otherwise passes matplotlib's 20-figure warning (an error here)."""
    yield
    plt = sys.modules.get("matplotlib.pyplot")
    if plt is not None:
        plt.close("all")


#: doctests that run an engine not in poinsot's extras (Basilisk: ``pip install bsk`` in an
#: environment of its own): skipped, with the reason, where it is not installed
_ENGINE_DOCTESTS = {
    "poinsot.verify._basilisk.run_basilisk": "Basilisk",
    "poinsot.verify._basilisk.build_basilisk": "Basilisk",
}


def pytest_collection_modifyitems(config, items):
    for item in items:
        module = _ENGINE_DOCTESTS.get(item.name)
        if module and importlib.util.find_spec(module) is None:
            item.add_marker(pytest.mark.skip(
                reason=f"{module} is not installed (pip install bsk, in an environment of its own)"
            ))  # fmt: skip
