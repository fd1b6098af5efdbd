"""The model Hessian of the QP as a strategy with one small interface (as scipy's ``HessianUpdateStrategy``): the
paper's damped BFGS (Eq. 6) or the exact Lagrangian Hessian made positive definite. The loop calls the same three
methods whichever it holds; the kernels live in :mod:`sqp.hessian` and :mod:`sqp.multipliers`.

Symbols (Nocedal & Wright, Procedure 18.2): ``B`` the model, ``s = x+ - x``, ``y = grad L(x+, lam) - grad L(x, lam)``
with ``lam`` the QP's multipliers.
"""

from __future__ import annotations

from typing import Any, Protocol

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from sqp.hessian import augmented, convexify, damped_bfgs_update, initial_scaling, shifted_augmented
from sqp.iterate import Derivatives, Evaluator, State
from sqp.kkt import inf_norm
from sqp.multipliers import al_rows, equality_rows, held_rows, newton_multipliers, nonlinear_lagrangian_gradient
from sqp.problem import Problem
from sqp.structured import FactoredHessian
from sqp.subproblem import QPStep

#: Weights tried (tenfold apart, from the last one) for the augmented-Lagrangian term on every held row, where the
#: given rows' term leaves the model indefinite: the ladder of :func:`sqp.hessian.convexify`, without its identity
#: shift (with 4 rungs no widening succeeded on the tortuous 3-D vessel, whose insertion then stopped at 46 mm).
WIDENED_RUNGS = 10

Array = NDArray[np.float64]


#: The longest first step of a BFGS solve started without ``hess0``, in units of ``max(1, ||x0||_inf)`` (infinity
#: norm): the identity start is scaled up to ``||g0||_inf / (FIRST_STEP_LENGTH max(1, ||x0||_inf))`` when the
#: gradient is steeper. Chosen on Hock–Schittkowski (benchmarks/hock_schittkowski.py): 5 solved HS61 and cut the
#: mean evaluations by 1.5 (HS64: 181 -> 41) without losing a solved problem; 1-3 did as well on the mean but turned
#: ACCEPTABLE/SUCCESS answers of HS62 and HS268 into failures, 2 sent HS13 to the iteration limit.
FIRST_STEP_LENGTH = 5.0


class HessianStrategy(Protocol):
    """How the loop obtains the QP's Hessian ``B``: before the QP (:meth:`model`), around its multipliers
    (:meth:`multipliers`) and after an accepted step (:meth:`update`)."""

    def initial(self, st: State) -> Any:
        """``B`` before the first iteration, at the start ``st`` (whose ``B`` is not yet set); None when :meth:`model`
        builds every ``B`` itself."""
        ...

    def model(self, ev: Evaluator, st: State) -> Any:
        """``B`` for the QP at ``st`` (None when a user Hessian returned NaN or inf: ``ev.hessian_nonfinite`` names
        it)."""
        ...

    def multipliers(self, st: State, qp: QPStep) -> QPStep:
        """The QP's answer with the multipliers that belong to the model's step."""
        ...

    def update(self, st: State, der: Derivatives, qp: QPStep, s: Array, first: bool) -> tuple[Any, bool]:
        """``B`` after the step ``s`` from ``st`` to a point with derivatives ``der``, and whether it was damped."""
        ...


class DampedBFGS:
    """The paper's damped BFGS (Eq. 6, Powell 1978's damping; Nocedal & Wright Procedure 18.2).

    ``B`` starts from ``B0`` (``hess0``) or a multiple of the identity that keeps the first, steepest-descent step
    within :data:`FIRST_STEP_LENGTH` ``* max(1, ||x0||_inf)`` (in the infinity norm), the role of the unit first
    step of L-BFGS-B and of the scaled first step of Nocedal & Wright §6.1: with the bare identity a gradient of
    1e5 (HS64) asks for a step of 1e5 and the line search spends dozens of backtracks undoing it. That start is
    replaced by Shanno–Phua's ``(y^T y / s^T y) I`` before the first update (Nocedal & Wright, Eq. 6.20). ``y`` is
    the change of the gradient of the Lagrangian of the nonlinear rows at the QP's multipliers (linear rows and
    bounds have constant gradients).
    """

    def __init__(self, problem: Problem, B0: Array | None) -> None:
        self.problem = problem
        self.B0 = B0
        self.scale_start = B0 is None

    def initial(self, st: State) -> Any:
        B0 = self.B0
        if B0 is not None:
            return np.eye(self.problem.n) if sp.issparse(B0) else B0.copy()
        # the identity, scaled so that the first (steepest-descent) step is at most FIRST_STEP_LENGTH max(1, |x|)
        g = inf_norm(st.der.g)
        size = max(1.0, inf_norm(st.pt.x))
        return np.eye(self.problem.n) * max(1.0, g / (FIRST_STEP_LENGTH * size))

    def model(self, ev: Evaluator, st: State) -> Any:
        return st.B

    def multipliers(self, st: State, qp: QPStep) -> QPStep:
        return qp

    def update(self, st: State, der: Derivatives, qp: QPStep, s: Array, first: bool) -> tuple[Any, bool]:
        p = self.problem
        y = nonlinear_lagrangian_gradient(p, der, qp) - nonlinear_lagrangian_gradient(p, st.der, qp)
        B = np.eye(p.n) * initial_scaling(s, y) if self.scale_start and first else st.B
        return damped_bfgs_update(B, s, y)


class ConvexifiedExact:
    """The exact Lagrangian Hessian ``W = grad^2 f - sum lam_i grad^2 c_i`` at ``(x_k, lam_{k-1})`` made positive
    definite by :func:`~sqp.hessian.convexify` (an augmented-Lagrangian term on the rows the QP keeps as equalities,
    else an identity shift); with the augmented-Lagrangian term the QP's multipliers are corrected back to the
    Newton step's (:func:`~sqp.multipliers.newton_multipliers`).

    Keeps between iterations the last shift and augmented-Lagrangian weight (each the start of the next search) and
    the rows that weight was applied on.
    """

    def __init__(self, problem: Problem, lam0: Array | None, inequalities: bool | tuple[int, ...] = True,
                 rungs: int | None = None) -> None:
        self.problem = problem
        # (True: every held inequality joins the term; a tuple: those among these rows, and every held one where they
        # leave W indefinite; False: none)
        self.inequalities = bool(inequalities) if isinstance(inequalities, bool) else True
        self.allowed = None if isinstance(inequalities, bool) else np.union1d(
            problem.nonlinear.eq, np.asarray(inequalities, dtype=np.intp))
        self.rungs = rungs
        self.lam0 = np.zeros(problem.nonlinear.lb.size) if lam0 is None else lam0
        self.shift = 0.0
        self.weight = 0.0
        # whether W is expected positive definite (tested alone first): at a start without multipliers W is the
        # objective's Hessian (the guidewire's energy: positive definite); with them, and after a W that was not,
        # W + r0 C^T C is tested first (one factorisation less when W is indefinite, the same answer)
        self.definite = not np.any(self.lam0)
        self.rows: Array = np.zeros(0, dtype=np.intp)
        self.widened = False  # (whether the last model needed the term on every held row)
        self.widen_failed = False  # (whether it was tried and did not help: not tried again at the next model)
        self.held: Array | None = None  # (the rows the last QP found held, :func:`~sqp.multipliers.held_rows`)
        self.factored: FactoredHessian | None = None

    def initial(self, st: State) -> Any:
        # (no matrix: :meth:`model` builds one from the exact Hessian before the first QP)
        return None

    def model(self, ev: Evaluator, st: State) -> Any:
        lam = st.qp.lam_nl if st.qp is not None else self.lam0
        if not self.inequalities:
            self.rows = self.problem.nonlinear.eq
        elif st.qp is not None and self.held is not None:
            self.rows = self.held
        else:  # (the start's multipliers, or an elastic QP's)
            self.rows = al_rows(self.problem, lam)
        held = self.rows
        if self.allowed is not None:
            self.rows = np.intersect1d(self.rows, self.allowed, assume_unique=True)
        W = ev.lagrangian_hessian(st.pt.x, lam)
        if ev.hessian_nonfinite is not None:
            return None
        widen = self.allowed is not None and held.size > self.rows.size
        if widen and self.widened:  # (they were needed last time: tried first, the W it leaves indefinite spared)
            found = self._widened(W, st, held)
            if found is not None:
                return found
        C = equality_rows(self.problem, st.der.J, self.rows)
        B, self.shift, self.weight = convexify(W, self.shift, C, self.weight, self.definite,
                                               self.problem.equality_only, self.rungs,
                                               dense_limit=self.problem.dense_limit)
        self.widened = False
        if widen and self.shift > 0.0 and self.widen_failed:
            self.widen_failed = False  # (skipped once)
        elif widen and self.shift > 0.0:
            # (the given rows leave W indefinite: every held row joins the term before any identity shift — a shift
            # as large as the softest mode the held rows stabilise, a wire pushed against the walls and over a
            # crease, made each step move a few percent of the way)
            found = self._widened(W, st, held)
            if found is not None:
                return found
        if (not self.inequalities or self.allowed is not None or self.rungs is not None) and self.shift > 0.0 \
                and C is not None:
            # W is not positive definite on the held rows' null space (or only with a weight past the ladder's
            # rungs): the shift goes on top of the augmented-Lagrangian term, so that it need only cover that null
            # space (W alone can be far more indefinite across the rows: a compressed wire's closure forces)
            B, self.shift, self.weight = shifted_augmented(W, C, self.shift)
        return self._keep(B)

    def _widened(self, W: Any, st: State, held: Array) -> Any:
        """The model with the term on every ``held`` row when a weight of :data:`WIDENED_RUNGS` makes it positive
        definite (and ``widened`` set, so the next iteration tries it first), else None."""
        C_all = equality_rows(self.problem, st.der.J, held)
        found = augmented(W, C_all, self.weight, WIDENED_RUNGS, self.problem.dense_limit)
        self.widened = found is not None
        self.widen_failed = not self.widened
        if found is None:
            return None
        B, self.shift, self.weight = found
        self.rows = held
        return self._keep(B)

    def _keep(self, B: Any) -> Any:
        self.definite = self.shift == 0.0 and self.weight == 0.0
        self.factored = B if isinstance(B, FactoredHessian) else None
        return B

    def multipliers(self, st: State, qp: QPStep) -> QPStep:
        if self.factored is not None and self.factored.convexification is not None:
            # (the QP needed the factored W convexified after all: its shift and weight, as if model had made it)
            self.shift, self.weight = self.factored.convexification
            self.definite = self.shift == 0.0 and self.weight == 0.0
            self.factored = None
        if not qp.found:
            return qp
        if qp.elastic:
            self.held = None
            return qp
        self.held = held_rows(self.problem, st, qp) if self.inequalities else self.problem.nonlinear.eq
        if self.weight > 0.0:
            return newton_multipliers(self.problem, st, qp, self.rows, self.weight, self.held)
        return qp

    def update(self, st: State, der: Derivatives, qp: QPStep, s: Array, first: bool) -> tuple[Any, bool]:
        return st.B, False


def hessian_strategy(problem: Problem, B0: Array | None, lam0: Array | None,
                     inequalities: bool | tuple[int, ...] = True, rungs: int | None = None) -> HessianStrategy:
    """:class:`ConvexifiedExact` when the problem carries exact Hessians (its augmented-Lagrangian term on the active
    inequalities too when ``inequalities`` is True, on those among its rows when it is a tuple of nonlinear row
    indices, its weight's ladder ``rungs`` long), else :class:`DampedBFGS` from ``B0``."""
    if problem.hess is not None:
        return ConvexifiedExact(problem, lam0, inequalities, rungs)
    return DampedBFGS(problem, B0)
