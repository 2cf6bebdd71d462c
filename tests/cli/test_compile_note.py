"""The first run says it is compiling (issue 23: a cold `poinsot demo` sat silently at
"1%" for ~14 s while numba compiled); a run from the cache says nothing."""

from __future__ import annotations

import numpy as np
from numba import njit

from poinsot.cli import _runs


def test_a_compilation_is_announced_once(capsys, monkeypatch):
    monkeypatch.setattr(_runs._compile_note, "said", False)
    with _runs._compile_note(quiet=False):
        njit(lambda x: x + 1.0)(1.0)  # a new function: numba compiles it
        njit(lambda x: x * 2.0)(np.ones(2))
    err = capsys.readouterr().err
    assert err.count("compiling (first run only; about 1 s or less") == 1, err


def test_the_estimates_name_real_kernels():
    # the table the notices quote names kernels that exist (a renamed kernel would fall
    # back to the small default without a word) and each is a numba dispatcher
    import importlib

    from poinsot import _jit

    for name, seconds in _jit.COMPILE_S.items():
        module, qualname = name.rsplit(".", 1)
        kernel = getattr(importlib.import_module(module), qualname)
        assert hasattr(kernel, "py_func") and kernel.py_func.__qualname__ == qualname, name
        assert _jit.compile_estimate(kernel) in (seconds, _jit.COMPILE_LANE_KIND_S), name
        assert seconds > _jit.COMPILE_OTHER_S
    assert _jit.say_seconds(7.2) == "about 7 s" and "1 s or less" in _jit.say_seconds(0.3)


def test_no_compilation_no_word(capsys, monkeypatch):
    monkeypatch.setattr(_runs._compile_note, "said", False)
    f = njit(lambda x: x - 1.0)
    f(1.0)  # compiled before the run
    with _runs._compile_note(quiet=False):
        f(2.0)
    assert "compiling" not in capsys.readouterr().err


def test_quiet_says_nothing(capsys, monkeypatch):
    monkeypatch.setattr(_runs._compile_note, "said", False)
    with _runs._compile_note(quiet=True):
        njit(lambda x: x + 3.0)(1.0)
    assert "compiling" not in capsys.readouterr().err
