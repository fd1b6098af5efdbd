"""The SQP loop (paper §2.2) and the scipy-style front door :func:`minimize`.

One iteration: solve the QP (Eqs. 9–10; elastic if inconsistent) → test the KKT residuals → update the penalties
(Eq. 13) → backtrack on the L1 merit function (Eq. 12), with a second-order correction → damped BFGS (Eq. 6).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray
from scipy.optimize import OptimizeResult

from sqp.backends import AUTO, auto_choice
from sqp.build import build_problem
from sqp.hessian import DENSE_LIMIT, convexify, damped_bfgs_update, initial_scaling
from sqp.iterate import Derivatives, Evaluator, Point
from sqp.kkt import KKTResiduals, kkt_residuals, lagrangian_gradient, max_violation
from sqp.merit import ARMIJO, descent_penalty, directional_derivative, merit, next_step_length, update_penalty
from sqp.options import Options
from sqp.problem import Problem, format_point
from sqp.report import HEADER, format_row
from sqp.result import IterationRecord, Result, Status
from sqp.subproblem import LinearisedRows, QPStep, linearise, solve_subproblem

Array = NDArray[np.float64]

#: Smallest step length tried by the backtracking line search.
MIN_STEP_LENGTH = 1e-10
#: Scaled KKT level accepted as success (status ACCEPTABLE) when rounding errors stop progress towards ``tol``.
ACCEPTABLE_TOL = 1e-6
#: Consecutive steps below the rounding level of x (relative 1e-12) after which the solve stops.
STALL_ITERATIONS = 3
#: Largest price of a unit of slack in the elastic QP before a point is declared locally infeasible.
MAX_ELASTIC_PENALTY = 1e10


def minimize(
    fun: Callable[..., float],
    x0: Any,
    jac: Callable[..., Array] | str | None = None,
    bounds: Any = None,
    constraints: Any = (),
    *,
    args: tuple[Any, ...] = (),
    hess: Callable[..., Any] | None = None,
    hess0: Any = None,
    multipliers0: Any = None,
    qp_solver: str = "auto",
    qp_options: dict[str, Any] | None = None,
    tol: float = 1e-8,
    max_iter: int = 500,
    callback: Callable[[OptimizeResult], Any] | None = None,
    verbose: bool = False,
) -> Result:
    """Minimise ``fun(x)`` subject to bounds and constraints by SQP, as ``scipy.optimize.minimize`` does.

    Parameters
    ----------
    fun : callable
        Objective ``fun(x, *args) -> float``.
    x0 : array_like, shape (n,)
        Starting point. A start outside the bounds is projected onto them (clipped) with a
        :class:`~sqp.StartPointWarning` naming the variables (a start within rounding, ``1e-12 * max(1, |bound|)``,
        of a bound is clipped silently); a start violating the linear constraints is then projected onto them.
    jac : callable, '2-point' or None
        Gradient ``jac(x, *args) -> (n,)``; None or '2-point' for forward differences that stay inside the bounds.
    bounds : scipy.optimize.Bounds or sequence of (lo, hi), optional
        Variable bounds; ``None`` for an unbounded side.
    constraints : dict, NonlinearConstraint, LinearConstraint or a sequence of them
        SLSQP dicts ``{"type": "eq"|"ineq", "fun", "jac"}`` (``ineq`` means ``fun(x) >= 0``) and scipy constraint
        objects (rows with ``lb == ub`` are equalities). Linear constraints and bounds are kept exactly in every QP.
    args : tuple
        Extra arguments of ``fun``, ``jac`` and ``hess``.
    hess : callable, optional
        Exact objective Hessian ``hess(x, *args) -> (n, n)`` (array or sparse matrix). With it, every nonlinear
        constraint must carry its Hessian (``NonlinearConstraint.hess`` or a dict's ``"hess"``: ``hess(x, v) =
        sum_i v_i grad^2 c_i(x)``) and the model Hessian is the exact Lagrangian Hessian, shifted by a multiple of
        the identity where needed to make it positive definite, instead of damped BFGS.
    hess0 : array_like, shape (n, n), optional
        Initial Lagrangian Hessian approximation (e.g. the objective's known Hessian); symmetric, positive
        semidefinite (shifted to positive definite if needed). Default: identity, rescaled after the first step.
        Not used when ``hess`` is given (only its shape is checked then).
    multipliers0 : sequence of arrays, optional
        Starting multipliers, one array per constraint (e.g. ``res.constraint_multipliers`` of a neighbouring
        solve): the first exact Lagrangian Hessian and the first merit penalties use them (a warm start).
    qp_solver : str
        qpsolvers backend for the subproblems, or "auto" (default): chosen once from the problem's structure —
        "daqp" (dense active set) up to :data:`~sqp.DENSE_LIMIT` (300) variables, above it "piqp" when every
        constraint Jacobian is sparse and "clarabel" when some rows are dense (the rule, its measurements and why
        OSQP is not the default: :class:`sqp.Options`). Any installed backend by name (:func:`sqp.installed_solvers`)
        is used exactly as given. The backend used is ``res.qp_solver``.
    qp_options : dict, optional
        Backend settings merged over the engine's accurate defaults.
    tol : float
        Tolerance on the scaled KKT residuals and on the absolute constraint violation.
    max_iter : int
        Maximum number of iterations.
    callback : callable, optional
        ``callback(intermediate_result)`` after each iteration; raise ``StopIteration`` to stop (status CALLBACK).
    verbose : bool
        Print an iteration table.

    Returns
    -------
    Result
        An ``OptimizeResult`` with ``x, fun, jac, success, status, message, nit, nfev, njev, maxcv`` plus
        ``constraint_multipliers``, ``bound_multipliers``, ``multipliers``, ``kkt``, ``history``, ``hess`` and
        ``qp_solver`` (the backend used).
        ``success`` is True only for SUCCESS and ACCEPTABLE; every other :class:`~sqp.Status` says why the solve
        ended: NaN or inf that persists down to the shortest trial step, or at the start, is NONFINITE (the message
        names the function and the iteration); a locally infeasible problem is INFEASIBLE (the message gives the
        least violation reached), LINEAR_INFEASIBLE when the linear constraints and bounds alone are inconsistent;
        QP_FAILED names the QP backends tried (``qp_solver``, then the fallbacks quadprog and osqp).

    Raises
    ------
    TypeError, ValueError
        On malformed input, before any iteration, naming the argument and the fix. ValueError also when a user
        function changes the size or shape of its output during the solve (naming it and the iteration).
    Exception
        Whatever ``fun``, ``jac``, ``hess``, a constraint's ``fun``/``jac``/``hess`` or ``callback`` raises
        (other than ``StopIteration`` from the callback) propagates unchanged, with a note (``add_note``) naming
        the function, the iteration and ``x``.

    Warns
    -----
    StartPointWarning
        When ``x0`` lies outside the bounds (it is projected onto them).
    """
    options = Options(tol=tol, max_iter=max_iter, qp_solver=qp_solver, qp_options=dict(qp_options or {}),
                      callback=callback, verbose=verbose)
    problem = build_problem(fun, x0, jac, bounds, constraints, args, hess)
    if problem.hess is not None and hess0 is not None:  # exact Hessians replace it: check the shape only
        if np.shape(hess0) != (problem.n, problem.n):
            raise ValueError(f"hess0 has shape {np.shape(hess0)}; expected ({problem.n}, {problem.n}).")
        B0 = None
    else:
        B0 = _initial_hessian(hess0, problem.n)
    lam0 = None if multipliers0 is None else problem.stack_nonlinear_multipliers(multipliers0)
    return run(problem, options, B0, lam0)


def _initial_hessian(hess0: Any, n: int) -> Any:
    """Validate ``hess0``. A large sparse one stays sparse (it is only the metric of an exact-Hessian solve then);
    a dense or small one is checked for positive definiteness and shifted if merely semidefinite."""
    if hess0 is None:
        return None
    if sp.issparse(hess0) and n > DENSE_LIMIT:
        H = sp.csc_matrix(hess0, dtype=float)
        if H.shape != (n, n):
            raise ValueError(f"hess0 has shape {H.shape}; expected ({n}, {n}).")
        if not np.all(np.isfinite(H.data)) or abs(H - H.T).max() > 1e-10 * max(1.0, abs(H).max()):
            raise ValueError("hess0 must be finite and symmetric.")
        return H
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


#: A solve ends without a confirming QP when the last QP's multipliers pass the KKT test at the new point with
#: ``CONFIRMED_TOLERANCE * tol`` (at ``tol`` itself it would stop one Newton step earlier than the confirming QP's
#: test and leave a residual near ``tol`` where that step would square it).
CONFIRMED_TOLERANCE = 1e-2


@dataclass
class _State:
    """The handful of values carried from one iteration to the next."""

    pt: Point
    der: Derivatives
    B: Array
    mu: Array
    qp: QPStep | None = None


def run(problem: Problem, options: Options, B0: Array | None = None, lam0: Array | None = None) -> Result:
    """Run the SQP iteration on a validated problem, with ``qp_solver="auto"`` resolved for it first."""
    why = auto_choice(problem.n, problem.sparse_jacobians)[1] if options.qp_solver == AUTO else ""
    options = options.for_problem(problem)
    if options.verbose:
        print(f"sqp: {problem.n} variables, qp_solver = {options.qp_solver}" + (f" (auto: {why})" if why else ""))
    res = _iterate(problem, options, B0, lam0)
    res.qp_solver = options.qp_solver
    return res


def _iterate(problem: Problem, options: Options, B0: Array | None, lam0: Array | None) -> Result:
    t_start = time.perf_counter()
    ev = Evaluator(problem)
    history: list[IterationRecord] = []
    x, status, detail = _start_point(problem, options)
    if status is not None:
        return _result(problem, ev, None, None, None, status, history, t_start, x=x, detail=detail)
    pt = ev.point(x)
    if not pt.finite:
        return _result(problem, ev, pt, None, None, Status.NONFINITE, history, t_start,
                       detail=_nonfinite_detail(ev, pt, None, "at the start point"))
    der = ev.derivatives(pt)
    if not der.finite:
        return _result(problem, ev, pt, der, None, Status.NONFINITE, history, t_start,
                       detail=_nonfinite_detail(ev, pt, der, "at the start point"))
    exact = problem.hess is not None
    scaled_start = B0 is None and not exact
    shift = al_weight = 0.0
    # (with exact Hessians B is replaced before its first use: no dense n x n identity for a large sparse problem)
    B_start = sp.identity(problem.n, format="csc") if exact else (
        np.eye(problem.n) if B0 is None or sp.issparse(B0) else B0.copy())
    st = _State(pt=pt, der=der, B=B_start,
                mu=np.zeros(problem.nonlinear.lb.size) if lam0 is None else np.abs(lam0))
    if options.verbose:
        print(HEADER)
    status = Status.MAX_ITER
    detail = ""
    rho = 0.0
    stalled = 0
    best: tuple[KKTResiduals, QPStep] | None = None
    least = (max_violation(problem, pt.x, pt.c, pt.r), pt.x)  # the least violation reached, and where
    for nit in range(options.max_iter + 1):
        ev.nit = nit + 1  # evaluations from here to the acceptance of the next point belong to iteration nit + 1
        if exact:  # the exact Lagrangian Hessian at (x_k, lam_{k-1}), made positive definite
            lam_prev = st.qp.lam_nl if st.qp is not None else (
                np.zeros(problem.nonlinear.lb.size) if lam0 is None else lam0)
            al_rows = _al_rows(problem, lam_prev)
            W = ev.lagrangian_hessian(st.pt.x, lam_prev)
            if ev.hessian_nonfinite is not None:
                status = Status.NONFINITE
                detail = f"{ev.hessian_nonfinite} returned NaN or inf at {ev.where} (x = {format_point(st.pt.x)})."
                break
            st.B, shift, al_weight = convexify(W, shift, _equality_rows(problem, st.der.J, al_rows), al_weight)
        # the QP subproblem (Eqs. 9–10), elastic when its linearisation is inconsistent
        qp, rho = _subproblem(problem, options, st, rho)
        if exact and al_weight > 0.0 and qp.found and not qp.elastic:
            qp = _newton_multipliers(problem, st, qp, al_rows, al_weight)
        if not qp.found:
            eye = sp.identity(problem.n, format="csc") if sp.issparse(st.B) else np.eye(problem.n)
            st.B = eye * max(1.0, float(np.mean(np.abs(st.B.diagonal()))))
            qp, rho = _subproblem(problem, options, st, rho)
            if not qp.found:
                status = Status.QP_FAILED
                detail = (f"Backends tried: {', '.join(name for name, _ in options.backends)} (last answer: "
                          f"{qp.status}) at iteration {nit}.")
                break
        st.qp = qp
        kkt = _kkt(problem, st)
        if stalled == 0 or best is None or kkt.worst < best[0].worst:  # best multipliers at this (stalled) point
            best = (kkt, qp)
        if kkt.satisfied(options.tol):
            status = Status.SUCCESS
            break
        if nit == options.max_iter:
            break
        d = qp.d
        if qp.elastic and not kkt.feasible(options.tol) and np.max(np.abs(d)) <= 1e-10 * (1 + np.max(np.abs(st.pt.x))):
            status = Status.INFEASIBLE  # no step reduces the linearised violation: a stationary point of it
            break
        # the penalties (Eq. 13) and the merit line search (Eq. 12)
        st.mu = update_penalty(st.mu, qp.lam_nl)
        if st.mu.size:
            rows = problem.nonlinear
            dv = float(np.sum(rows.violation(st.pt.c)) - np.sum(rows.violation(st.pt.c + st.der.J @ d)))
            st.mu = np.maximum(st.mu, descent_penalty(float(st.der.g @ d), float(d @ (st.B @ d)), dv))
        search = _line_search(problem, options, ev, st, d)
        if search.pt is None and np.max(st.mu, initial=0.0) > 10.0 * max(
                float(np.max(np.abs(qp.lam_nl), initial=0.0)), 1e-12):
            # penalties inflated by early, poorly scaled multipliers: restart them from the current ones (Eq. 13)
            st.mu = np.abs(qp.lam_nl)
            search = _line_search(problem, options, ev, st, d)
        if search.pt is not None and _negligible(st.pt.x, search.pt.x):
            stalled += 1
        else:
            stalled = 0
        if search.pt is None or stalled >= STALL_ITERATIONS:
            if search.pt is not None:
                status = Status.SMALL_STEP
            elif search.nonfinite is not None:
                status = Status.NONFINITE  # NaN or inf down to the shortest step tried
                detail = (f"{search.nonfinite} returned NaN or inf at every trial point of iteration {nit + 1} down "
                          f"to step length {search.alpha:.1e} (from x = {format_point(st.pt.x)}).")
            else:
                status = _stalled_status(problem, st, d)
            # (the multiplier estimates of the QPs solved while x stood still all belong to this point: the best one
            # decides; rounding makes them scatter around the limit on ill-conditioned problems such as HS116)
            assert best is not None
            kkt_best, qp_best = best
            if kkt_best.feasible(options.tol) and max(kkt_best.stationarity, kkt_best.complementarity) <= max(
                    ACCEPTABLE_TOL, options.tol):
                status, st.qp = Status.ACCEPTABLE, qp_best
            break
        new_pt, new_der, alpha, soc = search.pt, search.der, search.alpha, search.soc
        assert new_der is not None
        # the damped BFGS update (Eq. 6)
        s = new_pt.x - st.pt.x
        damped = False
        if not exact:
            y = _lagrangian_gradient(problem, new_der, qp) - _lagrangian_gradient(problem, st.der, qp)
            if scaled_start and nit == 0:
                st.B = st.B * initial_scaling(s, y)
            st.B, damped = damped_bfgs_update(st.B, s, y)
        st.pt, st.der = new_pt, new_der
        rec = IterationRecord(
            nit=nit + 1, nfev=ev.nfev, f=new_pt.f, maxcv=max_violation(problem, new_pt.x, new_pt.c, new_pt.r),
            kkt=kkt.worst, step=float(np.max(np.abs(s), initial=0.0)), alpha=alpha,
            penalty=float(np.max(st.mu, initial=0.0)), qp_status=qp.status, damped=damped, soc=soc,
        )
        history.append(rec)
        if rec.maxcv < least[0]:
            least = (rec.maxcv, new_pt.x)
        if options.verbose:
            print(format_row(rec))
        if options.callback is not None:
            try:
                options.callback(OptimizeResult(x=new_pt.x.copy(), fun=new_pt.f, nit=nit + 1, nfev=ev.nfev,
                                                maxcv=rec.maxcv, kkt=rec.kkt))
            except StopIteration:
                status = Status.CALLBACK
                break
            except Exception as exc:
                exc.add_note(f"sqp.minimize: raised by callback at iteration {nit + 1} "
                             f"(x = {format_point(new_pt.x)}).")
                raise
        # the QP's multipliers are those of the new point to second order near a solution (Newton–SQP): when they
        # already satisfy the KKT test there with a wide margin, and every row they load is active there, the next
        # Hessian and QP would only confirm it
        early = CONFIRMED_TOLERANCE * options.tol
        if _kkt(problem, st).satisfied(early) and _loaded_rows_active(problem, st, early):
            status = Status.SUCCESS
            break
    if status is Status.INFEASIBLE:
        detail = f"Least violation reached: {least[0]:.2e} at x = {format_point(least[1])}."
    return _result(problem, ev, st.pt, st.der, st.qp, status, history, t_start, B=st.B, nit=len(history),
                   detail=detail)


def _nonfinite_detail(ev: Evaluator, pt: Point, der: Derivatives | None, where: str) -> str:
    """Which user function returned NaN or inf, where."""
    return f"{ev.nonfinite_source(pt, der)} returned NaN or inf {where} (iteration {ev.nit}, x = {format_point(pt.x)})."


def _start_point(problem: Problem, options: Options) -> tuple[Array, Status | None, str]:
    """Clip ``x0`` into the bounds; project it onto the linear rows when they are violated.

    When that projection (a QP) fails, an LP decides between LINEAR_INFEASIBLE and a failure of the QP backends."""
    x = np.clip(problem.x0, problem.lower, problem.upper)
    if problem.linear.lb.size == 0 or np.max(problem.linear.violation(problem.A @ x), initial=0.0) <= 1e-12:
        return x, None, ""
    n = problem.n
    empty = linearise(np.zeros((0, n)), np.zeros(0), problem.nonlinear.__class__.from_bounds(np.zeros(0), np.zeros(0)))
    lin = linearise(problem.A, problem.A @ x, problem.linear)
    qp = solve_subproblem(np.eye(n), np.zeros(n), empty, lin, problem.lower - x, problem.upper - x,
                          backends=options.backends)
    if qp.found:
        return np.clip(x + qp.d, problem.lower, problem.upper), None, ""
    if qp.status == "QP infeasible" or not _linear_rows_consistent(problem):
        return x, Status.LINEAR_INFEASIBLE, ""
    return x, Status.QP_FAILED, (f"Backends tried: {', '.join(name for name, _ in options.backends)} (on the "
                                 "projection of x0 onto the linear constraints, which have a common point).")


def _linear_rows_consistent(problem: Problem) -> bool:
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


def _linearised(problem: Problem, st: _State, c: Array | None = None) -> tuple[LinearisedRows, LinearisedRows]:
    nl = linearise(st.der.J, st.pt.c if c is None else c, problem.nonlinear)
    lin = linearise(problem.A, st.pt.r, problem.linear)
    return nl, lin


def _subproblem(problem: Problem, options: Options, st: _State, rho: float) -> tuple[QPStep, float]:
    """The QP at the current iterate; its elastic form when it is inconsistent.

    The slack price starts at ``max(100, 10 max mu, 10 ||g||_inf)`` and grows tenfold (up to
    :data:`MAX_ELASTIC_PENALTY`) only while the elastic step removes less than a tenth of the linearised violation.
    """
    nl, lin = _linearised(problem, st)
    x = st.pt.x
    kw = {"backends": options.backends, "initvals": None if st.qp is None else st.qp.d}
    qp = solve_subproblem(st.B, st.der.g, nl, lin, problem.lower - x, problem.upper - x, **kw)
    rows = problem.nonlinear
    v0 = float(np.sum(rows.violation(st.pt.c)))
    if qp.found and v0 > 0.1 * options.tol and len(options.backends) > 1 and not qp.elastic:
        # a consistent linearisation is met exactly by the QP's step; an answer that leaves the (small) violation
        # where it was hides inside the backend's own feasibility tolerance (DAQP: 1e-6): ask the next backend
        v1 = float(np.sum(rows.violation(st.pt.c + st.der.J @ qp.d)))
        if v1 > 0.5 * v0:
            other = solve_subproblem(st.B, st.der.g, nl, lin, problem.lower - x, problem.upper - x,
                                     backends=options.backends[1:], initvals=kw["initvals"])
            if other.found and float(np.sum(rows.violation(st.pt.c + st.der.J @ other.d))) < v1:
                qp = replace(other, status=f"opt[{options.backends[1][0]}]" if other.status == "optimal"
                             else other.status)
    if qp.found or rows.lb.size == 0:
        return qp, 0.0
    rho = min(MAX_ELASTIC_PENALTY, max(1e2, 10.0 * float(np.max(st.mu, initial=0.0)),
                                       10.0 * float(np.max(np.abs(st.der.g)))))
    while True:
        qp = solve_subproblem(st.B, st.der.g, nl, lin, problem.lower - x, problem.upper - x, elastic_penalty=rho,
                              **kw)
        if not qp.found or rho >= MAX_ELASTIC_PENALTY:
            return qp, rho
        v1 = float(np.sum(rows.violation(st.pt.c + st.der.J @ qp.d)))
        if v0 - v1 >= 0.1 * v0:
            return qp, rho
        rho = min(MAX_ELASTIC_PENALTY, 10.0 * rho)


def _al_rows(problem: Problem, lam: Array) -> Array:
    """Nonlinear rows the QP keeps as equalities: the equalities and the inequalities with a nonzero multiplier."""
    return np.union1d(problem.nonlinear.eq, np.flatnonzero(lam))


def _newton_multipliers(problem: Problem, st: _State, qp: QPStep, rows: Array, weight: float) -> QPStep:
    """The QP's multipliers with the augmented-Lagrangian term of :func:`~sqp.hessian.convexify` moved back into them.

    With ``B = W + weight C^T C`` the QP's stationarity ``B d + g - J^T lam - A^T lam_lin - z = 0`` is
    ``W d + g - J^T lam' - A^T lam_lin' - z = 0`` for ``lam' = lam - weight (C d)`` on the rows of ``C``: the step is
    Newton's and so are these multipliers, whereas ``lam`` itself is off by ``weight`` times the residual of those
    rows. (Near a solution the corrected ones are exact to second order, so the KKT test can use them at the new
    point.)"""
    lam_nl = qp.lam_nl.copy()
    if rows.size:
        lam_nl[rows] -= weight * np.asarray(st.der.J[rows] @ qp.d).ravel()
    lam_lin = qp.lam_lin.copy()
    eq = problem.linear.eq
    if eq.size:
        lam_lin[eq] -= weight * np.asarray(problem.A[eq] @ qp.d).ravel()
    return replace(qp, lam_nl=lam_nl, lam_lin=lam_lin)


def _equality_rows(problem: Problem, J: Any, rows: Array) -> Any:
    """The rows ``C`` of the augmented-Lagrangian convexification of an exact Hessian: the nonlinear ``rows``
    (:func:`_al_rows`) and the linear equalities."""
    parts = [J[rows]] if rows.size else []
    if problem.linear.eq.size:
        parts.append(problem.A[problem.linear.eq])
    if not parts:
        return None
    if any(sp.issparse(p) for p in parts):
        return sp.vstack(parts, format="csr")
    return np.vstack(parts)


def _kkt(problem: Problem, st: _State) -> KKTResiduals:
    qp = st.qp
    assert qp is not None
    return kkt_residuals(problem, st.pt.x, st.der.g, st.pt.c, st.der.J, st.pt.r, qp.lam_nl, qp.lam_lin, qp.z)


def _loaded_rows_active(problem: Problem, st: _State, tol: float) -> bool:
    """Whether every inequality row and bound with a nonzero multiplier in ``st.qp`` is active at ``st.pt`` to within
    the feasibility tolerance (so a solution reported with the last QP's multipliers has a contact force only where
    there is contact, as the next QP's would)."""
    qp = st.qp
    assert qp is not None
    x = st.pt.x
    limit = tol * max(1.0, float(np.max(np.abs(x), initial=0.0)))
    for rows, values, lam in ((problem.nonlinear, st.pt.c, qp.lam_nl), (problem.linear, st.pt.r, qp.lam_lin),
                              (problem.bound_rows if problem.has_bounds else None, x, qp.z)):
        if rows is None or lam.size == 0:
            continue
        with np.errstate(invalid="ignore"):
            gap = np.where(lam > 0, values - rows.lb, np.where(lam < 0, rows.ub - values, 0.0))
        if np.any(~(np.abs(gap) <= limit)):
            return False
    return True


def _lagrangian_gradient(problem: Problem, der: Derivatives, qp: QPStep) -> Array:
    """Only the nonlinear rows matter for ``y``: linear rows and bounds have constant gradients."""
    return lagrangian_gradient(der.g, der.J, qp.lam_nl, problem.A, np.zeros(0), np.zeros(der.g.size))


def _trial(problem: Problem, ev: Evaluator, x: Array, step: Array) -> Point:
    return ev.point(np.clip(x + step, problem.lower, problem.upper))


@dataclass(frozen=True)
class _Search:
    """What a line search gave: the accepted point with its derivatives (``pt is None`` when none was accepted).

    ``nonfinite`` names the user function that returned NaN or inf at the last point tried (None when that point was
    finite); ``alpha`` is the accepted step length, or the last one tried."""

    pt: Point | None = None
    der: Derivatives | None = None
    alpha: float = 0.0
    soc: bool = False
    nonfinite: str | None = None


def _line_search(problem: Problem, options: Options, ev: Evaluator, st: _State, d: Array) -> _Search:
    """Armijo backtracking on the L1 merit function, with one second-order correction of the full step.

    A point is accepted only when its values and its derivatives are finite: NaN or inf from any user function
    (objective, constraint, gradient or Jacobian) at a trial point shortens the step. Fails (``pt is None``) when no
    step length down to :data:`MIN_STEP_LENGTH` decreases the merit function enough.
    """
    rows = problem.nonlinear
    Jd = st.der.J @ d
    phi0 = merit(st.pt.f, st.pt.c, rows, st.mu)
    D = directional_derivative(st.der.g, d, st.pt.c, Jd, rows, st.mu)
    if D >= 0.0:
        # an inexact QP can give an ascent direction; a steeper penalty restores descent when d is infeasible
        viol = rows.violation(st.pt.c)
        if np.any(viol > 0):
            st.mu = st.mu + (D + 1.0) / float(np.sum(viol)) * (viol > 0)
            phi0 = merit(st.pt.f, st.pt.c, rows, st.mu)
            D = directional_derivative(st.der.g, d, st.pt.c, Jd, rows, st.mu)
        if D >= 0.0:
            return _Search()
    alpha = 1.0
    tried_soc = not options.second_order_correction or rows.lb.size == 0
    nonfinite: str | None = None
    tried = alpha
    while alpha >= MIN_STEP_LENGTH:
        trial = _trial(problem, ev, st.pt.x, alpha * d)
        if np.array_equal(trial.x, st.pt.x):
            # the step is below the rounding level of x: no progress is possible along d
            return _Search(alpha=tried, nonfinite=nonfinite)
        tried = alpha
        nonfinite = ev.nonfinite_source(trial)
        phi = merit(trial.f, trial.c, rows, st.mu)
        if phi <= phi0 + ARMIJO * alpha * D:
            der = ev.derivatives(trial)
            if der.finite:
                return _Search(trial, der, alpha, False)
            nonfinite, phi = ev.nonfinite_source(trial, der), np.inf  # shorten the step as for a NaN value
        if not tried_soc:
            tried_soc = True
            corrected = _second_order_correction(problem, options, ev, st, d, trial)
            if corrected is not None and merit(corrected.f, corrected.c, rows, st.mu) <= phi0 + ARMIJO * D:
                der = ev.derivatives(corrected)
                if der.finite:
                    return _Search(corrected, der, 1.0, True)
        alpha = next_step_length(alpha, phi0, D, phi)
    return _Search(alpha=tried, nonfinite=nonfinite)


def _second_order_correction(
    problem: Problem, options: Options, ev: Evaluator, st: _State, d: Array, trial: Point
) -> Point | None:
    """Re-solve the QP with the constraint values at ``x + d`` (Nocedal & Wright §18.3, Maratos remedy)."""
    if not trial.finite:
        return None
    c_shift = trial.c - st.der.J @ d
    nl, lin = _linearised(problem, st, c=c_shift)
    x = st.pt.x
    qp = solve_subproblem(st.B, st.der.g, nl, lin, problem.lower - x, problem.upper - x,
                          backends=options.backends, initvals=d)
    if not qp.found:
        return None
    return _trial(problem, ev, x, qp.d)


def _negligible(x: Array, x_new: Array) -> bool:
    """Whether a step changed x by less than a relative 1e-12 (rounding noise in f or c drives such steps)."""
    return bool(np.max(np.abs(x_new - x), initial=0.0) <= 1e-12 * (1.0 + np.max(np.abs(x), initial=0.0)))


def _stalled_status(problem: Problem, st: _State, d: Array) -> Status:
    """Why no step was accepted: non-finite values along the step, a vanishing step, or a failed search."""
    if np.max(np.abs(d), initial=0.0) <= 1e-14 * (1.0 + np.max(np.abs(st.pt.x))):
        if st.qp is not None and st.qp.elastic and np.max(problem.nonlinear.violation(st.pt.c), initial=0.0) > 0:
            return Status.INFEASIBLE
        return Status.SMALL_STEP
    if st.qp is not None and st.qp.elastic and _kkt(problem, st).feasibility > 1e-6:
        # the linearisation is inconsistent here and no step along the elastic direction reduces the merit: a
        # (local) minimiser of the violation, not a derivative or scaling problem
        return Status.INFEASIBLE
    return Status.LINE_SEARCH


def _result(
    problem: Problem,
    ev: Evaluator,
    pt: Point | None,
    der: Derivatives | None,
    qp: QPStep | None,
    status: Status,
    history: list[IterationRecord],
    t_start: float,
    *,
    x: Array | None = None,
    B: Array | None = None,
    nit: int = 0,
    detail: str = "",
) -> Result:
    n = problem.n
    if pt is None:
        xx = problem.x0.copy() if x is None else x
        f, c, r = np.nan, np.full(problem.nonlinear.lb.size, np.nan), problem.A @ xx
    else:
        xx, f, c, r = pt.x, pt.f, pt.c, pt.r
    lam_nl = qp.lam_nl if qp is not None else np.zeros(problem.nonlinear.lb.size)
    lam_lin = qp.lam_lin if qp is not None else np.zeros(problem.linear.lb.size)
    z = qp.z if qp is not None else np.zeros(n)
    g = der.g if der is not None else np.full(n, np.nan)
    if der is not None:
        kkt = kkt_residuals(problem, xx, g, c, der.J, r, lam_nl, lam_lin, z)
        kkt_dict = {"stationarity": kkt.stationarity, "feasibility": kkt.feasibility,
                    "complementarity": kkt.complementarity}
    else:
        kkt_dict = {"stationarity": np.nan, "feasibility": np.nan, "complementarity": np.nan}
    maxcv = max_violation(problem, xx, c, np.asarray(r).ravel()) if np.all(np.isfinite(c)) else np.inf
    eq_rows = np.concatenate([lam_nl[problem.nonlinear.eq], lam_lin[problem.linear.eq]])
    ineq_nl = np.setdiff1d(np.arange(lam_nl.size), problem.nonlinear.eq)
    ineq_lin = np.setdiff1d(np.arange(lam_lin.size), problem.linear.eq)
    message = status.message
    if status is Status.MAX_ITER:
        message = message.replace("max_iter", f"max_iter (now {nit})")
    if detail:
        message = f"{message} {detail}"
    res = Result(
        x=xx.copy(), fun=float(f), jac=g, success=status in (Status.SUCCESS, Status.ACCEPTABLE),
        status=status.code, message=message,
        nit=nit, nfev=ev.nfev, njev=ev.njev, maxcv=float(maxcv),
        constraint_multipliers=problem.split_multipliers(lam_lin, lam_nl),
        bound_multipliers=z.copy(),
        multipliers={"eq": eq_rows, "ineq": np.concatenate([lam_nl[ineq_nl], lam_lin[ineq_lin]]), "bounds": z.copy()},
        nhev=ev.nhev, kkt=kkt_dict, history=history, hess=B, status_name=status.name,
        solve_time=time.perf_counter() - t_start,
    )
    return res
