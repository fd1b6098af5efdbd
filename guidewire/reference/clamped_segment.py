"""The elastica between two fully clamped ends: :func:`clamped_segment` and :func:`clamped_segment_equilibria`.

Several equilibria exist, so :func:`scipy.integrate.solve_bvp` is started from several guesses
(:mod:`~guidewire.reference.segment_guesses`), every converged branch is polished by Newton (multiple)
shooting with variational equations (DOP853, ``rtol = 1e-12``) and the lowest energy wins.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike
from scipy.integrate import solve_bvp, solve_ivp

from .. import fields
from .ode import IVP_ATOL, IVP_RTOL, SENS0, Stitched, bvp_fun, bvp_fun_jac, rhs_sens
from .pieces import assemble, curved_piece, lowest_first, straight_piece
from .segment_guesses import fallback_guesses, force_fit, guesses
from .shapes import Array, ContinuumShape

__all__ = ["SHOOT_GROWTH", "SHOOT_TOL", "TAUT_RTOL", "clamped_segment", "clamped_segment_equilibria",
           "segment_feasibility"]

#: Newton shooting stops when the non-dimensional end-pose residual is below this.
SHOOT_TOL = 1e-11
#: Relative tolerance under which a chord is considered equal to the available length.
TAUT_RTOL = 1e-12


_BC_JAC_A = np.zeros((6, 4))
_BC_JAC_A[0, 0] = _BC_JAC_A[1, 1] = _BC_JAC_A[2, 2] = 1.0
_BC_JAC_B = np.zeros((6, 4))
_BC_JAC_B[3, 0] = _BC_JAC_B[4, 1] = _BC_JAC_B[5, 2] = 1.0



def _bvp(theta0: float, theta1: float, X1: float, Y1: float, u: Array, theta: Array, g: Array) -> Any:
    """``solve_bvp`` (``tol = 1e-6``) from the angle profile ``theta`` on the mesh ``u`` and the force guess ``g``."""
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
            bvp_fun, bc, u, y0, p=g, fun_jac=bvp_fun_jac, bc_jac=bc_jac, tol=1e-6, max_nodes=1000
        )


#: Sub-intervals of multiple shooting: one per ``6 / sqrt(|g|)`` of non-dimensional length, so that the
#: growth ``exp(sqrt(|g|) Δu)`` of the linearised problem stays below ``e^6`` on each.
SHOOT_GROWTH = 6.0


def _shoot(
    theta0: float, theta1: float, X1: float, Y1: float, res: Any
) -> tuple[float, Array, Stitched, float] | None:
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
            w0 = np.concatenate([Z[j], [0.0], SENS0])
            sol = solve_ivp(
                rhs_sens,
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
            dense = Stitched(breaks, [s.sol for s in sols], offsets)
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
    """The unknowns ``(κ̂(0), g_x, g_y)`` that tell two ``solve_bvp`` branches apart."""
    return np.array([res.y[3, 0], res.p[0], res.p[1]])


def _validate_segment(
    p0: ArrayLike, theta0: Any, p1: ArrayLike, theta1: Any, length: Any, EI: Any
) -> tuple[Array, float, Array, float, float, float]:
    """The clamped-segment arguments validated and converted (points as arrays, the rest as floats)."""
    return (
        np.asarray(fields.point(p0, "p0")),
        fields.real(theta0, "theta0"),
        np.asarray(fields.point(p1, "p1")),
        fields.real(theta1, "theta1"),
        fields.real(length, "length", positive=True),
        fields.real(EI, "EI", positive=True),
    )


def segment_feasibility(p0: Array, theta0: float, p1: Array, theta1: float, length: float) -> bool:
    """Raise when no wire of ``length`` connects the poses; return ``True`` for the straight case."""
    chord = float(np.linalg.norm(p1 - p0))
    if chord > length * (1.0 + TAUT_RTOL):
        raise ValueError(
            f"infeasible segment: the ends {fields.fmt_point(p0)} and {fields.fmt_point(p1)} are {chord:.2f} mm "
            f"apart but only {length:.2f} mm of wire lies between them ({chord - length:.2f} mm short)"
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
    TypeError
        A value of the wrong type (a string or a bool for a number, a non-sequence for a point), as
        :mod:`guidewire.fields` reports it.
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
    if segment_feasibility(p0, theta0, p1, theta1, length):
        return [assemble([straight_piece(0.0, length, p0, theta0)], length, EI, p0, [(length, "clamp")])]
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

    for theta in guesses(theta0, theta1, X1, Y1, u):
        attempt(theta, force_fit(u, theta))
    if not found:  # hard case: a wide grid of profiles, fitted and zero force guesses
        for theta in fallback_guesses(theta0, theta1, u):
            if not attempt(theta, force_fit(u, theta)):
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
        piece = curved_piece(0.0, length, p0, theta0, kappa_hat0, g, EI, dense, energy_hat)
        shapes.append(assemble([piece], length, EI, p0, [(length, "clamp")]))
    if not shapes:
        raise RuntimeError(
            f"no clamped elastica found between {fields.fmt_point(p0)} at {theta0:g} rad and {fields.fmt_point(p1)} at "
            f"{theta1:g} rad with length {length:g} mm"
        )
    return lowest_first(shapes)  # equal energies (mirror twins) keep the guess order, Hermite first


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
    TypeError
        A value of the wrong type (a string or a bool for a number, a non-sequence for a point), as
        :mod:`guidewire.fields` reports it.
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
