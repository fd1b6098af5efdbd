"""When a solve ends: the tests of the SQP loop that stop it or restart it — divergence (unbounded), stalled
infeasibility, the ACCEPTABLE rule, stalls, a vanishing constraint gradient that calls for a bounded restart — each a
pure function of its inputs, with its constants named here."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from sqp.iterate import Point, State
from sqp.kkt import KKTResiduals, cancellation, inf_norm, kkt_residuals
from sqp.options import Options
from sqp.problem import Problem
from sqp.result import Result, Status
from sqp.subproblem import QPStep

Array = NDArray[np.float64]

#: Scaled KKT level accepted as success (status ACCEPTABLE) when rounding errors stop progress towards ``tol``; the
#: stationarity level is this times the cancellation factor of the Lagrangian gradient (:func:`acceptable`). The
#: level of IPOPT's ``acceptable_tol`` (1e-6), which serves the same purpose.
ACCEPTABLE_TOL = 1e-6

#: A step that changes x by at most this, relative to ``1 + ||x||_inf``, is negligible (:func:`negligible`): about
#: ten thousand times the rounding unit (2.2e-16), where rounding noise in f or c drives the steps.
NEGLIGIBLE_STEP = 1e-12

#: A QP step at most this, relative to ``1 + ||x||_inf``, is a vanishing one (:func:`stalled_status`): a hundred times
#: the rounding unit.
VANISHING_STEP = 1e-14

#: The violation above which a failed elastic search is a (local) minimiser of the violation
#: (:func:`stalled_status`): SLSQP's default ``acc`` (1e-6), far above any rounding-limited residual.
INFEASIBLE_VIOLATION = 1e-6

#: Failures that, at an infeasible point, start the solve again from ``x0`` with a step bound
#: (:func:`sqp.solver.run`):
#: the ends of first steps that jumped into a region where the linearisation misleads (HS88, HS90, HS92: to
#: ``x = 0``, where the constraint gradient vanishes, a local minimiser of the violation).
RESTART_STATUSES = (Status.INFEASIBLE, Status.LINE_SEARCH, Status.SMALL_STEP)

#: How far the linearisation of a violated row may ask the step to go, in units of ``max(1, ||x||_inf)``, before its
#: gradient counts as vanishing (:func:`flat_violation`).
RESTART_REACH = 100.0

#: The step bound of the restart, relative to ``max(1, ||x0||_inf)``, on every component of the step.
RESTART_STEP_BOUND = 0.2

#: The number of iterations of the restart that keep the step bound (the trust region of the first iterations).
RESTART_BOUNDED_ITERATIONS = 10


def flat_violation(problem: Problem, st: State, tol: float) -> bool:
    """Whether some nonlinear row is violated at ``st`` by more than ``tol * max(1, ||x||_inf)`` while its gradient is
    so small that the linearisation would need a step longer than :data:`RESTART_REACH` ``* max(1, ||x||_inf)`` to
    remove the violation: a point where the constraint gradient (nearly) vanishes, whose INFEASIBLE verdict says
    nothing about the problem (HS88: ``x = 0``)."""
    v = problem.nonlinear.violation(st.pt.c)
    x_scale = max(1.0, float(np.max(np.abs(st.pt.x), initial=0.0)))
    rows = np.flatnonzero(v > tol * x_scale)
    if rows.size == 0:
        return False
    J = st.der.J[rows]
    size = np.asarray(abs(J).max(axis=1).todense()).ravel() if sp.issparse(J) else np.max(np.abs(J), axis=1)
    return bool(np.any(v[rows] > RESTART_REACH * x_scale * size))


#: Iterates diverge (status UNBOUNDED) at a feasible point whose objective fell below ``f(x0)`` by this factor of
#: ``max(1, |f(x0)|)`` while ``||x||_inf`` grew beyond this factor of ``max(1, ||x0||_inf)``: ten orders of magnitude
#: in both, far from any Hock–Schittkowski solve. (IPOPT's ``diverging_iterates_tol`` is an absolute 1e20 on x
#: alone; on a linear objective the damped-BFGS steps grow geometrically, so 1e10 is reached in about a dozen
#: iterations.)
DIVERGENCE_FACTOR = 1e10

#: Consecutive elastic iterations without a 1 % reduction of the least violation reached after which the solve
#: ends INFEASIBLE: the elastic steps no longer reduce the violation, so the iterates circle a local minimiser of it
#: (Fletcher & Leyffer's filter SQP and SNOPT's elastic mode stop on the same evidence).
INFEASIBLE_STALL = 10

#: The relative reduction of the least violation that counts as progress within :data:`INFEASIBLE_STALL`.
INFEASIBLE_PROGRESS = 0.01


@dataclass(frozen=True)
class Origin:
    """The objective and the size of the start, against which divergence is measured."""

    f: float
    x_scale: float


def diverging(origin: Origin, pt: Point, maxcv: float, tol: float) -> bool:
    """Whether ``pt`` is feasible and both its objective and its size have run away from the start by
    :data:`DIVERGENCE_FACTOR` (an unbounded problem)."""
    x_size = inf_norm(pt.x)
    if maxcv > tol * max(1.0, x_size):
        return False
    return bool(pt.f < origin.f - DIVERGENCE_FACTOR * max(1.0, abs(origin.f))
                and x_size > DIVERGENCE_FACTOR * origin.x_scale)


def infeasibility_stalled(least_trace: list[float], elastic_run: int, tol: float) -> bool:
    """Whether the last :data:`INFEASIBLE_STALL` iterations were all elastic and the least violation reached, still
    above ``tol``, fell by less than :data:`INFEASIBLE_PROGRESS` over them."""
    if elastic_run < INFEASIBLE_STALL or least_trace[-1] <= tol:
        return False
    return least_trace[-1] > (1.0 - INFEASIBLE_PROGRESS) * least_trace[-1 - INFEASIBLE_STALL]


def acceptable(problem: Problem, st: State, kkt: KKTResiduals, qp: QPStep, tol: float,
               feasibility_tol: float | None = None) -> bool:
    """Whether a point where no step makes progress passes the ACCEPTABLE test with the multipliers of ``qp``:
    feasible to ``feasibility_tol`` (default ``tol``), complementarity at most ``max(ACCEPTABLE_TOL, tol)`` and
    stationarity at most that times the factor by which the terms of the Lagrangian gradient exceed it
    (:func:`~sqp.kkt.cancellation`): rounding in those terms, not the distance to a KKT point, limits the residual
    there (a hanging chain of 150 links: residual 2e-6 with tensions 150 times the gradient)."""
    level = max(ACCEPTABLE_TOL, tol)
    if not kkt.feasible(tol if feasibility_tol is None else feasibility_tol) or kkt.complementarity > level:
        return False
    if kkt.stationarity <= level:
        return True
    return kkt.stationarity <= level * cancellation(problem, st.pt.x, st.der.g, st.der.J, qp.lam_nl, qp.lam_lin, qp.z)


def closer(second: Result, first: Result, tol: float) -> bool:
    """Whether the failed ``second`` is nearer a solution than the failed ``first``: less violation when ``first``
    is infeasible, else feasible with a lower objective."""
    if first.success:
        return False
    if first.maxcv > tol:
        return bool(second.maxcv < first.maxcv)
    return bool(second.maxcv <= tol and second.fun < first.fun)


def at_step_bound(options: Options, d: Array) -> bool:
    """Whether the step ``d`` reaches ``options.step_bound`` in some component (to a relative 1e-9)."""
    return bool(np.isfinite(options.step_bound)
                and inf_norm(d) >= (1.0 - 1e-9) * options.step_bound)


#: A Newton step (exact Hessians) of at most this, relative to ``1 + ||x||_inf``, is settled (:func:`settled`): about
#: the square root of the rounding unit, so that the point it leads to lies within about its square (~1e-16, times
#: the curvature's scale) of the limit, where more steps only move x by rounding. At 1e-10 the threshold sat inside the
#: rounding noise of the guidewire's 3-D rod at 1 600-3 200 bars (19 µm bars: steps of 2.6-5.2e-10 after
#: convergence), so one to three more iterations and a 14-evaluation line search ran or not by rounding luck; at 1e-8
#: those steps end in 4 iterations instead of 5-7, their nodes within 6e-12 mm and energies within 7e-15 of the
#: longer solves', and none of the project's 148 bit-comparison cases (paper scenes, vessels, Hock–Schittkowski) moves.
SETTLED_STEP = 1e-8


def settled(x: Array, d: Array) -> bool:
    """Whether an exact-Hessian QP step ``d`` from ``x`` is at most :data:`SETTLED_STEP` relative to
    ``1 + ||x||_inf``: Newton's method then stands within about the square of that of its limit, and once the
    residual is rounding's, more iterations only move x by rounding noise (the guidewire's 3-D rod at 3 200 bars:
    KKT residual ~5e-7 after 5 iterations, then 3-7 more steps of 1e-13-5e-10 mm, the residual scattering between
    5e-8 and 3e-4, before three negligible ones in a row stopped it; see :data:`sqp.monitor.SETTLED_STEPS`)."""
    return _relatively_below(d, x, SETTLED_STEP)


def negligible(x: Array, x_new: Array) -> bool:
    """Whether a step changed x by at most :data:`NEGLIGIBLE_STEP` relative to ``1 + ||x||_inf`` (rounding noise in
    f or c drives such steps)."""
    return _relatively_below(x_new - x, x, NEGLIGIBLE_STEP)


def _relatively_below(step: Array, x: Array, level: float) -> bool:
    """Whether ``||step||_inf <= level (1 + ||x||_inf)``."""
    return bool(inf_norm(step) <= level * (1.0 + inf_norm(x)))


def stalled_status(problem: Problem, st: State, d: Array) -> Status:
    """Why no step was accepted: non-finite values along the step, a vanishing step, or a failed search."""
    if _relatively_below(d, st.pt.x, VANISHING_STEP):
        if st.qp is not None and st.qp.elastic and np.max(st.pt.v, initial=0.0) > 0:
            return Status.INFEASIBLE
        return Status.SMALL_STEP
    if st.qp is not None and st.qp.elastic and st.pt.maxcv > INFEASIBLE_VIOLATION:
        # the linearisation is inconsistent here and no step along the elastic direction reduces the merit: a
        # (local) minimiser of the violation, not a derivative or scaling problem
        return Status.INFEASIBLE
    return Status.LINE_SEARCH


def kkt_at(problem: Problem, st: State, feasibility: float | None = None) -> KKTResiduals:
    """The KKT residuals at the state's point with its last QP's multipliers (``feasibility``: the point's largest
    violation, when known)."""
    qp = st.qp
    assert qp is not None
    return kkt_residuals(problem, st.pt.x, st.der.g, st.pt.c, st.der.J, st.pt.r, qp.lam_nl, qp.lam_lin, qp.z,
                         feasibility)
