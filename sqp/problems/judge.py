"""Judge a point of a test problem independently of any solver's own stopping test.

The multipliers are recovered by a bounded least-squares fit of ``grad f = sum_i lam_i grad c_i`` over the
constraints active at ``x`` (``lam_i >= 0`` for inequalities and bounds), so a solver's claim of success can be checked
without trusting its multipliers.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import LinearConstraint, lsq_linear

from sqp.problems.problem import TestProblem

Array = NDArray[np.float64]

#: A constraint or bound within this distance of its limit counts as active when judging stationarity.
ACTIVE_TOL = 1e-5
#: Largest scaled stationarity residual of a point judged to be a KKT point.
KKT_TOL = 1e-4
#: Largest absolute violation of a point judged feasible (the collection's strict criterion).
FEASIBILITY_TOL = 1e-6


@dataclass(frozen=True)
class Verdict:
    """How good a point is: the collection's strict test and an independent KKT certificate."""

    solved: bool
    feasible: bool
    kkt_point: bool
    maxcv: float
    stationarity: float
    f_error: float

    def false_success(self, claimed_success: bool) -> bool:
        """A claimed success at a point that is infeasible or not a KKT point (an honest local minimum is not)."""
        return bool(claimed_success and not self.solved and not (self.feasible and self.kkt_point))


def _gradients(prob: TestProblem, x: Array) -> tuple[list[Array], list[Array], list[Array]]:
    """Rows of active constraints written as ``a^T x`` with sign so that ``a`` points into the feasible side."""
    eq_rows: list[Array] = []
    ineq_rows: list[Array] = []
    values: list[Array] = []
    for con in prob.constraints:
        if isinstance(con, LinearConstraint):
            _linear_rows(con, x, eq_rows, ineq_rows)
        else:
            values.append(_nonlinear_rows(con, x, eq_rows, ineq_rows))
    ineq_rows.extend(_active_bounds(prob, x))
    return eq_rows, ineq_rows, values


def _linear_rows(con: LinearConstraint, x: Array, eq_rows: list[Array], ineq_rows: list[Array]) -> None:
    """Append a LinearConstraint's equality rows and active inequality sides (signed into the feasible side)."""
    A = np.atleast_2d(np.asarray(con.A.toarray() if hasattr(con.A, "toarray") else con.A, dtype=float))
    v = A @ x
    lb = np.broadcast_to(np.asarray(con.lb, float), v.shape)
    ub = np.broadcast_to(np.asarray(con.ub, float), v.shape)
    for i in range(v.size):
        scale = max(1.0, abs(v[i]))
        if lb[i] == ub[i]:
            eq_rows.append(A[i])
            continue
        if np.isfinite(lb[i]) and v[i] - lb[i] <= ACTIVE_TOL * scale:
            ineq_rows.append(A[i])
        if np.isfinite(ub[i]) and ub[i] - v[i] <= ACTIVE_TOL * scale:
            ineq_rows.append(-A[i])


def _nonlinear_rows(con: dict[str, Any], x: Array, eq_rows: list[Array], ineq_rows: list[Array]) -> Array:
    """Append an SLSQP dict's equality rows and active inequality rows; return its values at ``x``."""
    c = np.atleast_1d(np.asarray(con["fun"](x), dtype=float))
    J = np.atleast_2d(np.asarray(con["jac"](x), dtype=float)).reshape(c.size, x.size)
    for i in range(c.size):
        if con["type"] == "eq":
            eq_rows.append(J[i])
        elif c[i] <= ACTIVE_TOL * max(1.0, np.max(np.abs(J[i]))):
            ineq_rows.append(J[i])
    return c


def _active_bounds(prob: TestProblem, x: Array) -> list[Array]:
    """The active bounds as signed unit rows."""
    rows: list[Array] = []
    for j, (lo, hi) in enumerate(prob.bounds or ()):
        e = np.zeros(x.size)
        e[j] = 1.0
        if lo is not None and x[j] - lo <= ACTIVE_TOL * max(1.0, abs(lo)):
            rows.append(e)
        if hi is not None and hi - x[j] <= ACTIVE_TOL * max(1.0, abs(hi)):
            rows.append(-e)
    return rows


def stationarity(prob: TestProblem, x: Array) -> float:
    """``min ||grad f - sum lam_i a_i||_inf / max(1, ||grad f||_inf)`` over multipliers of the right sign."""
    x = np.asarray(x, dtype=float)
    g = np.asarray(prob.jac(x), dtype=float)
    eq_rows, ineq_rows, _ = _gradients(prob, x)
    rows = eq_rows + ineq_rows
    scale = max(1.0, float(np.max(np.abs(g))))
    if not rows:
        return float(np.max(np.abs(g))) / scale
    M = np.array(rows).T
    lo = np.concatenate([np.full(len(eq_rows), -np.inf), np.zeros(len(ineq_rows))])
    fit = lsq_linear(M, g, bounds=(lo, np.full(len(rows), np.inf)), method="bvls", tol=1e-14)
    return float(np.max(np.abs(M @ fit.x - g))) / scale


def judge(prob: TestProblem, x: Array, f: float | None = None) -> Verdict:
    """The verdict on ``x``: strict solved test, feasibility, independent KKT certificate."""
    x = np.asarray(x, dtype=float)
    if not np.all(np.isfinite(x)):
        return Verdict(False, False, False, np.inf, np.inf, np.inf)
    fx = float(prob.fun(x)) if f is None else float(f)
    maxcv = prob.max_violation(x)
    stat = stationarity(prob, x)
    return Verdict(
        solved=prob.is_solved(x, fx, maxcv),
        feasible=maxcv <= FEASIBILITY_TOL,
        kkt_point=stat <= KKT_TOL,
        maxcv=maxcv,
        stationarity=stat,
        f_error=(fx - prob.fstar) / max(1.0, abs(prob.fstar)),
    )
