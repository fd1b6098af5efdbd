"""Initial guesses for the clamped-clamped elastica: angle profiles and internal forces for ``solve_bvp``.

The profiles are the cubic Hermite curve through the poses resampled by arc length, the low-energy minimisers
of an 8-mode Ritz approximation, the circular arc, and (only when all of those fail) a wide grid of modal
profiles.  Non-dimensional: arc length ``u ∈ [0, 1]``, chord ``(X1, Y1)``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from scipy.optimize import brentq, minimize

from .shapes import Array

__all__ = ["RITZ_KEEP", "RITZ_MODES", "RITZ_STARTS", "fallback_guesses", "force_fit", "guesses"]


def force_fit(u: Array, theta: Array) -> Array:
    """Least-squares ``g`` in ``θ'' = g_x sin θ - g_y cos θ`` along a guessed angle profile."""
    d2 = np.gradient(np.gradient(theta, u), u)
    A = np.column_stack([np.sin(theta), -np.cos(theta)])
    g, *_ = np.linalg.lstsq(A[2:-2], d2[2:-2], rcond=None)
    return g


def _hermite_guess(theta0: float, theta1: float, X1: float, Y1: float, u: Array) -> Array | None:
    """Angle profile of the cubic Hermite curve through the poses, with arc length 1, resampled by arc."""
    t = np.linspace(0.0, 1.0, 401)
    t0 = np.array([math.cos(theta0), math.sin(theta0)])
    t1 = np.array([math.cos(theta1), math.sin(theta1)])
    p1 = np.array([X1, Y1])
    # derivative of P(t) = h00 p0 + h10 α t0 + h01 p1 + h11 α t1 with p0 = 0
    d10 = 3 * t**2 - 4 * t + 1
    d01, d11 = -6 * t**2 + 6 * t, 3 * t**2 - 2 * t

    def velocity(alpha: Array) -> Array:  # (len(alpha), len(t), 2)
        a = alpha[:, None, None]
        return (d01[:, None] * p1)[None] + a * (d10[:, None] * t0 + d11[:, None] * t1)[None]

    def arclength(alpha: Array) -> Array:
        speed = np.linalg.norm(velocity(alpha), axis=2)
        return np.sum(0.5 * (speed[:, 1:] + speed[:, :-1]) * np.diff(t), axis=1)

    alphas = np.geomspace(1e-3, 20.0, 60)
    lengths = arclength(alphas) - 1.0
    cross = np.nonzero((lengths[:-1] < 0.0) & (lengths[1:] >= 0.0))[0]
    if cross.size == 0:
        return None
    lo, hi = alphas[cross[0]], alphas[cross[0] + 1]
    alpha = brentq(lambda a: float(arclength(np.array([a]))[0] - 1.0), lo, hi, xtol=1e-10)
    v = velocity(np.array([alpha]))[0]
    speed = np.linalg.norm(v, axis=1)
    if np.any(speed < 1e-9):
        return None
    arc = np.concatenate([[0.0], np.cumsum(0.5 * (speed[1:] + speed[:-1]) * np.diff(t))])
    th = np.unwrap(np.arctan2(v[:, 1], v[:, 0]))
    th += theta0 - th[0]
    th += (theta1 - th[-1]) * arc / arc[-1]
    return np.interp(u, arc / arc[-1], th)


#: Number of sine modes of the Ritz approximation used to generate initial guesses.
RITZ_MODES = 8
#: Ritz minimisers with more than this multiple of the lowest Ritz energy are not tried.
RITZ_KEEP = 2.0
#: Starting ``(a_1, a_2) / π`` of the Ritz minimisations: both bending senses, loops, S-shapes.
RITZ_STARTS = tuple((a1, a2) for a1 in (-2.0, -1.0, 0.0, 1.0, 2.0) for a2 in (-1.0, 0.0, 1.0))


def _ritz_guesses(theta0: float, theta1: float, X1: float, Y1: float) -> list[Array]:
    """Local minimisers of the energy over ``θ = θ0 + Δθ u + Σ_k a_k sin kπu`` meeting the chord exactly.

    The energy ``∫ θ'² du = Δθ² + Σ (kπ)² a_k² / 2`` is diagonal in the modal coefficients; the two chord
    constraints are imposed with Gauss-Legendre quadrature.  Solved by SLSQP from a grid of ``(a_1, a_2)``
    starts (both bending senses, S-shapes, loops); the distinct converged coefficient vectors are returned.
    """
    xg, wg = np.polynomial.legendre.leggauss(64)
    u, w = 0.5 * (xg + 1.0), 0.5 * wg
    k = np.arange(1, RITZ_MODES + 1)
    modes = np.sin(np.pi * np.outer(u, k))
    weight = 0.5 * (np.pi * k) ** 2
    base = theta0 + (theta1 - theta0) * u
    target = np.array([X1, Y1])

    def energy(a: Array) -> tuple[float, Array]:
        return float(weight @ (a * a)), 2.0 * weight * a

    def chord(a: Array) -> Array:
        th = base + modes @ a
        return np.array([np.cos(th) @ w, np.sin(th) @ w]) - target

    def chord_jac(a: Array) -> Array:
        th = base + modes @ a
        return np.vstack([-(np.sin(th) * w) @ modes, (np.cos(th) * w) @ modes])

    found: list[Array] = []
    for a1, a2 in RITZ_STARTS:
        a0 = np.zeros(RITZ_MODES)
        a0[:2] = np.pi * a1, np.pi * a2
        with np.errstate(all="ignore"):
            res = minimize(
                energy,
                a0,
                jac=True,
                method="SLSQP",
                constraints=[{"type": "eq", "fun": chord, "jac": chord_jac}],
                options={"maxiter": 50, "ftol": 1e-9},
            )
        if not (res.success and np.all(np.isfinite(res.x)) and np.max(np.abs(chord(res.x))) < 1e-7):
            continue
        if all(np.max(np.abs(res.x - f)) > 1e-3 for f in found):
            found.append(res.x)
    if not found:
        return found
    energies = np.array([energy(a)[0] for a in found])
    keep = energies <= RITZ_KEEP * energies.min() + 1e-12
    return [found[i] for i in np.argsort(energies) if keep[i]]


def guesses(theta0: float, theta1: float, X1: float, Y1: float, u: Array) -> list[Array]:
    """Distinct initial angle profiles: the cubic Hermite curve, the low Ritz minimisers, the circular arc."""
    profiles: list[Array] = []
    herm = _hermite_guess(theta0, theta1, X1, Y1, u)
    if herm is not None:
        profiles.append(herm)
    linear = theta0 + (theta1 - theta0) * u
    modes = np.sin(np.pi * np.outer(u, np.arange(1, RITZ_MODES + 1)))
    for a in _ritz_guesses(theta0, theta1, X1, Y1):
        profiles.append(linear + modes @ a)
    profiles.append(linear)  # the arc of constant curvature with the prescribed turning
    return _distinct(profiles)


def fallback_guesses(theta0: float, theta1: float, u: Array) -> list[Array]:
    """A wide grid of modal profiles that ignore the chord, for when every primary guess failed."""
    linear = theta0 + (theta1 - theta0) * u
    s1, s2, s3 = (np.sin(j * np.pi * u) for j in (1, 2, 3))
    return [
        linear + np.pi * (a * s1 + b * s2 + c * s3)
        for a in (-3.0, -2.0, -1.0, 0.0, 1.0, 2.0, 3.0)
        for b in (-2.0, -1.0, 0.0, 1.0, 2.0)
        for c in (-1.0, 0.0, 1.0)
    ]


def _distinct(profiles: Sequence[Array]) -> list[Array]:
    """The profiles, dropping any within 1e-3 rad everywhere of an earlier one."""
    distinct: list[Array] = []
    for th in profiles:
        if all(np.max(np.abs(th - d)) > 1e-3 for d in distinct):
            distinct.append(th)
    return distinct
