"""The SQP loop (paper §2.2) and the scipy-style front door :func:`minimize`.

One iteration: solve the QP (Eqs. 9–10; elastic if inconsistent) → test the KKT residuals → update the penalties
(Eq. 13) → backtrack on the L1 merit function (Eq. 12), with a second-order correction → damped BFGS (Eq. 6) →
record. The pieces live in modules named for them: :mod:`sqp.start` (start point, ``hess0``), :mod:`sqp.step` (the QP
at the iterate, :mod:`sqp.subproblem` solving it), :mod:`sqp.kkt`, :mod:`sqp.merit` (Eqs. 12–13),
:mod:`sqp.linesearch`, :mod:`sqp.hessian` (Eq. 6, or an exact Hessian made positive definite) and
:mod:`sqp.multipliers` (the estimates around the QP); :mod:`sqp.backends` chooses the QP backend.
"""

from __future__ import annotations

import time
import warnings
from collections.abc import Callable
from dataclasses import replace
from typing import Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray
from scipy.optimize import OptimizeResult

from sqp.backends import AUTO, auto_choice
from sqp.build import build_problem
from sqp.hessian import convexify, damped_bfgs_update, initial_scaling
from sqp.iterate import Derivatives, Evaluator, Point, State
from sqp.kkt import KKTResiduals, max_violation
from sqp.linesearch import line_search
from sqp.merit import descent_penalty, update_penalty
from sqp.multipliers import (
    al_rows,
    equality_rows,
    loaded_rows_active,
    newton_multipliers,
    nonlinear_lagrangian_gradient,
)
from sqp.options import Options
from sqp.problem import Problem, format_point
from sqp.report import HEADER, format_row
from sqp.result import IterationRecord, Result, Status, build_result
from sqp.scipy_call import adapt_callback, check_method, print_summary, read_settings
from sqp.start import initial_hessian, start_point
from sqp.step import qp_step
from sqp.subproblem import QPStep
from sqp.termination import (
    RESTART_BOUNDED_ITERATIONS,
    RESTART_STATUSES,
    RESTART_STEP_BOUND,
    Origin,
    acceptable,
    at_step_bound,
    closer,
    diverging,
    flat_violation,
    infeasibility_stalled,
    kkt_at,
    negligible,
    stalled_status,
)

Array = NDArray[np.float64]

#: Scaled KKT level accepted as success (status ACCEPTABLE) when rounding errors stop progress towards ``tol``; the
#: stationarity level is this times the cancellation factor of the Lagrangian gradient (:func:`acceptable`).
STALL_ITERATIONS = 3


def minimize(
    fun: Callable[..., Any],
    x0: Any,
    args: Any = (),
    method: str | None = None,
    jac: Callable[..., Any] | str | bool | None = None,
    hess: Callable[..., Any] | None = None,
    hessp: Callable[..., Any] | None = None,
    bounds: Any = None,
    constraints: Any = (),
    tol: float | None = None,
    callback: Callable[..., Any] | None = None,
    options: dict[str, Any] | None = None,
    *,
    hess0: Any = None,
    multipliers0: Any = None,
    qp_solver: str = "auto",
    qp_options: dict[str, Any] | None = None,
    max_iter: int | None = None,
    verbose: bool = False,
) -> Result:
    """Minimise ``fun(x, *args)`` subject to bounds and constraints by SQP; scipy's ``minimize(method="SLSQP")`` call.

    The positional and keyword arguments up to ``options`` are scipy's, in scipy's order; the engine's own settings
    follow, keyword-only.

    Parameters
    ----------
    fun : callable
        Objective ``fun(x, *args) -> float`` (``(f, g)`` with ``jac=True``).
    x0 : array_like, shape (n,) or scalar
        Starting point. A start outside the bounds is clipped onto them silently, as SLSQP does
        (``res.x0_clipped`` lists the indices; ``disp`` prints them); a start violating the linear constraints is
        then projected onto them.
    args : tuple
        Extra arguments of ``fun``, ``jac`` and ``hess`` (a non-tuple is one argument, as in scipy).
    method : None or "SLSQP"
        Accepted for scipy's call (any case); any other method is a ValueError.
    jac : callable, True, False, None, '2-point', '3-point' or 'cs'
        Gradient ``jac(x, *args) -> (n,)``; ``True``: ``fun`` returns ``(f, g)``; None/False: forward differences
        with the absolute step ``options["eps"]``; a scheme name: that scheme with the relative step
        ``options["finite_diff_rel_step"]``. Difference points stay inside the bounds. Constraints without a
        ``jac`` are differenced the same way.
    hess : callable, optional
        Exact objective Hessian ``hess(x, *args) -> (n, n)`` (array or sparse matrix). With it, every nonlinear
        constraint must carry its Hessian (``NonlinearConstraint.hess`` or a dict's ``"hess"``: ``hess(x, v) =
        sum_i v_i grad^2 c_i(x)``) and the model Hessian is the exact Lagrangian Hessian, shifted by a multiple of
        the identity where needed to make it positive definite, instead of damped BFGS. (SLSQP ignores ``hess``.)
    hessp : callable, optional
        Not used (a RuntimeWarning says so, as scipy's SLSQP does).
    bounds : scipy.optimize.Bounds or sequence of (lo, hi), optional
        Variable bounds; ``None`` for an unbounded side; scalars and 1-element arrays broadcast to every variable.
    constraints : dict, NonlinearConstraint, LinearConstraint or a sequence of them
        SLSQP dicts ``{"type": "eq"|"ineq", "fun", "jac", "args"}`` (``ineq`` means ``fun(x) >= 0``) and scipy
        constraint objects (rows with ``lb == ub`` are equalities). Linear constraints and bounds are kept exactly
        in every QP.
    tol : float, optional
        Tolerance on the scaled KKT residuals and on the violation; sets ``options["ftol"]`` when that is absent,
        as in scipy. Without either: 1e-8 with a gradient ``jac``, 1e-6 (SLSQP's ``ftol`` default) with finite
        differences, whose error is of order 1e-8.
    callback : callable, optional
        ``callback(xk)``, or ``callback(intermediate_result)`` when that is its only parameter's name (scipy's rule:
        an ``OptimizeResult`` with ``x, fun, nit, nfev, maxcv, kkt``), after each iteration; raising
        ``StopIteration`` stops the solve with ``success=False`` and status CALLBACK (99, as scipy).
    options : dict, optional
        SLSQP's options: ``maxiter`` (default 500 here, 100 in SLSQP), ``ftol`` (the KKT tolerance), ``disp`` (print
        SLSQP's summary at the end), ``iprint`` (>= 2 with ``disp``: also the iteration table), ``eps``,
        ``finite_diff_rel_step``, ``workers`` (finite differences). Any other key warns (``OptimizeWarning``) and is
        ignored.
    hess0 : array_like, shape (n, n), optional
        Initial Lagrangian Hessian approximation (e.g. the objective's known Hessian); symmetric, positive
        semidefinite (shifted to positive definite if needed). Default: identity, rescaled after the first step.
        Not used when ``hess`` is given (only its shape is checked then). Dense or sparse (BFGS keeps a dense
        matrix, so a sparse one is made dense whatever its size).
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
    max_iter : int, optional
        Maximum number of iterations (the same as ``options["maxiter"]``; give one of them).
    verbose : bool
        Print the backend used and an iteration table.

    Returns
    -------
    Result
        An ``OptimizeResult`` with scipy's ``x, fun, jac, success, status, message, nit, nfev, njev`` and
        ``multipliers`` (SLSQP's array: equality rows first, then inequality rows, in SLSQP's order and sign;
        :meth:`sqp.problem.Problem.slsqp_rows`), plus ``maxcv``, ``constraint_multipliers`` (one array per
        constraint), ``bound_multipliers``, ``kkt``, ``history``, ``hess``, ``qp_solver``, ``x0_clipped``.
        ``status`` is a :class:`~sqp.Status` (an int whose codes agree with SLSQP's table); ``success`` is True
        only for SUCCESS and ACCEPTABLE.

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
    OptimizeWarning
        For an unknown key of ``options`` (ignored).
    RuntimeWarning
        When ``hessp`` is given (not used).
    """
    check_method(method)
    if not isinstance(args, tuple):
        args = (args,)
    if hessp is not None:
        warnings.warn("sqp.minimize does not use Hessian-vector product information (hessp); pass hess.",
                      RuntimeWarning, stacklevel=2)
    call = read_settings(jac, tol, options, max_iter, verbose)
    options_ = Options(tol=call.tol, max_iter=call.max_iter, qp_solver=qp_solver, qp_options=dict(qp_options or {}),
                       callback=adapt_callback(callback), verbose=call.table)
    problem = build_problem(fun, x0, jac, bounds, constraints, args, hess, call.differences)
    if problem.hess is not None and hess0 is not None:  # exact Hessians replace it: check the shape only
        if np.shape(hess0) != (problem.n, problem.n):
            raise ValueError(f"hess0 has shape {np.shape(hess0)}; expected ({problem.n}, {problem.n}).")
        B0 = None
    else:
        B0 = initial_hessian(hess0, problem.n)
    lam0 = None if multipliers0 is None else problem.stack_nonlinear_multipliers(multipliers0)
    res = run(problem, options_, B0, lam0)
    if call.disp:
        print_summary(res)
    return res


#: A solve ends without a confirming QP when the last QP's multipliers pass the KKT test at the new point with
#: ``CONFIRMED_TOLERANCE * tol`` (at ``tol`` itself it would stop one Newton step earlier than the confirming QP's
#: test and leave a residual near ``tol`` where that step would square it).
CONFIRMED_TOLERANCE = 1e-2


def run(problem: Problem, options: Options, B0: Array | None = None, lam0: Array | None = None) -> Result:
    """Run the SQP iteration on a validated problem, with ``qp_solver="auto"`` resolved for it first."""
    why = auto_choice(problem.n, problem.sparse_jacobians)[1] if options.qp_solver == AUTO else ""
    options = options.for_problem(problem)
    if options.verbose:
        print(f"sqp: {problem.n} variables, qp_solver = {options.qp_solver}" + (f" (auto: {why})" if why else ""))
    res, flat = _iterate(problem, options, B0, lam0)
    if options.restart and flat and res.status in RESTART_STATUSES:
        res = _restart(problem, options, B0, lam0, res)
    res.qp_solver = options.qp_solver
    return res


def _restart(problem: Problem, options: Options, B0: Array | None, lam0: Array | None, first: Result) -> Result:
    """Solve again from ``x0`` with every step bounded by :data:`RESTART_STEP_BOUND` for the first
    :data:`RESTART_BOUNDED_ITERATIONS` iterations; the better of the two results, with the work of both counted."""
    x_scale = max(1.0, float(np.max(np.abs(problem.x0), initial=0.0)))
    bounded = replace(options, step_bound=RESTART_STEP_BOUND * x_scale)
    second = _iterate(problem, bounded, B0, lam0)[0]
    better = second if second.success or closer(second, first, options.tol) else first
    better.nfev, better.njev, better.nhev = (first.nfev + second.nfev, first.njev + second.njev,
                                             first.nhev + second.nhev)
    better.nit = first.nit + second.nit
    better.solve_time = first.solve_time + second.solve_time
    return better


def _iterate(problem: Problem, options: Options, B0: Array | None, lam0: Array | None) -> tuple[Result, bool]:
    """The SQP iteration from ``x0``; with its result, whether it ended at a point where a violated row is flat
    (:func:`flat_violation`)."""
    t_start = time.perf_counter()
    ev = Evaluator(problem)
    history: list[IterationRecord] = []
    x, status, detail = start_point(problem, options)
    if status is not None:
        return build_result(problem, ev, None, None, None, status, history, t_start, x=x, detail=detail), False
    pt = ev.point(x)
    if not pt.finite:
        return build_result(problem, ev, pt, None, None, Status.NONFINITE, history, t_start,
                            detail=_nonfinite_detail(ev, pt, None, "at the start point")), False
    der = ev.derivatives(pt)
    if not der.finite:
        return build_result(problem, ev, pt, der, None, Status.NONFINITE, history, t_start,
                            detail=_nonfinite_detail(ev, pt, der, "at the start point")), False
    exact = problem.hess is not None
    scaled_start = B0 is None and not exact
    shift = al_weight = 0.0
    # (with exact Hessians B is replaced before its first use: no dense n x n identity for a large sparse problem)
    B_start = sp.identity(problem.n, format="csc") if exact else (
        np.eye(problem.n) if B0 is None or sp.issparse(B0) else B0.copy())
    st = State(pt=pt, der=der, B=B_start,
               mu=np.zeros(problem.nonlinear.lb.size) if lam0 is None else np.abs(lam0))
    if options.verbose:
        print(HEADER)
    status = Status.MAX_ITER
    detail = ""
    rho = 0.0
    stalled = 0
    best: tuple[KKTResiduals, QPStep] | None = None
    least = (max_violation(problem, pt.x, pt.c, pt.r), pt.x)  # the least violation reached, and where
    least_trace = [least[0]]  # the least violation after each iteration
    elastic_run = 0  # consecutive iterations whose QP was elastic
    origin = Origin(f=pt.f, x_scale=max(1.0, float(np.max(np.abs(pt.x)))))
    for nit in range(options.max_iter + 1):
        if nit == RESTART_BOUNDED_ITERATIONS and np.isfinite(options.step_bound):
            options = replace(options, step_bound=np.inf)  # the step bound covers the first iterations only
        ev.nit = nit + 1  # evaluations from here to the acceptance of the next point belong to iteration nit + 1
        if exact:  # the exact Lagrangian Hessian at (x_k, lam_{k-1}), made positive definite
            lam_prev = st.qp.lam_nl if st.qp is not None else (
                np.zeros(problem.nonlinear.lb.size) if lam0 is None else lam0)
            kept_rows = al_rows(problem, lam_prev)
            W = ev.lagrangian_hessian(st.pt.x, lam_prev)
            if ev.hessian_nonfinite is not None:
                status = Status.NONFINITE
                detail = f"{ev.hessian_nonfinite} returned NaN or inf at {ev.where} (x = {format_point(st.pt.x)})."
                break
            st.B, shift, al_weight = convexify(W, shift, equality_rows(problem, st.der.J, kept_rows), al_weight)
        # the QP subproblem (Eqs. 9–10), elastic when its linearisation is inconsistent
        qp, rho = qp_step(problem, options, st, rho)
        if exact and al_weight > 0.0 and qp.found and not qp.elastic:
            qp = newton_multipliers(problem, st, qp, kept_rows, al_weight)
        if not qp.found:
            eye = sp.identity(problem.n, format="csc") if sp.issparse(st.B) else np.eye(problem.n)
            st.B = eye * max(1.0, float(np.mean(np.abs(st.B.diagonal()))))
            qp, rho = qp_step(problem, options, st, rho)
            if not qp.found:
                status = Status.QP_FAILED
                detail = (f"Backends tried: {', '.join(name for name, _ in options.backends)} (last answer: "
                          f"{qp.status}) at iteration {nit}.")
                break
        st.qp = qp
        kkt = kkt_at(problem, st)
        if at_step_bound(options, qp.d):  # the bound's multipliers hide in z: no KKT certificate from this QP
            kkt = replace(kkt, stationarity=np.inf)
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
        st.mu = _penalties(problem, st, qp)
        search = line_search(problem, options, ev, st, d)
        if search.pt is None and np.max(st.mu, initial=0.0) > 10.0 * max(
                float(np.max(np.abs(qp.lam_nl), initial=0.0)), 1e-12):
            # penalties inflated by early, poorly scaled multipliers: restart them from the current ones (Eq. 13)
            st.mu = np.abs(qp.lam_nl)
            search = line_search(problem, options, ev, st, d)
        if search.pt is not None and negligible(st.pt.x, search.pt.x):
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
                status = stalled_status(problem, st, d)
            # (the multiplier estimates of the QPs solved while x stood still all belong to this point: the best one
            # decides; rounding makes them scatter around the limit on ill-conditioned problems such as HS116)
            assert best is not None
            if acceptable(problem, st, *best, options.tol):
                status, st.qp = Status.ACCEPTABLE, best[1]
            break
        new_pt, new_der, alpha, soc = search.pt, search.der, search.alpha, search.soc
        assert new_der is not None
        # the damped BFGS update (Eq. 6)
        s = new_pt.x - st.pt.x
        damped = False
        if not exact:
            st.B, damped = _bfgs(problem, st, new_der, qp, s, scale=scaled_start and nit == 0)
        st.pt, st.der = new_pt, new_der
        # record the iteration (history, verbose table, callback)
        rec = IterationRecord(
            nit=nit + 1, nfev=ev.nfev, f=new_pt.f, maxcv=max_violation(problem, new_pt.x, new_pt.c, new_pt.r),
            kkt=kkt.worst, step=float(np.max(np.abs(s), initial=0.0)), alpha=alpha,
            penalty=float(np.max(st.mu, initial=0.0)), qp_status=qp.status, damped=damped, soc=soc,
        )
        history.append(rec)
        if rec.maxcv < least[0]:
            least = (rec.maxcv, new_pt.x)
        least_trace.append(least[0])
        elastic_run = elastic_run + 1 if qp.elastic else 0
        if diverging(origin, new_pt, rec.maxcv, options.tol):
            status = Status.UNBOUNDED
            detail = (f"At iteration {nit + 1} f = {new_pt.f:.3e} (from {origin.f:.3e}) at a feasible x with "
                      f"||x||_inf = {np.max(np.abs(new_pt.x)):.3e}.")
            break
        if infeasibility_stalled(least_trace, elastic_run, options.tol):
            status = Status.INFEASIBLE
            break
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
        if (rec.maxcv <= early * max(1.0, float(np.max(np.abs(new_pt.x), initial=0.0)))  # (the feasibility test first)
                and not at_step_bound(options, qp.d) and kkt_at(problem, st).satisfied(early)
                and loaded_rows_active(problem, st, early)):
            status = Status.SUCCESS
            break
    if status is Status.INFEASIBLE:
        detail = f"Least violation reached: {least[0]:.2e} at x = {format_point(least[1])}."
    flat = status in RESTART_STATUSES and flat_violation(problem, st, options.tol)
    return build_result(problem, ev, st.pt, st.der, st.qp, status, history, t_start, B=st.B, nit=len(history),
                        detail=detail), flat


def _penalties(problem: Problem, st: State, qp: QPStep) -> Array:
    """Powell's update of the merit penalties (Eq. 13), raised where needed to make the step ``qp.d`` a descent
    direction of the merit function (:func:`~sqp.merit.descent_penalty`)."""
    mu = update_penalty(st.mu, qp.lam_nl)
    if mu.size:
        d, rows = qp.d, problem.nonlinear
        dv = float(np.sum(rows.violation(st.pt.c)) - np.sum(rows.violation(st.pt.c + st.der.J @ d)))
        mu = np.maximum(mu, descent_penalty(float(st.der.g @ d), float(d @ (st.B @ d)), dv))
    return mu


def _bfgs(problem: Problem, st: State, new_der: Derivatives, qp: QPStep, s: Array, scale: bool) -> tuple[Array, bool]:
    """The damped BFGS update (Eq. 6) of ``st.B`` for the step ``s``, with ``y`` the change of the Lagrangian
    gradient at the QP's multipliers; the identity start is rescaled first (Shanno–Phua) when ``scale``."""
    y = nonlinear_lagrangian_gradient(problem, new_der, qp) - nonlinear_lagrangian_gradient(problem, st.der, qp)
    B = st.B * initial_scaling(s, y) if scale else st.B
    return damped_bfgs_update(B, s, y)


def _nonfinite_detail(ev: Evaluator, pt: Point, der: Derivatives | None, where: str) -> str:
    """Which user function returned NaN or inf, where."""
    return f"{ev.nonfinite_source(pt, der)} returned NaN or inf {where} (iteration {ev.nit}, x = {format_point(pt.x)})."


