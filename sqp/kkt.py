"""Lagrangian gradient and the KKT residuals (stationarity, feasibility, complementarity) at a point."""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from sqp.problem import Problem, Rows

Array = NDArray[np.float64]


#: The residuals a :class:`KKTResiduals` holds, as its mapping keys (``res.kkt["stationarity"]``).
KKT_KEYS = ("stationarity", "feasibility", "complementarity")


@dataclass(frozen=True)
class KKTResiduals(Mapping[str, float]):
    """Residuals of the first-order conditions at ``(x, lam, z)``: a typed value that also reads as the mapping
    ``{"stationarity": ..., "feasibility": ..., "complementarity": ...}`` (``res.kkt["stationarity"]``,
    ``dict(res.kkt)``).

    Attributes
    ----------
    stationarity : float
        ``||D (grad f - J^T lam - A^T lam_lin - z)||_inf / max(1, ||D grad f||_inf)`` with
        ``D = diag(max(1, |x_i|))``: the change of the Lagrangian for a unit change of every variable, or a relative
        one for variables larger than 1, so that a tiny gradient of a huge variable is not taken for stationarity.
    feasibility : float
        Largest absolute violation of any row or bound (the same number as ``maxcv``); the test compares it with
        ``tol * feasibility_scale``, ``feasibility_scale = max(1, ||x||_inf)``.
    complementarity : float
        Largest ``|lam_i| * slack_i`` of an inequality side (and of a bound), scaled like stationarity, together
        with any multiplier of the wrong sign.
    """

    stationarity: float
    feasibility: float
    complementarity: float
    feasibility_scale: float = 1.0

    def satisfied(self, tol: float, feasibility_tol: float | None = None) -> bool:
        """Stationarity and complementarity at most ``tol``; violation at most ``feasibility_tol`` (default
        ``tol``) times ``max(1, ||x||_inf)``."""
        feasible = self.feasible(tol if feasibility_tol is None else feasibility_tol)
        return bool(self.stationarity <= tol and feasible and self.complementarity <= tol)

    def feasible(self, tol: float) -> bool:
        """Violation at most ``tol * max(1, ||x||_inf)``."""
        return bool(self.feasibility <= tol * self.feasibility_scale)

    @property
    def worst(self) -> float:
        return max(self.stationarity, self.feasibility, self.complementarity)

    def __getitem__(self, key: str) -> float:
        if key not in KKT_KEYS:
            raise KeyError(key)
        return float(getattr(self, key))

    def __iter__(self) -> Iterator[str]:
        return iter(KKT_KEYS)

    def __len__(self) -> int:
        return len(KKT_KEYS)

    @classmethod
    def unknown(cls) -> KKTResiduals:
        """Residuals of a solve that ended before the derivatives at its point were evaluated (all NaN)."""
        return cls(stationarity=np.nan, feasibility=np.nan, complementarity=np.nan)


def inf_norm(v: Array) -> float:
    """``||v||_inf`` (0 for an empty array): the method call, a third of ``np.max(np.abs(v), initial=0.0)``'s cost on
    the small arrays of one iteration."""
    return float(np.abs(v).max()) if v.size else 0.0


def lagrangian_gradient(g: Array, J: Array, lam_nl: Array, A: Array, lam_lin: Array, z: Array) -> Array:
    """``grad_x L = g - J^T lam - A^T lam_lin - z``."""
    out = g - z
    if lam_nl.size:
        out = out - J.T @ lam_nl
    if lam_lin.size:
        out = out - A.T @ lam_lin
    return np.asarray(out).ravel()


def cancellation(problem: Problem, x: Array, g: Array, J: Any, lam_nl: Array, lam_lin: Array, z: Array) -> float:
    """How much larger the terms of the Lagrangian gradient are than the gradient itself:
    ``||D (|g| + |J|^T |lam| + |A|^T |lam_lin| + |z|)||_inf / max(1, ||D g||_inf)`` (>= 1), ``D`` as in
    :class:`KKTResiduals`. Rounding errors in ``f``, ``c``, their derivatives and the QP's multipliers leave a
    stationarity residual of about this factor times the relative accuracy reached; on a hanging chain of 150 links
    the tensions make it about 150."""
    typical = np.maximum(1.0, np.abs(x))
    terms = np.abs(g) + np.abs(z)
    if lam_nl.size:
        terms = terms + np.asarray(abs(J).T @ np.abs(lam_nl)).ravel()
    if lam_lin.size:
        terms = terms + np.asarray(abs(problem.A).T @ np.abs(lam_lin)).ravel()
    scale = max(1.0, float(np.max(np.abs(g) * typical, initial=0.0)))
    return max(1.0, float(np.max(terms * typical, initial=0.0)) / scale)


def max_violation(problem: Problem, x: Array, c: Array, r: Array, v_nl: Array | None = None) -> float:
    """Largest absolute violation of the nonlinear rows, the linear rows and the bounds (``v_nl``: the nonlinear
    rows' violations at ``c``, when already known)."""
    v = 0.0
    if c.size:
        v = float((problem.nonlinear.violation(c) if v_nl is None else v_nl).max())
    if r.size:
        v = max(v, float(problem.linear.violation(r).max()))
    if problem.has_bounds:
        v = max(v, float((problem.lower - x).max()), float((x - problem.upper).max()))
    return v


def _complementarity(rows: Rows, values: Array, lam: Array) -> float:
    """``max |lam| * distance-to-the-side`` over inequality rows ``lb <= values <= ub``, and the size of any
    multiplier of the wrong sign (a positive multiplier belongs to the lower side, a negative one to the upper side;
    one on a side that does not exist is wrong)."""
    if lam.size == 0 or rows.eq.size == lam.size:
        return 0.0
    out = 0.0
    lo, up = rows.lower, rows.upper
    if lo.size:
        out = float((np.maximum(lam[lo], 0.0) * np.abs(values[lo] - rows.lb[lo])).max())
    if up.size:
        out = max(out, float((np.maximum(-lam[up], 0.0) * np.abs(rows.ub[up] - values[up])).max()))
    no_lo, no_up = rows.inequality_without_lower, rows.inequality_without_upper
    if no_lo.size:
        out = max(out, float(lam[no_lo].max()))
    if no_up.size:
        out = max(out, float((-lam[no_up]).max()))
    return out


def kkt_residuals(
    problem: Problem, x: Array, g: Array, c: Array, J: Array, r: Array, lam_nl: Array, lam_lin: Array, z: Array,
    feasibility: float | None = None,
) -> KKTResiduals:
    """KKT residuals at ``x`` for the multipliers ``(lam_nl, lam_lin, z)`` (engine sign convention); ``feasibility``
    is :func:`max_violation` at ``x`` when already known."""
    typical = np.maximum(1.0, np.abs(x))  # a unit change of a variable is relative to its size beyond 1
    grad_l = lagrangian_gradient(g, J, lam_nl, problem.A, lam_lin, z) * typical
    scale = max(1.0, inf_norm(g * typical))
    comp = max(
        _complementarity(problem.nonlinear, c, lam_nl),
        _complementarity(problem.linear, r, lam_lin),
        _complementarity(problem.bound_rows, x, z) if problem.has_bounds else 0.0,
    )
    return KKTResiduals(
        stationarity=inf_norm(grad_l) / scale,
        feasibility=max_violation(problem, x, c, r) if feasibility is None else feasibility,
        complementarity=comp / scale,
        feasibility_scale=max(1.0, float(typical.max()) if typical.size else 1.0),
    )
