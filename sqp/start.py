"""Where a solve starts: the checked initial Hessian ``hess0`` and a start point that satisfies the bounds and the
linear rows.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from sqp.options import Options
from sqp.problem import Problem
from sqp.result import Status
from sqp.subproblem import linearise, solve_subproblem

Array = NDArray[np.float64]


def initial_hessian(hess0: Any, n: int) -> Any:
    """Validate ``hess0``, the start of the damped-BFGS matrix (dense: the updates fill it; a sparse one is made
    dense whatever its size); check it for positive definiteness and shift it if merely semidefinite."""
    if hess0 is None:
        return None
    H = np.asarray(hess0.toarray() if hasattr(hess0, "toarray") else hess0, dtype=float)
    if H.shape != (n, n):
        raise ValueError(f"hess0 has shape {H.shape}; expected ({n}, {n}).")
    if not np.all(np.isfinite(H)):
        raise ValueError("hess0 has non-finite entries.")
    if not np.allclose(H, H.T, rtol=1e-10, atol=1e-12 * max(1.0, float(np.max(np.abs(H))))):
        raise ValueError("hess0 is not symmetric; pass a symmetric matrix (e.g. (H + H.T) / 2).")
    H = 0.5 * (H + H.T)
    scale = max(1.0, float(np.max(np.abs(H))))
    try:
        np.linalg.cholesky(H - 1e-8 * scale * np.eye(n))  # positive definite with margin: nothing to shift
        return H
    except np.linalg.LinAlgError:
        pass
    lam_min = float(np.linalg.eigvalsh(H)[0])
    if lam_min < -1e-8 * scale:
        raise ValueError(f"hess0 has a negative eigenvalue {lam_min:.3g}; it must be positive semidefinite.")
    if lam_min < 1e-8 * scale:
        H = H + (1e-8 * scale - min(lam_min, 0.0)) * np.eye(n)
    return H


def start_point(problem: Problem, options: Options) -> tuple[Array, Status | None, str]:
    """Clip ``x0`` into the bounds; project it onto the linear rows when they are violated.

    When that projection (a QP) fails, an LP decides between LINEAR_INFEASIBLE and a failure of the QP backends."""
    x = np.clip(problem.x0, problem.lower, problem.upper) if problem.has_bounds else problem.x0.copy()
    if problem.linear.lb.size == 0 or np.max(problem.linear.violation(problem.A @ x), initial=0.0) <= 1e-12:
        return x, None, ""
    n = problem.n
    empty = linearise(np.zeros((0, n)), np.zeros(0), problem.nonlinear.__class__.from_bounds(np.zeros(0), np.zeros(0)))
    lin = linearise(problem.A, problem.A @ x, problem.linear)
    qp = solve_subproblem(np.eye(n), np.zeros(n), empty, lin, problem.lower - x, problem.upper - x,
                          backends=options.backends)
    if qp.found:
        return np.clip(x + qp.d, problem.lower, problem.upper), None, ""
    if qp.status == "QP infeasible" or not linear_rows_consistent(problem):
        return x, Status.LINEAR_INFEASIBLE, ""
    return x, Status.QP_FAILED, (f"Backends tried: {', '.join(name for name, _ in options.backends)} (on the "
                                 "projection of x0 onto the linear constraints, which have a common point).")


def linear_rows_consistent(problem: Problem) -> bool:
    """Whether the linear rows and bounds have a common point, by a feasibility LP (HiGHS); True unless the LP
    certifies infeasibility."""
    from scipy.optimize import linprog

    rows, A = problem.linear, problem.A
    A_ub = sp.vstack([A[rows.upper], -A[rows.lower]]) if sp.issparse(A) else np.vstack([A[rows.upper], -A[rows.lower]])
    b_ub = np.concatenate([rows.ub[rows.upper], -rows.lb[rows.lower]])
    bounds = [(None if np.isinf(lo) else lo, None if np.isinf(hi) else hi)
              for lo, hi in zip(problem.lower, problem.upper, strict=True)]
    res = linprog(np.zeros(problem.n), A_ub=A_ub if b_ub.size else None, b_ub=b_ub if b_ub.size else None,
                  A_eq=A[rows.eq] if rows.eq.size else None, b_eq=rows.lb[rows.eq] if rows.eq.size else None,
                  bounds=bounds, method="highs")
    return res.status != 2
