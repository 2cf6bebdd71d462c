"""Renamed keyword arguments: the old spelling keeps working, with a warning.

One decorator, :func:`renamed`, for the names of the public API that changed
(docs/conventions.md, "Names"). ``@renamed(params="parameters")`` lets a caller
still write ``f(..., params=p)``: the value goes to ``parameters`` and a
:class:`DeprecationWarning` names the new spelling. Positional calls are not
touched (a rename never moves an argument). The signature seen by
:func:`inspect.signature` is the new one; the old names are kept in
``__renamed__`` (old -> new) so that ``tests/test_signatures.py`` can check that
an old name lives only here.

A hot path that cannot afford a wrapper's call (``NumericLagrangian.__call__``,
called by ``solve_ivp`` at every step) takes ``**deprecated`` instead and hands
it to :func:`take_renamed`; ``@renamed`` then only records the old names and
hides ``**deprecated`` from the signature.
"""

from __future__ import annotations

import functools
import inspect
import warnings
from collections.abc import Callable
from typing import Any, TypeVar

from .errors import InvalidTypeError

__all__ = ["renamed", "take_renamed"]

F = TypeVar("F", bound=Callable[..., Any])


def renamed(**old_to_new: str) -> Callable[[F], F]:
    """Map the deprecated keyword names ``old`` to ``new`` (``old="new"``).

    Passing an old name warns (:class:`DeprecationWarning`, naming the new one)
    and calls the function with the new name; passing both is an
    :class:`~poinsot.errors.InvalidTypeError`.

    Examples
    --------
    >>> import warnings
    >>> @renamed(params="parameters")
    ... def f(x, parameters=None):
    ...     return x, parameters
    >>> with warnings.catch_warnings(record=True) as w:
    ...     warnings.simplefilter("always")
    ...     f(1, params=2)
    (1, 2)
    >>> str(w[0].message)
    '`f(params=...)` is deprecated: use `parameters=` instead.'
    """

    def decorate(fn: F) -> F:
        sig = inspect.signature(fn)
        names = sig.parameters
        for old, new in old_to_new.items():
            if new not in names or old in names:
                raise TypeError(f"renamed({old}={new!r}) does not fit {fn.__qualname__}{sig}")
        where = fn.__qualname__
        inline = names.get("deprecated")
        if inline is not None and inline.kind is inspect.Parameter.VAR_KEYWORD:
            # the function calls take_renamed itself: no wrapper
            fn.__signature__ = sig.replace(  # type: ignore[attr-defined]
                parameters=[p for p in names.values() if p is not inline]
            )
            fn.__renamed__ = dict(old_to_new)  # type: ignore[attr-defined]
            return fn

        @functools.wraps(fn)
        def wrapper(*args: Any, **kwargs: Any) -> Any:
            if kwargs:
                for old, new in old_to_new.items():
                    if old in kwargs:
                        if new in kwargs:
                            raise InvalidTypeError(
                                f"Expected one of `{new}` and its deprecated spelling `{old}`, "
                                "got both."
                            )
                        warnings.warn(
                            f"`{where}({old}=...)` is deprecated: use `{new}=` instead.",
                            DeprecationWarning,
                            stacklevel=2,
                        )
                        kwargs[new] = kwargs.pop(old)
            return fn(*args, **kwargs)

        wrapper.__renamed__ = dict(old_to_new)  # type: ignore[attr-defined]
        return wrapper  # type: ignore[return-value]

    return decorate


def take_renamed(
    where: str, deprecated: dict[str, Any], values: dict[str, Any], **old_to_new: str
) -> dict[str, Any]:
    """``values`` (new name -> value) updated from ``deprecated`` (the ``**deprecated``
    of ``where``, old names only), warning as :func:`renamed` does.

    Examples
    --------
    >>> import warnings
    >>> with warnings.catch_warnings():
    ...     warnings.simplefilter("ignore")
    ...     take_renamed("f", {"params": 2}, {"parameters": None}, params="parameters")
    {'parameters': 2}
    """
    out = dict(values)
    for key, value in deprecated.items():
        new = old_to_new.get(key)
        if new is None:
            raise TypeError(f"{where}() got an unexpected keyword argument {key!r}")
        if out[new] is not None:
            raise InvalidTypeError(
                f"Expected one of `{new}` and its deprecated spelling `{key}`, got both."
            )
        warnings.warn(
            f"`{where}({key}=...)` is deprecated: use `{new}=` instead.",
            DeprecationWarning,
            stacklevel=3,
        )
        out[new] = value
    return out
