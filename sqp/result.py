"""Status codes whose values are the user-facing messages, the per-iteration record and the result object."""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum

from scipy.optimize import OptimizeResult


class Status(Enum):
    """Why a solve ended. ``code`` is ``Result.status``; ``value`` is the message."""

    SUCCESS = (0, "Optimization terminated successfully: KKT residuals are below tol.")
    MAX_ITER = (1, "The iteration limit was reached before the KKT residuals fell below tol; increase max_iter.")
    LINE_SEARCH = (2, "The line search could not reduce the merit function; the derivatives may be wrong or the "
                      "problem badly scaled.")
    INFEASIBLE = (3, "The constraints could not be satisfied: the solver converged to a point that locally "
                     "minimises the constraint violation but is infeasible.")
    QP_FAILED = (4, "The QP subproblem could not be solved, even in its elastic form; try another qp_solver.")
    NONFINITE = (5, "A user function (the objective, a constraint or a derivative) returned NaN or inf, at the start "
                    "or at every trial point down to the shortest step.")
    CALLBACK = (6, "Stopped by the callback (StopIteration).")
    SMALL_STEP = (7, "The step became too small to make progress before the KKT residuals fell below tol.")
    LINEAR_INFEASIBLE = (8, "The linear constraints and bounds have no common point.")
    ACCEPTABLE = (9, "Converged to an acceptable level: the point is feasible to tol and its scaled KKT residuals are "
                     "below 1e-6, but rounding errors prevent further progress towards tol.")

    @property
    def code(self) -> int:
        return self.value[0]

    @property
    def message(self) -> str:
        return self.value[1]

    @classmethod
    def from_code(cls, code: int) -> Status:
        """The status whose :attr:`code` is ``code`` (``Result.status``); ValueError for an unknown code."""
        for status in cls:
            if status.code == code:
                return status
        raise ValueError(f"no sqp.Status has code {code!r}; codes are {[s.code for s in cls]}.")


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
    multipliers : dict
        The same by block: ``"eq"`` (equality rows), ``"ineq"`` (inequality rows), ``"bounds"``.
    kkt : dict
        ``stationarity``, ``feasibility``, ``complementarity`` at ``x``.
    history : list of IterationRecord
        One record per iteration.
    hess : ndarray
        The final quasi-Newton matrix.
    qp_solver : str
        The QP backend used (the one ``qp_solver="auto"`` chose, or the one named).
    """
