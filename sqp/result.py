"""Status codes whose values are the user-facing messages, the per-iteration record and the result object."""

from __future__ import annotations

import time
from dataclasses import dataclass
from enum import IntEnum
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import OptimizeResult

from sqp.kkt import KKTResiduals, kkt_residuals, max_violation

if TYPE_CHECKING:
    from sqp.iterate import Derivatives, Evaluator, Point
    from sqp.problem import Problem
    from sqp.subproblem import QPStep

Array = NDArray[np.float64]


class Status(IntEnum):
    """Why a solve ended: an ``int`` (``Result.status``) that carries its message.

    The numbering never contradicts scipy's SLSQP (``scipy.optimize.minimize(method="SLSQP")``): a code that SLSQP
    can return means the same here (0 success, 4 incompatible constraints, 8 no descent in the line search, 9
    iteration limit, and 99, which ``scipy.optimize.minimize`` sets when the callback raises ``StopIteration``). The
    outcomes SLSQP has no code for use 10 and above. SLSQP's 2, 3, 5, 6 and 7 (failures inside its own LSQ
    subproblem) have no counterpart here and are never returned.

    ======  =================  ====================================================================
    code    name               SLSQP's meaning of the code
    ======  =================  ====================================================================
    0       SUCCESS            "Optimization terminated successfully"
    4       INFEASIBLE         "Inequality constraints incompatible"
    8       LINE_SEARCH        "Positive directional derivative for linesearch"
    9       MAX_ITER           "Iteration limit reached"
    10      ACCEPTABLE         (none: a success at a looser level, ``success`` is True)
    11      QP_FAILED          (none)
    12      NONFINITE          (none)
    13      SMALL_STEP         (none)
    14      LINEAR_INFEASIBLE  (none)
    15      UNBOUNDED          (none)
    99      CALLBACK           "`callback` raised `StopIteration`." (set by scipy's ``minimize``)
    ======  =================  ====================================================================
    """

    message: str

    def __new__(cls, code: int, message: str) -> Status:
        member = int.__new__(cls, code)
        member._value_ = code
        member.message = message
        return member

    SUCCESS = (0, "Optimization terminated successfully: KKT residuals are below tol.")
    INFEASIBLE = (4, "The constraints could not be satisfied: the solver converged to a point that locally "
                     "minimises the constraint violation but is infeasible.")
    LINE_SEARCH = (8, "The line search could not reduce the merit function; the derivatives may be wrong or the "
                      "problem badly scaled.")
    MAX_ITER = (9, "The iteration limit was reached before the KKT residuals fell below tol; increase max_iter.")
    ACCEPTABLE = (10, "Converged to an acceptable level: the point is feasible to tol and its scaled KKT residuals are "
                      "below 1e-6 (stationarity relative to the size of the Lagrangian gradient's terms), but rounding "
                      "errors prevent further progress towards tol.")
    QP_FAILED = (11, "The QP subproblem could not be solved, even in its elastic form; try another qp_solver.")
    NONFINITE = (12, "A user function (the objective, a constraint or a derivative) returned NaN or inf, at the start "
                     "or at every trial point down to the shortest step.")
    SMALL_STEP = (13, "The step became too small to make progress before the KKT residuals fell below tol.")
    LINEAR_INFEASIBLE = (14, "The linear constraints and bounds have no common point.")
    UNBOUNDED = (15, "The problem appears unbounded below: the objective decreased without bound at feasible points.")
    CALLBACK = (99, "`callback` raised `StopIteration`.")  # scipy's own message for this end

    @property
    def code(self) -> int:
        """The number (``Result.status``)."""
        return int(self)

    @property
    def success(self) -> bool:
        """Whether the status counts as a success (SUCCESS and ACCEPTABLE)."""
        return self in (Status.SUCCESS, Status.ACCEPTABLE)

    @classmethod
    def from_code(cls, code: int) -> Status:
        """The status whose :attr:`code` is ``code`` (``Result.status``); ValueError for an unknown code."""
        try:
            return cls(int(code))
        except ValueError:
            raise ValueError(f"no sqp.Status has code {code!r}; codes are {[s.code for s in cls]}.") from None


@dataclass(frozen=True)
class IterationRecord:
    """One row of the iteration history (and of the verbose table)."""

    nit: int
    nfev: int
    f: float
    maxcv: float
    kkt: float
    step: float
    alpha: float
    penalty: float
    qp_status: str
    damped: bool
    soc: bool


class Result(OptimizeResult):
    """A :class:`scipy.optimize.OptimizeResult` with the engine's extra fields.

    Attributes
    ----------
    x, fun, jac, success, status, message, nit, nfev, njev, maxcv
        As in scipy. ``maxcv`` is the largest absolute violation of any constraint or bound at ``x``.
    constraint_multipliers : list of ndarray
        One array per entry of ``constraints`` as passed: ``grad f = sum_i J_i^T lam_i + bound_multipliers`` at a KKT
        point; ``lam >= 0`` for an ``ineq`` dict; for two-sided rows ``lam > 0`` when the lower side is active and
        ``lam < 0`` when the upper side is.
    bound_multipliers : ndarray (n,)
        Positive at an active lower bound, negative at an active upper bound.
    multipliers : ndarray
        As scipy's SLSQP returns them: equality rows first, then inequality rows, in SLSQP's order, ``>= 0`` on
        every inequality written ``g(x) >= 0`` (an upper side is ``ub - c(x) >= 0``); no bound multipliers
        (:attr:`sqp.problem.Problem.slsqp_rows`).
    x0_clipped : ndarray of int
        Indices where ``x0`` lay outside the bounds and was clipped onto them.
    kkt : KKTResiduals
        ``stationarity``, ``feasibility``, ``complementarity`` at ``x``, as attributes and as a read-only mapping
        (``res.kkt["stationarity"]``).
    history : list of IterationRecord
        One record per iteration.
    hess : ndarray
        The final quasi-Newton matrix.
    qp_solver : str
        The QP backend used (the one ``qp_solver="auto"`` chose, or the one named).
    """


def build_result(
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
    kkt: KKTResiduals | None = None,
) -> Result:
    """The :class:`Result` of a solve that ended with ``status`` at ``pt`` (None: before the start was evaluated,
    at ``x``), with the multipliers of ``qp`` and the KKT residuals there (``kkt``, when the loop computed them
    already)."""
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
    finite = bool(np.isfinite(c).all())
    # (a Point carries max_violation at its x already: the same number, not computed again)
    if pt is not None:
        violation = pt.maxcv
    else:
        violation = max_violation(problem, xx, c, np.asarray(r).ravel()) if finite else np.inf
    if kkt is None:
        kkt = (kkt_residuals(problem, xx, g, c, der.J, r, lam_nl, lam_lin, z, feasibility=violation)
               if der is not None else KKTResiduals.unknown())
    maxcv = violation if finite else np.inf
    per_constraint = problem.split_multipliers(lam_lin, lam_nl)
    message = status.message
    if status is Status.MAX_ITER:
        message = message.replace("max_iter", f"max_iter (now {nit})")
    if detail:
        message = f"{message} {detail}"
    res = Result(
        x=xx.copy(), fun=float(f), jac=g, success=status.success,
        status=status, message=message,
        nit=nit, nfev=ev.nfev, njev=ev.njev, maxcv=float(maxcv),
        constraint_multipliers=per_constraint,
        bound_multipliers=z.copy(),
        multipliers=problem.slsqp_multipliers(per_constraint),
        x0_clipped=problem.x0_clipped.copy(),
        nhev=ev.nhev, kkt=kkt, history=history, hess=B, status_name=status.name,
        solve_time=time.perf_counter() - t_start,
    )
    return res
