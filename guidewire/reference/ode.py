"""ODE kernels of the planar elastica in non-dimensional form.

With ``u = (s - s0) / length``, ``X = (x - x0) / length``, ``κ̂ = κ length`` and ``g = F length² / EI`` the
state ``(X, Y, θ, κ̂, E)`` obeys ``X' = cos θ``, ``Y' = sin θ``, ``θ' = κ̂``, ``κ̂' = g_x sin θ - g_y cos θ`` and
``E' = κ̂²``.  This module holds the right-hand sides (plain, with variational equations for shooting, and the
vectorised form with Jacobians for :func:`scipy.integrate.solve_bvp`), the dense-output integration and the
stitching of multiple-shooting sub-solutions.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np
from scipy.integrate import solve_ivp

from .shapes import Array

__all__ = ["IVP_ATOL", "IVP_RTOL", "SENS0", "Stitched", "bvp_fun", "bvp_fun_jac", "integrate", "rhs_sens"]

#: Integration tolerances of every elastica piece (non-dimensional states of order one).
IVP_RTOL = 1e-12
IVP_ATOL = 1e-12


def _rhs(_u: float, z: Array, gx: float, gy: float) -> Array:
    """Non-dimensional elastica ``(X, Y, θ, κ̂, E)``; ``g = F L² / EI``, ``E' = κ̂²``."""
    c, s = np.cos(z[2]), np.sin(z[2])
    return np.array([c, s, z[3], gx * s - gy * c, z[3] * z[3]])


def rhs_sens(_u: float, w: Array, gx: float, gy: float) -> Array:
    """:func:`_rhs` plus the sensitivities of ``(X, Y, θ, κ̂)`` to ``(X, Y, θ, κ̂)`` at the start and ``g``."""
    c, s = math.cos(w[2]), math.sin(w[2])
    S = w[5:].reshape(4, 6)
    out = np.empty(29)
    out[:5] = (c, s, w[3], gx * s - gy * c, w[3] * w[3])
    dS = out[5:].reshape(4, 6)
    dS[0] = -s * S[2]
    dS[1] = c * S[2]
    dS[2] = S[3]
    dS[3] = (gx * c + gy * s) * S[2]
    dS[3, 4] += s
    dS[3, 5] -= c
    return out


#: Initial sensitivities for :func:`rhs_sens`: identity in ``(X, Y, θ, κ̂)``, zero in ``g``, flattened ``(4, 6)``.
SENS0 = np.hstack([np.eye(4), np.zeros((4, 2))]).ravel()


class Stitched:
    """Dense output over ``u ∈ [0, 1]`` stitched from the sub-interval solutions of multiple shooting.

    Each sub-solution integrates the energy from zero; ``offsets`` adds the energy of the earlier ones.
    """

    def __init__(self, breaks: Array, sols: Sequence[Any], offsets: Array) -> None:
        self.breaks, self.sols, self.offsets = breaks, list(sols), offsets

    def __call__(self, u: Array) -> Array:
        u = np.atleast_1d(np.asarray(u, dtype=float))
        which = np.clip(np.searchsorted(self.breaks, u, side="right") - 1, 0, len(self.sols) - 1)
        out = np.empty((5, u.size))
        for j, sol in enumerate(self.sols):
            mask = which == j
            if np.any(mask):
                out[:, mask] = sol(u[mask])[:5]
                out[4, mask] += self.offsets[j]
        return out


def integrate(theta0: float, kappa_hat0: float, g: Array) -> Any:
    """Integrate the non-dimensional elastica over ``u ∈ [0, 1]`` with dense output."""
    return solve_ivp(
        _rhs,
        (0.0, 1.0),
        np.array([0.0, 0.0, theta0, kappa_hat0, 0.0]),
        method="DOP853",
        args=(float(g[0]), float(g[1])),
        rtol=IVP_RTOL,
        atol=IVP_ATOL,
        dense_output=True,
    )


def bvp_fun(_u: Array, y: Array, p: Array) -> Array:
    """Vectorised ``(X, Y, θ, κ̂)`` right-hand side for ``solve_bvp``, the unknown parameters ``p = g``."""
    c, s = np.cos(y[2]), np.sin(y[2])
    return np.vstack([c, s, y[3], p[0] * s - p[1] * c])


def bvp_fun_jac(_u: Array, y: Array, p: Array) -> tuple[Array, Array]:
    """Jacobians of :func:`bvp_fun` with respect to the state, shape ``(4, 4, m)``, and to ``p``, ``(4, 2, m)``."""
    c, s = np.cos(y[2]), np.sin(y[2])
    m = y.shape[1]
    dy = np.zeros((4, 4, m))
    dy[0, 2] = -s
    dy[1, 2] = c
    dy[2, 3] = 1.0
    dy[3, 2] = p[0] * c + p[1] * s
    dp = np.zeros((4, 2, m))
    dp[3, 0] = s
    dp[3, 1] = -c
    return dy, dp

