"""Rounding at the solution: an objective whose value cancels large terms (noise far above the decrease a step can
make) and an ill-conditioned equality QP with nearly dependent rows (the nearly taut wire between two points)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import cholesky

import sqp
from sqp.build import build_problem
from sqp.iterate import Evaluator, State
from sqp.linesearch import line_search
from sqp.structured import REFINE_RTOL, range_space_kkt


def _cancelling_quadratic(scale: float):
    """``sum c_i (x_i - 1)^2`` written as ``x^T C x - 2 c^T x + sum c`` plus and minus ``scale``: the same function,
    with its value at the minimiser (0) computed as a difference of numbers of size ``scale``; the gradient is
    exact to rounding."""
    c = np.geomspace(1e-2, 3e4, 6)

    def fun(x):
        return float(x @ (c * x) - 2.0 * c @ x + (c.sum() + scale)) - scale

    def jac(x):
        return 2.0 * c * (x - 1.0)

    return fun, jac, c


@pytest.mark.parametrize("scale", [1e5, 1e7])
def test_objective_noise_does_not_stop_the_solve_short_of_the_kkt_point(scale):
    fun, jac, c = _cancelling_quadratic(scale)
    x0 = np.array([3.0, -2.0, 0.5, 2.0, 1.5, -1.0])
    # a linear row through the minimiser (x_1 + x_2 = 2) keeps the merit function of an SQP step
    cons = [{"type": "eq", "fun": lambda x: x[0] + x[1] - 2.0, "jac": lambda x: np.array([[1.0, 1, 0, 0, 0, 0]])}]
    res = sqp.minimize(fun, x0, jac=jac, constraints=cons)
    assert res.success, res.message
    assert res.kkt["stationarity"] <= 1e-6
    # the noise in f is ~1e-16 * scale; the answer is still as accurate as the gradient allows
    assert np.max(np.abs(res.x - 1.0)) <= 1e-6


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
