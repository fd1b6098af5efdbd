"""The shared benchmark modules (``benchmarks/_*.py``) on small problems: conversions, peers, timing."""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import LinearConstraint, NonlinearConstraint

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))

import _peers  # noqa: E402
import _problems  # noqa: E402
import _timing  # noqa: E402


def circle_problem(kind: str) -> _problems.Problem:
    """min (x0 - 2)² + (x1 - 1)² on the unit disc with x0 - x1 = 0.5, the disc as a dict or a NonlinearConstraint.

    Answer: on the circle where x0 - x1 = 0.5 (the unconstrained minimum (2, 1) is outside the disc).
    """
    def fun(x):
        return float((x[0] - 2.0) ** 2 + (x[1] - 1.0) ** 2)

    def jac(x):
        return np.array([2.0 * (x[0] - 2.0), 2.0 * (x[1] - 1.0)])

    def hess(x):
        return 2.0 * np.eye(2)

    def disc(x):
        return np.array([1.0 - x @ x])

    def disc_jac(x):
        return -2.0 * x[None, :]

    def disc_hess(x, v):
        return -2.0 * v[0] * np.eye(2)

    linear = LinearConstraint([[1.0, -1.0]], 0.5, 0.5)
    if kind == "dict":
        nonlinear = {"type": "ineq", "fun": disc, "jac": disc_jac, "hess": disc_hess}
    else:
        nonlinear = NonlinearConstraint(disc, 0.0, np.inf, jac=disc_jac, hess=disc_hess)
    return _problems.Problem(fun, jac, np.array([0.1, 0.2]), (linear, nonlinear), None, hess)


ANSWER_X0 = (0.5 + np.sqrt(2.0 - 0.25)) / 2.0
ANSWER = np.array([ANSWER_X0, ANSWER_X0 - 0.5])


@pytest.mark.parametrize("kind", ["dict", "nonlinear"])
def test_as_dicts_and_violations(kind):
    problem = circle_problem(kind)
    assert _problems.has_exact_hessians(problem)
    dicts = _problems.as_dicts(problem, with_hess=True)
    assert [d["type"] for d in dicts] == ["eq", "ineq"]
    x = np.array([2.0, 0.0])  # outside the disc by 3, off the line by 1.5
    assert dicts[0]["fun"](x) == pytest.approx([1.5])
    assert dicts[1]["fun"](x) == pytest.approx([-3.0])
    assert np.allclose(dicts[1]["hess"](x, np.array([1.0])), -2.0 * np.eye(2))
    assert _problems.violations(problem, x) == pytest.approx([1.5, 3.0])
    assert _problems.max_violation(problem, ANSWER) == pytest.approx(0.0, abs=1e-12)


def test_two_sided_nonlinear_constraint_splits_into_sides():
    problem = _problems.Problem(lambda x: 0.0, lambda x: np.zeros(2), np.zeros(2), (
        NonlinearConstraint(lambda x: np.array([x[0], x[1]]), [-1.0, 2.0], [1.0, 2.0],
                            jac=lambda x: np.eye(2), hess=lambda x, v: np.diag(v)),))
    dicts = _problems.as_dicts(problem, with_hess=True)
    x = np.array([3.0, 5.0])
    assert [(d["type"], list(d["fun"](x))) for d in dicts] == [("eq", [3.0]), ("ineq", [4.0]), ("ineq", [-2.0])]
    assert np.allclose(dicts[2]["jac"](x), [[-1.0, 0.0]])
    assert np.allclose(dicts[2]["hess"](x, np.array([1.0])), np.diag([-1.0, 0.0]))
    assert _problems.violations(problem, x) == pytest.approx([2.0, 3.0])


@pytest.mark.parametrize("kind", ["dict", "nonlinear"])
@pytest.mark.parametrize("runner", ["SLSQP", "trust-constr", "IPOPT"])
def test_peers_solve_the_circle(kind, runner):
    runs = _peers.peer_runners((runner,))
    if not runs:
        pytest.skip(f"{runner} not installed")
    (run,) = runs.values()
    out = run(circle_problem(kind))
    assert out["success"], out["message"]
    # trust-constr's barrier stops at scipy's default tolerances 2e-4 inside the disc
    assert np.allclose(out["x"], ANSWER, atol=1e-3 if runner == "trust-constr" else 1e-5)
    assert out["nfev"] > 0 and out["time"] > 0


def test_sgm():
    assert np.isnan(_timing.sgm([]))
    assert _timing.sgm([1.0, 4.0, float("nan")], shift=0.0) == pytest.approx(2.0)


def test_measure_outcomes_and_budget():
    def slow(_):
        time.sleep(1.0)
        return {"time": 1.0}

    def broken(_):
        raise RuntimeError("boom")

    assert _timing.measure(slow, None, 1, 0.05)["outcome"] == "timeout"
    assert _timing.measure(broken, None, 1)["message"] == "raised RuntimeError: boom"
    fast = _timing.measure(lambda _: {"time": 1e-4, "x": 1}, None, 3)
    assert fast["outcome"] == "ran" and fast["repeats"] == _timing.FAST_REPEATS
    assert _timing.measure(lambda _: {"time": 1e-4}, None, 3, adaptive=False)["repeats"] == 3
    budget = _timing.Budget(0.05)
    assert budget.measure("peer", "scene", 10, slow, None, 1)["outcome"] == "timeout"
    assert budget.measure("peer", "scene", 20, slow, None, 1)["outcome"] == "skipped"
