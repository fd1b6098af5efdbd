"""The SQP loop (paper §2.2) and the scipy-style front door :func:`minimize`.

One iteration, one line each in :func:`_iterate`: the model Hessian (a :class:`~sqp.hessian_strategy.HessianStrategy`:
damped BFGS, Eq. 6, or the exact Lagrangian Hessian made positive definite) → the QP (Eqs. 9–10, elastic when
inconsistent; :func:`subproblem`) → the termination tests (:class:`~sqp.monitor.Monitor`) → the penalty update
(Eq. 13, :func:`~sqp.merit.penalties`) → the line search on the L1 merit function (Eq. 12, with a second-order
correction; :func:`~sqp.linesearch.merit_search`, a function returning its result) → the Hessian update → record.
The loop owns the state (:class:`~sqp.iterate.State`, replaced, never changed in place); every exit is a
:class:`~sqp.monitor.Stop` from one of those steps. :mod:`sqp.start` gives the start point and ``hess0``;
:mod:`sqp.step` and :mod:`sqp.subproblem` the QP; :mod:`sqp.backends` chooses its backend.
"""

from __future__ import annotations

import time
import warnings
from collections.abc import Callable, Sequence
from dataclasses import replace
from typing import Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray
from scipy.optimize import OptimizeResult

from sqp.backends import AUTO, auto_choice
from sqp.build import build_problem
from sqp.hessian import DENSE_LIMIT
from sqp.hessian_strategy import HessianStrategy, hessian_strategy
from sqp.iterate import Derivatives, Evaluator, Point, State
from sqp.kkt import KKTResiduals, inf_norm
from sqp.linesearch import Search, merit_search
from sqp.merit import penalties
from sqp.monitor import Monitor, Stop
from sqp.options import Options
from sqp.problem import Problem, format_point
from sqp.report import HEADER, format_row
from sqp.restoration import least_violation
from sqp.result import IterationRecord, Result, Status, build_result
from sqp.scipy_call import adapt_callback, check_method, print_summary, read_settings
from sqp.start import initial_hessian, start_point
from sqp.step import qp_step
from sqp.subproblem import QPStep
from sqp.termination import (
    RESTART_BOUNDED_ITERATIONS,
    RESTART_STATUSES,
    RESTART_STEP_BOUND,
    closer,
    flat_violation,
)

Array = NDArray[np.float64]

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
    feasibility_tol: float | None = None,
    verbose: bool = False,
    convexify_inequalities: bool | Sequence[int] = True,
    qp_fallbacks: tuple[str, ...] | None = None,
    active_set_guess: bool = False,
    step_bound: float = float("inf"),
    augmented_rungs: int | None = None,
    extend_shifted_steps: bool = True,
    dense_limit: int = DENSE_LIMIT,
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
        constraint Jacobian is sparse and "daqp" again when some rows are dense (the rule, its measurements and why
        OSQP is not the default: :class:`sqp.Options`). Any installed backend by name (:func:`sqp.installed_solvers`)
        is used exactly as given. The backend used is ``res.qp_solver``.
    qp_options : dict, optional
        Backend settings merged over the engine's accurate defaults.
    max_iter : int, optional
        Maximum number of iterations (the same as ``options["maxiter"]``; give one of them).
    feasibility_tol : float, optional
        Largest violation of a SUCCESS, relative to ``max(1, ||x||_inf)``; default ``tol``, and ``min(tol, 1e-10)``
        when some derivative is a finite difference: the violation is computed from the constraint values, exact to
        rounding however inexact the derivatives, and is driven near rounding as SLSQP's final iterates are
        (:attr:`sqp.Options.feasibility_tol`).
    verbose : bool
        Print the backend used and an iteration table.
    convexify_inequalities : bool or sequence of int
        With ``hess``: whether the augmented-Lagrangian convexification of an indefinite Lagrangian Hessian also
        covers the active inequalities (:attr:`sqp.Options.convexify_inequalities`; False when the active set moves
        along many rows at every iteration), or those among the given nonlinear rows only.
    qp_fallbacks : tuple of str or None
        Backends asked when the chosen one fails a subproblem (:attr:`sqp.Options.qp_fallbacks`); None: its
        default.
    active_set_guess : bool
        Solve each QP with inequality rows and a sparse (or a factored dense) model Hessian first on the active set
        the last multipliers guess, the backends asked only when that fails (:attr:`sqp.Options.active_set_guess`).
    step_bound : float
        Largest change of any variable in each of the first :data:`~sqp.termination.RESTART_BOUNDED_ITERATIONS`
        steps (a box trust region on those QPs, :attr:`sqp.Options.step_bound`); ``inf`` (the default): none. For a
        start whose linearisation misleads (a constraint gradient that vanishes there, so that the first QP does
        not see the row at all).
    augmented_rungs : int or None
        With ``hess``: the weights of the augmented-Lagrangian ladder tried before an identity shift goes on top of
        the term (:attr:`sqp.Options.augmented_rungs`); None: the engine's ladder.
    extend_shifted_steps : bool
        With ``hess``: extend a full step of a shifted model while the merit keeps falling
        (:attr:`sqp.Options.extend_shifted_steps`).
    dense_limit : int
        The most variables at which the engine works with dense matrices (the Lagrangian Hessian, the linear rows,
        DAQP as ``"auto"``'s backend); default :data:`~sqp.DENSE_LIMIT` (300), where a small problem's dense
        algebra beats scipy.sparse's per-call overhead. A program whose derivatives are sparse and banded (a
        discretised rod: the guidewire's 3-D program, 6 variables a bar) is faster kept sparse at every size, its
        QPs then solved by banded KKT solves of the guessed active set (``active_set_guess``): 0 keeps any
        sparse input sparse.

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
    options_ = Options(tol=call.tol, feasibility_tol=feasibility_tol, max_iter=call.max_iter, qp_solver=qp_solver,
                       qp_options=dict(qp_options or {}),
                       callback=adapt_callback(callback), verbose=call.table,
                       convexify_inequalities=_row_selection(convexify_inequalities),
                       active_set_guess=bool(active_set_guess),
                       step_bound=float(step_bound), augmented_rungs=augmented_rungs,
                       extend_shifted_steps=bool(extend_shifted_steps),
                       **({} if qp_fallbacks is None else {"qp_fallbacks": tuple(qp_fallbacks)}))
    if isinstance(dense_limit, bool) or not isinstance(dense_limit, int | np.integer) or dense_limit < 0:
        raise ValueError(f"dense_limit is {dense_limit!r}; give the most variables to work densely at, a whole "
                         f"number >= 0 (default {DENSE_LIMIT}; 0 keeps sparse input sparse).")
    problem = build_problem(fun, x0, jac, bounds, constraints, args, hess, call.differences, int(dense_limit))
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


def run(problem: Problem, options: Options, B0: Array | None = None, lam0: Array | None = None) -> Result:
    """Run the SQP iteration on a validated problem, with ``qp_solver="auto"`` resolved for it first."""
    why = (auto_choice(problem.n, problem.sparse_jacobians, dense_limit=problem.dense_limit)[1]
           if options.qp_solver == AUTO and options.verbose else "")
    options = options.for_problem(problem)
    if options.verbose:
        print(f"sqp: {problem.n} variables, qp_solver = {options.qp_solver}" + (f" (auto: {why})" if why else ""))
    res, flat = _iterate(problem, options, B0, lam0)
    if options.restart and flat and res.status in RESTART_STATUSES:
        res = _restart(problem, options, B0, lam0, res)
    if options.restoration and res.status is Status.INFEASIBLE and problem.nonlinear.lb.size:
        res = _restore(problem, options, B0, lam0, res)
    res.qp_solver = options.qp_solver
    return res


def _restore(problem: Problem, options: Options, B0: Array | None, lam0: Array | None, first: Result) -> Result:
    """After an INFEASIBLE end: the least violation from its point (:func:`~sqp.restoration.least_violation`). A
    violation within tolerance there means the problem is feasible after all, and the solve starts again from that
    point; otherwise the result is INFEASIBLE at the restoration's point, whose ``x``, ``maxcv`` and message agree."""
    t_start = time.perf_counter()
    ev = Evaluator(problem)
    quiet = replace(options, restart=False, restoration=False, callback=None, verbose=False)
    rest = least_violation(problem, ev, np.asarray(first.x, dtype=float), quiet, run)
    pt = ev.point(rest.x)
    if pt.maxcv <= options.constraint_tol * max(1.0, inf_norm(rest.x)):
        res = _iterate(replace(problem, x0=rest.x, start=None), options, B0, lam0)[0]
        res.nfev, res.njev, res.nit = res.nfev + ev.nfev, res.njev + ev.njev, res.nit + rest.result.nit
    else:
        der = ev.derivatives(pt)
        verdict = ("a stationary point of the violation (the restoration problem's KKT test holds)" if rest.stationary
                   else f"where the restoration ended {rest.result.status.name}: not certified a minimiser of the "
                        "violation")
        res = build_result(problem, ev, pt, der, None, Status.INFEASIBLE, list(first.history), t_start,
                           nit=rest.result.nit, detail=f"Least violation reached: {rest.violation:.3e} (sum over the "
                                                       f"rows; largest {pt.maxcv:.3e}) at x = {format_point(rest.x)}, "
                                                       f"{verdict}.")
    # (the work of the first solve counts too)
    res.nfev, res.njev, res.nit = res.nfev + first.nfev, res.njev + first.njev, res.nit + first.nit
    res.solve_time += first.solve_time
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
    """The SQP iteration from ``x0`` (paper §2.2); with its result, whether it ended at a point where a violated row
    is flat (:func:`flat_violation`)."""
    t_start = time.perf_counter()
    ev = Evaluator(problem)
    st, failed = _start(problem, options, ev, B0, lam0, t_start)
    if st is None:
        assert failed is not None
        return failed, False
    hessian = hessian_strategy(problem, B0, lam0, options.convexify_inequalities, options.augmented_rungs)
    st = State(st.pt, st.der, hessian.initial(st), st.mu)
    monitor = Monitor(problem, options.tol, options.max_iter, st.pt, st.pt.maxcv, options.constraint_tol)
    history: list[IterationRecord] = []
    rho = 0.0  # the elastic QP's slack price
    noise = 0.0  # the merit function's rounding noise, once a line search has found it
    stop = Stop(Status.MAX_ITER)
    if options.verbose:
        print(HEADER)
    for nit in range(options.max_iter + 1):
        options, ev.nit = bounded_steps(options, nit), nit + 1  # (iteration nit + 1's evaluations from here)
        B = hessian.model(ev, st)  # Hessian: damped BFGS (Eq. 6) or the exact one made positive definite
        if B is None:
            stop = Stop(Status.NONFINITE, f"{ev.hessian_nonfinite} returned NaN or inf at {ev.where} "
                                          f"(x = {format_point(st.pt.x)}).")
            break
        qp, rho, B = subproblem(problem, options, State(st.pt, st.der, B, st.mu, st.qp), rho, hessian)  # QP (9–10)
        st = State(st.pt, st.der, B, st.mu, qp if qp.found else st.qp)
        if (stop := monitor.after_qp(options, st, qp, nit)) is not None:  # KKT test
            break
        mu = penalties(problem, st, qp)  # penalty update (Eq. 13)
        # (the exact Hessian needed an identity shift: the full step is extended while the merit keeps falling)
        shifted = options.extend_shifted_steps and getattr(hessian, "shift", 0.0) > 0.0
        search = merit_search(problem, options, ev, st, qp, mu, noise, shifted)  # line search on the merit (Eq. 12)
        noise = max(noise, search.noise)
        st = State(st.pt, st.der, st.B, search.mu, qp)
        if (stop := monitor.after_search(st, search.pt, search.nonfinite, search.alpha, nit)) is not None:
            break
        assert search.pt is not None and search.der is not None
        s = search.pt.x - st.pt.x
        B, damped = hessian.update(st, search.der, qp, s, nit == 0)  # the BFGS update (Eq. 6) for the next model
        st = State(pt=search.pt, der=search.der, B=B, mu=st.mu, qp=qp)
        rec = _record(problem, ev, nit, st, monitor.kkt, s, search, damped)
        history.append(rec)
        if (stop := monitor.after_step(st, rec.maxcv, nit)) is not None:  # divergence, stalled infeasibility
            break
        if (stop := _report(options, rec, st)) is not None:  # verbose table, callback
            break
        if (stop := monitor.confirmed(options, st, rec.maxcv)) is not None:  # converged: no confirming QP needed
            break
    if stop.qp is not None:
        st = replace(st, qp=stop.qp)
    stop = monitor.detail(stop)
    flat = stop.status in RESTART_STATUSES and flat_violation(problem, st, options.tol)
    return build_result(problem, ev, st.pt, st.der, st.qp, stop.status, history, t_start, B=st.B, nit=len(history),
                        detail=stop.detail, kkt=monitor.residuals(st)), flat


def _row_selection(value: bool | Sequence[int]) -> bool | tuple[int, ...]:
    """``convexify_inequalities`` as :class:`~sqp.options.Options` keeps it: a bool, or the row indices (a TypeError
    for anything else)."""
    if isinstance(value, bool | np.bool_):
        return bool(value)
    try:
        rows = tuple(int(i) for i in value)
    except (TypeError, ValueError):
        raise TypeError(f"convexify_inequalities is {value!r}; expected True, False or a sequence of nonlinear row "
                        "indices.") from None
    if any(i < 0 for i in rows):
        raise ValueError("convexify_inequalities: row indices must be non-negative (rows of the nonlinear "
                         "constraints, in their order).")
    return rows


def bounded_steps(options: Options, nit: int) -> Options:
    """``options`` for iteration ``nit``: its step bound (a restart's trust region) lifted after the first
    :data:`RESTART_BOUNDED_ITERATIONS` iterations."""
    if nit == RESTART_BOUNDED_ITERATIONS and np.isfinite(options.step_bound):
        return replace(options, step_bound=np.inf)
    return options


def subproblem(problem: Problem, options: Options, st: State, rho: float,
               hessian: HessianStrategy) -> tuple[QPStep, float, Any]:
    """The QP at ``st`` (Eqs. 9–10, elastic when inconsistent: :func:`~sqp.step.qp_step`) with the multipliers of the
    model's step; when no backend solves it, once more with ``B`` replaced by a multiple of the identity. Returns the
    answer, the elastic slack price and the ``B`` it was solved with."""
    qp, rho, B = qp_step(problem, options, st, rho)
    qp = hessian.multipliers(State(st.pt, st.der, B, st.mu, st.qp), qp)
    if qp.found:
        return qp, rho, B
    eye = sp.identity(problem.n, format="csc") if sp.issparse(B) else np.eye(problem.n)
    B = eye * max(1.0, float(np.mean(np.abs(B.diagonal()))))
    qp, rho, B = qp_step(problem, options, State(st.pt, st.der, B, st.mu, st.qp), rho)
    return qp, rho, B


def _start(problem: Problem, options: Options, ev: Evaluator, B0: Array | None, lam0: Array | None,
           t_start: float) -> tuple[State | None, Result | None]:
    """The state at the start point (``B`` still to be set), or the result of a solve that cannot start."""
    history: list[IterationRecord] = []
    x, status, detail = start_point(problem, options)
    if status is not None:
        return None, build_result(problem, ev, None, None, None, status, history, t_start, x=x, detail=detail)
    pt = ev.point(x)
    if not pt.finite:
        return None, build_result(problem, ev, pt, None, None, Status.NONFINITE, history, t_start,
                                  detail=_nonfinite_detail(ev, pt, None, "at the start point"))
    der = ev.derivatives(pt)
    if not der.finite:
        return None, build_result(problem, ev, pt, der, None, Status.NONFINITE, history, t_start,
                                  detail=_nonfinite_detail(ev, pt, der, "at the start point"))
    mu = np.zeros(problem.nonlinear.lb.size) if lam0 is None else np.abs(lam0)
    return State(pt=pt, der=der, B=None, mu=mu), None


def _record(problem: Problem, ev: Evaluator, nit: int, st: State, kkt: KKTResiduals, s: Array, search: Search,
            damped: bool) -> IterationRecord:
    """The history row of iteration ``nit + 1``, which reached ``st`` by the step ``s``."""
    assert st.qp is not None
    return IterationRecord(
        nit=nit + 1, nfev=ev.nfev, f=st.pt.f, maxcv=st.pt.maxcv,
        kkt=kkt.worst, step=inf_norm(s), alpha=search.alpha,
        penalty=float(st.mu.max()) if st.mu.size else 0.0, qp_status=st.qp.status, damped=damped, soc=search.soc,
    )


def _report(options: Options, rec: IterationRecord, st: State) -> Stop | None:
    """Print the iteration's row (``verbose``) and call the callback; CALLBACK when it raises StopIteration."""
    if options.verbose:
        print(format_row(rec))
    if options.callback is None:
        return None
    try:
        options.callback(OptimizeResult(x=st.pt.x.copy(), fun=st.pt.f, nit=rec.nit, nfev=rec.nfev, maxcv=rec.maxcv,
                                        kkt=rec.kkt))
    except StopIteration:
        return Stop(Status.CALLBACK)
    except Exception as exc:
        exc.add_note(f"sqp.minimize: raised by callback at iteration {rec.nit} (x = {format_point(st.pt.x)}).")
        raise
    return None


def _nonfinite_detail(ev: Evaluator, pt: Point, der: Derivatives | None, where: str) -> str:
    """Which user function returned NaN or inf, where."""
    return f"{ev.nonfinite_source(pt, der)} returned NaN or inf {where} (iteration {ev.nit}, x = {format_point(pt.x)})."
