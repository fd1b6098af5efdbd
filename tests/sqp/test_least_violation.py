"""An INFEASIBLE result names the least-violation point it reached, and ``x``, ``maxcv`` and the message agree."""

from __future__ import annotations

import numpy as np
import pytest

import sqp
from sqp.problem import format_point


def _disc_and_half_plane(theta: float):
    """The unit disc and ``a . x >= 3`` with ``|a| = sqrt 2`` at angle ``theta``: no common point; the L1 violation
    ``(|x|^2 - 1)^+ + (3 - a . x)^+`` is least at ``x* = a / |a|``, where it is ``3 - sqrt 2`` (along ``a`` it is
    ``3 - sqrt 2 t`` inside the disc and grows outside it, since ``2 t > sqrt 2`` there)."""
    a = np.sqrt(2.0) * np.array([np.cos(theta), np.sin(theta)])
    cons = [{"type": "ineq", "fun": lambda x: 1.0 - x @ x, "jac": lambda x: -2.0 * x},
            {"type": "ineq", "fun": lambda x: a @ x - 3.0, "jac": lambda x: a}]
    return cons, a / np.sqrt(2.0)


@pytest.mark.parametrize("theta", [np.pi / 4, 0.3, 2.0, -1.2, 3.9])
def test_infeasible_result_is_the_least_violation_point(theta):
    cons, xstar = _disc_and_half_plane(theta)
    rng = np.random.default_rng(int(100 * abs(theta)))
    for x0 in [np.zeros(2), *rng.uniform(-2.0, 2.0, (5, 2))]:
        res = sqp.minimize(lambda x: x @ x, x0, jac=lambda x: 2.0 * x, constraints=cons)
        assert res.status == sqp.Status.INFEASIBLE, (x0, res.message)
        np.testing.assert_allclose(res.x, xstar, atol=1e-6)
        # maxcv is the largest violation at res.x, judged here; the message names the same point and values
        violations = [max(0.0, -float(c["fun"](res.x))) for c in cons]
        assert res.maxcv == pytest.approx(max(violations), rel=1e-12, abs=1e-15)
        assert sum(violations) == pytest.approx(3.0 - np.sqrt(2.0), abs=1e-6)
        assert format_point(res.x) in res.message and f"{sum(violations):.3e}" in res.message
        assert "stationary point of the violation" in res.message


def test_a_feasible_problem_that_looked_infeasible_is_solved_from_the_restored_point():
    """A feasible problem whose start lies far from its feasible arc ends a success, never INFEASIBLE: a restoration
    that reaches violation 0 hands its point back to the solve."""
    cons = [{"type": "eq", "fun": lambda x: x @ x - 1.0, "jac": lambda x: 2.0 * x},
            {"type": "ineq", "fun": lambda x: x[0] + x[1] - 1.2, "jac": lambda x: np.array([1.0, 1.0])}]
    res = sqp.minimize(lambda x: x[0], np.array([-1.0, 0.0]), jac=lambda x: np.array([1.0, 0.0]), constraints=cons)
    assert res.success, res.message
    assert res.maxcv <= 1e-8
