"""The engine's one-pass residual check of a backend's answer gives qpsolvers' own residuals, bit for bit."""

import numpy as np
import pytest
import qpsolvers

from sqp.subproblem import _residuals


def _qp(seed, ineq, eq, box):
    rng = np.random.default_rng(seed)
    n = 6
    M = rng.standard_normal((n, n))
    P, q = M @ M.T + np.eye(n), rng.standard_normal(n)
    G = rng.standard_normal((3, n)) if ineq else None
    h = rng.random(3) if ineq else None
    A = rng.standard_normal((2, n)) if eq else None
    b = 0.1 * rng.standard_normal(2) if eq else None
    lb, ub = (-0.3 * np.ones(n), 0.3 * np.ones(n)) if box else (None, None)
    return qpsolvers.Problem(P, q, G, h, A, b, lb, ub)


@pytest.mark.parametrize("seed", range(3))
@pytest.mark.parametrize(("ineq", "eq", "box"), [(1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 1, 1), (0, 0, 0)])
def test_residuals_equal_qpsolvers(seed, ineq, eq, box):
    sol = qpsolvers.solve_problem(_qp(seed, ineq, eq, box), solver="daqp")
    assert sol.found
    sol.x = sol.x + 1e-3 * np.arange(sol.x.size)  # off the solution: nonzero residuals of both kinds
    assert _residuals(sol) == (sol.primal_residual(), sol.dual_residual())
    assert _residuals(sol)[1] > 0.0


def test_a_missing_multiplier_makes_the_dual_residual_infinite():
    sol = qpsolvers.solve_problem(_qp(0, 1, 1, 0), solver="daqp")
    sol.y = None
    assert _residuals(sol)[1] == np.inf == sol.dual_residual()


def test_an_answer_of_the_wrong_size_raises_as_qpsolvers_does():
    sol = qpsolvers.solve_problem(_qp(0, 1, 0, 0), solver="daqp")
    sol.x = np.ones(sol.x.size + 1)
    with pytest.raises(ValueError):
        _residuals(sol)
