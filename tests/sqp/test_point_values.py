"""What an evaluated Point carries (its violations, largest violation, finiteness) is what the rows say at its x."""

import numpy as np
from scipy.optimize import Bounds, LinearConstraint, NonlinearConstraint

from sqp.build import build_problem
from sqp.iterate import Evaluator
from sqp.merit import merit, merit_at


def _problem(fun=lambda x: float(x @ x)):
    cons = [
        {"type": "eq", "fun": lambda x: np.array([x[0] + x[1] - 1.0]), "jac": lambda x: np.array([[1.0, 1.0, 0.0]])},
        NonlinearConstraint(lambda x: np.array([x[0] * x[2], x[1] ** 2]), [-1.0, 0.5], [2.0, np.inf],
                            jac=lambda x: np.array([[x[2], 0.0, x[0]], [0.0, 2 * x[1], 0.0]])),
        LinearConstraint(np.array([[1.0, -1.0, 2.0]]), -np.inf, 0.5),
    ]
    return build_problem(fun, np.zeros(3), lambda x: 2 * x, Bounds([-1.0, -np.inf, 0.0], [1.0, 3.0, np.inf]),
                         cons, (), None, None)


def test_point_violations_and_largest_violation_are_the_rows_and_bounds_at_x():
    p = _problem()
    x = np.array([1.5, -2.0, 2.0])  # violates the equality, the product's upper side, the square, the linear row, x0<=1
    pt = Evaluator(p).point(x)
    c = np.array([x[0] + x[1] - 1.0, x[0] * x[2], x[1] ** 2])
    expected_v = np.array([abs(c[0]), max(0.0, c[1] - 2.0), max(0.0, 0.5 - c[2])])
    np.testing.assert_array_equal(pt.v, expected_v)
    linear = max(0.0, x[0] - x[1] + 2 * x[2] - 0.5)
    bounds = max(x[0] - 1.0, 0.0 - x[2], -1.0 - x[0], 0.0)
    assert pt.maxcv == max(expected_v.max(), linear, bounds) == linear  # the linear row is the worst here (7.0)
    assert pt.finite
    mu = np.array([1.0, 2.0, 3.0])
    assert merit_at(pt, mu) == merit(pt.f, pt.c, p.nonlinear, mu) == pt.f + mu @ expected_v


def test_a_point_with_a_nan_objective_is_not_finite_and_its_merit_is_infinite():
    p = _problem(fun=lambda x: np.nan)
    pt = Evaluator(p).point(np.array([0.2, 0.8, 0.0]))
    assert not pt.finite
    assert merit_at(pt, np.ones(3)) == np.inf
    assert pt.maxcv == 0.0  # feasible: the rows do not depend on the objective
