"""The Hock–Schittkowski definitions themselves: derivatives against finite differences, f(x*) = f*, x* feasible."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import LinearConstraint

from sqp.problems import hs_optima
from sqp.problems.hock_schittkowski import BUILDERS

NAMES = list(BUILDERS)


def _points(prob, rng):
    """x0 and two points near it, pushed inside the bounds."""
    pts = [np.asarray(prob.x0, float)]
    for _ in range(2):
        pts.append(pts[0] + 0.1 * (1 + np.abs(pts[0])) * rng.standard_normal(prob.n))
    if prob.bounds is not None:
        lo = np.array([-np.inf if b[0] is None else b[0] for b in prob.bounds])
        hi = np.array([np.inf if b[1] is None else b[1] for b in prob.bounds])
        with np.errstate(invalid="ignore"):
            lo_in = np.where(np.isfinite(lo), lo + 1e-3 * (1 + abs(lo)), -np.inf)
            hi_in = np.where(np.isfinite(hi), hi - 1e-3 * (1 + abs(hi)), np.inf)
        pts = [np.clip(p, np.minimum(lo_in, hi), hi_in) for p in pts]
    return pts


def _fd_jac(fun, x):
    x = np.asarray(x, float)
    f0 = np.atleast_1d(fun(x))
    J = np.empty((f0.size, x.size))
    for j in range(x.size):
        h = 1e-6 * max(1.0, abs(x[j]))
        e = np.zeros_like(x)
        e[j] = h
        J[:, j] = (np.atleast_1d(fun(x + e)) - np.atleast_1d(fun(x - e))) / (2 * h)
    return J


def test_at_least_sixty_problems_and_known_optima():
    assert len(NAMES) >= 60
    optima = hs_optima()
    for name in NAMES:
        assert name in optima, name


@pytest.mark.parametrize("name", NAMES)
def test_derivatives_match_finite_differences(name):
    prob = BUILDERS[name]()
    rng = np.random.default_rng(0)
    assert prob.fstar == pytest.approx(hs_optima()[name])
    for x in _points(prob, rng):
        g = prob.jac(x)
        assert np.shape(g) == (prob.n,)
        fd = _fd_jac(lambda z: np.array([prob.fun(z)]), x)[0]
        np.testing.assert_allclose(g, fd, rtol=1e-5, atol=1e-6 * max(1.0, np.max(np.abs(fd))))
        for con in prob.constraints:
            if isinstance(con, LinearConstraint):
                continue
            J = np.atleast_2d(con["jac"](x))
            fd = _fd_jac(con["fun"], x)
            assert J.shape == fd.shape
            np.testing.assert_allclose(J, fd, rtol=1e-5, atol=1e-6 * max(1.0, np.max(np.abs(fd))))


@pytest.mark.parametrize("name", [n for n in NAMES if BUILDERS[n]().xstar is not None])
def test_known_minimiser_is_feasible_and_optimal(name):
    prob = BUILDERS[name]()
    f = prob.fun(prob.xstar)
    assert prob.max_violation(prob.xstar) <= 1e-4 * max(1.0, np.max(np.abs(prob.xstar)))
    assert abs(f - prob.fstar) <= 1e-4 * max(1.0, abs(prob.fstar))
