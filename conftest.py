"""pytest configuration for the whole tree."""

import importlib.util

# poinsot.jax needs the extra poinsot[jax]: without JAX its doctests cannot be collected
collect_ignore = [] if importlib.util.find_spec("jax") else ["src/poinsot/jax.py"]
