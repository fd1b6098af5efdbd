"""Finite-difference derivatives whose evaluation points stay inside the variable bounds."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

Array = NDArray[np.float64]


def forward_difference(
    fun: Callable[[Array], Array], x: Array, lower: Array, upper: Array, f0: Array | None = None
) -> Array:
    """Forward-difference Jacobian ``(m, n)`` of ``fun`` at ``x``, stepping backwards where a bound is too close.

    The step is ``h_j = sqrt(eps) * max(1, |x_j|)``; when ``x_j + h_j`` would leave ``[lower_j, upper_j]`` the
    backward point ``x_j - h_j`` is used instead, so no evaluation point leaves the box.
    """
    x = np.asarray(x, dtype=float)
    f0 = np.atleast_1d(np.asarray(fun(x), dtype=float)) if f0 is None else np.atleast_1d(f0)
    h = np.sqrt(np.finfo(float).eps) * np.maximum(1.0, np.abs(x))
    h = np.where(x + h > upper, -h, h)
    J = np.empty((f0.size, x.size))
    for j in range(x.size):
        xj = x.copy()
        xj[j] += h[j]
        J[:, j] = (np.atleast_1d(np.asarray(fun(xj), dtype=float)) - f0) / h[j]
    return J
