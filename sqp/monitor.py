"""The termination step of the SQP loop: one monitor that watches the iterates and says when and why the solve ends.

It owns what the tests need across iterations — the count of stalled steps, the best multipliers seen at a stalled
point, the least violation reached (and its trace), the run of elastic QPs and the start divergence is measured
from — and answers, at three points of an iteration, with a :class:`Stop` or None. The tests themselves are the pure
functions of :mod:`sqp.termination`.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from sqp.iterate import Point, State
from sqp.kkt import KKTResiduals, inf_norm
from sqp.multipliers import loaded_rows_active
from sqp.options import Options
from sqp.problem import Problem, format_point
from sqp.result import Status
from sqp.subproblem import QPStep
from sqp.termination import (
    Origin,
    acceptable,
    at_step_bound,
    diverging,
    infeasibility_stalled,
    kkt_at,
    negligible,
    settled,
    stalled_status,
)

Array = NDArray[np.float64]

#: Consecutive steps below the rounding level of x (:func:`~sqp.termination.negligible`) after which the solve stops
#: (SMALL_STEP, or ACCEPTABLE by the best multipliers of the stalled point).
STALL_ITERATIONS = 3

#: Consecutive settled exact-Hessian QP steps (:func:`~sqp.termination.settled`) after which a point that passes the
#: ACCEPTABLE test ends the solve: the first such step takes Newton's method to rounding's level, whose residual
#: may still exceed ``tol`` by the Hessian's norm times the step (a hanging chain of 400-1 000 links: SUCCESS one
#: iteration later); a second one finds the residual where rounding leaves it.
SETTLED_STEPS = 2

#: A solve ends without a confirming QP when the last QP's multipliers pass the KKT test at the new point with
#: ``CONFIRMED_TOLERANCE * tol`` (at ``tol`` itself it would stop one Newton step earlier than the confirming QP's
#: test and leave a residual near ``tol`` where that step would square it).
CONFIRMED_TOLERANCE = 1e-2

#: An elastic QP step shorter than this, relative to ``1 + ||x||_inf``, at an infeasible point: no step reduces the
#: linearised violation, a stationary point of it (status INFEASIBLE).
ELASTIC_STATIONARY_STEP = 1e-10


@dataclass(frozen=True)
class Stop:
    """Why the loop ends: the status, a detail for the message, and the QP whose multipliers the result reports
    instead of the last one (None: the last one)."""

    status: Status
    detail: str = ""
    qp: QPStep | None = None


class Monitor:
    """Termination tests of one run of the SQP loop, with the few values they carry across iterations.

    Parameters
    ----------
    problem : Problem
    tol : float
        The KKT tolerance (``Options.tol``).
    max_iter : int
        The iteration limit (``Options.max_iter``).
    feasibility_tol : float
        The violation tolerance of a success (``Options.constraint_tol``).
    pt : Point
        The start, evaluated.
    maxcv : float
        Its largest violation.
    """

    def __init__(self, problem: Problem, tol: float, max_iter: int, pt: Point, maxcv: float,
                 feasibility_tol: float | None = None) -> None:
        self.problem = problem
        self.tol = tol
        self.feasibility_tol = tol if feasibility_tol is None else feasibility_tol
        self.max_iter = max_iter
        self.stalled = 0  # consecutive negligible steps
        self.settled_run = 0  # consecutive settled Newton steps (:func:`~sqp.termination.settled`), this one's QP's
        self.best: tuple[KKTResiduals, QPStep] | None = None  # best residuals (and their QP) at the stalled point
        self.least = (maxcv, pt.x)  # the least violation reached, and where
        self.least_trace = [maxcv]  # the least violation after each iteration
        self.elastic_run = 0  # consecutive iterations whose QP was elastic
        self.origin = Origin(f=pt.f, x_scale=max(1.0, inf_norm(pt.x)))
        #: The KKT residuals at the current point with the last QP's multipliers (set by :meth:`after_qp`).
        self.kkt = KKTResiduals.unknown()
        # the last residuals computed, with the point and QP they belong to (:meth:`residuals`)
        self._last: tuple[Point, QPStep, KKTResiduals] | None = None
        self.maxcv = maxcv  # the current point's largest violation (one evaluation per point)

    def after_qp(self, options: Options, st: State, qp: QPStep, nit: int) -> Stop | None:
        """The tests after the QP at ``st`` (``st.qp is qp`` when it was solved): a failed QP, the KKT test
        (SUCCESS), the :data:`SETTLED_STEPS`-th settled Newton step in a row (:func:`~sqp.termination.settled`) at a
        point that passes the ACCEPTABLE test, the iteration limit, a vanishing elastic step at an infeasible point
        (INFEASIBLE)."""
        if not qp.found:
            return Stop(Status.QP_FAILED, f"Backends tried: {', '.join(name for name, _ in options.backends)} "
                                          f"(last answer: {qp.status}) at iteration {nit}.")
        kkt = self._kkt_at(st, self.maxcv)
        if at_step_bound(options, qp.d):  # the bound's multipliers hide in z: no KKT certificate from this QP
            kkt = replace(kkt, stationarity=np.inf)
        self.kkt = kkt
        if self.stalled == 0 or self.best is None or kkt.worst < self.best[0].worst:
            self.best = (kkt, qp)  # the best multipliers at this (stalled) point
        if kkt.satisfied(self.tol, options.constraint_tol):
            return Stop(Status.SUCCESS)
        exact = self.problem.hess is not None and not qp.elastic
        self.settled_run = self.settled_run + 1 if exact and settled(st.pt.x, qp.d) else 0
        if self.settled_run >= SETTLED_STEPS and acceptable(self.problem, st, kkt, qp, self.tol, self.feasibility_tol):
            return Stop(Status.ACCEPTABLE)
        if nit == self.max_iter:
            return Stop(Status.MAX_ITER)
        if qp.elastic and not kkt.feasible(self.tol) and np.max(np.abs(qp.d)) <= ELASTIC_STATIONARY_STEP * (
                1 + np.max(np.abs(st.pt.x))):
            return Stop(Status.INFEASIBLE)
        return None

    def after_search(self, st: State, pt: Point | None, nonfinite: str | None, alpha: float, nit: int) -> Stop | None:
        """The tests after the line search from ``st`` found ``pt`` (None: no point accepted, ``nonfinite`` naming
        the function that returned NaN or inf at the last trial, ``alpha`` its step length): a failed search or
        :data:`STALL_ITERATIONS` negligible steps end the solve, ACCEPTABLE when the best multipliers seen at this
        point pass :func:`~sqp.termination.acceptable`."""
        self.stalled = self.stalled + 1 if pt is not None and negligible(st.pt.x, pt.x) else 0
        if pt is not None and self.stalled < STALL_ITERATIONS:
            return None
        assert st.qp is not None and self.best is not None
        if pt is not None:
            stop = Stop(Status.SMALL_STEP)
        elif nonfinite is not None:  # NaN or inf down to the shortest step tried
            stop = Stop(Status.NONFINITE, f"{nonfinite} returned NaN or inf at every trial point of iteration "
                                          f"{nit + 1} down to step length {alpha:.1e} (from x = "
                                          f"{format_point(st.pt.x)}).")
        else:
            stop = Stop(stalled_status(self.problem, st, st.qp.d))
        # (the multiplier estimates of the QPs solved while x stood still all belong to this point: the best one
        # decides; rounding makes them scatter around the limit on ill-conditioned problems such as HS116)
        if acceptable(self.problem, st, *self.best, self.tol, self.feasibility_tol):
            return Stop(Status.ACCEPTABLE, qp=self.best[1])
        return stop

    def after_step(self, st: State, maxcv: float, nit: int) -> Stop | None:
        """The tests at the new iterate ``st`` (largest violation ``maxcv``): divergence (UNBOUNDED) and elastic
        steps that no longer reduce the least violation reached (INFEASIBLE)."""
        self.maxcv = maxcv
        if maxcv < self.least[0]:
            self.least = (maxcv, st.pt.x)
        self.least_trace.append(self.least[0])
        assert st.qp is not None
        self.elastic_run = self.elastic_run + 1 if st.qp.elastic else 0
        if diverging(self.origin, st.pt, maxcv, self.tol):
            return Stop(Status.UNBOUNDED, f"At iteration {nit + 1} f = {st.pt.f:.3e} (from {self.origin.f:.3e}) at a "
                                          f"feasible x with ||x||_inf = {np.max(np.abs(st.pt.x)):.3e}.")
        if infeasibility_stalled(self.least_trace, self.elastic_run, self.tol):
            return Stop(Status.INFEASIBLE)
        return None

    def confirmed(self, options: Options, st: State, maxcv: float) -> Stop | None:
        """SUCCESS at the new iterate ``st`` without a confirming QP: the QP's multipliers are those of the new point
        to second order near a solution (Newton–SQP); when they already pass the KKT test there with
        :data:`CONFIRMED_TOLERANCE` ``* tol``, and every row they load is active there, the next Hessian and QP would
        only confirm it."""
        early = CONFIRMED_TOLERANCE * self.tol
        assert st.qp is not None
        # (the violation is measured at the new point, not predicted: it needs no margin below its tolerance)
        if (maxcv <= min(early, options.constraint_tol) * max(1.0, inf_norm(st.pt.x))  # (the cheap test first)
                and not at_step_bound(options, st.qp.d) and self._kkt_at(st, maxcv).satisfied(early, early)
                and loaded_rows_active(self.problem, st, early)):
            return Stop(Status.SUCCESS)
        return None

    def residuals(self, st: State) -> KKTResiduals | None:
        """The KKT residuals at ``st`` with its QP's multipliers when a test computed them already (the result reports
        them), else None."""
        if self._last is None:
            return None
        pt, qp, kkt = self._last
        return kkt if st.pt is pt and st.qp is qp and kkt.feasibility == pt.maxcv else None

    def _kkt_at(self, st: State, maxcv: float) -> KKTResiduals:
        """:func:`~sqp.termination.kkt_at`, remembered for :meth:`residuals`."""
        kkt = kkt_at(self.problem, st, maxcv)
        assert st.qp is not None
        self._last = (st.pt, st.qp, kkt)
        return kkt

    def detail(self, stop: Stop) -> Stop:
        """``stop`` with the least violation reached in its detail when it is INFEASIBLE."""
        if stop.status is Status.INFEASIBLE:
            return replace(stop, detail=f"Least violation reached: {self.least[0]:.2e} at x = "
                                        f"{format_point(self.least[1])}.")
        return stop
