"""Solver options, validated once before any work."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field, replace
from functools import cached_property
from typing import TYPE_CHECKING, Any

from sqp.backends import AUTO, DEFAULT_QP_OPTIONS, auto_choice, check_solver_name, installed_solvers

#: The default ``qp_fallbacks``.
DEFAULT_QP_FALLBACKS = ("quadprog", "clarabel")

#: Backends that work on dense matrices (their cost O(n^3)), left out of the default fallbacks of a program that
#: ``qp_solver="auto"`` solves with a sparse backend (above ``DENSE_LIMIT`` variables, every Jacobian sparse).
DENSE_BACKENDS = frozenset({"quadprog", "daqp"})

if TYPE_CHECKING:
    from sqp.problem import Problem


#: The default violation tolerance of a SUCCESS (relative to ``max(1, ||x||_inf)``): about a million rounding units,
#: the level SLSQP's final iterates reach, far below any finite-difference error in the derivatives.
FEASIBILITY_TOL = 1e-10


@dataclass(frozen=True)
class Options:
    """Settings of one solve (:func:`sqp.minimize` builds one from its keyword arguments).

    Attributes
    ----------
    tol : float
        Tolerance on the scaled KKT residuals (stationarity, complementarity).
    feasibility_tol : float or None
        Tolerance on the largest constraint violation, relative to ``max(1, ||x||_inf)``, for a SUCCESS. None (the
        default): ``tol`` when every derivative is the user's, and ``min(tol, FEASIBILITY_TOL)`` (1e-10) when some
        are finite differences (:meth:`for_problem`). The violation is computed from the constraint values, exact to
        rounding however inexact the derivatives, so the loose stationarity tolerance that differences need (1e-6)
        must not loosen it: a success at ``x0^2 - 1 = -2e-8`` would fail a user's ``>= -1e-8`` check, where SLSQP's
        final iterate meets its rows near rounding.
    max_iter : int
        Maximum number of SQP iterations.
    qp_solver : str
        qpsolvers backend for the subproblems, or ``"auto"`` (the default): chosen once per solve, after the problem
        is built, from its structure (:func:`sqp.backends.choose_qp_solver`), and reported as ``Result.qp_solver``
        and in the verbose header. The rule, with ``n`` variables:

        - ``n <=`` :data:`sqp.DENSE_LIMIT` (300; :func:`sqp.minimize`'s ``dense_limit``), where the engine works
          densely: ``"daqp"`` (dense dual active set). On the Hock–Schittkowski subproblems it was both the most
          accurate installed backend (exact active sets and multipliers) and the fastest
          (``benchmarks/results/hock_schittkowski.md``).
        - larger, with every constraint Jacobian sparse (each nonlinear ``jac`` at ``x0`` and each
          ``LinearConstraint.A`` a scipy.sparse matrix): ``"piqp"`` (sparse interior point), 10-20 ms per
          subproblem on a sparse full-space program with 1600 bars (4800 variables), where Clarabel took 50 ms and
          OSQP did not converge.
        - larger, with some dense Jacobian rows: ``"daqp"`` again (such a program is dense anyway; Clarabel, a
          sparse interior point, took 30-80x longer on the guidewire's reduced wall programs at 400-800 bars).

        A backend the rule picks but that is not installed is replaced by the first installed one of
        ``daqp, piqp, clarabel, osqp, quadprog, proxqp`` (:data:`sqp.backends.PREFERENCE`).

        Any installed backend can be named instead (:func:`sqp.installed_solvers`); a name is used exactly as
        given. ``"osqp"`` (the backend first named for the project) runs with SQP-grade accuracy settings,
        warm-started and polished, but is not the default: an ADMM method, its multipliers are sometimes too
        inexact for the merit and BFGS updates even at eps 1e-9 (117 Hock–Schittkowski problems solved against
        DAQP's 118, and 3.1x slower), and on the large sparse program it did not converge in 4000 iterations.
    qp_options : dict
        Backend settings, merged over :data:`sqp.backends.DEFAULT_QP_OPTIONS` of the backend used.
    callback : callable or None
        ``callback(intermediate_result)`` after every iteration; raising ``StopIteration`` ends the solve.
    verbose : bool
        Print the backend used and the iteration table.
    second_order_correction : bool
        Try a second-order correction when the full step is rejected (the Maratos-effect remedy).
    qp_fallbacks : tuple of str
        Backends asked, in order, when ``qp_solver`` fails a subproblem even after its retries (skipped when not
        installed). The iteration table marks such a step ``opt[name]``. ``()`` disables the fallback. With
        ``qp_solver="auto"`` above the dense limit (:data:`sqp.DENSE_LIMIT` variables), every Jacobian sparse, the
        default list
        drops the dense backends (:data:`DENSE_BACKENDS`): an O(n^3) fallback of a large sparse program is no
        rescue. OSQP is not among the defaults: on the guidewire's aortic arch at 250 bars 52 subproblems failed
        DAQP, quadprog and Clarabel (degenerate elastic QPs the iteration recovers from), where OSQP spent 0.9 s each
        for a 49 s solve; without it 5.8 s and the same answer; Hock–Schittkowski unchanged (115 solved, 0 false
        successes).
    step_bound : float
        Largest change of any variable in one step of the first :data:`sqp.termination.RESTART_BOUNDED_ITERATIONS` (10)
        iterations (a box trust region on the QP); ``inf`` (the default): none. A QP whose step reaches it gives no
        KKT certificate (its bound multipliers include the box's).
    convexify_inequalities : bool or tuple of int
        With exact Hessians, whether the augmented-Lagrangian term that makes the model Hessian positive definite
        (:func:`sqp.hessian.convexify`) also covers the nonlinear inequalities active at the last step (True, the
        default), only those among the given nonlinear rows (indices into the nonlinear rows, in the order of
        ``constraints``: rows whose curvature makes ``W`` indefinite where they hold, as a wire over a convex edge;
        where the term on them leaves ``W`` indefinite, every held inequality joins it before an identity shift is
        tried), or only the equalities (False; where ``W`` is not positive definite on their null space an identity
        shift is added on top of the term, :func:`sqp.hessian.shifted_augmented`). On a row the QP keeps active the
        term leaves the step unchanged; on a row the QP releases it penalises leaving, so when the active set moves
        along many rows at every iteration (a wire sliding along a vessel wall: its contact nodes change from step
        to step) each step can release a row only a little and convergence turns linear. A 3-D wire pushed through
        a helix: 300+ iterations per step with True, 3-7 with False.
    active_set_guess : bool
        Solve a QP with a sparse model Hessian and no bounds first on the active set the last QP's multipliers (or
        the starting ones) guess, by one banded KKT solve corrected at most twice (once for the first QP;
        :func:`sqp.active_set.guessed_qp`; an equality-only QP by that one solve), and ask the backends only when
        that fails (False, the default: the backends always). The answer is the QP's exact solution where an
        interior-point backend gives it to its tolerance; on the guidewire's 3-D program (1200-1500 variables) one
        such solve takes about 1 ms against PIQP's 5-7 ms. A dense model Hessian that carries its Cholesky factor
        (:class:`sqp.hessian.CholeskyHessian`, an exact Hessian convexified) gets the same guess by the
        range-space method (:func:`sqp.subproblem._factored_guess`): the solution DAQP gives, to rounding, without
        transforming every row into the factor's coordinates (the guidewire's 250 mm arch insertion, 200-250 bars
        and 400-500 dense rows: about 3 ms a QP with DAQP).
    augmented_rungs : int or None
        With exact Hessians, how many weights of the augmented-Lagrangian ladder (each tenfold the last, from
        :data:`sqp.hessian.AL_WEIGHT_START`) are tried before an identity shift is added on top of the term
        (:func:`sqp.hessian.shifted_augmented`); None (the default): :data:`sqp.hessian.AL_WEIGHT_RUNGS` (10), then
        a shift of ``W`` alone on the inequality path. Large weights certify a Hessian whose curvature on the held
        rows' null space is tiny, but leave the QP ill-conditioned: on the guidewire's compressed wires in the
        full-space vessel program (S-bend and tortuous vessels, 320-800 bars) the full ladder reached model
        diagonals of 1e15, the guessed active set failed its residual check and PIQP its iteration limit (a solve
        took 2.8-20 s); with 5 rungs and the shift on top, 0.25-2.1 s and the same energies to 1e-9.
    extend_shifted_steps : bool
        With exact Hessians, whether a full step of a model that needed an identity shift is extended (doubled
        while the merit function keeps falling, :func:`sqp.linesearch.expanded`; True, the default): near a saddle
        the shifted step creeps at ``|g| / delta``. On the guidewire's compressed 2-D wires it took the S-bend at
        400 bars from 512 iterations to 77 and a double well from its saddle in 5-13 instead of 23-35. A program
        whose shifted steps cross a snap (the guidewire's 3-D J tip turned in a helix) may spend the doublings
        overshooting; there False (measured there: 75 s for the whole turn against more than 7 min).
    restoration : bool
        After an INFEASIBLE end with nonlinear rows, minimise the violation from the last point
        (:mod:`sqp.restoration`) and report that point, or solve again from it when its violation is within
        tolerance.
    restart : bool
        After a failure (INFEASIBLE, LINE_SEARCH, SMALL_STEP) on a problem with nonlinear constraints, solve again
        from ``x0`` with a step bound on the first iterations (:func:`sqp.solver.run`).

    Raises
    ------
    TypeError, ValueError
        On construction, naming the field and the fix (an unknown ``qp_solver`` lists ``"auto"`` and the installed
        backends).
    """

    tol: float = 1e-8
    feasibility_tol: float | None = None
    max_iter: int = 500
    qp_solver: str = AUTO
    qp_options: dict[str, Any] = field(default_factory=dict)
    callback: Callable[[Any], Any] | None = None
    verbose: bool = False
    second_order_correction: bool = True
    qp_fallbacks: tuple[str, ...] = DEFAULT_QP_FALLBACKS
    step_bound: float = float("inf")
    restart: bool = True
    restoration: bool = True
    convexify_inequalities: bool | tuple[int, ...] = True
    active_set_guess: bool = False
    augmented_rungs: int | None = None
    extend_shifted_steps: bool = True

    def __post_init__(self) -> None:
        if not isinstance(self.tol, int | float) or not self.tol > 0:
            raise ValueError(f"tol = {self.tol!r}; expected a positive number such as 1e-8.")
        if self.feasibility_tol is not None and (not isinstance(self.feasibility_tol, int | float)
                                                 or not self.feasibility_tol > 0):
            raise ValueError(f"feasibility_tol = {self.feasibility_tol!r}; expected a positive number such as 1e-10, "
                             "or None for min(tol, 1e-10).")
        if isinstance(self.max_iter, bool) or not isinstance(self.max_iter, int) or self.max_iter < 0:
            raise ValueError(f"max_iter = {self.max_iter!r}; expected a nonnegative integer.")
        if self.augmented_rungs is not None and (isinstance(self.augmented_rungs, bool)
                                                 or not isinstance(self.augmented_rungs, int)
                                                 or self.augmented_rungs < 0):
            raise ValueError(f"augmented_rungs = {self.augmented_rungs!r}; expected a nonnegative integer (the "
                             "weights tried, e.g. 5), or None for the engine's ladder.")
        if not isinstance(self.step_bound, int | float) or not self.step_bound > 0:
            raise ValueError(f"step_bound = {self.step_bound!r}; expected a positive number (inf: no bound).")
        if not isinstance(self.qp_solver, str):
            raise TypeError(f"qp_solver must be a backend name (str) or 'auto'; got {type(self.qp_solver).__name__}.")
        check_solver_name(self.qp_solver)
        if not isinstance(self.qp_options, dict):
            raise TypeError(f"qp_options must be a dict of backend settings; got {type(self.qp_options).__name__}.")
        if self.callback is not None and not callable(self.callback):
            raise TypeError("callback must be callable: callback(intermediate_result).")

    @property
    def constraint_tol(self) -> float:
        """The violation tolerance of a SUCCESS: ``feasibility_tol``, else ``tol``."""
        return self.feasibility_tol if self.feasibility_tol is not None else self.tol

    def for_problem(self, problem: Problem) -> Options:
        """These options with ``qp_solver="auto"`` replaced by the backend chosen for ``problem`` (unchanged when a
        backend is named) and ``feasibility_tol=None`` by its value for ``problem`` (``min(tol, FEASIBILITY_TOL)``
        when some derivative is a finite difference, else ``tol``)."""
        out = self
        if self.feasibility_tol is None:
            out = replace(out, feasibility_tol=min(self.tol, FEASIBILITY_TOL) if problem.differenced else self.tol)
        if self.qp_solver != AUTO:
            return out
        choice = auto_choice(problem.n, problem.sparse_jacobians, dense_limit=problem.dense_limit)[0]
        out = replace(out, qp_solver=choice)
        if not problem.dense and problem.sparse_jacobians and self.qp_fallbacks == DEFAULT_QP_FALLBACKS:
            # (a sparse program above the dense limit: a dense backend's O(n^3) fallback is no rescue — quadprog took
            # 55-111 s a subproblem of a 2 900-variable 3-D arch step where Clarabel took 0.7-1.1 s for the same
            # step, and 2.3 s each of 11 subproblems of a 960-variable 2-D S-bend)
            out = replace(out, qp_fallbacks=tuple(b for b in self.qp_fallbacks if b not in DENSE_BACKENDS))
        return out

    @property
    def backend_options(self) -> dict[str, Any]:
        """Backend settings actually passed to qpsolvers."""
        return {**DEFAULT_QP_OPTIONS.get(self.qp_solver, {}), **self.qp_options}

    @cached_property
    def backends(self) -> list[tuple[str, dict[str, Any]]]:
        """The chosen backend with its settings, then the installed fallbacks with theirs."""
        if self.qp_solver == AUTO:
            raise ValueError("qp_solver='auto' names no backend yet; use options.for_problem(problem).backends.")
        out = [(self.qp_solver, self.backend_options)]
        for name in self.qp_fallbacks:
            if name != self.qp_solver and name in installed_solvers():
                out.append((name, dict(DEFAULT_QP_OPTIONS.get(name, {}))))
        return out
