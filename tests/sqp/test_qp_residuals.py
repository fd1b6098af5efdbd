"""The engine's one-pass residual check of a backend's answer gives qpsolvers' own residuals, bit for bit."""

import numpy as np
import pytest
import qpsolvers

from sqp.backends import solve_problem
from sqp.qp_call import _residuals


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


@pytest.mark.parametrize("seed", range(3))
@pytest.mark.parametrize(("ineq", "eq", "box"), [(1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 1, 1), (0, 0, 0), (1, 1, 0)])
@pytest.mark.parametrize("warm", [False, True])
def test_the_direct_daqp_call_answers_as_qpsolvers_does_bit_for_bit(seed, ineq, eq, box, warm):
    problem = _qp(seed, ineq, eq, box)
    initvals = np.full(problem.q.size, 0.1) if warm else None
    ours = solve_problem(problem, "daqp", initvals=initvals)
    ref = qpsolvers.solve_problem(problem, solver="daqp", initvals=initvals)
    assert ours.found and ref.found and ours.problem is problem
    for name in ("x", "y", "z", "z_box"):
        a, b = getattr(ours, name), getattr(ref, name)
        assert (a is None and b is None) or (a.size == 0 and b.size == 0) or np.array_equal(a, b), name
    assert _residuals(ours) == (ref.primal_residual(), ref.dual_residual())
    assert _residuals(ours)[0] <= 1e-9 and _residuals(ours)[1] <= 1e-9


def test_the_direct_daqp_call_reports_an_infeasible_qp_as_not_found():
    n = 3
    G = np.vstack([np.eye(n)[:1], -np.eye(n)[:1]])
    problem = qpsolvers.Problem(np.eye(n), np.ones(n), G, np.array([-1.0, -1.0]))  # x0 <= -1 and x0 >= 1
    ours = solve_problem(problem, "daqp")
    assert not ours.found and ours.x is None
    assert not qpsolvers.solve_problem(problem, solver="daqp").found
