"""The safeguards of the first iterations: a step bound (a box trust region on the QP) and the restart with it
after a failure at a point where a violated constraint's gradient vanishes."""

from __future__ import annotations

import numpy as np
import pytest

import sqp
from sqp.build import build_problem
from sqp.options import Options
from sqp.problems.hock_schittkowski import BUILDERS
from sqp.problems.judge import judge
from sqp.solver import run
from sqp.termination import RESTART_BOUNDED_ITERATIONS


def _run(prob, **options):
    problem = build_problem(prob.fun, prob.x0, prob.jac, prob.bounds, prob.constraints, (), None, None)
    return run(problem, Options(**options))


@pytest.mark.parametrize("name", ["HS88", "HS90", "HS92"])
def test_restart_leaves_the_point_where_the_constraint_gradient_vanishes(name):
    prob = BUILDERS[name]()
    first = _run(prob, restart=False)
    assert first.status == sqp.Status.INFEASIBLE and np.max(np.abs(first.x)) < 1e-2  # x = 0: grad h = 0
    res = _run(prob)
    assert res.success and judge(prob, res.x).solved, res.message
    assert res.nfev > first.nfev and res.nit > first.nit  # the work of both solves is counted


def test_an_infeasible_problem_is_not_restarted():
    """Inconsistent constraints with nonvanishing gradients: the INFEASIBLE verdict stands after one solve."""
    kwargs = {"fun": lambda x: x @ x, "x0": [0.0, 0.0],
              "constraints": [{"type": "ineq", "fun": lambda x: 1 - x @ x, "jac": lambda x: -2 * x},
                              {"type": "ineq", "fun": lambda x: x[0] + x[1] - 3,
                               "jac": lambda x: np.array([1.0, 1.0])}]}
    res = sqp.minimize(**kwargs, jac=lambda x: 2 * x)
    problem = build_problem(kwargs["fun"], kwargs["x0"], lambda x: 2 * x, None, kwargs["constraints"], (), None, None)
    alone = run(problem, Options(restart=False))
    assert res.status == alone.status == sqp.Status.INFEASIBLE
    assert res.nfev == alone.nfev


def test_step_bound_limits_every_step_and_gives_no_certificate_at_the_bound():
    """With the box active the QP's bound multipliers absorb the gradient; that is no KKT point."""
    prob = BUILDERS["HS28"]()
    res = _run(prob, step_bound=0.25)
    assert res.success and judge(prob, res.x).solved, res.message
    bounded = res.history[:RESTART_BOUNDED_ITERATIONS]
    assert max(rec.step for rec in bounded) <= 0.25 * (1 + 1e-12) < max(rec.step for rec in _run(prob).history)
    free = build_problem(lambda x: float((x[0] - 5.0) ** 2), [0.0], lambda x: np.array([2 * (x[0] - 5.0)]), None, (),
                         (), None, None)
    res = run(free, Options(step_bound=0.5))
    assert res.success and res.x[0] == pytest.approx(5.0, abs=1e-8) and res.nit == RESTART_BOUNDED_ITERATIONS


@pytest.mark.parametrize(("name", "bound"), [("HS28", 0.25), ("HS71", 0.1), ("HS100", 0.5)])
def test_minimize_takes_the_step_bound(name, bound):
    """``sqp.minimize(step_bound=...)`` is the options' bound: the first steps within it (in every component), the
    same problem solved; a bound that is not positive is refused."""
    prob = BUILDERS[name]()
    res = sqp.minimize(prob.fun, prob.x0, jac=prob.jac, bounds=prob.bounds, constraints=prob.constraints,
                       step_bound=bound)
    assert res.success and judge(prob, res.x).solved, res.message
    assert max(rec.step for rec in res.history[:RESTART_BOUNDED_ITERATIONS]) <= bound * (1 + 1e-12)
    with pytest.raises(ValueError, match="step_bound"):
        sqp.minimize(prob.fun, prob.x0, jac=prob.jac, constraints=prob.constraints, step_bound=0.0)


def _hanging_chain(links: int) -> dict:
    """A chain of ``links`` equal links hanging between (0, 0) and (1, 0), total length 1.5, written as a new user
    would: the heights' sum as the objective, one equality per link on its squared length, dense Jacobian."""
    m = links - 1
    ell = 1.5 / links

    def ends(z):
        return np.concatenate(([0.0], z[:m], [1.0])), np.concatenate(([0.0], z[m:], [0.0]))

    def cfun(z):
        x, y = ends(z)
        return np.diff(x) ** 2 + np.diff(y) ** 2 - ell**2

    def cjac(z):
        x, y = ends(z)
        dx, dy = np.diff(x), np.diff(y)
        J = np.zeros((links, 2 * m))
        i = np.arange(m)
        J[i + 1, i], J[i + 1, m + i] = -2 * dx[1:], -2 * dy[1:]  # link i + 1 starts at interior point i
        J[i, i], J[i, m + i] = 2 * dx[:-1], 2 * dy[:-1]  # link i ends at interior point i
        return J

    xs = np.linspace(0.0, 1.0, links + 1)[1:-1]
    return {"fun": lambda z: float(np.sum(z[m:])), "x0": np.concatenate((xs, -1.2 * xs * (1 - xs))),
            "jac": lambda z: np.concatenate((np.zeros(m), np.ones(m))),
            "constraints": [{"type": "eq", "fun": cfun, "jac": cjac}]}


def test_a_rounding_limited_hanging_chain_is_a_success():
    """150 links, 298 variables: the tensions make the terms of the Lagrangian gradient 150 times the gradient, so
    rounding limits the stationarity residual; the solve ends a success, at tol (SUCCESS, once the line search
    tolerates the merit function's noise) or at the rounding-limited level (ACCEPTABLE), never LINE_SEARCH."""
    kw = _hanging_chain(150)
    res = sqp.minimize(**kw)
    assert res.success and res.status in (sqp.Status.SUCCESS, sqp.Status.ACCEPTABLE), res.message
    assert res.maxcv <= 1e-12
    # an independent certificate: least-squares multipliers leave a small residual, and the chain is symmetric
    J = kw["constraints"][0]["jac"](res.x)
    g = kw["jac"](res.x)
    lam = np.linalg.lstsq(J.T, g, rcond=None)[0]
    assert np.max(np.abs(J.T @ lam - g)) <= 1e-5
    m = 149
    assert np.allclose(res.x[:m], 1.0 - res.x[:m][::-1], atol=1e-6) and np.allclose(res.x[m:], res.x[m:][::-1],
                                                                                    atol=1e-6)
