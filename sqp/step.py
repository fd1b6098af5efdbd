"""The QP step at the current iterate (paper Eqs. 9–10): the subproblem assembled from the state, its elastic form
when the linearisation is inconsistent, and the second-order correction of a rejected step.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from numpy.typing import NDArray

from sqp.iterate import Evaluator, Point, State
from sqp.kkt import inf_norm
from sqp.options import Options
from sqp.problem import Problem
from sqp.structured import needs_convexification
from sqp.subproblem import LinearisedRows, QPStep, linearise, solve_subproblem

Array = NDArray[np.float64]


#: Largest price of a unit of slack in the elastic QP before a point is declared locally infeasible.
MAX_ELASTIC_PENALTY = 1e10


def linearised(problem: Problem, st: State, c: Array | None = None) -> tuple[LinearisedRows, LinearisedRows]:
    """The nonlinear rows linearised at ``st`` (with the values ``c`` instead of ``st.pt.c`` when given) and the
    linear rows, as QP rows in the step ``d``."""
    nl = linearise(st.der.J, st.pt.c if c is None else c, problem.nonlinear)
    lin = linearise(problem.A, st.pt.r, problem.linear)
    return nl, lin


def qp_step(problem: Problem, options: Options, st: State, rho: float) -> tuple[QPStep, float]:
    """The QP at the current iterate; its elastic form when it is inconsistent.

    The slack price starts at ``max(100, 10 max mu, 10 ||g||_inf)`` and grows tenfold (up to
    :data:`MAX_ELASTIC_PENALTY`) only while the elastic step removes less than a tenth of the linearised violation.

    An indefinite :class:`sqp.structured.FactoredHessian` in ``st.B`` (an exact Hessian left unconvexified by
    :func:`sqp.hessian.convexify`) serves an equality-only QP whose KKT matrix has the right inertia; otherwise
    ``st.B`` is replaced by its convexification here, before any backend sees it.
    """
    nl, lin = linearised(problem, st)
    x = st.pt.x
    kw = {"backends": options.backends, "initvals": None if st.qp is None else st.qp.d}
    box = _box(problem, options, x)
    if needs_convexification(st.B) and not _equality_only(problem, box):
        st.B = st.B.convexified()
    qp = solve_subproblem(st.B, st.der.g, nl, lin, *box, **kw)
    if not qp.found and needs_convexification(st.B):  # K's inertia is wrong: W is not convex on E's null space
        st.B = st.B.convexified()
        qp = solve_subproblem(st.B, st.der.g, nl, lin, *box, **kw)
    rows = problem.nonlinear
    v0 = float(st.pt.v.sum())
    if qp.found and rows.lb.size:
        qp = _with_violation(qp, linearised_violation(problem, st, qp.d))
    if qp.found and v0 > 0.1 * options.tol and len(options.backends) > 1 and not qp.elastic:
        # a consistent linearisation is met exactly by the QP's step; an answer that leaves the (small) violation
        # where it was hides inside the backend's own feasibility tolerance (DAQP: 1e-6): ask the next backend
        assert qp.v_lin is not None  # (v0 > 0: there are nonlinear rows)
        v1 = float(qp.v_lin.sum())
        if v1 > 0.5 * v0:
            other = solve_subproblem(st.B, st.der.g, nl, lin, *_box(problem, options, x),
                                     backends=options.backends[1:], initvals=kw["initvals"])
            v_other = linearised_violation(problem, st, other.d) if other.found else None
            if v_other is not None and float(v_other.sum()) < v1:
                qp = replace(other, status=f"opt[{options.backends[1][0]}]" if other.status == "optimal"
                             else other.status, v_lin=v_other)
    if qp.found or rows.lb.size == 0:
        return qp, 0.0
    rho = min(MAX_ELASTIC_PENALTY, max(1e2, 10.0 * float(np.max(st.mu, initial=0.0)),
                                       10.0 * inf_norm(st.der.g)))
    while True:
        qp = solve_subproblem(st.B, st.der.g, nl, lin, *_box(problem, options, x), elastic_penalty=rho,
                              **kw)
        if not qp.found:
            return qp, rho
        qp = _with_violation(qp, linearised_violation(problem, st, qp.d))
        if rho >= MAX_ELASTIC_PENALTY:
            return qp, rho
        v1 = float(np.sum(qp.v_lin))
        if v0 - v1 >= 0.1 * v0:
            return qp, rho
        rho = min(MAX_ELASTIC_PENALTY, 10.0 * rho)


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
