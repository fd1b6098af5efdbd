"""Feasibility restoration: the least violation of the nonlinear rows, found as a problem of its own.

When the SQP iteration ends INFEASIBLE, its last iterate is only where the elastic steps stopped making progress, not
necessarily where the violation is least. The restoration problem

    min  sum(p + q)   over (x, p, q)
    s.t. lb <= c(x) + p - q <= ub,   p, q >= 0,   the linear rows and the bounds on x,

always feasible, has the local minimisers of the L1 violation ``sum_i v_i(x)`` for its x-parts (with ``p, q`` the
violations below and above), and its KKT conditions are those of the violation: multipliers in [0, 1] on the rows
(Fletcher & Leyffer's filter SQP and SNOPT's elastic mode restore feasibility the same way). Solved by this engine
from the least-violation iterate, its answer is a point the message, ``x`` and ``maxcv`` of the result can all
describe, certified by the restoration's own KKT test.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray
from scipy.optimize import LinearConstraint, NonlinearConstraint

from sqp.build import build_problem
from sqp.iterate import Evaluator, Point
from sqp.options import Options
from sqp.problem import Problem
from sqp.result import Result

Array = NDArray[np.float64]


@dataclass(frozen=True)
class Restoration:
    """The restoration problem's answer: ``x``, the L1 violation ``violation = sum_i v_i(x)`` of the nonlinear rows
    there, whether the restoration solve certified ``x`` a KKT point of the violation (``stationary``), and its
    result (``result``, for its counts)."""

    x: Array
    violation: float
    stationary: bool
    result: Result


def least_violation(problem: Problem, ev: Evaluator, x: Array, options: Options,
                    solve: Callable[[Problem, Options], Result]) -> Restoration:
    """Minimise the L1 violation of ``problem``'s nonlinear rows from ``x`` (keeping its linear rows and bounds), by
    ``solve`` (the engine's run, given to avoid an import cycle) with ``options`` (restart off, no callback). User
    functions are called through ``ev``, so their evaluations count in the solve's totals."""
    n, rows = problem.n, problem.nonlinear
    m = rows.lb.size
    cache: dict[str, Point] = {}

    def at(z: Array) -> Point:
        pt = cache.get("pt")
        if pt is None or not np.array_equal(pt.x, z[:n]):
            pt = cache["pt"] = ev.point(np.array(z[:n]))
        return pt

    def values(z: Array) -> Array:
        return at(z).c + z[n:n + m] - z[n + m:]

    def jacobian(z: Array) -> Any:
        J = ev.derivatives(at(z)).J
        if sparse:  # (the slacks' columns are an identity: sparse whenever J is, or the dense block would be large)
            eye = sp.identity(m, format="csr")
            return sp.hstack([sp.csr_matrix(J), eye, -eye], format="csr")
        return np.hstack([np.asarray(J), np.eye(m), -np.eye(m)])

    sparse = problem.sparse_jacobians and bool(problem.blocks) or n + 2 * m > problem.dense_limit
    start = ev.point(np.asarray(x, dtype=float))
    below = np.maximum(rows.lb - start.c, 0.0)
    above = np.maximum(start.c - rows.ub, 0.0)
    z0 = np.concatenate([start.x, below, above])
    cost = np.concatenate([np.zeros(n), np.ones(2 * m)])
    constraints: list[object] = [NonlinearConstraint(values, rows.lb, rows.ub, jac=jacobian)]
    if problem.linear.lb.size:
        A = problem.A
        wide = (sp.hstack([sp.csr_matrix(A), sp.csr_matrix((A.shape[0], 2 * m))], format="csr") if sparse
                else np.hstack([A.toarray() if sp.issparse(A) else np.asarray(A), np.zeros((A.shape[0], 2 * m))]))
        constraints.append(LinearConstraint(wide, problem.linear.lb, problem.linear.ub))
    bounds = list(zip(np.concatenate([problem.lower, np.zeros(2 * m)]),
                      np.concatenate([problem.upper, np.full(2 * m, np.inf)]), strict=True))
    restoration = build_problem(lambda z: float(cost @ z), z0, lambda z: cost, bounds, constraints,
                                dense_limit=problem.dense_limit)
    res = solve(restoration, options)
    xr = np.asarray(res.x[:n], dtype=float)
    return Restoration(x=xr, violation=float(np.sum(ev.point(xr).v)), stationary=bool(res.success), result=res)
