"""Backtracking on the L1 merit function (paper Eq. 12) along the QP step, with one second-order correction: pure
functions of the state and the penalties, returning what they found (the evaluations they make are counted by the
:class:`~sqp.iterate.Evaluator`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from sqp.iterate import Derivatives, Evaluator, Point, State
from sqp.merit import ARMIJO, merit_at, next_step_length
from sqp.options import Options
from sqp.problem import Problem
from sqp.step import second_order_correction, trial_point
from sqp.subproblem import QPStep

Array = NDArray[np.float64]


#: Smallest step length tried by the backtracking line search.
MIN_STEP_LENGTH = 1e-10

#: Only steps this short measure the merit function's noise (:func:`line_search`): there a smooth merit function's
#: departure from its linear model, ``O(alpha^2)``, is at most 1e-4 of the full step's.
NOISE_STEP_LENGTH = 1e-2

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
    full step.

    A point is accepted only when its values and its derivatives are finite: NaN or inf from any user function
    (objective, constraint, gradient or Jacobian) at a trial point shortens the step. Fails (``pt is None``) when no
    step length down to :data:`MIN_STEP_LENGTH` decreases the merit function enough. ``mu`` is not modified.
    ``v_lin``: the rows' violations linearised at ``d`` (:attr:`~sqp.subproblem.QPStep.v_lin`), when known.

    ``noise``: the merit function's rounding noise found by an earlier search (0: none), allowed twice over in the
    sufficient-decrease test (the noise-tolerant Armijo test of Berahas, Byrd & Nocedal, SIAM J. Optim. 29, 2019).
    When the backtracking fails, the departures ``|phi(alpha) - phi0 - alpha D|`` of the short steps
    (``alpha <= NOISE_STEP_LENGTH``), which a smooth merit function keeps at ``O(alpha^2)``, measure that noise. If
    the departures of all the shortened steps exceed even the full step's predicted decrease ``|D|``, the merit
    function cannot tell good steps from bad ones (a value summing large terms that cancel near the solution:
    HS268's constant 14463 with ``f* = 0``), and the full step is taken when its merit is within twice the noise of
    ``phi0`` (a merit function equal to ``phi0`` at every trial, its changes below its resolution, has a noise of
    at least ``|D|``); the search reports the noise (:attr:`Search.noise`) for the next ones. Progress is then
    judged by the KKT residuals, which do not suffer the cancellation.
    """
    rows = problem.nonlinear
    # (the violations at x and of the linearisation at x + d, once: merit(), directional_derivative() in one)
    v0 = st.pt.v
    if v_lin is None:
        v_lin = rows.violation(st.pt.c + st.der.J @ d)
    gd = float(st.der.g @ d)
    phi0 = float(st.pt.f + mu @ v0)
    D = float(gd + mu @ (v_lin - v0))
    if D >= 0.0:
        # an inexact QP can give an ascent direction; a steeper penalty restores descent when d is infeasible
        if np.any(v0 > 0):
            mu = mu + (D + 1.0) / float(np.sum(v0)) * (v0 > 0)
            phi0 = float(st.pt.f + mu @ v0)
            D = float(gd + mu @ (v_lin - v0))
        if D >= 0.0:
            return Search(mu=mu)
    alpha = 1.0
    tried_soc = not options.second_order_correction or rows.lb.size == 0
    nonfinite: str | None = None
    tried = alpha
    full: tuple[Point, float] | None = None  # the full step and its merit
    seen = 0.0  # the largest |phi(alpha) - phi0 - alpha D| over the short steps (alpha <= NOISE_STEP_LENGTH)
    spread = 0.0  # the same over every shortened step
    flat = True  # every merit value so far equal to phi0: a change of |D| is below the merit's resolution
    while alpha >= MIN_STEP_LENGTH:
        trial = trial_point(problem, ev, st.pt.x, d if alpha == 1.0 else alpha * d)  # (1.0 * d is d)
        if (trial.x == st.pt.x).all():
            # the step is below the rounding level of x: no progress is possible along d
            break
        tried = alpha
        nonfinite = None if trial.finite else ev.nonfinite_source(trial)
        phi = merit_at(trial, mu)
        flat = flat and phi == phi0
        if alpha == 1.0:
            full = (trial, phi)
        elif np.isfinite(phi):
            departure = abs(phi - phi0 - alpha * D)
            spread = max(spread, departure)
            if alpha <= NOISE_STEP_LENGTH:
                seen = max(seen, departure)
        if phi <= phi0 + ARMIJO * alpha * D + 2.0 * noise:
            der = ev.derivatives(trial)
            if der.finite:
                return Search(trial, der, alpha, False, mu=mu, noise=noise)
            nonfinite, phi = ev.nonfinite_source(trial, der), np.inf  # shorten the step as for a NaN value
        if not tried_soc and _curvature_rejected(trial, v_lin, mu, phi0 + ARMIJO * D):
            tried_soc = True
            corrected = second_order_correction(problem, options, ev, st, d, trial)
            if corrected is not None and merit_at(corrected, mu) <= phi0 + ARMIJO * D:
                der = ev.derivatives(corrected)
                if der.finite:
                    return Search(corrected, der, 1.0, True, mu=mu)
        alpha = next_step_length(alpha, phi0, D, phi)
    floor = abs(D) if flat else 0.0
    return (_within_noise(ev, full, phi0, D, max(seen, noise, floor), max(spread, noise, floor), mu)
            or Search(alpha=tried, nonfinite=nonfinite, mu=mu))


def _within_noise(ev: Evaluator, full: tuple[Point, float] | None, phi0: float, D: float, seen: float,
                  spread: float, mu: Array) -> Search | None:
    """After a failed backtracking: the full step, carrying the noise ``seen``, when the departures from the linear
    model (``spread``, over every shortened step) exceed the full step's predicted decrease ``|D|`` and the step's
    merit is within twice the noise ``seen`` (measured on the short steps only, where curvature cannot pose as
    noise) of ``phi0`` (see :func:`line_search`); else None."""
    if full is None or not (seen > 0.0 and abs(D) <= spread):
        return None
    trial, phi = full
    if not (trial.finite and phi <= phi0 + 2.0 * seen):
        return None
    der = ev.derivatives(trial)
    return Search(trial, der, 1.0, False, mu=mu, noise=seen) if der.finite else None


def merit_search(problem: Problem, options: Options, ev: Evaluator, st: State, qp: QPStep, mu: Array,
                 noise: float = 0.0) -> Search:
    """:func:`line_search` along ``qp.d`` with the penalties ``mu``; when it fails with penalties above
    :data:`PENALTY_RESET_FACTOR` times the QP's largest multiplier, once more with the penalties restarted from the
    QP's multipliers (Eq. 13 from scratch)."""
    search = line_search(problem, options, ev, st, qp.d, mu, qp.v_lin, noise)
    assert search.mu is not None
    if search.pt is None and np.max(search.mu, initial=0.0) > PENALTY_RESET_FACTOR * max(
            float(np.max(np.abs(qp.lam_nl), initial=0.0)), 1e-12):
        search = line_search(problem, options, ev, st, qp.d, np.abs(qp.lam_nl), qp.v_lin, noise)
    return search


def _curvature_rejected(trial: Point, v_lin: Array, mu: Array, accept: float) -> bool:
    """Whether a rejected full step would have been accepted with the violation its linearisation predicts
    (``v_lin``, per row) instead of the one found at ``trial``: the constraints' curvature rejected it, which a
    second-order correction removes (the Maratos effect; Nocedal & Wright §15.5, §18.3). A step whose objective alone
    fails the test ``accept`` was rejected for the objective's sake, which a correction of the constraint values,
    a change of second order in the step, does not repair."""
    return bool(trial.finite and trial.f + mu @ v_lin <= accept)
