"""Backtracking on the L1 merit function (paper Eq. 12) along the QP step, with one second-order correction: pure
functions of the state and the penalties, returning what they found (the evaluations they make are counted by the
:class:`~sqp.iterate.Evaluator`).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from sqp.iterate import Derivatives, Evaluator, Point, State
from sqp.merit import ARMIJO, linear_change, merit_at, next_step_length
from sqp.noise import noise_along
from sqp.options import Options
from sqp.problem import Problem
from sqp.step import second_order_correction, trial_point
from sqp.subproblem import QPStep
from sqp.termination import negligible

Array = NDArray[np.float64]


#: Smallest step length tried by the backtracking line search.
MIN_STEP_LENGTH = 1e-10

#: The sufficient-decrease test allows this much rounding relative to ``|phi0|`` (IPOPT's comparisons ``lhs <= rhs``
#: of its line search allow ``10 eps_mach |phi0|``): a change below the resolution of ``phi0`` proves nothing.
ROUNDING_RELAXATION = 10.0 * np.finfo(float).eps

#: A failed search is repeated with the penalties reset to the QP's multipliers when they exceed the largest of those
#: by this factor: penalties inflated by early, poorly scaled multipliers (Powell's update, Eq. 13, only lets them
#: fall by halves) make the merit function reject every step.
PENALTY_RESET_FACTOR = 10.0


@dataclass(frozen=True)
class Search:
    """What a line search gave: the accepted point with its derivatives (``pt is None`` when none was accepted).

    ``nonfinite`` names the user function that returned NaN or inf at the last point tried (None when that point was
    finite); ``alpha`` is the accepted step length, or the last one tried; ``mu`` the penalties of the merit function
    used (the ones given, or raised to make an ascent direction of the merit function a descent one)."""

    pt: Point | None = None
    der: Derivatives | None = None
    alpha: float = 0.0
    soc: bool = False
    nonfinite: str | None = None
    mu: Array | None = None
    #: The merit function's rounding noise as this search found it (0 when it saw none; see :func:`line_search`).
    noise: float = 0.0


def line_search(problem: Problem, options: Options, ev: Evaluator, st: State, d: Array, mu: Array,
                v_lin: Array | None = None, noise: float = 0.0) -> Search:
    """Armijo backtracking on the L1 merit function with penalties ``mu``, with one second-order correction of the
    full step, tolerant of the merit function's noise.

    A point is accepted only when its values and its derivatives are finite: NaN or inf from any user function
    (objective, constraint, gradient or Jacobian) at a trial point shortens the step. ``mu`` is not modified.
    ``v_lin``: the rows' violations linearised at ``d`` (:attr:`~sqp.subproblem.QPStep.v_lin`), when known.

    Noise: ``noise`` is a bound ``eps_f`` on the merit function's noise found by an earlier search (0: none), and the
    sufficient-decrease test is relaxed by ``2 eps_f`` (the noise-tolerant Armijo test of Berahas, Byrd & Nocedal,
    SIAM J. Optim. 29, 2019). When backtracking fails down to :data:`MIN_STEP_LENGTH` with finite values, the
    merit function's noise along ``d`` is estimated from its values on a small stencil (Moré & Wild's ECnoise,
    :func:`sqp.noise.noise_along`); if that bound exceeds ``noise`` the backtracking is repeated once with it. A
    step whose predicted decrease is below the noise is then taken on the evidence of the values being within their
    noise, and progress is judged by the KKT residuals, computed from the derivatives, which do not suffer the
    cancellation. A failure with noise-free values (wrong derivatives, a step that is not a descent direction) is
    still a failure (``pt is None``). The bound used is returned (:attr:`Search.noise`) for the next searches.
    """
    v0 = st.pt.v  # (the violations at x and of the linearisation at x + d, each computed once)
    if v_lin is None:
        v_lin = problem.nonlinear.violation(st.pt.c + st.der.J @ d)
    gd = float(st.der.g @ d)
    phi0 = merit_at(st.pt, mu)  # the merit function (Eq. 12) and its directional derivative along d
    D = linear_change(gd, v0, v_lin, mu)
    if D >= 0.0:
        # an inexact QP can give an ascent direction; a steeper penalty restores descent when d is infeasible
        if np.any(v0 > 0):
            mu = mu + (D + 1.0) / float(np.sum(v0)) * (v0 > 0)
            phi0 = merit_at(st.pt, mu)
            D = linear_change(gd, v0, v_lin, mu)
        if D >= 0.0:
            return Search(mu=mu)
    search, full = _backtrack(problem, options, ev, st, d, mu, v_lin, phi0, D, noise)
    if not _noise_suspected(st, search, full):
        return search
    assert full is not None
    bound = _merit_noise(problem, ev, st, d, mu, full)
    if bound <= noise:
        return search
    if search.pt is None:
        return _backtrack(problem, options, ev, st, d, mu, v_lin, phi0, D, bound)[0]
    # a short step was accepted: when the full step is within the noise found, its rejection was the noise's
    if merit_at(full, mu) <= phi0 + ARMIJO * D + 2.0 * bound:
        der = ev.derivatives(full)
        if der.finite:
            return Search(full, der, 1.0, False, mu=mu, noise=bound)
    return replace(search, noise=bound)


def _noise_suspected(st: State, search: Search, full: Point | None) -> bool:
    """Whether a search's outcome may be the merit function's noise: no step accepted though every value was
    finite, or only a shortened step that changes ``x`` by no more than rounding does (:func:`negligible`)."""
    if full is None or not full.finite or search.nonfinite is not None:
        return False
    if search.pt is None:
        return True
    return search.alpha < 1.0 and negligible(st.pt.x, search.pt.x)


def _merit_noise(problem: Problem, ev: Evaluator, st: State, d: Array, mu: Array, full: Point) -> float:
    """A bound on the merit function's noise along ``d``: the objective's noise plus the penalties times the
    constraint values' noise (a violation changes by no more than its row's value), each estimated on its own
    (:func:`sqp.noise.noise_along`; the merit's kinks where a row turns active would pose as noise)."""

    def values_at(alpha: float) -> Array | None:
        pt = trial_point(problem, ev, st.pt.x, alpha * d)
        return np.concatenate(([pt.f], pt.c)) if pt.finite else None

    slopes = np.concatenate(([float(st.der.g @ d)], np.asarray(st.der.J @ d).ravel()))
    bounds, _ = noise_along(values_at, np.concatenate(([st.pt.f], st.pt.c)), slopes,
                            np.concatenate(([full.f], full.c)))
    return float(bounds[0] + mu @ bounds[1:])


def _backtrack(problem: Problem, options: Options, ev: Evaluator, st: State, d: Array, mu: Array, v_lin: Array,
               phi0: float, D: float, noise: float) -> tuple[Search, Point | None]:
    """Backtracking from the full step with the Armijo test of the full step (and of its second-order correction)
    relaxed by ``2 noise`` and the rounding of ``phi0``, and one second-order correction of the full step; the
    search's result and the full step's point (None when it was not evaluated). The shortened steps get the plain
    test: a short step accepted within the noise would be no progress either way, and would only postpone the
    verdict of the stall test (a run of such steps of 1e-11 reached the iteration limit)."""
    alpha = 1.0
    tried_soc = not options.second_order_correction or problem.nonlinear.lb.size == 0
    nonfinite: str | None = None
    tried = alpha
    full: Point | None = None
    relax = 2.0 * noise + ROUNDING_RELAXATION * abs(phi0)
    while alpha >= MIN_STEP_LENGTH:
        trial = trial_point(problem, ev, st.pt.x, d if alpha == 1.0 else alpha * d)  # (1.0 * d is d)
        if (trial.x == st.pt.x).all():
            # the step is below the rounding level of x: no progress is possible along d
            break
        tried = alpha
        nonfinite = None if trial.finite else ev.nonfinite_source(trial)
        phi = merit_at(trial, mu)
        if alpha == 1.0:
            full = trial
        if phi <= phi0 + ARMIJO * alpha * D + (relax if alpha == 1.0 else 0.0):
            der = ev.derivatives(trial)
            if der.finite:
                return Search(trial, der, alpha, False, mu=mu, noise=noise), full
            nonfinite, phi = ev.nonfinite_source(trial, der), np.inf  # shorten the step as for a NaN value
        if not tried_soc and _curvature_rejected(trial, v_lin, mu, phi0 + ARMIJO * D + relax):
            tried_soc = True
            corrected = second_order_correction(problem, options, ev, st, d, trial)
            if corrected is not None and merit_at(corrected, mu) <= phi0 + ARMIJO * D + relax:
                der = ev.derivatives(corrected)
                if der.finite:
                    return Search(corrected, der, 1.0, True, mu=mu, noise=noise), full
        alpha = next_step_length(alpha, phi0, D, phi)
    return Search(alpha=tried, nonfinite=nonfinite, mu=mu, noise=noise), full


def merit_search(problem: Problem, options: Options, ev: Evaluator, st: State, qp: QPStep, mu: Array,
                 noise: float = 0.0, shifted: bool = False) -> Search:
    """:func:`line_search` along ``qp.d`` with the penalties ``mu``; when it fails with penalties above
    :data:`PENALTY_RESET_FACTOR` times the QP's largest multiplier, once more with the penalties restarted from the
    QP's multipliers (Eq. 13 from scratch). With ``shifted`` (the model Hessian was the exact one plus an identity
    shift: indefinite on the null space of the rows the QP holds) an accepted full step is then extended
    (:func:`expanded`)."""
    search = line_search(problem, options, ev, st, qp.d, mu, qp.v_lin, noise)
    assert search.mu is not None
    if search.pt is None and np.max(search.mu, initial=0.0) > PENALTY_RESET_FACTOR * max(
            float(np.max(np.abs(qp.lam_nl), initial=0.0)), 1e-12):
        search = line_search(problem, options, ev, st, qp.d, np.abs(qp.lam_nl), qp.v_lin, noise)
    if shifted and search.pt is not None and search.alpha == 1.0 and not search.soc:
        search = expanded(problem, ev, st, qp.d, search, options.step_bound)
    return search


#: Longest step, in units of the QP's step, that :func:`expanded` tries.
MAX_EXPANSION = 2.0**10


def expanded(problem: Problem, ev: Evaluator, st: State, d: Array, search: Search,
             step_bound: float = np.inf) -> Search:
    """The accepted full step ``d`` doubled while the merit function keeps falling, by at least the Armijo fraction
    of its slope at the last length, and the linear rows stay as met as at ``d`` (up to :data:`MAX_EXPANSION`, and
    never past the QP's ``step_bound`` in the infinity norm: a bounded start keeps its steps short).

    A shifted model makes the step short where the Hessian is indefinite: along a direction of negative curvature
    ``d = -(W + delta I)^-1 g`` has length ``|g| / (delta - |lambda|)``, so near a saddle of the Lagrangian on the
    held rows (a compressed wire about to buckle sideways) the iterates creep at ``|g| / delta`` a step while the
    merit function falls ever faster along ``d``. The doubling is the extrapolation phase of a line search
    (Nocedal & Wright, Algorithm 3.5): it stops at the first length that does not improve on the last, so it costs
    one evaluation where the full step was already right."""
    assert search.pt is not None and search.mu is not None
    mu = search.mu
    best, phi_best, alpha_best = search.pt, merit_at(search.pt, mu), 1.0
    linear_cv = float(np.max(problem.linear.violation(best.r), initial=0.0)) if problem.linear.lb.size else 0.0
    slope = float(st.der.g @ d)  # (the merit's slope along d at alpha = 1 is not known: the objective's at 0)
    longest = min(MAX_EXPANSION, step_bound / max(float(np.max(np.abs(d), initial=0.0)), np.finfo(float).tiny))
    alpha = 1.0
    while 2.0 * alpha <= longest:
        alpha *= 2.0
        trial = trial_point(problem, ev, st.pt.x, alpha * d)
        phi = merit_at(trial, mu)
        if not phi < phi_best + ARMIJO * (alpha - alpha_best) * min(slope, 0.0):
            break
        if problem.linear.lb.size and float(np.max(problem.linear.violation(trial.r), initial=0.0)) > linear_cv:
            break
        best, phi_best, alpha_best = trial, phi, alpha
    if alpha_best == 1.0:
        return search
    der = ev.derivatives(best)
    if not der.finite:
        return search
    return Search(best, der, alpha_best, False, mu=mu, noise=search.noise)


def _curvature_rejected(trial: Point, v_lin: Array, mu: Array, accept: float) -> bool:
    """Whether a rejected full step would have been accepted with the violation its linearisation predicts
    (``v_lin``, per row) instead of the one found at ``trial``: the constraints' curvature rejected it, which a
    second-order correction removes (the Maratos effect; Nocedal & Wright §15.5, §18.3). A step whose objective alone
    fails the test ``accept`` was rejected for the objective's sake, which a correction of the constraint values,
    a change of second order in the step, does not repair."""
    return bool(trial.finite and trial.f + mu @ v_lin <= accept)
