"""Type aliases shared by the annotations of poinsot (no runtime behaviour).

Public functions take array-like inputs (:data:`numpy.typing.ArrayLike`: lists, tuples,
arrays, scalars) and return float64 arrays (:data:`FloatArray`).
"""

from __future__ import annotations

from typing import TypeAlias

import numpy as np
import numpy.typing as npt

__all__ = ["ArrayLike", "FloatArray", "BoolArray", "IntArray"]

ArrayLike: TypeAlias = npt.ArrayLike
#: float64 array of any shape
FloatArray: TypeAlias = npt.NDArray[np.float64]
#: boolean array of any shape
BoolArray: TypeAlias = npt.NDArray[np.bool_]
#: integer array of any shape
IntArray: TypeAlias = npt.NDArray[np.intp]
