"""The "structure limit": a minimal Newton–KKT solve of an equality-constrained program, written for the benchmarks.

What the problem's structure allows at least, against which every solver's time is read: plain Newton steps on the
KKT conditions ``grad f = J^T lam, c = 0`` from the same start, each one banded LU solve of the Lagrangian Hessian
``W = hess f - sum lam_i hess c_i`` (``scipy.linalg.solve_banded``, bandwidth read off ``W``) for ``m + 1``
right-hand sides and an ``m x m`` dense Schur complement for the ``m`` constraint rows. No globalisation (line
search, convexification, working set), no checks beyond the KKT test: it is the cost floor of a solver that already
knew it would converge from this start, not a solver. Applies to equality-only programs (the contact scenes); the
answer must be the one the solvers reach (the benchmarks judge it like any other).
"""

from __future__ import annotations

import time
from typing import Any

import numpy as np
import scipy.sparse as sp
from _problems import Problem, as_dicts, dense
from scipy.linalg import solve_banded

#: KKT tolerance: scaled stationarity and absolute feasibility (``tol`` of ours and of the peers).
TOL = 1e-8
#: Newton steps before giving up (it converges in 3-5 from the formulation's start).
MAX_ITER = 50


def applicable(problem: Problem) -> bool:
    """Whether every row of ``problem`` is an equality and there are no bounds."""
    return problem.bounds is None and all(c["type"] == "eq" for c in as_dicts(problem, with_hess=True))


def _banded(W: Any) -> tuple[int, np.ndarray]:
    """``(b, ab)``: the bandwidth of ``W`` and its diagonal-ordered storage for ``solve_banded((b, b), ab, ...)``."""
    coo = sp.coo_matrix(W)
    coo.sum_duplicates()  # (one entry per position: plain assignment below)
    offset = coo.row.astype(np.int64) - coo.col
    b = int(np.max(np.abs(offset), initial=0))
    ab = np.zeros((2 * b + 1, W.shape[0]))
    ab[b + offset, coo.col] = coo.data
    return b, ab


def run_structure_limit(problem: Problem, *, tol: float = TOL, max_iter: int = MAX_ITER) -> dict[str, Any]:
    """Newton on the KKT conditions of the equality-only ``problem`` from ``problem.x0``; the result in the peers'
    format (``x``, ``f``, ``success``, ``message``, ``nit``, ``nfev``, ``time``: the Newton loop alone).

    Raises
    ------
    ValueError
        When ``problem`` has bounds or inequality rows (see :func:`applicable`) or no exact Hessians.
    """
    if not applicable(problem):
        raise ValueError("the structure limit is written for equality-only programs without bounds (contact "
                         "scenes); skip it on programs with walls or bounds.")
    cons = as_dicts(problem, with_hess=True)
    if problem.hess is None or any("hess" not in c for c in cons):
        raise ValueError("the structure limit needs exact Hessians of the objective and of every constraint.")
    funs = [c["fun"] for c in cons]
    jacs = [c["jac"] for c in cons]
    hesses = [c["hess"] for c in cons]
    sizes = [int(np.atleast_1d(f(problem.x0)).size) for f in funs]
    splits = np.cumsum(sizes)[:-1]

    def rows(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        c = np.concatenate([np.atleast_1d(f(x)) for f in funs])
        J = np.vstack([np.atleast_2d(dense(j(x))) for j in jacs])
        return c, J

    start = time.perf_counter()
    x = np.array(problem.x0, dtype=float)
    g = np.asarray(problem.jac(x), dtype=float)
    c, J = rows(x)
    lam = np.linalg.lstsq(J.T, g, rcond=None)[0]
    nit, converged = 0, False
    while nit < max_iter:
        W = sp.csc_matrix(problem.hess(x))
        for h, v in zip(hesses, np.split(lam, splits), strict=True):
            W = W - sp.csc_matrix(h(x, v))
        b, ab = _banded(W)
        try:
            sol = solve_banded((b, b), ab, np.column_stack((g, J.T)))
            w, X = sol[:, 0], sol[:, 1:]
            y = np.linalg.solve(J @ X, c - J @ w)
        except np.linalg.LinAlgError:  # a singular W or Schur complement: plain Newton has no step here
            break
        x = x - (w + X @ y)
        lam = -y
        nit += 1
        g = np.asarray(problem.jac(x), dtype=float)
        c, J = rows(x)
        stationarity = float(np.max(np.abs(g - J.T @ lam))) / max(1.0, float(np.max(np.abs(g))))
        if stationarity <= tol and float(np.max(np.abs(c))) <= tol:
            converged = True
            break
    elapsed = time.perf_counter() - start
    return {"x": x, "f": float(problem.fun(x)), "success": converged, "nit": nit, "nfev": nit + 1, "time": elapsed,
            "message": "KKT residuals below tol" if converged else (
                f"no KKT point in {max_iter} Newton steps" if nit == max_iter else
                f"singular KKT matrix at Newton step {nit + 1} (no globalisation: a limit, not a solver)")}
