"""Asking the qpsolvers backends for a QP's answer, and checking every answer before it is trusted.

:func:`solve_qp` asks each backend in turn (with its retries, :data:`sqp.backends.RETRY_QP_OPTIONS`) until one gives
an answer whose primal and dual residuals pass :data:`QP_RESIDUAL_TOL`; a backend's certificate of primal
infeasibility ends the search (the elastic QP of :mod:`sqp.subproblem` is the remedy for that). The QPs themselves
are assembled in :mod:`sqp.subproblem`.
"""

from __future__ import annotations

import contextlib
import os
import sys
import warnings
from collections.abc import Iterator, Sequence
from typing import Any

import numpy as np
import qpsolvers
import scipy.sparse as sp
from numpy.typing import NDArray

from sqp import backends as _backends
from sqp.backends import RETRY_QP_OPTIONS
from sqp.kkt import inf_norm

Array = NDArray[np.float64]

#: qpsolvers backends to ask in turn, each with its settings: the chosen one first, then the fallbacks.
Backends = Sequence[tuple[str, dict[str, Any]]]

#: A QP answer is trusted when its primal and dual residuals are below this, relative to the data's scale.
QP_RESIDUAL_TOL = 1e-6

#: What a QP backend raises when it fails a subproblem (qpsolvers' own errors; quadprog's ValueError on an indefinite
#: or inconsistent problem, numpy's LinAlgError, a C extension's RuntimeError, an overflow). Anything else, a
#: TypeError or an AttributeError say, is a bug of this package and is not dressed up as "QP failed".
BACKEND_ERRORS: tuple[type[Exception], ...] = (qpsolvers.QPError, ValueError, ArithmeticError, RuntimeError)


def _prepare(solver: str, P: Any, G: Any, E: Any) -> tuple[Any, Any, Any]:
    """Dense arrays for dense-only backends, CSC for sparse ones. PIQP and ProxQP have both kinds of backend: they
    get CSC when the model Hessian is sparse (the large case), dense arrays otherwise (faster for small QPs)."""
    if solver in qpsolvers.sparse_solvers and (solver not in ("piqp", "proxqp") or sp.issparse(P)):
        conv = lambda M: None if M is None else sp.csc_matrix(M)  # noqa: E731
    else:
        conv = lambda M: None if M is None else (M.toarray() if sp.issparse(M) else np.asarray(M))  # noqa: E731
    # (DAQP keeps a CholeskyHessian's factor: sqp.backends solves a large QP in the factor's coordinates)
    return P if solver == "daqp" and isinstance(P, np.ndarray) else conv(P), conv(G), conv(E)


def solve_qp(
    backends: Backends, P: Any, q: Array, G: Any, h: Array, E: Any, e: Array, lb: Array | None, ub: Array | None,
    initvals: Array | None, scale: float,
) -> tuple[qpsolvers.Solution | None, str]:
    """Ask each backend in turn (with its retries) until one gives an answer that passes the residual check.

    Returns the trusted solution and the backend's name, or ``(None, reason)``; a certified infeasibility ends the
    search at once (the elastic QP is the remedy for that, not another backend).
    """
    reason = "QP failed"
    for solver, options in backends:
        Ps, Gs, Es = _prepare(solver, P, G if G.shape[0] else None, E if E.shape[0] else None)
        problem = qpsolvers.Problem(Ps, q, Gs, h if Gs is not None else None, Es, e if Es is not None else None,
                                    lb, ub)
        for retry in [{}, *RETRY_QP_OPTIONS.get(solver, [])]:
            try:
                quiet = _silence_c_stdout() if solver == "osqp" else contextlib.nullcontext()
                with warnings.catch_warnings(), quiet:
                    warnings.simplefilter("ignore")
                    sol = _backends.solve_problem(problem, solver=solver, initvals=initvals,
                                                  **{**options, **retry})
            except BACKEND_ERRORS:  # a backend's error is a failed subproblem; any other is our bug, and propagates
                sol = None
            if not isinstance(sol, qpsolvers.Solution):
                sol = None  # nothing usable came back
            if _trusted(sol, scale):
                return sol, solver
            if sol is not None and _declared_infeasible(sol):
                return None, "QP infeasible"
            if sol is not None and _ran_out(solver, sol):
                break  # (not retried: the next backend is asked, see _ran_out)
    return None, reason


def _declared_infeasible(sol: qpsolvers.Solution) -> bool:
    """Whether the backend certified primal infeasibility (no point in retrying with looser tolerances, nor in
    asking the next backend): OSQP's and PIQP's ``info.status``, Clarabel's ``status`` (``PrimalInfeasible``, not
    ``AlmostPrimalInfeasible``); a dual infeasibility is not one. DAQP's exit flag -1 is not trusted as a
    certificate: it also ends elastic QPs, which are feasible by construction (a contradictory pair of equalities,
    tests/sqp/test_faults.py). Measured on the aortic arch's cold solve at 250 bars: Clarabel's two attempts at each
    of 9 inconsistent QPs cost 0.6 s of 1.8 s."""
    extras = sol.extras if isinstance(sol.extras, dict) else {}
    status = str(getattr(extras.get("info"), "status", "") or extras.get("status", "")).lower()
    return "infeasible" in status and "inaccurate" not in status and "almost" not in status and "dual" not in status


def _ran_out(solver: str, sol: qpsolvers.Solution) -> bool:
    """Whether an interior-point backend stopped at its iteration limit (PIQP's ``info.status``): it is not retried.
    A looser tolerance follows the same iterates (measured on the guidewire's vessels at 1 600-3 200 bars: 20 of 20
    such retries failed, 2.9 s of the solves' 17 s); iterative refinement of its KKT solves does change them, but
    rescued one QP of the vessels' cold solves at 3 200 bars and doubled the cost of every failed QP of a 3-D solve
    whose linearisations stayed inconsistent (271 QPs in the J wire's helix at 100 mm: 4.9 → 14.3 s)."""
    if solver != "piqp":
        return False
    extras = sol.extras if isinstance(sol.extras, dict) else {}
    return "max_iter" in str(getattr(extras.get("info"), "status", "")).lower()


@contextlib.contextmanager
def _silence_c_stdout() -> Iterator[None]:
    """Redirect the process's stdout file descriptor to /dev/null (OSQP's C code prints
    "Polishing not needed" unconditionally)."""
    try:
        fd = sys.__stdout__.fileno() if sys.__stdout__ is not None else 1
    except (AttributeError, OSError, ValueError):
        yield
        return
    sys.stdout.flush()
    saved = os.dup(fd)
    devnull = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(devnull, fd)
        yield
    finally:
        os.dup2(saved, fd)
        os.close(saved)
        os.close(devnull)


def _trusted(sol: qpsolvers.Solution | None, scale: float) -> bool:
    if sol is None or not sol.found or sol.x is None or not np.isfinite(sol.x).all():
        return False
    try:
        with np.errstate(all="ignore"):  # (an overflowing answer fails the test below; no warning for it)
            prim, dual = _residuals(sol)
    except (ValueError, ArithmeticError):  # an answer of the wrong shape, or overflowing
        return False
    return bool(np.isfinite(prim) and np.isfinite(dual) and prim <= QP_RESIDUAL_TOL * scale
                and dual <= QP_RESIDUAL_TOL * scale)


def _residuals(sol: qpsolvers.Solution) -> tuple[float, float]:
    """qpsolvers' ``primal_residual()`` and ``dual_residual()`` of a found solution, the same numbers by the same
    operations in the same order, in one pass over the problem (a third of their cost on small QPs):
    ``max(0, [G x - h]^+, ||A x - b||_inf, [lb - x]^+, [x - ub]^+)`` and ``||P x + q + G^T z + A^T y + z_box||_inf``
    (``inf`` when a multiplier the problem needs is missing)."""
    qp, x = sol.problem, sol.x
    prim = 0.0
    r = qp.P.dot(x) + qp.q
    if qp.G is not None:
        prim = max(prim, float(np.max(qp.G.dot(x) - qp.h)))
        r = r + qp.G.T.dot(sol.z) if sol.z is not None else None
    if qp.A is not None:
        prim = max(prim, float(np.max(np.abs(qp.A.dot(x) - qp.b))))
        r = None if r is None or sol.y is None else r + qp.A.T.dot(sol.y)
    if qp.lb is not None:
        prim = max(prim, float(np.max(qp.lb - x)))
    if qp.ub is not None:
        prim = max(prim, float(np.max(x - qp.ub)))
    if qp.lb is not None or qp.ub is not None:
        r = None if r is None or sol.z_box is None else r + sol.z_box
    return prim, (np.inf if r is None else inf_norm(r))
