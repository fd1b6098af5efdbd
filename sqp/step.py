"""The QP step at the current iterate (paper Eqs. 9–10): the subproblem assembled from the state, its elastic form
when the linearisation is inconsistent, and the second-order correction of a rejected step.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from sqp.iterate import Evaluator, Point, State
from sqp.kkt import inf_norm
from sqp.options import Options
from sqp.problem import Problem
from sqp.structured import needs_convexification
from sqp.subproblem import LinearisedRows, QPStep, active_guess, inequality_bounds, linearise, solve_subproblem

Array = NDArray[np.float64]


#: Largest price of a unit of slack in the elastic QP before a point is declared locally infeasible.
MAX_ELASTIC_PENALTY = 1e10

#: The elastic QP's first slack price is at least this, and at least this factor times the largest penalty and the
#: gradient's size (a slack must cost more than any multiplier the merit function could pay for it); the price grows
#: by the same factor while a step removes less than :data:`ELASTIC_PROGRESS` of the linearised violation (the
#: steering rule of Byrd, Nocedal & Waltz, "Steering exact penalty methods", 2008, in its simplest form).
ELASTIC_PRICE_FLOOR = 1e2
ELASTIC_PRICE_FACTOR = 10.0
ELASTIC_PROGRESS = 0.1

#: A point whose largest violation is within this fraction of the success tolerance does not need its QP's rows met
#: more exactly than the first backend met them (:func:`_met_by_another_backend`).
FEASIBLE_ENOUGH = 0.1


def linearised(problem: Problem, st: State, c: Array | None = None) -> tuple[LinearisedRows, LinearisedRows]:
    """The nonlinear rows linearised at ``st`` (with the values ``c`` instead of ``st.pt.c`` when given) and the
    linear rows, as QP rows in the step ``d``."""
    nl = linearise(st.der.J, st.pt.c if c is None else c, problem.nonlinear)
    lin = linearise(problem.A, st.pt.r, problem.linear)
    return nl, lin


def qp_step(problem: Problem, options: Options, st: State, rho: float) -> tuple[QPStep, float, Any]:
    """The QP at the current iterate; its elastic form when it is inconsistent. Returns the answer, the elastic slack
    price and the model Hessian the QP was solved with.

    That Hessian is ``st.B``, or its convexification: an indefinite :class:`sqp.structured.FactoredHessian` in
    ``st.B`` (an exact Hessian left unconvexified by :func:`sqp.hessian.convexify`) serves an equality-only QP whose
    KKT matrix has the right inertia; otherwise it is convexified here, before any backend sees it (``st`` itself is
    not changed).
    """
    nl, lin = linearised(problem, st)
    kw = {"backends": options.backends, "initvals": None if st.qp is None else st.qp.d}
    box = _box(problem, options, st.pt.x)
    B = st.B
    if needs_convexification(B) and not _equality_only(problem, box):
        B = B.convexified()
    guess = _guess(problem, options, st, nl, lin) if options.active_set_guess else None
    first = st.qp is None or not st.qp.found
    qp = solve_subproblem(B, st.der.g, nl, lin, *box, **kw, active=guess, first=first)
    if not qp.found and needs_convexification(B):  # K's inertia is wrong: W is not convex on E's null space
        B = B.convexified()
        qp = solve_subproblem(B, st.der.g, nl, lin, *box, **kw, active=guess, first=first)
    if qp.found and problem.nonlinear.lb.size:
        qp = _with_violation(qp, linearised_violation(problem, st, qp.d))
    if qp.found:
        qp = _met_by_another_backend(problem, options, st, B, qp, (nl, lin), box, kw["initvals"])
    if qp.found or problem.nonlinear.lb.size == 0:
        return qp, 0.0, B
    qp, rho = _elastic(problem, st, B, (nl, lin), box, kw)
    return qp, rho, B


def _guess(problem: Problem, options: Options, st: State, nl: LinearisedRows,
           lin: LinearisedRows) -> NDArray[np.bool_]:
    """The QP's inequality rows guessed active (:func:`sqp.subproblem.active_guess`): those the last QP's
    multipliers hold, or at the first iteration those with a starting multiplier (``st.mu`` is then its size; a
    two-sided row is guessed on its upper side). At a start without multipliers, the rows its zero step violates or
    meets with no slack (within ``tol · max(1, ‖x‖∞)``): the start's working set. (Not at a start with
    multipliers: there a violated row is mostly one the step leaves, e.g. a pushed wire's new tip outside the lumen.)"""
    if st.qp is not None and st.qp.found:
        return active_guess(problem.nonlinear, problem.linear, st.qp.lam_nl, st.qp.lam_lin)
    if np.any(st.mu):
        lam = np.array(st.mu, dtype=float)
        lam[problem.nonlinear.upper] *= -1.0
        return active_guess(problem.nonlinear, problem.linear, lam, np.zeros(problem.linear.lb.size))
    return inequality_bounds([nl, lin]) <= options.tol * max(1.0, inf_norm(st.pt.x))


def _met_by_another_backend(problem: Problem, options: Options, st: State, B: Any, qp: QPStep,
                            rows: tuple[LinearisedRows, LinearisedRows], box: tuple[Array, Array],
                            initvals: Array | None) -> QPStep:
    """A consistent linearisation is met exactly by the QP's step; an answer that leaves the (small) violation where
    it was hides inside the backend's own feasibility tolerance: the next backend's answer when it meets the rows
    better, else ``qp``. Only while the point's violation could keep the solve from a SUCCESS: a largest violation
    already within a tenth of the success tolerance (``constraint_tol · max(1, ‖x‖∞)``) is not worth another
    backend (an interior-point QP of 9 600 variables took 0.17 s to meet rows violated by 3e-10 mm)."""
    v0 = float(st.pt.v.sum())
    if not (v0 > 0.1 * options.tol and len(options.backends) > 1 and not qp.elastic):
        return qp
    if st.pt.maxcv <= FEASIBLE_ENOUGH * options.constraint_tol * max(1.0, inf_norm(st.pt.x)):
        return qp
    assert qp.v_lin is not None  # (v0 > 0: there are nonlinear rows)
    v1 = float(qp.v_lin.sum())
    if v1 <= 0.5 * v0:
        return qp
    other = solve_subproblem(B, st.der.g, *rows, *box, backends=options.backends[1:], initvals=initvals)
    v_other = linearised_violation(problem, st, other.d) if other.found else None
    if v_other is not None and float(v_other.sum()) < v1:
        return replace(other, status=f"opt[{options.backends[1][0]}]" if other.status == "optimal" else other.status,
                       v_lin=v_other)
    return qp


def _elastic(problem: Problem, st: State, B: Any, rows: tuple[LinearisedRows, LinearisedRows],
             box: tuple[Array, Array], kw: dict[str, Any]) -> tuple[QPStep, float]:
    """The elastic QP of an inconsistent linearisation, and its slack price: starting at
    ``max(100, 10 max mu, 10 ||g||_inf)``, it grows tenfold (up to :data:`MAX_ELASTIC_PENALTY`) only while the elastic
    step removes less than a tenth of the linearised violation."""
    v0 = float(st.pt.v.sum())
    rho = min(MAX_ELASTIC_PENALTY, max(ELASTIC_PRICE_FLOOR, ELASTIC_PRICE_FACTOR * float(np.max(st.mu, initial=0.0)),
                                       ELASTIC_PRICE_FACTOR * inf_norm(st.der.g)))
    while True:
        qp = solve_subproblem(B, st.der.g, *rows, *box, elastic_penalty=rho, **kw)
        if not qp.found:
            return qp, rho
        qp = _with_violation(qp, linearised_violation(problem, st, qp.d))
        if rho >= MAX_ELASTIC_PENALTY:
            return qp, rho
        if v0 - float(np.sum(qp.v_lin)) >= ELASTIC_PROGRESS * v0:
            return qp, rho
        rho = min(MAX_ELASTIC_PENALTY, ELASTIC_PRICE_FACTOR * rho)


def linearised_violation(problem: Problem, st: State, d: Array) -> Array:
    """The nonlinear rows' violations linearised at the step ``d`` from ``st``: ``v(c + J d)``."""
    return problem.nonlinear.violation(st.pt.c + st.der.J @ d)


def second_order_correction(
    problem: Problem, options: Options, ev: Evaluator, st: State, d: Array, trial: Point
) -> Point | None:
    """Re-solve the QP with the constraint values at ``x + d`` (Nocedal & Wright §18.3, Maratos remedy)."""
    if not trial.finite:
        return None
    c_shift = trial.c - st.der.J @ d
    nl, lin = linearised(problem, st, c=c_shift)
    x = st.pt.x
    # the chosen backend only: a correction is optional, and a QP it fails (most often an inconsistent shifted
    # linearisation) is not worth the fallbacks' time (Clarabel: 18 % of the Hock-Schittkowski run went there)
    qp = solve_subproblem(st.B, st.der.g, nl, lin, *_box(problem, options, x),
                          backends=options.backends[:1], initvals=d)
    if not qp.found:
        return None
    return trial_point(problem, ev, x, qp.d)


def trial_point(problem: Problem, ev: Evaluator, x: Array, step: Array) -> Point:
    """``x + step`` clipped into the bounds (rounding only: the QP keeps the bounds), evaluated."""
    x_new = x + step
    return ev.point(np.clip(x_new, problem.lower, problem.upper) if problem.has_bounds else x_new)


def _with_violation(qp: QPStep, v_lin: Array) -> QPStep:
    """``qp`` carrying ``v_lin`` (the constructor: a third of ``dataclasses.replace``'s cost)."""
    return QPStep(d=qp.d, lam_nl=qp.lam_nl, lam_lin=qp.lam_lin, z=qp.z, found=qp.found, elastic=qp.elastic,
                  slack=qp.slack, status=qp.status, v_lin=v_lin)


def _equality_only(problem: Problem, box: tuple[Array, Array]) -> bool:
    """Whether the QP has equality rows only: no inequality side of any row, no finite bound on the step."""
    rows = (problem.nonlinear, problem.linear)
    return (not any(r.lower.size or r.upper.size for r in rows)
            and not (np.isfinite(box[0]).any() or np.isfinite(box[1]).any()))


def _box(problem: Problem, options: Options, x: Array) -> tuple[Array, Array]:
    """The bounds on the step ``d``: the variable bounds, within ``options.step_bound`` of ``x`` in every component."""
    return (np.maximum(problem.lower - x, -options.step_bound), np.minimum(problem.upper - x, options.step_bound))
