"""The registry of scenario kinds: one line per kind (``docs/adding-a-motion.md``).

A file names its kind with a top-level ``kind = "..."``; without it, the kinds are
asked in the order below (:meth:`~poinsot.scenarios.kind.ScenarioKind.claims` on
the raw TOML) and the first that claims the file reads it.
"""

from __future__ import annotations

from collections.abc import Mapping
from types import MappingProxyType
from typing import Any

from ..errors import InvalidInputError
from .kind import ScenarioKind
from .kinds import (
    attitude,
    bouncing,
    central_orbit,
    coning,
    estimation,
    free_body,
    gyrostat,
    heavy_top,
    lagrangian,
    rotating_frame,
    spacecraft,
    torqued_body,
)

__all__ = ["KINDS", "get_kind", "kind_for"]

#: name -> adapter, in the order kinds are asked to claim a file without ``kind``.
KINDS: Mapping[str, ScenarioKind] = MappingProxyType(
    {
        k.name: k
        for k in (
            lagrangian.KIND,  # [lagrangian]: generalized coordinates, T and P as formulas
            rotating_frame.FREE_FALL,  # [free_fall]
            rotating_frame.FOUCAULT,  # [foucault]
            spacecraft.KIND,  # [orbit] with a [body] and its [angular_velocity]: attitude
            central_orbit.KIND,  # [orbit]
            coning.KIND,  # [omega_profile] kind = "coning"
            attitude.KIND,  # any other [omega_profile]
            estimation.KIND,  # [gyro] with a [body]: sensors and the MEKF on exact motion
            bouncing.KIND,  # [floor] with a [body]: thrown onto a floor, impacts
            gyrostat.KIND,  # [rotor] or [wheels]: a body with a rotor or reaction wheels
            heavy_top.KIND,  # [torque] model = "gravity" (a body about a fixed point)
            torqued_body.KIND,  # [torque] with a model other than "none"
            free_body.KIND,  # a [body] with an [angular_velocity] (the default)
        )
    }
)


def get_kind(name: str) -> ScenarioKind:
    """The adapter registered as ``name``.

    Examples
    --------
    >>> get_kind("free-body").title
    'torque-free rigid body (Euler-Poinsot case)'
    """
    try:
        return KINDS[name]
    except KeyError:
        raise InvalidInputError(
            f"Expected a scenario kind, one of {', '.join(map(repr, KINDS))}; got {name!r}."
        ) from None


def kind_for(data: Mapping[str, Any]) -> ScenarioKind:
    """The kind that claims a file without a ``kind`` key (``data``: the raw TOML).

    Examples
    --------
    >>> kind_for({"omega_profile": {"kind": "coning"}}).name
    'coning'
    >>> kind_for({"body": {}, "angular_velocity": {}}).name
    'free-body'
    """
    for k in KINDS.values():
        if k.claims(data):
            return k
    return KINDS["free-body"]
