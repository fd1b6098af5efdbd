"""Exact continuum reference for the bar-chain guidewire: the planar inextensible Kirchhoff elastica.

The paper (Li et al., Appl. Sci. 2019, 9, 280, §3.2) measures its discrete model against ABAQUS beam
elements; this module replaces that with the exact continuum solution.  Units: mm, rad, N, N·mm.

Model
-----
A wire of bending stiffness ``EI`` (N·mm²) is described by its tangent angle ``theta(s)`` over the arc
length ``s``.  On a stretch without external load the internal force ``F`` (N, the force that the distal
part ``(s, L]`` exerts on the proximal part ``[0, s]``) is constant and

.. math::

    x' = \\cos\\theta,\\quad y' = \\sin\\theta,\\quad \\theta' = \\kappa,\\quad
    EI\\,\\kappa' = F \\times t = F_x \\sin\\theta - F_y \\cos\\theta,

with bending energy ``EI/2 ∫ κ² ds`` (N·mm).  The bending moment is ``M = EI κ`` (counter-clockwise
positive) and ``EI κ²/2 + F·t`` is a first integral.

Solvers
-------
* :func:`clamped_segment` -- both ends fully clamped (position and angle, angles not wrapped).  Several
  equilibria exist, so :func:`scipy.integrate.solve_bvp` is started from several guesses (the cubic Hermite
  curve through the poses resampled by arc length, the low-energy minimisers of an 8-mode Ritz
  approximation, the circular arc; a wide grid of profiles only if all of those fail), every converged
  branch is polished by Newton (multiple) shooting with variational equations (DOP853, ``rtol = 1e-12``),
  and the lowest energy wins.  :func:`clamped_segment_equilibria` returns every branch found.
* :func:`clamp_wall_free_end` -- clamp plus free end pushed against one straight wall: closed form in
  incomplete elliptic integrals (pendulum substitution), tangential contact with a straight tail along
  the wall or, for a shallow wall, the free end resting on it; verified by integrating the elastica.
* :func:`reference_shape` -- a whole scene: base clamp, fully clamped contacts (segments decouple), a
  straight free tail, or the one-wall free-end case.  :func:`reference_shapes` lists every tied minimiser
  of a symmetric scene (mirror twins), for comparing a discrete solution with the nearest one.

Every result is a :class:`ContinuumShape` whose pieces are initial-value solutions with dense output, so
positions, angles and curvatures can be evaluated at any arc length (error well below 1e-7 mm), with the
support reactions (forces and moments) that balance.

Paper scenes (``EI = 64.65`` N·mm²): Table 1 ``θ_B = π/4`` 4.5551 N·mm; Fig. 6b 1.0312 N·mm.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.integrate import solve_bvp, solve_ivp
from scipy.optimize import brentq, minimize
from scipy.special import ellipeinc, ellipkinc

Array = NDArray[np.float64]

__all__ = [
    "ContinuumShape",
    "ElasticaPiece",
    "Reaction",
    "clamp_wall_free_end",
    "clamped_segment",
    "clamped_segment_equilibria",
    "reference_shape",
    "reference_shapes",
    "straight_shape",
]

#: Integration tolerances of every elastica piece (non-dimensional states of order one).
IVP_RTOL = 1e-12
IVP_ATOL = 1e-12
#: Newton shooting stops when the non-dimensional end-pose residual is below this.
SHOOT_TOL = 1e-11
#: Relative tolerance under which a chord is considered equal to the available length.
TAUT_RTOL = 1e-12
#: Relative energy difference under which two equilibria count as equally low (mirror twins).
TIE_RTOL = 1e-9
#: At most this many tied whole-wire minimisers are assembled by :func:`reference_shapes`.
MAX_TIES = 64


# ----------------------------------------------------------------------------------------------------
# Result types
# ----------------------------------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class Reaction:
    """Force and moment that a support (clamp, contact or wall) exerts on the wire.

    Attributes
    ----------
    s : float
        Arc length of the support point (mm).
    point : ndarray, shape (2,)
        Position of the support point (mm).
    force : ndarray, shape (2,)
        Force exerted on the wire (N).
    moment : float
        Moment exerted on the wire (N·mm, counter-clockwise positive).
    kind : str
        ``"clamp"`` for the base and fully clamped contacts, ``"wall"`` for a wall contact.
    """

    s: float
    point: Array
    force: Array
    moment: float
    kind: str


@dataclass(frozen=True, eq=False)
class ElasticaPiece:
    """One unloaded stretch of the wire: an elastica with constant internal force.

    The piece starts at arc length ``s0`` at ``point`` with angle ``theta0`` and curvature ``kappa0`` and
    carries the internal force ``force``.  Its shape is stored as the dense output of an initial-value
    integration in the non-dimensional arc length ``u = (s - s0) / length`` (``None`` for a straight piece
    without force, which is evaluated in closed form).

    Attributes
    ----------
    s0, length : float
        Start arc length and length (mm).
    point : ndarray, shape (2,)
        Start position (mm).
    theta0 : float
        Start tangent angle (rad, not wrapped).
    kappa0 : float
        Start curvature (1/mm).
    force : ndarray, shape (2,)
        Internal force (N): the force the distal part exerts on the proximal part.
    energy : float
        Bending energy of the piece (N·mm).
    dense : object or None
        Callable ``u -> (5, k)`` array (a ``scipy`` ``OdeSolution``, or several stitched together by multiple
        shooting) of the non-dimensional state ``(X, Y, theta, kappa_hat, E)`` with ``X = (x - x0) / length``,
        ``kappa_hat = kappa * length`` and ``E = ∫ kappa_hat² du``.
    """

    s0: float
    length: float
    point: Array
    theta0: float
    kappa0: float
    force: Array
    energy: float
    dense: Any

    @property
    def s1(self) -> float:
        """End arc length (mm)."""
        return self.s0 + self.length

    def state(self, s: Array) -> tuple[Array, Array, Array, Array]:
        """Return ``(x, y, theta, kappa)`` at arc lengths ``s`` (which must lie in the piece)."""
        ds = np.asarray(s, dtype=float) - self.s0
        if self.dense is None:
            c, si = math.cos(self.theta0), math.sin(self.theta0)
            theta = np.full(ds.shape, self.theta0)
            return self.point[0] + c * ds, self.point[1] + si * ds, theta, np.zeros(ds.shape)
        z = self.dense(ds / self.length)
        return (
            self.point[0] + self.length * z[0],
            self.point[1] + self.length * z[1],
            z[2],
            z[3] / self.length,
        )

    def end_state(self) -> tuple[Array, float, float]:
        """Return ``(point, theta, kappa)`` at the end of the piece."""
        x, y, th, k = self.state(np.array([self.s1]))
        return np.array([x[0], y[0]]), float(th[0]), float(k[0])


@dataclass(frozen=True, eq=False)
class ContinuumShape:
    """Equilibrium shape of the continuum wire: a chain of :class:`ElasticaPiece`.

    Attributes
    ----------
    length : float
        Total arc length (mm).
    energy : float
        Bending energy ``EI/2 ∫ κ² ds`` (N·mm).
    EI : float
        Bending stiffness (N·mm²).
    pieces : tuple of ElasticaPiece
        Consecutive pieces covering ``[0, length]``.
    reactions : tuple of Reaction
        Forces and moments of the supports on the wire (they balance: the wire carries no other load).

    Notes
    -----
    At a piece boundary ``s`` belongs to the following piece (the curvature may jump at an interior clamp;
    position and angle are continuous).
    """

    length: float
    energy: float
    EI: float
    pieces: tuple[ElasticaPiece, ...]
    reactions: tuple[Reaction, ...] = ()

    @property
    def breakpoints(self) -> Array:
        """Arc lengths where the pieces start, and the total length, shape ``(len(pieces) + 1,)``."""
        return np.array([p.s0 for p in self.pieces] + [self.length])

    def _evaluate(self, s: ArrayLike) -> tuple[Array, Array, Array, Array, Array]:
        s = np.atleast_1d(np.asarray(s, dtype=float))
        if s.ndim != 1:
            raise ValueError(f"s must be a scalar or a 1-D array, got shape {s.shape}")
        if not np.all(np.isfinite(s)):
            raise ValueError("s must be finite")
        slack = 1e-9 * max(self.length, 1.0)
        if s.size and (s.min() < -slack or s.max() > self.length + slack):
            raise ValueError(
                f"s must lie in [0, {self.length:g}] mm, got values in [{s.min():g}, {s.max():g}]"
            )
        s = np.clip(s, 0.0, self.length)
        starts = np.array([p.s0 for p in self.pieces])
        which = np.clip(np.searchsorted(starts, s, side="right") - 1, 0, len(self.pieces) - 1)
        x, y, th, k = (np.empty(s.shape) for _ in range(4))
        force = np.empty((s.size, 2))
        for j, piece in enumerate(self.pieces):
            mask = which == j
            if np.any(mask):
                x[mask], y[mask], th[mask], k[mask] = piece.state(s[mask])
                force[mask] = piece.force
        return x, y, th, k, force

    def position(self, s: ArrayLike) -> Array:
        """Positions (mm) at arc lengths ``s``, shape ``(k, 2)``."""
        x, y, *_ = self._evaluate(s)
        return np.column_stack([x, y])

    def tangent_angle(self, s: ArrayLike) -> Array:
        """Tangent angles (rad, continuous, not wrapped) at arc lengths ``s``, shape ``(k,)``."""
        return self._evaluate(s)[2]

    def curvature(self, s: ArrayLike) -> Array:
        """Curvatures ``dθ/ds`` (1/mm) at arc lengths ``s``, shape ``(k,)``."""
        return self._evaluate(s)[3]

    def bending_moment(self, s: ArrayLike) -> Array:
        """Bending moments ``EI κ`` (N·mm) at arc lengths ``s``, shape ``(k,)``."""
        return self.EI * self._evaluate(s)[3]

    def internal_force(self, s: ArrayLike) -> Array:
        """Internal forces (N) at arc lengths ``s``, shape ``(k, 2)``: distal part on proximal part."""
        return self._evaluate(s)[4]


# ----------------------------------------------------------------------------------------------------
# Input validation
# ----------------------------------------------------------------------------------------------------


def _point(value: ArrayLike, name: str) -> Array:
    try:
        p = np.asarray(value, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{name} must be a pair of numbers (x, y), got {value!r}") from exc
    if p.shape != (2,) or not np.all(np.isfinite(p)):
        raise ValueError(f"{name} must be a finite pair (x, y), got {value!r}")
    return p


def _fmt(p: Array) -> str:
    return f"({p[0]:g}, {p[1]:g})"


def _real(value: Any, name: str, *, positive: bool = False) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{name} must be a real number, got {value!r}") from exc
    if not math.isfinite(v):
        raise ValueError(f"{name} must be finite, got {value!r}")
    if positive and v <= 0.0:
        raise ValueError(f"{name} must be positive, got {v:g}")
    return v


# ----------------------------------------------------------------------------------------------------
# Elastica pieces
# ----------------------------------------------------------------------------------------------------


def _rhs(_u: float, z: Array, gx: float, gy: float) -> Array:
    """Non-dimensional elastica ``(X, Y, θ, κ̂, E)``; ``g = F L² / EI``, ``E' = κ̂²``."""
    c, s = np.cos(z[2]), np.sin(z[2])
    return np.array([c, s, z[3], gx * s - gy * c, z[3] * z[3]])


def _rhs_sens(_u: float, w: Array, gx: float, gy: float) -> Array:
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


_SENS0 = np.hstack([np.eye(4), np.zeros((4, 2))]).ravel()


class _Stitched:
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


def _integrate(theta0: float, kappa_hat0: float, g: Array) -> Any:
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


def _piece(
    s0: float,
    length: float,
    point: Array,
    theta0: float,
    kappa_hat0: float,
    g: Array,
    EI: float,
    dense: Any,
    energy_hat: float,
) -> ElasticaPiece:
    """A curved piece from its non-dimensional solution (``energy_hat = ∫ κ̂² du``)."""
    return ElasticaPiece(
        s0=s0,
        length=length,
        point=np.array(point, dtype=float),
        theta0=float(theta0),
        kappa0=float(kappa_hat0) / length,
        force=np.asarray(g, dtype=float) * EI / length**2,
        energy=EI / (2.0 * length) * float(energy_hat),
        dense=dense,
    )


def _straight_piece(s0: float, length: float, point: Array, theta: float) -> ElasticaPiece:
    return ElasticaPiece(
        s0=s0,
        length=length,
        point=np.array(point, dtype=float),
        theta0=float(theta),
        kappa0=0.0,
        force=np.zeros(2),
        energy=0.0,
        dense=None,
    )


def _shift(piece: ElasticaPiece, ds: float) -> ElasticaPiece:
    """The same piece starting ``ds`` further along the wire."""
    return ElasticaPiece(
        s0=piece.s0 + ds,
        length=piece.length,
        point=piece.point,
        theta0=piece.theta0,
        kappa0=piece.kappa0,
        force=piece.force,
        energy=piece.energy,
        dense=piece.dense,
    )


def straight_shape(p0: ArrayLike, theta0: float, length: float, EI: float) -> ContinuumShape:
    """A straight, unloaded wire from ``p0`` in the direction ``theta0`` (energy 0).

    Parameters
    ----------
    p0 : array_like, shape (2,)
        Start point (mm).
    theta0 : float
        Direction (rad).
    length : float
        Length (mm), positive.
    EI : float
        Bending stiffness (N·mm²), positive.

    Returns
    -------
    ContinuumShape
        The straight wire, with a zero clamp reaction at ``p0``.
    """
    p0 = _point(p0, "p0")
    theta0 = _real(theta0, "theta0")
    length = _real(length, "length", positive=True)
    EI = _real(EI, "EI", positive=True)
    piece = _straight_piece(0.0, length, p0, theta0)
    base = Reaction(0.0, p0, np.zeros(2), 0.0, "clamp")
    return ContinuumShape(length=length, energy=0.0, EI=EI, pieces=(piece,), reactions=(base,))


# ----------------------------------------------------------------------------------------------------
# Clamped-clamped segment
# ----------------------------------------------------------------------------------------------------


def _bvp_fun(_u: Array, y: Array, p: Array) -> Array:
    c, s = np.cos(y[2]), np.sin(y[2])
    return np.vstack([c, s, y[3], p[0] * s - p[1] * c])


def _bvp_fun_jac(_u: Array, y: Array, p: Array) -> tuple[Array, Array]:
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


_BC_JAC_A = np.zeros((6, 4))
_BC_JAC_A[0, 0] = _BC_JAC_A[1, 1] = _BC_JAC_A[2, 2] = 1.0
_BC_JAC_B = np.zeros((6, 4))
_BC_JAC_B[3, 0] = _BC_JAC_B[4, 1] = _BC_JAC_B[5, 2] = 1.0


def _force_fit(u: Array, theta: Array) -> Array:
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


def _guesses(theta0: float, theta1: float, X1: float, Y1: float, u: Array) -> list[Array]:
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


def _fallback_guesses(theta0: float, theta1: float, u: Array) -> list[Array]:
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
    distinct: list[Array] = []
    for th in profiles:
        if all(np.max(np.abs(th - d)) > 1e-3 for d in distinct):
            distinct.append(th)
    return distinct


def _bvp(theta0: float, theta1: float, X1: float, Y1: float, u: Array, theta: Array, g: Array) -> Any:
    c, s = np.cos(theta), np.sin(theta)
    du = np.diff(u)
    X = np.concatenate([[0.0], np.cumsum(0.5 * (c[1:] + c[:-1]) * du)])
    Y = np.concatenate([[0.0], np.cumsum(0.5 * (s[1:] + s[:-1]) * du)])
    y0 = np.vstack([X, Y, theta, np.gradient(theta, u)])

    def bc(ya: Array, yb: Array, p: Array) -> Array:
        return np.array([ya[0], ya[1], ya[2] - theta0, yb[0] - X1, yb[1] - Y1, yb[2] - theta1])

    def bc_jac(_ya: Array, _yb: Array, _p: Array) -> tuple[Array, Array, Array]:
        return _BC_JAC_A, _BC_JAC_B, np.zeros((6, 2))

    with np.errstate(over="ignore", invalid="ignore"):
        return solve_bvp(
            _bvp_fun, bc, u, y0, p=g, fun_jac=_bvp_fun_jac, bc_jac=bc_jac, tol=1e-6, max_nodes=1000
        )


#: Sub-intervals of multiple shooting: one per ``6 / sqrt(|g|)`` of non-dimensional length, so that the
#: growth ``exp(sqrt(|g|) Δu)`` of the linearised problem stays below ``e^6`` on each.
SHOOT_GROWTH = 6.0


def _shoot(
    theta0: float, theta1: float, X1: float, Y1: float, res: Any
) -> tuple[float, Array, _Stitched, float] | None:
    """Polish a :func:`solve_bvp` solution by Newton (multiple) shooting with variational equations.

    Unknowns: ``κ̂`` at ``u = 0``, the full state at the interior breaks and ``g``; residuals: continuity at
    the breaks and the end pose.  Returns ``(κ̂(0), g, dense, ∫ κ̂² du)`` or ``None`` without convergence.
    """
    g = np.array(res.p, dtype=float)
    M = int(min(64, max(1, math.ceil(math.sqrt(float(np.max(np.abs(g)))) / SHOOT_GROWTH))))
    breaks = np.linspace(0.0, 1.0, M + 1)
    Z = res.sol(breaks[:-1]).T.copy()  # (M, 4) states at the starts of the sub-intervals
    Z[0, :3] = 0.0, 0.0, theta0
    target = np.array([X1, Y1, theta1])
    n = 4 * M - 1
    best = math.inf
    for _ in range(40):
        sols, r, J = [], np.empty(n), np.zeros((n, n))
        for j in range(M):
            w0 = np.concatenate([Z[j], [0.0], _SENS0])
            sol = solve_ivp(
                _rhs_sens,
                (breaks[j], breaks[j + 1]),
                w0,
                method="DOP853",
                args=(float(g[0]), float(g[1])),
                rtol=IVP_RTOL,
                atol=IVP_ATOL,
                dense_output=True,
            )
            if sol.status != 0 or not np.all(np.isfinite(sol.y[:, -1])):
                return None
            sols.append(sol)
            end = sol.y[:4, -1]
            sens = sol.y[5:, -1].reshape(4, 6)
            rows = slice(4 * j, 4 * j + 4) if j < M - 1 else slice(4 * j, 4 * j + 3)
            nrow = 4 if j < M - 1 else 3
            if j < M - 1:
                r[rows] = end - Z[j + 1]
                J[rows, 1 + 4 * j : 1 + 4 * j + 4] = -np.eye(4)
            else:
                r[rows] = end[:3] - target
            if j == 0:
                J[rows, 0] = sens[:nrow, 3]
            else:
                J[rows, 1 + 4 * (j - 1) : 1 + 4 * j] = sens[:nrow, :4]
            J[rows, n - 2 :] = sens[:nrow, 4:]
        nr = float(np.max(np.abs(r)))
        if nr < SHOOT_TOL or (nr < 1e-9 and nr > 0.5 * best):  # converged, or at the noise floor
            energy = np.array([s.y[4, -1] for s in sols])
            offsets = np.concatenate([[0.0], np.cumsum(energy)[:-1]])
            dense = _Stitched(breaks, [s.sol for s in sols], offsets)
            return float(Z[0, 3]), g.copy(), dense, float(np.sum(energy))
        best = min(best, nr)
        try:
            step = np.linalg.solve(J, r)
        except np.linalg.LinAlgError:
            return None
        step /= max(1.0, float(np.max(np.abs(step))) / 10.0)
        Z[0, 3] -= step[0]
        Z[1:] -= step[1 : n - 2].reshape(M - 1, 4)
        g = g - step[n - 2 :]
    return None


def _q(res: Any) -> Array:
    return np.array([res.y[3, 0], res.p[0], res.p[1]])


def _validate_segment(
    p0: ArrayLike, theta0: Any, p1: ArrayLike, theta1: Any, length: Any, EI: Any
) -> tuple[Array, float, Array, float, float, float]:
    return (
        _point(p0, "p0"),
        _real(theta0, "theta0"),
        _point(p1, "p1"),
        _real(theta1, "theta1"),
        _real(length, "length", positive=True),
        _real(EI, "EI", positive=True),
    )


def _feasibility(p0: Array, theta0: float, p1: Array, theta1: float, length: float) -> bool:
    """Raise when no wire of ``length`` connects the poses; return ``True`` for the straight case."""
    chord = float(np.linalg.norm(p1 - p0))
    if chord > length * (1.0 + TAUT_RTOL):
        raise ValueError(
            f"infeasible segment: the ends {_fmt(p0)} and {_fmt(p1)} are {chord:.2f} mm apart but only "
            f"{length:.2f} mm of wire lies between them ({chord - length:.2f} mm short)"
        )
    if chord >= length * (1.0 - TAUT_RTOL):
        phi = math.atan2(p1[1] - p0[1], p1[0] - p0[0])
        if abs(theta1 - theta0) > 1e-12 or abs(math.remainder(theta0 - phi, 2.0 * math.pi)) > 1e-9:
            raise ValueError(
                f"infeasible segment: the ends are exactly length = {length:g} mm apart, so the wire must be "
                f"straight along {phi:.6f} rad, but theta0 = {theta0:.6f} and theta1 = {theta1:.6f} rad"
            )
        return True
    return False


def clamped_segment_equilibria(
    p0: ArrayLike, theta0: float, p1: ArrayLike, theta1: float, length: float, EI: float
) -> list[ContinuumShape]:
    """All distinct clamped-clamped equilibria found from the built-in initial guesses, lowest energy first.

    Parameters
    ----------
    p0, p1 : array_like, shape (2,)
        Clamped end points (mm).
    theta0, theta1 : float
        Clamped tangent angles (rad).  They are not wrapped: ``theta1 - theta0`` is the total turning.
    length : float
        Arc length between the clamps (mm).
    EI : float
        Bending stiffness (N·mm²).

    Returns
    -------
    list of ContinuumShape
        Each converged equilibrium once (energies differing by more than 1e-9 relative), sorted by energy.

    Raises
    ------
    ValueError
        For malformed input or when the ends are farther apart than ``length``.
    RuntimeError
        When no initial guess converges.

    Notes
    -----
    Initial guesses: the cubic Hermite curve through the poses (tangent scale chosen so that its length is
    ``length``) resampled by arc length; the local minimisers of the energy over
    ``θ = θ0 + Δθ u + Σ_{k≤8} a_k sin kπu`` under the exact chord constraints (SLSQP from 15 starts covering
    both bending senses, loops and S-shapes; those within twice the lowest Ritz energy); the circular arc
    ``θ = θ0 + Δθ u``.  The internal force guess is a least-squares fit of the elastica equation along each
    profile.  Every guess goes through :func:`scipy.integrate.solve_bvp` (``tol = 1e-6``); only if none
    converges, a grid of 105 modal profiles with fitted and zero forces is tried.  The distinct converged
    branches are polished by Newton shooting, on ``ceil(sqrt(|g|) / 6)`` sub-intervals for a
    non-dimensional force ``g = F L² / EI`` (multiple shooting keeps high tension well conditioned), to an
    end-pose error below ``1e-11 * length``.  On 90 random segments (chord 0.2-0.97 of the length, end
    angles up to 3.5 rad apart) the result was never above the lowest of ~700 brute-force BVP starts (to
    their 1e-4 accuracy); hard cases (several loops) reach the fallback and take up to ~15 s.

    A symmetric scene can have two lowest-energy equilibria.  With equal end angles (Table 1 with
    ``θ_B = 0``) the problem is invariant under ``γ(s) → p0 + p1 - γ(L - s)`` (point reflection through the
    chord midpoint and reversal), and an asymmetric minimiser has a twin of equal energy; both are listed,
    in the order the guesses (Hermite first) reached them, and :func:`clamped_segment` returns the first.
    """
    p0, theta0, p1, theta1, length, EI = _validate_segment(p0, theta0, p1, theta1, length, EI)
    if _feasibility(p0, theta0, p1, theta1, length):
        return [_assemble([_straight_piece(0.0, length, p0, theta0)], length, EI, p0, [(length, "clamp")])]
    X1, Y1 = (p1 - p0) / length
    u = np.linspace(0.0, 1.0, 41)
    found: list[Any] = []

    def attempt(theta: Array, g: Array) -> bool:
        res = _bvp(theta0, theta1, X1, Y1, u, theta, g)
        if not res.success:
            return False
        q = np.array([res.y[3, 0], res.p[0], res.p[1]])
        if all(np.max(np.abs(q - _q(f)) / (1.0 + np.abs(_q(f)))) >= 1e-4 for f in found):
            found.append(res)
        return True

    for theta in _guesses(theta0, theta1, X1, Y1, u):
        attempt(theta, _force_fit(u, theta))
    if not found:  # hard case: a wide grid of profiles, fitted and zero force guesses
        for theta in _fallback_guesses(theta0, theta1, u):
            if not attempt(theta, _force_fit(u, theta)):
                attempt(theta, np.zeros(2))
    shapes: list[ContinuumShape] = []
    polished_q: list[Array] = []
    for res in found:
        polished = _shoot(theta0, theta1, X1, Y1, res)
        if polished is None:
            continue
        kappa_hat0, g, dense, energy_hat = polished
        qp = np.array([kappa_hat0, *g])
        if any(np.max(np.abs(qp - q2) / (1.0 + np.abs(q2))) < 1e-6 for q2 in polished_q):
            continue
        polished_q.append(qp)
        piece = _piece(0.0, length, p0, theta0, kappa_hat0, g, EI, dense, energy_hat)
        shapes.append(_assemble([piece], length, EI, p0, [(length, "clamp")]))
    if not shapes:
        raise RuntimeError(
            f"no clamped elastica found between {_fmt(p0)} at {theta0:g} rad and {_fmt(p1)} at "
            f"{theta1:g} rad with length {length:g} mm"
        )
    return _lowest_first(shapes)  # equal energies (mirror twins) keep the guess order, Hermite first


def clamped_segment(
    p0: ArrayLike, theta0: float, p1: ArrayLike, theta1: float, length: float, EI: float
) -> ContinuumShape:
    """Lowest-energy elastica between two fully clamped ends.

    Parameters
    ----------
    p0, p1 : array_like, shape (2,)
        Clamped end points (mm).
    theta0, theta1 : float
        Clamped tangent angles (rad).  They are not wrapped: ``theta1 - theta0`` is the total turning.
    length : float
        Arc length between the clamps (mm); must be at least ``|p1 - p0|``.
    EI : float
        Bending stiffness (N·mm²).

    Returns
    -------
    ContinuumShape
        Arc length from 0 (at ``p0``) to ``length``; reactions of both clamps.

    Raises
    ------
    ValueError
        For malformed input, or when the ends are farther apart than ``length`` (the message says by how
        much), or when they are exactly ``length`` apart with angles that are not those of the chord.
    RuntimeError
        When no initial guess converges.

    See Also
    --------
    clamped_segment_equilibria : all branches found, with the guesses used.

    Examples
    --------
    >>> shape = clamped_segment((0, 0), 0.0, (60, 40), np.pi / 4, 100.0, 64.65)
    >>> round(shape.energy, 4)
    4.5551
    """
    return clamped_segment_equilibria(p0, theta0, p1, theta1, length, EI)[0]


def _assemble(
    pieces: Sequence[ElasticaPiece],
    length: float,
    EI: float,
    base_point: Array,
    supports: Sequence[tuple[float, str]],
) -> ContinuumShape:
    """Concatenate pieces and derive the reactions of the base clamp and the supports at piece ends.

    ``supports`` lists ``(s, kind)`` of the supports; each must coincide with the end of a piece.  A support
    at the end of piece ``j`` exerts ``F_j - F_{j+1}`` and ``EI (κ_j(end) - κ_{j+1}(start))`` on the wire.
    """
    reactions = [
        Reaction(0.0, np.array(base_point, dtype=float), -pieces[0].force, -EI * pieces[0].kappa0, "clamp")
    ]
    ends = np.array([p.s1 for p in pieces])
    for s, kind in supports:
        j = int(np.argmin(np.abs(ends - s)))
        point, _, kappa = pieces[j].end_state()
        force = pieces[j].force.copy()
        moment = EI * kappa
        if j + 1 < len(pieces):
            force -= pieces[j + 1].force
            moment -= EI * pieces[j + 1].kappa0
        reactions.append(Reaction(float(s), point, force, float(moment), kind))
    return ContinuumShape(
        length=length,
        energy=float(sum(p.energy for p in pieces)),
        EI=EI,
        pieces=tuple(pieces),
        reactions=tuple(reactions),
    )


# ----------------------------------------------------------------------------------------------------
# Clamp, free end and one straight wall
# ----------------------------------------------------------------------------------------------------


def _pendulum_integrals(phi0: float, sigma: float, amplitude: Array) -> tuple[Array, Array, Array, Array]:
    """Oriented elliptic integrals of the path ``φ0 → σA`` of ``φ'' = -(f/EI) sin φ`` ending at rest.

    With ``sin(φ/2) = k sin ψ``, ``k = sin(A/2)``, ``m = k²`` the path runs over ``ψ ∈ [ψ0, σπ/2]`` and
    ``ds = λ dψ / sqrt(1 - m sin²ψ)`` with ``λ = sqrt(EI/f)``.  Returns ``(ψ0, m, I_F, I_E)`` where
    ``I_F = σ (F(σπ/2|m) - F(ψ0|m))`` and ``I_E`` likewise with ``E``; then the length is ``λ I_F``, the
    displacement along the wall normal ``λ (2 I_E - I_F)``, and the energy ``2 EI/λ (I_E - (1 - m) I_F)``.
    """
    k = np.sin(0.5 * amplitude)
    m = k * k
    psi0 = np.arcsin(np.clip(math.sin(0.5 * phi0) / k, -1.0, 1.0))
    end = sigma * 0.5 * np.pi
    i_f = sigma * (ellipkinc(end, m) - ellipkinc(psi0, m))
    i_e = sigma * (ellipeinc(end, m) - ellipeinc(psi0, m))
    return psi0, m, i_f, i_e


def _wall_parameters(
    phi0: float, sigma: float, depth: float, length: float
) -> list[tuple[float, float, float]]:
    """Candidate contact solutions ``(A, λ, ℓ)`` for one turning sense (``A = π/2``: tangential contact)."""
    out = []
    _, _, i_f, i_e = _pendulum_integrals(phi0, sigma, np.array([0.5 * np.pi]))
    reach = float(2.0 * i_e[0] - i_f[0])
    if reach > 0.0:
        lam = depth / reach
        if lam * float(i_f[0]) <= length * (1.0 + 1e-12):
            out.append((0.5 * np.pi, lam, lam * float(i_f[0])))
            return out
    # tip contact: the whole wire is bent, its free end rests on the wall at an angle
    lo = abs(phi0)
    amps = lo + (0.5 * np.pi - lo) * np.concatenate([[1e-7], np.linspace(0.0, 1.0, 65)[1:]])

    def ratio(a: Array) -> Array:
        _, _, f_, e_ = _pendulum_integrals(phi0, sigma, a)
        with np.errstate(divide="ignore", invalid="ignore"):
            return (2.0 * e_ - f_) / f_ - depth / length

    h = ratio(amps)
    for j in np.nonzero(np.isfinite(h[:-1]) & np.isfinite(h[1:]) & (np.sign(h[:-1]) != np.sign(h[1:])))[0]:
        a = brentq(lambda x: float(ratio(np.array([x]))[0]), amps[j], amps[j + 1], xtol=1e-15, rtol=1e-15)
        if a >= 0.5 * np.pi * (1.0 - 1e-12):
            continue
        _, _, i_f, _ = _pendulum_integrals(phi0, sigma, np.array([a]))
        out.append((a, length / float(i_f[0]), length))
    return out


def _wall(normal: ArrayLike, offset: Any, name: str = "wall") -> tuple[Array, float]:
    n = _point(normal, f"{name} normal")
    norm = float(np.linalg.norm(n))
    if norm == 0.0:
        raise ValueError(f"{name} normal must be non-zero")
    return n / norm, _real(offset, f"{name} offset") / norm


def _max_wall_violation(shape: ContinuumShape, n: Array, c: float, samples: int = 4001) -> float:
    s = np.unique(np.concatenate([np.linspace(0.0, shape.length, samples), shape.breakpoints]))
    return float(np.max(shape.position(s) @ n - c))


def clamp_wall_free_end(
    p0: ArrayLike, theta0: float, length: float, wall_normal: ArrayLike, wall_offset: float, EI: float
) -> ContinuumShape:
    """Clamped wire with a free end, bent by one straight frictionless wall ``{p : normal·p ≤ offset}``.

    Parameters
    ----------
    p0 : array_like, shape (2,)
        Clamp point (mm); must lie strictly inside the allowed half-plane.
    theta0 : float
        Clamp angle (rad).
    length : float
        Wire length (mm).
    wall_normal : array_like, shape (2,)
        Outward normal of the wall (any non-zero length; normalised internally).
    wall_offset : float
        Offset in the units of ``wall_normal``: the allowed side is ``wall_normal · p ≤ wall_offset``.
    EI : float
        Bending stiffness (N·mm²).

    Returns
    -------
    ContinuumShape
        The straight wire when it does not cross the wall.  Otherwise an elastica with constant internal
        force ``F = -f n`` (the wall reaction, ``f > 0``) from the clamp to the contact point ``s_c``, where
        the moment vanishes; for ``s_c < length`` the contact is tangential and a straight tail lies on the
        wall, otherwise (small penetration) the free end rests on the wall at an angle.  Reactions: base
        clamp and wall (kind ``"wall"``, at ``s_c``).

    Raises
    ------
    ValueError
        For malformed input, or when ``p0`` is not strictly inside the allowed half-plane while the wire is
        pushed against the wall.
    RuntimeError
        When no candidate passes the verification (should not happen).

    Notes
    -----
    With ``φ = θ - α`` (``α`` the direction of the normal) the elastica is a pendulum,
    ``EI φ'' = -f sin φ``, with first integral ``EI κ²/2 - f cos φ = const``.  The clamp-to-contact stretch
    is a monotone swing of amplitude ``A`` ending at rest (``κ = 0``) on the wall; the substitution
    ``sin(φ/2) = sin(A/2) sin ψ`` turns length, penetration depth and energy into incomplete elliptic
    integrals (see :func:`_pendulum_integrals`).  Tangential contact is ``A = π/2``, which fixes the force
    from the clamp-to-wall distance ``d``; for ``φ0 = 0`` the energy is ``EI J² / (2 d)`` with
    ``J = ∫_0^{π/2} sqrt(cos φ) dφ = sqrt(2) (2 E(1/2) - K(1/2))``, i.e. 1.0312 N·mm for Fig. 6b
    (``d = 45``, ``EI = 64.65``), and the contact is at ``s_c = d K(1/2) / (2 E(1/2) - K(1/2)) = 98.48``
    mm.  Both turning senses are solved; the lower-energy one is kept (the counter-clockwise one on a
    tie).  The result is re-integrated as an initial-value problem and verified: it ends on the wall with
    zero curvature and never crosses it.
    """
    p0 = _point(p0, "p0")
    theta0 = _real(theta0, "theta0")
    length = _real(length, "length", positive=True)
    EI = _real(EI, "EI", positive=True)
    n, c = _wall(wall_normal, wall_offset)
    return _wall_shapes(p0, theta0, length, n, c, EI)[0]


def _wall_shapes(
    p0: Array, theta0: float, length: float, n: Array, c: float, EI: float
) -> list[ContinuumShape]:
    """Every verified clamp-wall shape (validated input, unit normal), lowest energy first."""
    depth = c - float(n @ p0)
    alpha = math.atan2(n[1], n[0])
    phi0 = math.remainder(theta0 - alpha, 2.0 * math.pi)
    if depth < 0.0:
        raise ValueError(f"p0 = {_fmt(p0)} lies {-depth:.6g} mm beyond the wall")
    if length * math.cos(phi0) <= depth:
        return [straight_shape(p0, theta0, length, EI)]
    if depth == 0.0:
        raise ValueError(f"p0 = {_fmt(p0)} lies on the wall and the wire points into it")
    shapes: list[ContinuumShape] = []
    for sigma in (1.0, -1.0):
        for amp, lam, ell in _wall_parameters(phi0, sigma, depth, length):
            psi0, m, i_f, i_e = _pendulum_integrals(phi0, sigma, np.array([amp]))
            kappa0 = sigma * 2.0 * math.sin(0.5 * amp) * math.cos(float(psi0[0])) / lam
            g = -((ell / lam) ** 2) * n
            sol = _integrate(theta0, kappa0 * ell, g)
            if sol.status != 0:
                continue
            piece = _piece(0.0, ell, p0, theta0, kappa0 * ell, g, EI, sol.sol, sol.y[4, -1])
            pieces = [piece]
            end, theta_end, kappa_end = piece.end_state()
            theta_exact = theta0 + sigma * amp - phi0
            scale = max(1.0, length)
            if (
                abs(theta_end - theta_exact) > 1e-8
                or abs(kappa_end) * scale > 1e-8
                or abs(float(n @ end) - c) > 1e-8 * scale
            ):
                continue
            if length - ell > 1e-12 * length:
                pieces.append(_straight_piece(ell, length - ell, end, theta_exact))
            shape = _assemble(pieces, length, EI, p0, [(ell, "wall")])
            expected = 2.0 * EI / lam * float(i_e[0] - (1.0 - m[0]) * i_f[0])
            if abs(shape.energy - expected) > 1e-8 * max(expected, 1e-12):
                continue
            if _max_wall_violation(shape, n, c) > 1e-9 * scale:
                continue
            shapes.append(shape)
    if not shapes:
        raise RuntimeError("no verified wall-contact shape found")
    return _lowest_first(shapes)


def _lowest_first(shapes: list[ContinuumShape]) -> list[ContinuumShape]:
    """Sort by energy; energies equal to the lowest within ``TIE_RTOL`` keep their order."""
    lowest = min(sh.energy for sh in shapes)
    return sorted(shapes, key=lambda sh: max(sh.energy, lowest * (1.0 + TIE_RTOL)))


def _ties(shapes: list[ContinuumShape]) -> list[ContinuumShape]:
    """The leading shapes whose energy equals the lowest within ``TIE_RTOL``."""
    return [sh for sh in shapes if sh.energy <= shapes[0].energy * (1.0 + TIE_RTOL) + 1e-15]


# ----------------------------------------------------------------------------------------------------
# Whole scenes
# ----------------------------------------------------------------------------------------------------


def _field(item: Any, index: int, name: str) -> Any:
    """Read ``name`` from a tuple ``(s, point, angle)``, a mapping or an object with attributes."""
    if isinstance(item, dict):
        return item.get(name)
    if hasattr(item, name):
        return getattr(item, name)
    if isinstance(item, Sequence) and not isinstance(item, str):
        order = {"s": 0, "point": 1, "angle": 2, "normal": 0, "offset": 1}
        return item[order[name]] if order[name] < len(item) else None
    raise ValueError(f"{index}: expected a tuple, a mapping or an object with .{name}, got {item!r}")


def _contacts(contacts: Iterable[Any], total_length: float) -> list[tuple[float, Array, float]]:
    out: list[tuple[float, Array, float]] = []
    for i, item in enumerate(contacts):
        label = f"contacts[{i}]"
        s = _real(_field(item, i, "s"), f"{label}.s")
        point, angle = _field(item, i, "point"), _field(item, i, "angle")
        if point is None or angle is None:
            missing = " and ".join(k for k, v in (("point", point), ("angle", angle)) if v is None)
            raise NotImplementedError(
                f"{label} at s = {s:g} has no {missing}: the continuum reference only handles fully clamped "
                "contacts (position and angle given)"
            )
        point = _point(point, f"{label}.point")
        angle = _real(angle, f"{label}.angle")
        previous = out[-1][0] if out else 0.0
        if s <= previous:
            raise ValueError(f"{label}.s = {s:g} must exceed the previous arc length {previous:g}")
        if s > total_length * (1.0 + 1e-12):
            raise ValueError(f"{label}.s = {s:g} exceeds total_length = {total_length:g}")
        out.append((min(s, total_length), point, angle))
    return out


def reference_shape(
    base_point: ArrayLike,
    base_angle: float | None,
    contacts: Iterable[Any],
    total_length: float,
    EI: float,
    walls: Iterable[Any] = (),
) -> ContinuumShape:
    """Continuum reference of a whole scene: base clamp, fully clamped contacts, free tail, walls.

    Parameters
    ----------
    base_point : array_like, shape (2,)
        Clamp at ``s = 0`` (mm).
    base_angle : float
        Clamp angle (rad).  ``None`` (free rotation) is not supported.
    contacts : iterable
        Contacts ``(s, point, angle)`` in increasing ``s`` (tuples, mappings or objects with attributes ``s``,
        ``point``, ``angle``), each fully clamped.  Consecutive clamps decouple; each segment is the
        lowest-energy :func:`clamped_segment`.  Beyond the last contact the wire is a straight free tail.
    total_length : float
        Inserted length ``L`` (mm).
    EI : float
        Bending stiffness (N·mm²).
    walls : iterable, optional
        Walls ``(normal, offset)`` (tuples, mappings or objects), allowed side ``normal · p ≤ offset``.

    Returns
    -------
    ContinuumShape
        The whole wire from ``s = 0`` to ``total_length``, with the reactions of the base and every support.
        When the minimiser is not unique (mirror twins, see :func:`reference_shapes`) the first one.

    Raises
    ------
    ValueError
        For malformed input, contacts out of order or beyond ``total_length``, or an infeasible segment
        (two contacts farther apart than the wire between them; the message says by how much).  Every
        segment is checked before any is solved.
    NotImplementedError
        For a contact without position or angle, a free base angle, or walls that are active together with
        contacts or with each other (walls that the wall-free solution respects are accepted).

    Notes
    -----
    Supported cases: no contacts and no wall (straight wire); no contacts and one active wall
    (:func:`clamp_wall_free_end`); fully clamped contacts with inactive walls.
    """
    return reference_shapes(base_point, base_angle, contacts, total_length, EI, walls)[0]


def reference_shapes(
    base_point: ArrayLike,
    base_angle: float | None,
    contacts: Iterable[Any],
    total_length: float,
    EI: float,
    walls: Iterable[Any] = (),
) -> list[ContinuumShape]:
    """Every lowest-energy continuum shape of a scene (ties within ``TIE_RTOL``), the default one first.

    Symmetric scenes have several minimisers of equal energy: a segment with equal end angles (Table 1 with
    ``θ_B = 0``, both segments of Table 2 with ``θ_C = 0``) has mirror twins, and Fig. 6b can turn either
    way.  A discrete solution should be compared with the nearest of them.  Parameters, errors and
    supported cases as :func:`reference_shape`; at most ``MAX_TIES`` combinations are assembled.

    Returns
    -------
    list of ContinuumShape
        One shape per combination of tied segment minimisers; a single element when the minimiser is unique.
    """
    base_point = _point(base_point, "base_point")
    if base_angle is None:
        raise NotImplementedError(
            "base_angle = None (a freely rotating base) is not supported by the reference"
        )
    base_angle = _real(base_angle, "base_angle")
    total_length = _real(total_length, "total_length", positive=True)
    EI = _real(EI, "EI", positive=True)
    clamps = _contacts(contacts, total_length)
    wall_list = [
        _wall(_field(w, i, "normal"), _field(w, i, "offset"), f"walls[{i}]") for i, w in enumerate(walls)
    ]
    for i, (n, c) in enumerate(wall_list):
        if float(n @ base_point) > c + 1e-12 * max(1.0, abs(c)):
            raise ValueError(f"base_point lies beyond walls[{i}] by {float(n @ base_point) - c:.6g} mm")

    if not clamps:
        straight = straight_shape(base_point, base_angle, total_length, EI)
        active = [i for i, (n, c) in enumerate(wall_list) if _max_wall_violation(straight, n, c, 3) > 0.0]
        if len(active) > 1:
            raise NotImplementedError(
                f"the straight wire crosses {len(active)} walls ({active}); only one active wall is supported"
            )
        shapes = [straight]
        if active:
            n, c = wall_list[active[0]]
            shapes = _ties(_wall_shapes(base_point, base_angle, total_length, n, c, EI))
    else:
        s_prev, p_prev, a_prev = 0.0, base_point, base_angle
        for i, (s, point, angle) in enumerate(clamps):  # every segment is checked before any is solved
            try:
                _feasibility(p_prev, a_prev, point, angle, s - s_prev)
            except ValueError as exc:
                raise ValueError(f"segment s = {s_prev:g} .. {s:g} (to contacts[{i}]): {exc}") from exc
            s_prev, p_prev, a_prev = s, point, angle
        options: list[list[list[ElasticaPiece]]] = []  # per segment: the pieces of each tied minimiser
        s_prev, p_prev, a_prev = 0.0, base_point, base_angle
        for s, point, angle in clamps:
            segment = _ties(clamped_segment_equilibria(p_prev, a_prev, point, angle, s - s_prev, EI))
            options.append([[_shift(piece, s_prev) for piece in sh.pieces] for sh in segment])
            s_prev, p_prev, a_prev = s, point, angle
        tail = []
        if total_length - s_prev > 1e-12 * total_length:
            tail = [_straight_piece(s_prev, total_length - s_prev, p_prev, a_prev)]
        supports = [(s, "clamp") for s, _, _ in clamps]
        shapes = [
            _assemble([p for seg in combo for p in seg] + tail, total_length, EI, base_point, supports)
            for combo in itertools.islice(itertools.product(*options), MAX_TIES)
        ]
    tol = 1e-9 * max(1.0, total_length)
    for shape in shapes:
        for i, (n, c) in enumerate(wall_list):
            excess = _max_wall_violation(shape, n, c)
            if excess > tol:
                raise NotImplementedError(
                    f"walls[{i}] is crossed by {excess:.4g} mm by the wall-free solution: active walls "
                    "combined with contacts (or with other walls) are not supported by the reference"
                )
    return shapes
