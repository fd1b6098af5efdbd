"""Damped BFGS update of the Lagrangian Hessian (paper Eq. 6 with Powell's damping).

Symbols (Nocedal & Wright, Procedure 18.2): ``B`` the current approximation, ``s = x+ - x``,
``y = grad L(x+, lam+) - grad L(x, lam+)``.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

Array = NDArray[np.float64]

#: Powell's damping threshold: the update keeps ``s^T r >= 0.2 s^T B s`` (Nocedal & Wright, Eq. 18.15).
MIN_CURVATURE = 0.2


def damped_bfgs_update(B: Array, s: Array, y: Array) -> tuple[Array, bool]:
    """One damped BFGS update.

    Parameters
    ----------
    B : ndarray, shape (n, n)
        Symmetric positive-definite approximation of the Lagrangian Hessian.
    s, y : ndarray, shape (n,)
        Step and change of the Lagrangian gradient.

    Returns
    -------
    B_new : ndarray, shape (n, n)
        ``B - B s s^T B / (s^T B s) + r r^T / (s^T r)`` with ``r = theta y + (1 - theta) B s``, where
        ``theta = 1`` if ``s^T y >= 0.2 s^T B s`` and ``theta = 0.8 s^T B s / (s^T B s - s^T y)`` otherwise.
        Positive definite whenever ``B`` is. Returned unchanged when ``s^T B s`` is not positive.
    damped : bool
        Whether ``theta < 1`` was used.
    """
    Bs = B @ s
    sBs = float(s @ Bs)
    if not np.isfinite(sBs) or sBs <= 0.0 or not np.all(np.isfinite(y)):
        return B, False
    sy = float(s @ y)
    damped = sy < MIN_CURVATURE * sBs
    theta = (1.0 - MIN_CURVATURE) * sBs / (sBs - sy) if damped else 1.0
    r = theta * y + (1.0 - theta) * Bs
    sr = float(s @ r)
    B_new = B - np.outer(Bs, Bs) / sBs + np.outer(r, r) / sr
    return 0.5 * (B_new + B_new.T), damped


def initial_scaling(s: Array, y: Array) -> float:
    """Shanno–Phua scale ``y^T y / s^T y`` of an identity start (Nocedal & Wright, Eq. 6.20), or 1 if undefined."""
    sy = float(s @ y)
    yy = float(y @ y)
    if sy <= 0.0 or not np.isfinite(sy) or yy <= 0.0:
        return 1.0
    return yy / sy
