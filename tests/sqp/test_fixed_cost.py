"""The per-solve shortcuts give what the general code gives: SLSQP's multiplier order for all-dict constraints,
the result's violation and KKT feasibility from the final point."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from scipy.optimize import NonlinearConstraint
from scipy.optimize import minimize as scipy_minimize

import sqp
from sqp.build import build_problem
from sqp.kkt import max_violation


def _dicts() -> list[dict]:
    """Mixed eq/ineq dicts of several sizes (one empty), interleaved so the order matters."""
    return [
        {"type": "ineq", "fun": lambda x: np.array([1.0 - x[0], 2.0 - x[1]])},
        {"type": "eq", "fun": lambda x: np.array([x[0] + x[1] + x[2] - 1.0])},
        {"type": "ineq", "fun": lambda x: np.zeros(0)},
        {"type": "eq", "fun": lambda x: np.array([x[0] - x[2], x[1] - 0.5 * x[2]])},
        {"type": "ineq", "fun": lambda x: np.array([x[2] + 3.0])},
    ]


def test_dict_rows_follow_the_general_slsqp_rule():
    problem = build_problem(lambda x: x @ x, np.ones(3), None, None, _dicts())
    index, sign, two = problem.slsqp_rows
    # the general rule (the branch every other constraint type takes), on the same rows
    general = replace(problem, blocks=tuple(replace(b, dict_style=False) for b in problem.blocks)).slsqp_rows
    np.testing.assert_array_equal(index, general[0])
    np.testing.assert_array_equal(sign, general[1])
    np.testing.assert_array_equal(two, general[2])
    # rows 0, 1 (ineq), 2 (eq), 3, 4 (eq), 5 (ineq): equalities first, then inequalities, each in the given order
    np.testing.assert_array_equal(index, [2, 3, 4, 0, 1, 5])
    assert index.dtype == np.intp and not two.any() and np.all(sign == 1.0)


def test_dict_multipliers_match_scipy_slsqp():
    fun = lambda x: (x[0] - 2.0) ** 2 + (x[1] - 3.0) ** 2 + (x[2] + 1.0) ** 2  # noqa: E731
    cons = _dicts()
    ours = sqp.minimize(fun, np.array([0.2, 0.3, 0.5]), constraints=cons, tol=1e-10)
    ref = scipy_minimize(fun, np.array([0.2, 0.3, 0.5]), constraints=cons, method="SLSQP",
                         options={"ftol": 1e-12})
    assert ours.success and ref.success
    np.testing.assert_allclose(ours.x, ref.x, atol=1e-6)
    np.testing.assert_allclose(ours.multipliers, ref.multipliers, atol=1e-5)


@pytest.mark.parametrize("x0", [[0.2, 0.3, 0.5], [5.0, -4.0, 9.0]])
def test_result_violation_is_the_final_points(x0):
    cons = _dicts()
    res = sqp.minimize(lambda x: x @ x, np.array(x0), constraints=cons, max_iter=1)
    problem = build_problem(lambda x: x @ x, np.array(x0), None, None, cons)
    c = np.concatenate([np.atleast_1d(k["fun"](res.x)) for k in cons])
    assert res.maxcv == max_violation(problem, res.x, c, np.zeros(0))
    assert res.kkt.feasibility == res.maxcv


def _counting(fn, log, name):
    def wrapped(x, *extra):
        log.append((name, np.array(x)))
        return fn(x, *extra)
    return wrapped


@pytest.mark.parametrize("kind", ["dict", "object"])
def test_start_values_are_reused_once_and_change_nothing(kind):
    """The input checks' evaluation at x0 is the solve's evaluation of its start: every user function is called
    once there, and the solve is the one that calls them again (same iterates, same counts)."""
    from sqp.options import Options
    from sqp.solver import run

    log: list[tuple[str, np.ndarray]] = []
    fun = _counting(lambda x: float((x[0] - 2.0) ** 2 + (x[1] - 1.0) ** 2 + x[2] ** 2), log, "fun")
    jac = _counting(lambda x: np.array([2.0 * (x[0] - 2.0), 2.0 * (x[1] - 1.0), 2.0 * x[2]]), log, "jac")
    cfun = _counting(lambda x: np.array([1.0 - x[0] ** 2 - x[1] ** 2, x[0] - x[2]]), log, "cfun")
    cjac = _counting(lambda x: np.array([[-2.0 * x[0], -2.0 * x[1], 0.0], [1.0, 0.0, -1.0]]), log, "cjac")
    if kind == "dict":
        cons = [{"type": "ineq", "fun": lambda x: cfun(x)[:1], "jac": lambda x: cjac(x)[:1]},
                {"type": "eq", "fun": lambda x: cfun(x)[1:], "jac": lambda x: cjac(x)[1:]}]
    else:
        cons = [NonlinearConstraint(cfun, [0.0, 0.0], [np.inf, 0.0], jac=cjac)]
    x0 = np.array([0.1, 0.2, 0.3])
    problem = build_problem(fun, x0, jac, None, cons)
    assert problem.start is not None
    options = Options(tol=1e-10)
    log.clear()
    reused = run(problem, options)
    at_x0 = [name for name, x in log if np.array_equal(x, x0)]
    assert at_x0 == []  # nothing called again at the start
    log.clear()
    fresh = run(replace(problem, start=None), options)
    assert sorted({name for name, x in log if np.array_equal(x, x0)}) == ["cfun", "cjac", "fun", "jac"]
    np.testing.assert_array_equal(reused.x, fresh.x)
    assert (reused.nit, reused.nfev, reused.njev) == (fresh.nit, fresh.nfev, fresh.njev)
    np.testing.assert_array_equal(reused.multipliers, fresh.multipliers)


@pytest.mark.parametrize("kinds", [("eq", "eq"), ("ineq",), ("ineq", "ineq", "ineq"), ("eq", "ineq")])
def test_slsqp_multipliers_of_dicts_of_one_type_are_the_constraints_own(kinds):
    cons = [{"type": k, "fun": (lambda x, i=i: np.array([x[0] - i, x[1] + i]))} for i, k in enumerate(kinds)]
    problem = build_problem(lambda x: x @ x, np.ones(3), None, None, cons)
    per = [np.array([1.5 * i - 1.0, -0.25 * i]) for i in range(len(kinds))]
    index, sign, two = problem.slsqp_rows
    np.testing.assert_array_equal(problem.slsqp_multipliers(per),
                                  np.where(two, np.maximum(sign * np.concatenate(per)[index], 0.0),
                                           sign * np.concatenate(per)[index]))
