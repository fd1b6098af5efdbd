"""The L1 merit function (paper Eq. 12), its directional derivative, the penalty update (Eq. 13) and backtracking.

``phi(x; mu) = f(x) + sum_i mu_i v_i(x)`` where ``v_i`` is the violation of nonlinear row ``i`` (``|c_i - lb_i|`` for
an equality, ``max(0, lb_i - c_i, c_i - ub_i)`` otherwise). Linear rows and bounds are satisfied by every iterate and
so do not enter ``phi``.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from sqp.iterate import Point, State
from sqp.problem import Problem, Rows
from sqp.subproblem import QPStep

Array = NDArray[np.float64]

#: Armijo sufficient-decrease fraction ``eta`` of the merit line search (Nocedal & Wright, Algorithm 18.3 and
#: Eq. 3.4, where ``c1 = 1e-4`` is the customary value).
ARMIJO = 1e-4
#: Backtracking keeps the new step within [BACKTRACK_MIN, BACKTRACK_MAX] times the old one: the safeguards of the
#: quadratic-interpolation backtrack of Dennis & Schnabel (1983), Algorithm A6.3.1 (``[0.1, 0.5]``).
BACKTRACK_MIN = 0.1
BACKTRACK_MAX = 0.5
#: The fraction ``rho`` of the decrease of the quadratic model the penalty must secure (Nocedal & Wright, Eq. 18.36,
#: ``rho in (0, 1)``).
DESCENT_FRACTION = 0.5


def merit(f: float, c: Array, rows: Rows, mu: Array) -> float:
    """``phi = f + sum(mu * v(c))`` (Eq. 12); ``inf`` when ``f`` or ``c`` is not finite."""
    if not np.isfinite(f) or not np.all(np.isfinite(c)):
        return np.inf
    return float(f + mu @ rows.violation(c))


def merit_at(pt: Point, mu: Array) -> float:
    """:func:`merit` at an evaluated point, from the violations it holds."""
    if not pt.finite:
        return np.inf
    return float(pt.f + mu @ pt.v)


def directional_derivative(g: Array, d: Array, c: Array, Jd: Array, rows: Rows, mu: Array) -> float:
    """``D(phi; d) = g^T d + sum mu_i (v_i(c + J d) - v_i(c))`` of the linearised merit function.

    Equals ``g^T d - sum mu_i v_i(c)`` when ``d`` satisfies the linearised rows (Nocedal & Wright, Thm 18.2).
    """
    return linear_change(float(g @ d), rows.violation(c), rows.violation(c + Jd), mu)


def linear_change(gd: float, v0: Array, v_lin: Array, mu: Array) -> float:
    """:func:`directional_derivative` from its parts: ``g^T d``, the violations at ``x`` and those of the rows
    linearised at ``x + d``."""
    return float(gd + mu @ (v_lin - v0))


def update_penalty(mu: Array, lam: Array) -> Array:
    """Powell's update (Eq. 13; Powell 1978, Eq. 4.4): ``mu_i = max(|lam_i|, (mu_i + |lam_i|) / 2)``."""
    a = np.abs(lam)
    return np.maximum(a, 0.5 * (mu + a))


def next_step_length(alpha: float, phi0: float, D: float, phi_alpha: float) -> float:
    """Safeguarded quadratic-interpolation backtrack; a non-finite trial shrinks by the minimum factor."""
    if not np.isfinite(phi_alpha):
        return BACKTRACK_MIN * alpha
    denom = 2.0 * (phi_alpha - phi0 - D * alpha)
    trial = -D * alpha * alpha / denom if denom > 0 else BACKTRACK_MAX * alpha
    return float(np.clip(trial, BACKTRACK_MIN * alpha, BACKTRACK_MAX * alpha))


def descent_penalty(gd: float, dBd: float, violation_decrease: float, rho: float = DESCENT_FRACTION) -> float:
    """Smallest uniform penalty making ``d`` a descent direction of enough decrease (Nocedal & Wright, Eq. 18.36).

    ``mu >= (g^T d + 1/2 d^T B d) / ((1 - rho) * dv)`` where ``dv = v(c) - v(c + J d)`` is the decrease of the
    linearised violation. Powell's update (Eq. 13) alone leaves ``mu = 0`` for a violated row whose QP multiplier is
    zero, and the line search would then trade feasibility for objective decrease.
    """
    if violation_decrease <= 0.0:
        return 0.0
    return max(0.0, (gd + 0.5 * max(dBd, 0.0)) / ((1.0 - rho) * violation_decrease))


def penalties(problem: Problem, st: State, qp: QPStep) -> Array:
    """The merit penalties for the step ``qp.d`` from ``st``: Powell's update (Eq. 13) of ``st.mu`` with the QP's
    multipliers, raised where needed to make the step a descent direction of the merit function with enough decrease
    (:func:`descent_penalty`, Nocedal & Wright Eq. 18.36)."""
    mu = update_penalty(st.mu, qp.lam_nl)
    if mu.size:
        d, rows = qp.d, problem.nonlinear
        v_lin = qp.v_lin if qp.v_lin is not None else rows.violation(st.pt.c + st.der.J @ d)
        dv = float(st.pt.v.sum() - v_lin.sum())
        mu = np.maximum(mu, descent_penalty(float(st.der.g @ d), float(d @ (st.B @ d)), dv))
    return mu
