"""The QP backends: which are installed, their settings, and the ``qp_solver="auto"`` policy.

The engine solves its subproblems through `qpsolvers <https://github.com/qpsolvers/qpsolvers>`_, so any installed
backend can be named; every call goes through :func:`solve_problem`, which asks DAQP directly for dense data (the
same call qpsolvers makes, without its per-call layer). ``"auto"`` (the default) picks one from the model's
structure, once per solve, by the rule of :func:`choose_qp_solver`; every measurement behind it is quoted there.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import qpsolvers
from scipy.linalg import lapack

from sqp.hessian import DENSE_LIMIT

#: Backend settings that make the subproblem accurate enough for the multipliers the merit function and the
#: BFGS update depend on (OSQP's defaults, eps 1e-3 without polishing, are far too loose for SQP).
DEFAULT_QP_OPTIONS: dict[str, dict[str, Any]] = {
    "osqp": {"eps_abs": 1e-9, "eps_rel": 1e-9, "polishing": True, "polish_refine_iter": 5, "max_iter": 4000,
             "eps_prim_inf": 1e-7, "eps_dual_inf": 1e-7},
    "proxqp": {"eps_abs": 1e-10, "eps_rel": 0.0, "max_iter": 1000},
    # PIQP's iteration limit (its default 250): on the guidewire's full-space vessel subproblems (960-2400 variables)
    # the QPs it solves take 17-94 iterations (median ~27), and the ones it cannot (a large augmented-Lagrangian
    # weight) ran to the limit twice (with the looser retry) before Clarabel answered: 8.2 of 9.2 s of a tortuous
    # solve at 400 bars; at 100 the same QPs are solved and the failures cost 0.4 of their time.
    # Its Ruiz equilibration (``preconditioner_iter``, default 10 passes): on the compressed vessel programs at
    # 1 600-3 200 bars (9 600 variables, model Hessian diagonal 3e3-8e7) the QPs it could not solve stalled at a dual
    # residual ~1e-2 for all 100 iterations; with 3 passes (0 about as well) they are solved in 14-29 iterations: of 116
    # full-space QPs captured from the shipped vessels' cold solves at 400-3 200 bars, 101 → 114 solved, their time
    # 5.9 → 3.8 s; the ones solved either way take about as many iterations
    "piqp": {"eps_abs": 1e-10, "eps_rel": 1e-12, "max_iter": 100, "preconditioner_iter": 3},
    "clarabel": {"tol_gap_abs": 1e-10, "tol_gap_rel": 1e-10, "tol_feas": 1e-10},
    # DAQP's default primal tolerance (1e-6, absolute) leaves rows of the linearisation violated up to 1e-6: near a
    # solution that is the whole violation the step should remove, and such a step can be no descent direction of
    # the merit function (a finite-difference solve of scipy's inconsistent-linearisation problem ended LINE_SEARCH
    # from 8 of 40 starts; 1 at 1e-9, 0 at 1e-10, where HS13 is lost: 1e-9 keeps Hock–Schittkowski at 118 solved).
    # Its iteration limit (its default 10 000): the QPs it solves take at most 81 iterations over Hock–Schittkowski,
    # the paper scenes and the shipped vessels, 236 on the aortic arch at 211 bars, where three elastic QPs (633
    # variables, a singular Hessian DAQP regularises) ran to 10 000 iterations and failed after 10 s each
    "daqp": {"primal_tol": 1e-9, "iter_limit": 2000},
    "quadprog": {},
}

#: Settings added to a backend's for an elastic QP (:mod:`sqp.subproblem`) of more than :data:`DENSE_LIMIT`
#: variables, whose slack variables carry no curvature but a regularisation ``1e-10 max|B_ii|``: DAQP's default
#: (``eps_prox < 0``: regularise only where its Cholesky factorisation fails) factors that nearly singular block as it
#: stands and can spend seconds an iteration near the end; its proximal iteration (``eps_prox > 0``) solves the same
#: QP. Measured on the aortic arch's cold solve at 216 bars: an elastic QP of 759 variables and 543 rows 16.3 s →
#: 0.40 s, the same answer to 5e-12 (Clarabel's within its tolerance, 0.66 s). The small elastic QPs of the
#: Hock–Schittkowski problems (tens of variables, solved in microseconds either way) keep DAQP's default: there the
#: proximal iterates end a few ulps away (HS61, HS63), and HS109 took 148 function evaluations instead of 173.
ELASTIC_QP_OPTIONS: dict[str, dict[str, Any]] = {"daqp": {"eps_prox": 1e-6}}


def elastic_backends(
    backends: Sequence[tuple[str, dict[str, Any]]], variables: int
) -> Sequence[tuple[str, dict[str, Any]]]:
    """``backends`` (name, settings) as an elastic QP of ``variables`` variables asks them: with
    :data:`ELASTIC_QP_OPTIONS` above :data:`DENSE_LIMIT` variables."""
    if variables <= DENSE_LIMIT:
        return backends
    return [(name, {**settings, **ELASTIC_QP_OPTIONS.get(name, {})}) for name, settings in backends]

#: When a backend's answer is not found (OSQP: "solved inaccurate" at the tight default), it is asked again with these
#: looser tolerances; the answer is still only used if it passes the residual check
#: (:data:`sqp.qp_call.QP_RESIDUAL_TOL`).
RETRY_QP_OPTIONS: dict[str, list[dict[str, Any]]] = {
    "osqp": [{"eps_abs": 1e-7, "eps_rel": 1e-7}, {"eps_abs": 1e-5, "eps_rel": 1e-5, "max_iter": 20000}],
    "proxqp": [{"eps_abs": 1e-7}],
    # (PIQP: its stalls are not tolerance-bound, a looser one stalls alike, and one run out of iterations is not
    # retried at all, :func:`sqp.qp_call._ran_out`; iterative refinement of every KKT solve, for its other failures)
    "piqp": [{"iterative_refinement_always_enabled": True}],
    "clarabel": [{"tol_gap_abs": 1e-7, "tol_gap_rel": 1e-7, "tol_feas": 1e-7}],
}

#: The name that asks the engine to choose the backend (:func:`choose_qp_solver`).
AUTO = "auto"

#: Order in which ``"auto"`` falls back when the backend its rule picks is not installed: measured accuracy and speed
#: on the subproblems first (DAQP, then the sparse interior-point PIQP and Clarabel), then OSQP (loose multipliers),
#: quadprog (dense, no warm start) and ProxQP (slowest sparse backend measured).
PREFERENCE: tuple[str, ...] = ("daqp", "piqp", "clarabel", "osqp", "quadprog", "proxqp")


def installed_solvers() -> list[str]:
    """The qpsolvers backends installed here."""
    return list(qpsolvers.available_solvers)


def check_solver_name(name: str) -> None:
    """Raise ``ValueError`` naming the installed backends (and ``"auto"``) when ``name`` is neither of them."""
    if name != AUTO and name not in qpsolvers.available_solvers:
        raise ValueError(f"qp_solver={name!r} is not an installed qpsolvers backend; pass {AUTO!r} (the default: "
                         f"chosen by problem size and sparsity) or one of the installed: "
                         f"{', '.join(qpsolvers.available_solvers)}.")


def auto_choice(n: int, sparse_jacobians: bool, installed: list[str] | None = None,
                dense_limit: int = DENSE_LIMIT) -> tuple[str, str]:
    """What ``qp_solver="auto"`` picks for a model with ``n`` variables, and why (for the verbose header).

    See :func:`choose_qp_solver` for the rule; ``installed`` defaults to :func:`installed_solvers`, ``dense_limit``
    (the most variables the engine works densely at, :attr:`sqp.problem.Problem.dense_limit`) to
    :data:`DENSE_LIMIT`.
    """
    installed = installed_solvers() if installed is None else installed
    limit = "DENSE_LIMIT" if dense_limit == DENSE_LIMIT else "dense_limit"
    if n <= dense_limit:
        name, why = "daqp", f"n = {n} <= {limit} = {dense_limit}: dense active set"
    elif sparse_jacobians:
        name, why = "piqp", f"n = {n} > {limit} = {dense_limit}, every constraint Jacobian sparse"
    else:
        name, why = "daqp", f"n = {n} > {limit} = {dense_limit}, dense constraint rows: dense active set"
    if name in installed:
        return name, why
    for other in PREFERENCE:
        if other in installed:
            return other, f"{why}; {name} is not installed"
    raise ValueError(f"qp_solver='auto' found none of {', '.join(PREFERENCE)} installed; install one "
                     "(pip install daqp) or name an installed qpsolvers backend.")


def choose_qp_solver(n: int, sparse_jacobians: bool, installed: list[str] | None = None) -> str:
    """The backend ``qp_solver="auto"`` uses, chosen once per solve from the model's structure.

    Rule (it reproduces the choices the guidewire package made by hand, so no solve changed):

    1. ``n <= DENSE_LIMIT`` (300) variables: ``"daqp"``, a dense dual active-set method. The engine works densely
       there (:data:`sqp.hessian.DENSE_LIMIT`), and on the Hock–Schittkowski subproblems DAQP was both the most
       accurate backend (exact active sets and multipliers: 115 of 124 problems solved, OSQP 113) and the fastest
       (2.8x OSQP per problem, shifted geometric mean; ``benchmarks/results/hock_schittkowski.md``).
    2. More variables and every constraint Jacobian sparse (each nonlinear ``jac`` at ``x0`` and each
       ``LinearConstraint.A`` a scipy.sparse matrix; :attr:`sqp.problem.Problem.sparse_jacobians`): ``"piqp"``,
       whose sparse interior-point backend took 10-20 ms per subproblem on the guidewire's full-space program at
       1600 bars (4800 variables, 3200 equalities, 1600 wall rows), where Clarabel took 50 ms, OSQP did not converge
       in 4000 iterations and ProxQP's sparse backend took minutes.
    3. More variables with some dense Jacobian rows: ``"daqp"`` again. Such a program is dense anyway (the
       guidewire's reduced program, where every wall or lumen row involves all the bar angles before its node), and
       a sparse interior-point method pays for the density at every one of its iterations: the paper's wall scenes
       (Fig. 6a/6b) at 400 and 800 bars solved in 0.05-0.27 s with DAQP against 1.6-19.4 s with Clarabel (same
       iterations, energies equal to 3e-8), the S-bend vessel at 400 bars in 4.7 s against 94 s.

    If the backend picked is not installed, the first installed one of :data:`PREFERENCE` is used.

    Parameters
    ----------
    n : int
        Number of variables.
    sparse_jacobians : bool
        Whether every constraint Jacobian is sparse (True without constraints).
    installed : list of str, optional
        The installed backends; default :func:`installed_solvers`.
    """
    return auto_choice(n, sparse_jacobians, installed)[0]


try:
    import daqp as _daqp_module
except ImportError:  # pragma: no cover - DAQP not installed: qpsolvers reports it
    _daqp_module = None

#: DAQP's bound for a side that is absent (qpsolvers' DAQP interface uses the same).
_DAQP_INFINITY = 1e30

#: DAQP's sense flag of an equality row.
_DAQP_EQUALITY = 5


def solve_problem(problem: qpsolvers.Problem, solver: str, initvals: Any = None, **options: Any) -> Any:
    """``qpsolvers.solve_problem(problem, solver, initvals=initvals, **options)``: the one place the engine asks a
    backend for an answer.

    DAQP with dense matrices is called directly (:func:`_daqp`): the same ``daqp.solve`` call with the same arrays
    and settings as qpsolvers' DAQP interface, and the same :class:`qpsolvers.Solution` back, with less per-call
    work around it. Every other backend, and DAQP given sparse matrices, goes through qpsolvers.

    Returns
    -------
    qpsolvers.Solution
        The backend's answer (``found`` False when it found none).
    """
    if (solver == "daqp" and _daqp_module is not None and isinstance(problem.P, np.ndarray)
            and (problem.G is None or isinstance(problem.G, np.ndarray))
            and (problem.A is None or isinstance(problem.A, np.ndarray))):
        return _daqp(problem, initvals, **options)
    return qpsolvers.solve_problem(problem, solver=solver, initvals=initvals, **options)


#: From this many variables (and without bounds on them) a dense QP goes to DAQP in the coordinates of the Hessian's
#: Cholesky factor ``P = L L^T`` (``u = L^T x``: identity Hessian, rows ``G L^-T`` by one LAPACK triangular solve),
#: the factor reused when the model Hessian carries it (:class:`sqp.hessian.CholeskyHessian`). DAQP's own set-up
#: (its factorisation and ``G L^-T`` without BLAS) is then skipped: measured, random QPs with 3n/4 rows as fast at
#: 25 variables, 1.7x at 50, 2.4x at 100, 3x at 200 (core-pinned, same x to 2e-15); the guidewire's Fig. 6a at
#: 200 bars (152 wall rows) 2.32 -> 0.45 ms per QP. Below it DAQP is called as it is (the Hock–Schittkowski
#: problems: at most 16 variables).
LDP_MIN_VARIABLES = 40


def _ldp_factor(P: np.ndarray, n: int, bounded: int, equalities: int) -> np.ndarray | None:
    """The lower Cholesky factor of ``P`` for DAQP's factor coordinates (:data:`LDP_MIN_VARIABLES`), or None: too
    few variables, bounds on them (they would become dense rows), many equality rows (more than ``n / 8``:
    measured at 200 variables and 150 inequality rows, 2.4x faster with 4 or 20 equality rows, even at 50–100,
    slower at 150, where DAQP's own reduction of the equalities wins), or ``P`` not positive definite."""
    if n < LDP_MIN_VARIABLES or bounded or 8 * equalities > n:
        return None
    L = getattr(P, "cholesky", None)
    if L is not None:
        return L
    L, info = lapack.dpotrf(P, lower=1, clean=1)
    return L if info == 0 else None


def _daqp(problem: qpsolvers.Problem, initvals: Any, **options: Any) -> qpsolvers.Solution:
    """qpsolvers' ``daqp_solve_problem`` for dense data: rows ordered bounds, ``G x <= h``, ``A x = b`` (sense 5),
    absent sides at :data:`_DAQP_INFINITY`, multipliers split back into ``z_box``, ``z`` and ``y``."""
    P, q = problem.P, problem.q
    data = _DaqpRows.of(problem)
    L = _ldp_factor(P, q.size, data.ms, data.meq)
    if L is None:
        x, obj, exitflag, info = _daqp_module.solve(P, q, data.rows, data.upper, data.lower, data.sense,
                                                    primal_start=initvals, **options)
    else:  # in u = L^T x: min 1/2 |u|^2 + (L^-1 q)^T u, rows (rows L^-T) u, the same bounds and multipliers
        # (a new identity each call: DAQP takes its arrays writable)
        start = None if initvals is None else L.T @ initvals
        rows = data.rows
        rows_u = np.ascontiguousarray(lapack.dtrtrs(L, rows.T, lower=1)[0].T) if rows.shape[0] else rows
        u, obj, exitflag, info = _daqp_module.solve(np.eye(q.size), lapack.dtrtrs(L, q, lower=1)[0], rows_u,
                                                    data.upper, data.lower, data.sense, primal_start=start, **options)
        x = lapack.dtrtrs(L, u, lower=1, trans=1)[0] if exitflag > 0 else u
    sol = qpsolvers.Solution(problem)
    sol.found = exitflag > 0
    if sol.found:
        lam = info["lam"]
        ms, mineq = data.ms, data.mineq
        sol.x, sol.obj = x, obj
        sol.z_box, sol.z, sol.y = lam[:ms], lam[ms:ms + mineq], lam[ms + mineq:]
    return sol


@dataclass(frozen=True)
class _DaqpRows:
    """A QP's constraints in DAQP's layout: ``lower <= [I; G; A] x <= upper`` (the identity block only with bounds,
    ``ms`` rows), ``sense`` marking the equality rows, absent sides at :data:`_DAQP_INFINITY`."""

    rows: np.ndarray
    upper: np.ndarray
    lower: np.ndarray
    sense: np.ndarray
    ms: int
    mineq: int
    meq: int

    @classmethod
    def of(cls, problem: qpsolvers.Problem) -> _DaqpRows:
        _, q, G, h, A, b, lb, ub = problem.unpack()
        n = q.size
        ms = n if (lb is not None or ub is not None) else 0
        mineq = 0 if G is None else G.shape[0]
        meq = 0 if A is None else A.shape[0]
        m = ms + mineq + meq
        upper = np.empty(m)
        lower = np.full(m, -_DAQP_INFINITY)
        if ms:
            upper[:ms] = _DAQP_INFINITY if ub is None else ub
            if lb is not None:
                lower[:ms] = lb
        if mineq:
            upper[ms:ms + mineq] = h
        if meq:
            upper[ms + mineq:] = b
        if mineq and meq:
            rows = np.empty((mineq + meq, n))
            rows[:mineq] = G
            rows[mineq:] = A
        else:
            rows = G if mineq else A if meq else np.zeros((0, n))
        sense = np.zeros(m, dtype=np.intc)  # (DAQP's C int; numpy's intc, the fast spelling of ctypes.c_int)
        sense[ms + mineq:] = _DAQP_EQUALITY
        return cls(rows, upper, lower, sense, ms, mineq, meq)
