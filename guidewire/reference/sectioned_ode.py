"""The elastica of a wire with piecewise-constant stiffness and rest curvature, and its Newton multiple shooting.

On a stretch of constant ``EI`` and rest curvature ``κ₀`` without external load the state ``(x, y, θ, M)`` with the
bending moment ``M = EI (θ' − κ₀)`` obeys ``x' = cos θ``, ``y' = sin θ``, ``θ' = M / EI + κ₀`` and
``M' = F × t = F_x sin θ − F_y cos θ`` (``F`` the internal force, distal part on proximal part, the convention of
:mod:`guidewire.reference`; for constant ``EI`` and ``κ₀ = 0`` this is ``EI κ' = F × t``).  Across a section boundary
``x``, ``y``, ``θ`` and ``M`` are continuous while ``θ'`` jumps, so the first-order form integrates straight through
one; it is the shooting form of ``θ'' = (F × t − (EI)'(θ' − κ₀) + EI κ₀') / EI`` with the derivatives of the
piecewise constants as jumps.

Non-dimensional with a segment length ``ℓ`` and a reference stiffness ``EI_r``: ``u = s / ℓ``, ``X = x / ℓ``,
``m = M ℓ / EI_r``, ``g = F ℓ² / EI_r``, ``e = EI / EI_r``, ``k = κ₀ ℓ``; then ``θ' = m / e + k``,
``m' = g_x sin θ − g_y cos θ`` and the energy ``EI_r / (2 ℓ) ∫ m² / e du``.  :func:`shoot` solves a boundary-value
problem on a :class:`Grid` of sub-intervals (every section boundary is a break) by Newton's method on the states at
the breaks, the start moment and the force parameters, with variational equations (DOP853, ``rtol = 1e-12``).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.integrate import solve_ivp

from .clamped_segment import SHOOT_GROWTH, SHOOT_TOL
from .ode import IVP_ATOL, IVP_RTOL, SENS0
from .shapes import Array, ElasticaPiece

__all__ = ["MAX_SUBINTERVAL", "EndResidual", "Grid", "Shot", "integrate_free", "pieces_of", "shoot"]

#: No shooting sub-interval is longer than this (non-dimensional), whatever the force.
MAX_SUBINTERVAL = 0.25

#: ``end(z, g) -> (r, dr/dz, dr/dg)``: the end conditions from the end state ``z = (X, Y, θ, m)`` and the force.
EndResidual = Callable[[Array, Array], tuple[Array, Array, Array]]


def _rhs(_u: float, z: Array, e: float, k: float, gx: float, gy: float) -> Array:
    c, s = math.cos(z[2]), math.sin(z[2])
    return np.array([c, s, z[3] / e + k, gx * s - gy * c, z[3] * z[3] / e])


def _rhs_sens(_u: float, w: Array, e: float, k: float, gx: float, gy: float) -> Array:
    """:func:`_rhs` plus the sensitivities of ``(X, Y, θ, m)`` to the start state and ``g``, flattened ``(4, 6)``."""
    c, s = math.cos(w[2]), math.sin(w[2])
    S = w[5:].reshape(4, 6)
    out = np.empty(29)
    out[:5] = (c, s, w[3] / e + k, gx * s - gy * c, w[3] * w[3] / e)
    dS = out[5:].reshape(4, 6)
    dS[0] = -s * S[2]
    dS[1] = c * S[2]
    dS[2] = S[3] / e
    dS[3] = (gx * c + gy * s) * S[2]
    dS[3, 4] += s
    dS[3, 5] -= c
    return out


@dataclass(frozen=True)
class Grid:
    """Sub-intervals ``[breaks[j], breaks[j+1]]`` of ``u ∈ [0, 1]`` with constant ``e[j]`` and ``k[j]``.

    Attributes
    ----------
    breaks : ndarray, shape (M + 1,)
        Increasing, from 0 to 1; every section boundary is one.
    e, k : ndarray, shape (M,)
        ``EI / EI_r`` and ``κ₀ ℓ`` on each sub-interval.
    """

    breaks: Array
    e: Array
    k: Array

    @classmethod
    def of(cls, breaks: Array, e: Array, k: Array, g: Array) -> Grid:
        """Split the sections ``breaks``/``e``/``k`` so that no sub-interval is longer than :data:`MAX_SUBINTERVAL`
        or than ``SHOOT_GROWTH / sqrt(|g| / e)`` (the linearised growth stays below ``e⁶`` on each)."""
        out_b, out_e, out_k = [0.0], [], []
        gnorm = float(np.max(np.abs(g))) if np.size(g) else 0.0
        for a, b, ej, kj in zip(breaks[:-1], breaks[1:], e, k, strict=True):
            width = min(MAX_SUBINTERVAL, SHOOT_GROWTH / math.sqrt(max(gnorm / ej, 1e-300)))
            parts = int(min(64, max(1, math.ceil((b - a) / width - 1e-12))))
            out_b.extend(np.linspace(a, b, parts + 1)[1:])
            out_e.extend([ej] * parts)
            out_k.extend([kj] * parts)
        out_b[-1] = 1.0
        return cls(np.array(out_b), np.array(out_e), np.array(out_k))

    @property
    def size(self) -> int:
        """Number ``M`` of sub-intervals."""
        return int(self.e.size)


@dataclass(frozen=True)
class Shot:
    """A converged shooting solution: start states ``Z`` (M, 4), force ``g`` and the sub-interval solutions."""

    Z: Array
    g: Array
    sols: tuple[Any, ...]


def _ivp(grid: Grid, j: int, z0: Array, g: Array, sens: bool) -> Any:
    w0 = np.concatenate([z0, [0.0], SENS0]) if sens else np.concatenate([z0, [0.0]])
    return solve_ivp(_rhs_sens if sens else _rhs, (grid.breaks[j], grid.breaks[j + 1]), w0, method="DOP853",
                     args=(float(grid.e[j]), float(grid.k[j]), float(g[0]), float(g[1])), rtol=IVP_RTOL,
                     atol=IVP_ATOL, dense_output=True)


def integrate_free(grid: Grid, z0: Array, g: Array) -> Shot | None:
    """Integrate the initial-value problem from ``z0 = (X, Y, θ, m)`` through every sub-interval."""
    Z, sols, z = np.empty((grid.size, 4)), [], np.asarray(z0, dtype=float)
    for j in range(grid.size):
        Z[j] = z
        sol = _ivp(grid, j, z, g, sens=False)
        if sol.status != 0 or not np.all(np.isfinite(sol.y[:, -1])):
            return None
        sols.append(sol)
        z = sol.y[:4, -1]
    return Shot(Z, np.asarray(g, dtype=float).copy(), tuple(sols))


def shoot(grid: Grid, Z: Array, g0: Array, G: Array, p: Array, end: EndResidual, maxiter: int = 40) -> Shot | None:
    """Newton multiple shooting with the start pose ``Z[0, :3]`` fixed and the force ``g = g0 + G p``.

    Unknowns: ``m`` at ``u = 0``, the states ``Z[1:]`` at the interior breaks and ``p``; residuals: continuity at the
    breaks and the ``1 + len(p)`` end conditions ``end``.  Returns None without convergence to :data:`SHOOT_TOL`.
    """
    M, npar = grid.size, G.shape[1]
    Z, p = np.array(Z, dtype=float), np.array(p, dtype=float)
    n = 4 * M - 3 + npar
    best = math.inf
    for _ in range(maxiter):
        g = g0 + G @ p
        sols, r, J = [], np.empty(n), np.zeros((n, n))
        for j in range(M):
            sol = _ivp(grid, j, Z[j], g, sens=True)
            if sol.status != 0 or not np.all(np.isfinite(sol.y[:, -1])):
                return None
            sols.append(sol)
            zend, sens = sol.y[:4, -1], sol.y[5:, -1].reshape(4, 6)
            if j < M - 1:
                rows = slice(4 * j, 4 * j + 4)
                r[rows] = zend - Z[j + 1]
                J[rows, 1 + 4 * j: 5 + 4 * j] = -np.eye(4)
                dz, dg = np.eye(4), np.zeros((4, 2))
            else:
                rows = slice(4 * j, n)
                r[rows], dz, dg = end(zend, g)
            J[rows, 0 if j == 0 else slice(4 * j - 3, 4 * j + 1)] = (dz @ sens[:, 3]) if j == 0 else dz @ sens[:, :4]
            J[rows, n - npar:] = (dz @ sens[:, 4:] + dg) @ G
        nr = float(np.max(np.abs(r)))
        if nr < SHOOT_TOL or (nr < 1e-9 and nr > 0.5 * best):  # converged, or at the noise floor
            return Shot(Z, g, tuple(sols))
        best = min(best, nr)
        try:
            step = np.linalg.solve(J, r)
        except np.linalg.LinAlgError:
            return None
        if not np.all(np.isfinite(step)):
            return None
        step /= max(1.0, float(np.max(np.abs(step))) / 2.0)
        Z[0, 3] -= step[0]
        Z[1:] -= step[1: n - npar].reshape(M - 1, 4)
        p -= step[n - npar:]
    return None


class _PieceDense:
    """Dense output of one sub-interval in the piece's own ``(X, Y, θ, κ̂, E)`` (see :class:`ElasticaPiece`)."""

    def __init__(self, sol: Any, u0: float, du: float, start: Array, e: float, k: float) -> None:
        self.sol, self.u0, self.du, self.start, self.e, self.k = sol, u0, du, start, e, k

    def __call__(self, v: Array) -> Array:
        z = self.sol(self.u0 + self.du * np.atleast_1d(np.asarray(v, dtype=float)))
        out = np.empty((5, z.shape[1]))
        out[0] = (z[0] - self.start[0]) / self.du
        out[1] = (z[1] - self.start[1]) / self.du
        out[2] = z[2]
        out[3] = (z[3] / self.e + self.k) * self.du
        out[4] = z[4] / self.du
        return out


def pieces_of(shot: Shot, grid: Grid, s0: float, length: float, point: Array, EI_ref: float) -> list[ElasticaPiece]:
    """One :class:`ElasticaPiece` (with its own ``EI`` and rest curvature) per sub-interval of a shooting solution
    of the segment ``[s0, s0 + length]`` that starts at ``point``."""
    pieces = []
    force = shot.g * EI_ref / length**2
    for j, sol in enumerate(shot.sols):
        u0, du = float(grid.breaks[j]), float(grid.breaks[j + 1] - grid.breaks[j])
        z = shot.Z[j]
        e, k = float(grid.e[j]), float(grid.k[j])
        pieces.append(ElasticaPiece(
            s0=s0 + u0 * length, length=du * length, point=np.asarray(point, dtype=float) + length * z[:2],
            theta0=float(z[2]), kappa0=(z[3] / e + k) / length, force=force.copy(),
            energy=EI_ref / (2.0 * length) * float(sol.y[4, -1]), dense=_PieceDense(sol.sol, u0, du, z[:2], e, k),
            EI=e * EI_ref, rest_curvature=k / length,
        ))
    return pieces
