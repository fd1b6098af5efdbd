"""Rounding at the solution: an objective whose value cancels large terms (noise far above the decrease a step can
make) and an ill-conditioned equality QP with nearly dependent rows (the nearly taut wire between two points)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import cholesky
from scipy.optimize import LinearConstraint

import sqp
from sqp.build import build_problem
from sqp.iterate import Evaluator, State
from sqp.linesearch import line_search
from sqp.noise import NOISE_BOUND, stencil_noise
from sqp.structured import REFINE_RTOL, range_space_kkt


def _cancelling_quadratic(scale: float):
    """``sum c_i (x_i - 1)^2`` written as ``x^T C x - 2 c^T x + sum c`` plus and minus ``scale``: the same function,
    with its value at the minimiser (0) computed as a difference of numbers of size ``scale`` (noise about
    ``1e-16 * scale``, far above the decrease of the last steps); the gradient and Hessian are exact to rounding."""
    c = np.geomspace(1e-2, 3e4, 6)

    def fun(x):
        return float(x @ (c * x) - 2.0 * c @ x + (c.sum() + scale)) - scale

    def jac(x):
        return 2.0 * c * (x - 1.0)

    def hess(x):
        return np.diag(2.0 * c)

    return fun, jac, hess


#: A row through the minimiser (x_1 + x_2 = 2): as a nonlinear row it enters the merit function with its penalty,
#: as a LinearConstraint every QP keeps it exactly.
_ROWS = {
    "none": (),
    "nonlinear row": ({"type": "eq", "fun": lambda x: x[0] + x[1] - 2.0,
                       "jac": lambda x: np.array([[1.0, 1, 0, 0, 0, 0]]), "hess": lambda x, v: np.zeros((6, 6))},),
    "linear row": (LinearConstraint(np.array([[1.0, 1, 0, 0, 0, 0]]), 2.0, 2.0),),
}


@pytest.mark.parametrize("hessian", ["bfgs", "exact"])
@pytest.mark.parametrize("rows", list(_ROWS))
def test_objective_noise_does_not_stop_the_solve_short_of_the_kkt_point(rows, hessian):
    """The family: 12 scales from 1e4 to 1e9 (noise 1e-12 to 1e-7 against a decrease that falls to 0), five random
    starts each; every solve reaches the KKT point the exact derivatives define, to the test's tolerances."""
    failures = []
    for scale in np.geomspace(1e4, 1e9, 12):
        fun, jac, hess = _cancelling_quadratic(scale)
        for seed in range(5):
            x0 = np.random.default_rng(seed).uniform(-3.0, 3.0, 6)
            res = sqp.minimize(fun, x0, jac=jac, hess=hess if hessian == "exact" else None, constraints=_ROWS[rows])
            error = float(np.max(np.abs(res.x - 1.0)))
            if not (res.success and res.kkt["stationarity"] <= 1e-6 and error <= 1e-6):
                failures.append(f"scale {scale:.1e}, seed {seed}: {res.status.name}, stationarity "
                                f"{res.kkt['stationarity']:.1e}, |x - 1| {error:.1e}")
    assert not failures, "\n".join(failures)


def test_stencil_noise_recovers_the_noise_of_smooth_functions():
    """ECnoise on known noise: three smooth functions plus Gaussian noise of deviation sigma over seven orders of
    magnitude, 30 seeds each (630 estimates from 7 values). The estimate is a sample deviation of a few
    differences, so it is judged as one: its median within a factor 1.5 of sigma, 90 % of the estimates within a
    factor 3 (about 96 % are, over thousands of seeds), at most 10 % left undecided (NaN: the next, narrower
    stencil decides those); without noise a wide
    stencil is recognised as smooth (NaN)."""
    t = np.linspace(0.0, 1e-6, 7)
    smooth = np.column_stack([1.0 + 2.0 * t, np.exp(t), 5.0 + np.sin(3e3 * t)])
    ratios = []
    for sigma in np.geomspace(1e-12, 1e-6, 7):
        for seed in range(30):
            noisy = smooth + sigma * np.random.default_rng(seed).standard_normal(smooth.shape)
            ratios.extend(stencil_noise(noisy) / sigma)
    ratios = np.asarray(ratios)
    decided = ratios[np.isfinite(ratios)]
    assert decided.size >= 0.9 * ratios.size
    assert 1 / 1.5 <= np.median(decided) <= 1.5
    assert np.mean((decided >= 1 / 3) & (decided <= 3)) >= 0.9
    wide = np.column_stack([np.exp(np.linspace(0.0, 1.0, 7)), np.linspace(0.0, 1.0, 7) ** 3])
    assert np.all(np.isnan(stencil_noise(wide)))


def test_stencil_noise_of_values_below_their_resolution():
    """Values that do not change across the stencil (a change below their rounding) are bounded by the larger of
    the change seen and the change the slope predicts."""
    flat = np.full((7, 2), 3.0)
    flat[4, 1] = np.nextafter(3.0, 4.0)
    est = stencil_noise(flat, np.array([1e-20, 1e-20])) * NOISE_BOUND
    assert est[0] == 1e-20 and est[1] == np.nextafter(3.0, 4.0) - 3.0


def test_line_search_takes_the_full_step_when_the_merit_function_is_all_noise():
    # f = 1e-11 * (pseudo-random sign) around a minimiser: the predicted decrease of the step (1e-17) is far below
    # the noise, so plain backtracking fails; the noise-tolerant test takes the full step and reports the noise
    rng = np.random.default_rng(3)

    def fun(x):
        return float(1e-10 * rng.uniform(-1, 1) + 1e-3 * np.sum((x - 1.0) ** 2))

    problem = build_problem(fun, np.full(3, 1.0 + 1e-7), lambda x: 2e-3 * (x - 1.0), None, ())
    ev = Evaluator(problem)
    pt = ev.point(problem.start.x)
    der = ev.derivatives(pt)
    st = State(pt, der, np.eye(3) * 2e-3, np.zeros(0))
    d = -(problem.start.x - 1.0)
    search = line_search(problem, sqp.Options().for_problem(problem), ev, st, d, np.zeros(0))
    assert search.pt is not None and search.alpha == 1.0
    assert search.noise > abs(float(der.g @ d))
    np.testing.assert_allclose(search.pt.x, 1.0, atol=1e-15)


def test_range_space_kkt_meets_nearly_dependent_rows_to_rounding():
    rng = np.random.default_rng(0)
    n = 48
    Q, _ = np.linalg.qr(rng.standard_normal((n, n)))
    B = (Q * np.geomspace(1e-3, 1e4, n)) @ Q.T
    B = 0.5 * (B + B.T)
    L = cholesky(B, lower=True)
    row = rng.standard_normal(n)
    E = np.vstack([row, row + 1e-7 * rng.standard_normal(n), rng.standard_normal((2, n))])
    e = 1e-12 * rng.standard_normal(4)
    g = rng.standard_normal(n) * 1e-6
    d, y = range_space_kkt(L, g, E, e)
    size = np.max(np.abs(e)) + np.max(np.abs(E) @ np.abs(d))
    assert np.max(np.abs(E @ d - e)) <= REFINE_RTOL * size
    np.testing.assert_allclose(B @ d + g + E.T @ y, 0.0, atol=1e-9 * (1 + np.max(np.abs(g))))
