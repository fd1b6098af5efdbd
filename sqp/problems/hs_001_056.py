"""Hock–Schittkowski problems 1 to 56, with the CUTEst variants HS3MOD, HS21MOD, HS35I, HS35MOD and HS44NEW.

Each builder returns a fresh :class:`~sqp.problems.problem.TestProblem` with analytic derivatives.

Notes
-----
Definitions follow W. Hock and K. Schittkowski, *Test Examples for Nonlinear Programming Codes*, LNEMS 187,
Springer 1981, as encoded in the CUTEst SIF files (which also define the variants and correct HS54). Nonlinear
constraints are SLSQP dicts (``ineq`` means ``fun(x) >= 0``); linear ones are ``scipy.optimize.LinearConstraint``.
``fstar`` is read from ``data/hs_optima.csv``. Where that value is a local solution rather than the global one
(HS2, HS20, HS55) ``xstar`` is the local minimiser it belongs to and ``notes`` gives the global one; where no
minimiser attains it (HS33) ``xstar`` is ``None``.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import LinearConstraint

from sqp.problems.problem import TestProblem
from sqp.problems.problem import eq as _eq
from sqp.problems.problem import hs_problem as _make
from sqp.problems.problem import ineq as _ineq

Array = NDArray[np.float64]
Bounds = Sequence[tuple[float | None, float | None]] | None

SQRT3 = np.sqrt(3.0)


# ---------------------------------------------------------------------------------------------------------------
# helpers
# ---------------------------------------------------------------------------------------------------------------





def _lin_eq(A: ArrayLike, b: ArrayLike) -> LinearConstraint:
    """Linear equalities ``A x = b``."""
    b = np.atleast_1d(np.asarray(b, dtype=float))
    return LinearConstraint(np.atleast_2d(np.asarray(A, dtype=float)), b, b)


def _lin_ge(A: ArrayLike, lb: ArrayLike) -> LinearConstraint:
    """Linear inequalities ``A x >= lb``."""
    lb = np.atleast_1d(np.asarray(lb, dtype=float))
    return LinearConstraint(np.atleast_2d(np.asarray(A, dtype=float)), lb, np.full(lb.shape, np.inf))


def _lin_le(A: ArrayLike, ub: ArrayLike) -> LinearConstraint:
    """Linear inequalities ``A x <= ub``."""
    ub = np.atleast_1d(np.asarray(ub, dtype=float))
    return LinearConstraint(np.atleast_2d(np.asarray(A, dtype=float)), np.full(ub.shape, -np.inf), ub)


def _rosen(x: Array) -> float:
    """Rosenbrock's function ``100 (x2 - x1^2)^2 + (1 - x1)^2``."""
    return float(100.0 * (x[1] - x[0] ** 2) ** 2 + (1.0 - x[0]) ** 2)


def _rosen_grad(x: Array) -> Array:
    """Gradient of :func:`_rosen`."""
    r = x[1] - x[0] ** 2
    return np.array([-400.0 * x[0] * r - 2.0 * (1.0 - x[0]), 200.0 * r])


# ---------------------------------------------------------------------------------------------------------------
# n = 2
# ---------------------------------------------------------------------------------------------------------------


def _hs1() -> TestProblem:
    """HS1: Rosenbrock with x2 >= -1.5, n=2, m=0."""
    return _make("HS1", _rosen, _rosen_grad, [-2.0, 1.0], [(None, None), (-1.5, None)], xstar=[1.0, 1.0])


def _hs2() -> TestProblem:
    """HS2: Rosenbrock with x2 >= 1.5, n=2, m=0."""
    return _make(
        "HS2",
        _rosen,
        _rosen_grad,
        [-2.0, 1.0],
        [(None, None), (1.5, None)],
        xstar=[-1.2210262460317687, 1.5],
        notes="f* = 4.941229 is the local minimum at x1 < 0 reached from x0; "
        "the global minimum is 0.0504261879 at (1.2243707507, 1.5).",
    )


def _hs3() -> TestProblem:
    """HS3: nearly flat quadratic with x2 >= 0, n=2, m=0."""

    def fun(x: Array) -> float:
        return float(x[1] + 1e-5 * (x[1] - x[0]) ** 2)

    def jac(x: Array) -> Array:
        d = 2e-5 * (x[1] - x[0])
        return np.array([-d, 1.0 + d])

    return _make("HS3", fun, jac, [10.0, 1.0], [(None, None), (0.0, None)], xstar=[0.0, 0.0])


def _hs3mod() -> TestProblem:
    """HS3MOD: CUTEst variant of HS3 with unit quadratic weight and x >= 0, n=2, m=0."""

    def fun(x: Array) -> float:
        return float(x[1] + (x[1] - x[0]) ** 2)

    def jac(x: Array) -> Array:
        d = 2.0 * (x[1] - x[0])
        return np.array([-d, 1.0 + d])

    return _make("HS3MOD", fun, jac, [10.0, 1.0], [(0.0, None), (0.0, None)], xstar=[0.0, 0.0])


def _hs4() -> TestProblem:
    """HS4: cubic in x1 plus x2 with lower bounds, n=2, m=0."""

    def fun(x: Array) -> float:
        return float((x[0] + 1.0) ** 3 / 3.0 + x[1])

    def jac(x: Array) -> Array:
        return np.array([(x[0] + 1.0) ** 2, 1.0])

    return _make("HS4", fun, jac, [1.125, 0.125], [(1.0, None), (0.0, None)], xstar=[1.0, 0.0])


def _hs5() -> TestProblem:
    """HS5: McCormick function on a box, n=2, m=0."""

    def fun(x: Array) -> float:
        return float(np.sin(x[0] + x[1]) + (x[0] - x[1]) ** 2 - 1.5 * x[0] + 2.5 * x[1] + 1.0)

    def jac(x: Array) -> Array:
        c = np.cos(x[0] + x[1])
        d = 2.0 * (x[0] - x[1])
        return np.array([c + d - 1.5, c - d + 2.5])

    xstar = [0.5 - np.pi / 3.0, -0.5 - np.pi / 3.0]
    return _make("HS5", fun, jac, [0.0, 0.0], [(-1.5, 4.0), (-3.0, 3.0)], xstar=xstar)


def _hs6() -> TestProblem:
    """HS6: (1 - x1)^2 on the parabola 10 (x2 - x1^2) = 0, n=2, m=1."""

    def fun(x: Array) -> float:
        return float((1.0 - x[0]) ** 2)

    def jac(x: Array) -> Array:
        return np.array([-2.0 * (1.0 - x[0]), 0.0])

    con = _eq(lambda x: np.array([10.0 * (x[1] - x[0] ** 2)]), lambda x: np.array([[-20.0 * x[0], 10.0]]))
    return _make("HS6", fun, jac, [-1.2, 1.0], None, [con], xstar=[1.0, 1.0])


def _hs7() -> TestProblem:
    """HS7: log objective on a quartic curve, n=2, m=1."""

    def fun(x: Array) -> float:
        return float(np.log1p(x[0] ** 2) - x[1])

    def jac(x: Array) -> Array:
        return np.array([2.0 * x[0] / (1.0 + x[0] ** 2), -1.0])

    con = _eq(
        lambda x: np.array([(1.0 + x[0] ** 2) ** 2 + x[1] ** 2 - 4.0]),
        lambda x: np.array([[4.0 * x[0] * (1.0 + x[0] ** 2), 2.0 * x[1]]]),
    )
    return _make("HS7", fun, jac, [2.0, 2.0], None, [con], xstar=[0.0, SQRT3])


def _hs8() -> TestProblem:
    """HS8: constant objective, intersection of a circle and a hyperbola, n=2, m=2."""

    def fun(x: Array) -> float:
        return -1.0

    def jac(x: Array) -> Array:
        return np.zeros(2)

    con = _eq(
        lambda x: np.array([x[0] ** 2 + x[1] ** 2 - 25.0, x[0] * x[1] - 9.0]),
        lambda x: np.array([[2.0 * x[0], 2.0 * x[1]], [x[1], x[0]]]),
    )
    x1 = np.sqrt((25.0 + np.sqrt(301.0)) / 2.0)
    return _make("HS8", fun, jac, [2.0, 1.0], None, [con], xstar=[x1, 9.0 / x1])


def _hs9() -> TestProblem:
    """HS9: periodic objective on the line 4 x1 = 3 x2, n=2, m=1."""
    a, b = np.pi / 12.0, np.pi / 16.0

    def fun(x: Array) -> float:
        return float(np.sin(a * x[0]) * np.cos(b * x[1]))

    def jac(x: Array) -> Array:
        return np.array([a * np.cos(a * x[0]) * np.cos(b * x[1]), -b * np.sin(a * x[0]) * np.sin(b * x[1])])

    return _make("HS9", fun, jac, [0.0, 0.0], None, [_lin_eq([[4.0, -3.0]], [0.0])], xstar=[-3.0, -4.0])


def _hs10() -> TestProblem:
    """HS10: linear objective inside an ellipse, n=2, m=1."""

    def fun(x: Array) -> float:
        return float(x[0] - x[1])

    def jac(x: Array) -> Array:
        return np.array([1.0, -1.0])

    con = _ineq(
        lambda x: np.array([-3.0 * x[0] ** 2 + 2.0 * x[0] * x[1] - x[1] ** 2 + 1.0]),
        lambda x: np.array([[-6.0 * x[0] + 2.0 * x[1], 2.0 * x[0] - 2.0 * x[1]]]),
    )
    return _make("HS10", fun, jac, [-10.0, 10.0], None, [con], xstar=[0.0, 1.0])


def _hs11() -> TestProblem:
    """HS11: distance to (5, 0) above a parabola, n=2, m=1."""

    def fun(x: Array) -> float:
        return float((x[0] - 5.0) ** 2 + x[1] ** 2 - 25.0)

    def jac(x: Array) -> Array:
        return np.array([2.0 * (x[0] - 5.0), 2.0 * x[1]])

    con = _ineq(lambda x: np.array([x[1] - x[0] ** 2]), lambda x: np.array([[-2.0 * x[0], 1.0]]))
    a = np.cbrt(7.5 * np.sqrt(6.0) + np.sqrt(338.5))
    xstar = [(a - 1.0 / a) / np.sqrt(6.0), (a * a - 2.0 + a**-2) / 6.0]
    return _make("HS11", fun, jac, [4.9, 0.1], None, [con], xstar=xstar)


def _hs12() -> TestProblem:
    """HS12: convex quadratic inside an ellipse, n=2, m=1."""

    def fun(x: Array) -> float:
        return float(0.5 * x[0] ** 2 + x[1] ** 2 - x[0] * x[1] - 7.0 * x[0] - 7.0 * x[1])

    def jac(x: Array) -> Array:
        return np.array([x[0] - x[1] - 7.0, 2.0 * x[1] - x[0] - 7.0])

    con = _ineq(
        lambda x: np.array([25.0 - 4.0 * x[0] ** 2 - x[1] ** 2]),
        lambda x: np.array([[-8.0 * x[0], -2.0 * x[1]]]),
    )
    return _make("HS12", fun, jac, [0.0, 0.0], None, [con], xstar=[2.0, 3.0])


def _hs13() -> TestProblem:
    """HS13: Kuhn–Tucker's cusp example (constraint qualification fails at x*), n=2, m=1."""

    def fun(x: Array) -> float:
        return float((x[0] - 2.0) ** 2 + x[1] ** 2)

    def jac(x: Array) -> Array:
        return np.array([2.0 * (x[0] - 2.0), 2.0 * x[1]])

    con = _ineq(
        lambda x: np.array([(1.0 - x[0]) ** 3 - x[1]]),
        lambda x: np.array([[-3.0 * (1.0 - x[0]) ** 2, -1.0]]),
    )
    return _make(
        "HS13",
        fun,
        jac,
        [-2.0, -2.0],
        [(0.0, None), (0.0, None)],
        [con],
        xstar=[1.0, 0.0],
        notes="x* is a cusp where no constraint qualification holds (no KKT multipliers); "
        "SQP methods only approach it slowly.",
    )


def _hs14() -> TestProblem:
    """HS14: distance to (2, 1) on a line inside an ellipse, n=2, m=2."""

    def fun(x: Array) -> float:
        return float((x[0] - 2.0) ** 2 + (x[1] - 1.0) ** 2)

    def jac(x: Array) -> Array:
        return np.array([2.0 * (x[0] - 2.0), 2.0 * (x[1] - 1.0)])

    con = _ineq(
        lambda x: np.array([1.0 - 0.25 * x[0] ** 2 - x[1] ** 2]),
        lambda x: np.array([[-0.5 * x[0], -2.0 * x[1]]]),
    )
    s7 = np.sqrt(7.0)
    xstar = [0.5 * (s7 - 1.0), 0.25 * (s7 + 1.0)]
    return _make("HS14", fun, jac, [2.0, 2.0], None, [_lin_eq([[1.0, -2.0]], [-1.0]), con], xstar=xstar)


def _hs15() -> TestProblem:
    """HS15: Rosenbrock with two nonlinear inequalities and x1 <= 0.5, n=2, m=2."""
    con = _ineq(
        lambda x: np.array([x[0] * x[1] - 1.0, x[0] + x[1] ** 2]),
        lambda x: np.array([[x[1], x[0]], [1.0, 2.0 * x[1]]]),
    )
    return _make("HS15", _rosen, _rosen_grad, [-2.0, 1.0], [(None, 0.5), (None, None)], [con], xstar=[0.5, 2.0])


def _hs16() -> TestProblem:
    """HS16: Rosenbrock with two nonlinear inequalities on a box, n=2, m=2."""
    con = _ineq(
        lambda x: np.array([x[0] + x[1] ** 2, x[0] ** 2 + x[1]]),
        lambda x: np.array([[1.0, 2.0 * x[1]], [2.0 * x[0], 1.0]]),
    )
    bounds = [(-0.5, 0.5), (None, 1.0)]
    return _make(
        "HS16",
        _rosen,
        _rosen_grad,
        [-2.0, 1.0],
        bounds,
        [con],
        xstar=[0.5, 0.25],
        notes="Nonconvex: (-0.5, 1/sqrt(2)) is a local minimiser with f = 23.1447, and solvers started "
        "from x0 (whose x1 = -2 is clipped to the bound -0.5) usually end there.",
    )


def _hs17() -> TestProblem:
    """HS17: Rosenbrock between two parabolas on a box, n=2, m=2."""
    con = _ineq(
        lambda x: np.array([x[1] ** 2 - x[0], x[0] ** 2 - x[1]]),
        lambda x: np.array([[-1.0, 2.0 * x[1]], [2.0 * x[0], -1.0]]),
    )
    bounds = [(-0.5, 0.5), (None, 1.0)]
    return _make("HS17", _rosen, _rosen_grad, [-2.0, 1.0], bounds, [con], xstar=[0.0, 0.0])


def _hs18() -> TestProblem:
    """HS18: scaled distance outside a hyperbola and a circle, n=2, m=2."""

    def fun(x: Array) -> float:
        return float(0.01 * x[0] ** 2 + x[1] ** 2)

    def jac(x: Array) -> Array:
        return np.array([0.02 * x[0], 2.0 * x[1]])

    con = _ineq(
        lambda x: np.array([x[0] * x[1] - 25.0, x[0] ** 2 + x[1] ** 2 - 25.0]),
        lambda x: np.array([[x[1], x[0]], [2.0 * x[0], 2.0 * x[1]]]),
    )
    bounds = [(2.0, 50.0), (0.0, 50.0)]
    return _make("HS18", fun, jac, [2.0, 2.0], bounds, [con], xstar=[np.sqrt(250.0), np.sqrt(2.5)])


def _hs19() -> TestProblem:
    """HS19: cubic objective on a crescent between two circles, n=2, m=2."""

    def fun(x: Array) -> float:
        return float((x[0] - 10.0) ** 3 + (x[1] - 20.0) ** 3)

    def jac(x: Array) -> Array:
        return np.array([3.0 * (x[0] - 10.0) ** 2, 3.0 * (x[1] - 20.0) ** 2])

    con = _ineq(
        lambda x: np.array(
            [(x[0] - 5.0) ** 2 + (x[1] - 5.0) ** 2 - 100.0, 82.81 - (x[1] - 5.0) ** 2 - (x[0] - 6.0) ** 2]
        ),
        lambda x: np.array([[2.0 * (x[0] - 5.0), 2.0 * (x[1] - 5.0)], [-2.0 * (x[0] - 6.0), -2.0 * (x[1] - 5.0)]]),
    )
    bounds = [(13.0, 100.0), (0.0, 100.0)]
    return _make("HS19", fun, jac, [20.1, 5.84], bounds, [con], xstar=[14.095, 0.84296079])


def _hs20() -> TestProblem:
    """HS20: Rosenbrock with three nonlinear inequalities and |x1| <= 0.5, n=2, m=3."""
    con = _ineq(
        lambda x: np.array([x[0] + x[1] ** 2, x[0] ** 2 + x[1], x[0] ** 2 + x[1] ** 2 - 1.0]),
        lambda x: np.array([[1.0, 2.0 * x[1]], [2.0 * x[0], 1.0], [2.0 * x[0], 2.0 * x[1]]]),
    )
    return _make(
        "HS20",
        _rosen,
        _rosen_grad,
        [-2.0, 1.0],
        [(-0.5, 0.5), (None, None)],
        [con],
        xstar=[-0.5, 0.5 * SQRT3],
        notes="f* = 40.19873502 is the local minimum at (-0.5, sqrt(3)/2) reached from x0; "
        "the global minimum is 81.5 - 25 sqrt(3) = 38.19873 at (0.5, sqrt(3)/2).",
    )


def _hs21() -> TestProblem:
    """HS21: separable quadratic with one linear inequality on a box, n=2, m=1."""

    def fun(x: Array) -> float:
        return float(0.01 * x[0] ** 2 + x[1] ** 2 - 100.0)

    def jac(x: Array) -> Array:
        return np.array([0.02 * x[0], 2.0 * x[1]])

    bounds = [(2.0, 50.0), (-50.0, 50.0)]
    con = _lin_ge([[10.0, -1.0]], [10.0])
    return _make("HS21", fun, jac, [-1.0, -1.0], bounds, [con], xstar=[2.0, 0.0])


def _hs21mod() -> TestProblem:
    """HS21MOD: CUTEst 7-variable extension of HS21, n=7, m=1."""
    w = np.array([0.01, 1.0, 0.01, 1.0, 0.01, 0.01, 1.0])

    def fun(x: Array) -> float:
        return float(w @ x**2 - 100.0)

    def jac(x: Array) -> Array:
        return 2.0 * w * x

    bounds = [(2.0, 50.0), (-50.0, 50.0), (None, 50.0), (2.0, None), (None, None), (None, 0.0), (0.0, None)]
    con = _lin_ge([[10.0, -1.0, 0.0, 0.0, 0.0, 0.0, 0.0]], [10.0])
    x0 = [-1.0, -1.0, 0.0, 0.0, 0.0, 0.0, 0.0]
    return _make("HS21MOD", fun, jac, x0, bounds, [con], xstar=[2.0, 0.0, 0.0, 2.0, 0.0, 0.0, 0.0])


def _hs22() -> TestProblem:
    """HS22: distance to (2, 1) below a line and above a parabola, n=2, m=2."""

    def fun(x: Array) -> float:
        return float((x[0] - 2.0) ** 2 + (x[1] - 1.0) ** 2)

    def jac(x: Array) -> Array:
        return np.array([2.0 * (x[0] - 2.0), 2.0 * (x[1] - 1.0)])

    con = _ineq(lambda x: np.array([x[1] - x[0] ** 2]), lambda x: np.array([[-2.0 * x[0], 1.0]]))
    return _make("HS22", fun, jac, [2.0, 2.0], None, [_lin_le([[1.0, 1.0]], [2.0]), con], xstar=[1.0, 1.0])


def _hs23() -> TestProblem:
    """HS23: squared norm with one linear and four nonlinear inequalities on a box, n=2, m=5."""

    def fun(x: Array) -> float:
        return float(x[0] ** 2 + x[1] ** 2)

    def jac(x: Array) -> Array:
        return 2.0 * np.asarray(x, dtype=float)

    con = _ineq(
        lambda x: np.array(
            [
                x[0] ** 2 + x[1] ** 2 - 1.0,
                9.0 * x[0] ** 2 + x[1] ** 2 - 9.0,
                x[0] ** 2 - x[1],
                x[1] ** 2 - x[0],
            ]
        ),
        lambda x: np.array(
            [
                [2.0 * x[0], 2.0 * x[1]],
                [18.0 * x[0], 2.0 * x[1]],
                [2.0 * x[0], -1.0],
                [-1.0, 2.0 * x[1]],
            ]
        ),
    )
    bounds = [(-50.0, 50.0), (-50.0, 50.0)]
    return _make("HS23", fun, jac, [3.0, 1.0], bounds, [_lin_ge([[1.0, 1.0]], [1.0]), con], xstar=[1.0, 1.0])


def _hs24() -> TestProblem:
    """HS24: Betts' cubic over a triangle, n=2, m=3."""
    c = 1.0 / (27.0 * SQRT3)

    def fun(x: Array) -> float:
        return float(c * ((x[0] - 3.0) ** 2 - 9.0) * x[1] ** 3)

    def jac(x: Array) -> Array:
        return np.array([2.0 * c * (x[0] - 3.0) * x[1] ** 3, 3.0 * c * ((x[0] - 3.0) ** 2 - 9.0) * x[1] ** 2])

    con = _lin_ge([[1.0 / SQRT3, -1.0], [1.0, SQRT3], [-1.0, -SQRT3]], [0.0, 0.0, -6.0])
    bounds = [(0.0, None), (0.0, None)]
    return _make("HS24", fun, jac, [1.0, 0.5], bounds, [con], xstar=[3.0, SQRT3])


# ---------------------------------------------------------------------------------------------------------------
# n = 3
# ---------------------------------------------------------------------------------------------------------------


def _hs25() -> TestProblem:
    """HS25: Holzmann's fitting problem (99 residuals) on a box, n=3, m=0."""
    i = np.arange(1.0, 100.0)
    t = 0.01 * i
    u = 25.0 + (-50.0 * np.log(t)) ** (2.0 / 3.0)

    def parts(x: Array) -> tuple[Array, Array, Array, Array]:
        d = u - x[1]
        p = d ** x[2]
        e = np.exp(-p / x[0])
        return d, p, e, e - t

    def fun(x: Array) -> float:
        r = parts(x)[3]
        return float(r @ r)

    def jac(x: Array) -> Array:
        d, p, e, r = parts(x)
        de = np.stack([e * p / x[0] ** 2, e * x[2] * p / (d * x[0]), -e * p * np.log(d) / x[0]])
        return 2.0 * (de @ r)

    bounds = [(0.1, 100.0), (0.0, 25.6), (0.0, 5.0)]
    return _make("HS25", fun, jac, [100.0, 12.5, 3.0], bounds, xstar=[50.0, 25.0, 1.5])


def _hs26() -> TestProblem:
    """HS26: quartic with one nonlinear equality (singular at x*), n=3, m=1."""

    def fun(x: Array) -> float:
        return float((x[0] - x[1]) ** 2 + (x[1] - x[2]) ** 4)

    def jac(x: Array) -> Array:
        a = 2.0 * (x[0] - x[1])
        b = 4.0 * (x[1] - x[2]) ** 3
        return np.array([a, -a + b, -b])

    con = _eq(
        lambda x: np.array([(1.0 + x[1] ** 2) * x[0] + x[2] ** 4 - 3.0]),
        lambda x: np.array([[1.0 + x[1] ** 2, 2.0 * x[0] * x[1], 4.0 * x[2] ** 3]]),
    )
    return _make("HS26", fun, jac, [-2.6, 2.0, 2.0], None, [con], xstar=[1.0, 1.0, 1.0])


def _hs27() -> TestProblem:
    """HS27: scaled Rosenbrock with one nonlinear equality, n=3, m=1."""

    def fun(x: Array) -> float:
        return float(0.01 * (x[0] - 1.0) ** 2 + (x[1] - x[0] ** 2) ** 2)

    def jac(x: Array) -> Array:
        r = x[1] - x[0] ** 2
        return np.array([0.02 * (x[0] - 1.0) - 4.0 * x[0] * r, 2.0 * r, 0.0])

    con = _eq(lambda x: np.array([x[0] + x[2] ** 2 + 1.0]), lambda x: np.array([[1.0, 0.0, 2.0 * x[2]]]))
    return _make("HS27", fun, jac, [2.0, 2.0, 2.0], None, [con], xstar=[-1.0, 1.0, 0.0])


def _hs28() -> TestProblem:
    """HS28: convex quadratic with one linear equality, n=3, m=1."""

    def fun(x: Array) -> float:
        return float((x[0] + x[1]) ** 2 + (x[1] + x[2]) ** 2)

    def jac(x: Array) -> Array:
        a = 2.0 * (x[0] + x[1])
        b = 2.0 * (x[1] + x[2])
        return np.array([a, a + b, b])

    con = _lin_eq([[1.0, 2.0, 3.0]], [1.0])
    return _make("HS28", fun, jac, [-4.0, 1.0, 1.0], None, [con], xstar=[0.5, -0.5, 0.5])


def _hs29() -> TestProblem:
    """HS29: largest box in an ellipsoid, n=3, m=1."""

    def fun(x: Array) -> float:
        return float(-x[0] * x[1] * x[2])

    def jac(x: Array) -> Array:
        return -np.array([x[1] * x[2], x[0] * x[2], x[0] * x[1]])

    con = _ineq(
        lambda x: np.array([48.0 - x[0] ** 2 - 2.0 * x[1] ** 2 - 4.0 * x[2] ** 2]),
        lambda x: np.array([[-2.0 * x[0], -4.0 * x[1], -8.0 * x[2]]]),
    )
    return _make("HS29", fun, jac, [1.0, 1.0, 1.0], None, [con], xstar=[4.0, 2.0 * np.sqrt(2.0), 2.0])


def _hs30() -> TestProblem:
    """HS30: squared norm outside a cylinder on a box, n=3, m=1."""

    def fun(x: Array) -> float:
        return float(x @ x)

    def jac(x: Array) -> Array:
        return 2.0 * np.asarray(x, dtype=float)

    con = _ineq(
        lambda x: np.array([x[0] ** 2 + x[1] ** 2 - 1.0]),
        lambda x: np.array([[2.0 * x[0], 2.0 * x[1], 0.0]]),
    )
    bounds = [(1.0, 10.0), (-10.0, 10.0), (-10.0, 10.0)]
    return _make("HS30", fun, jac, [1.0, 1.0, 1.0], bounds, [con], xstar=[1.0, 0.0, 0.0])


def _hs31() -> TestProblem:
    """HS31: weighted squared norm outside a hyperbolic cylinder on a box, n=3, m=1."""
    w = np.array([9.0, 1.0, 9.0])

    def fun(x: Array) -> float:
        return float(w @ x**2)

    def jac(x: Array) -> Array:
        return 2.0 * w * x

    con = _ineq(lambda x: np.array([x[0] * x[1] - 1.0]), lambda x: np.array([[x[1], x[0], 0.0]]))
    bounds = [(-10.0, 10.0), (1.0, 10.0), (-10.0, 1.0)]
    return _make("HS31", fun, jac, [1.0, 1.0, 1.0], bounds, [con], xstar=[1.0 / SQRT3, SQRT3, 0.0])


def _hs32() -> TestProblem:
    """HS32: quadratic on the unit simplex with a cubic inequality, n=3, m=2."""

    def fun(x: Array) -> float:
        return float((x[0] + 3.0 * x[1] + x[2]) ** 2 + 4.0 * (x[0] - x[1]) ** 2)

    def jac(x: Array) -> Array:
        s = 2.0 * (x[0] + 3.0 * x[1] + x[2])
        d = 8.0 * (x[0] - x[1])
        return np.array([s + d, 3.0 * s - d, s])

    con = _ineq(
        lambda x: np.array([6.0 * x[1] + 4.0 * x[2] - x[0] ** 3 - 3.0]),
        lambda x: np.array([[-3.0 * x[0] ** 2, 6.0, 4.0]]),
    )
    bounds = [(0.0, None)] * 3
    lin = _lin_eq([[1.0, 1.0, 1.0]], [1.0])
    return _make("HS32", fun, jac, [0.1, 0.7, 0.2], bounds, [con, lin], xstar=[0.0, 0.0, 1.0])


def _hs33() -> TestProblem:
    """HS33: cubic in x1 plus x3 between a cone and a sphere, n=3, m=2."""

    def fun(x: Array) -> float:
        return float((x[0] - 1.0) * (x[0] - 2.0) * (x[0] - 3.0) + x[2])

    def jac(x: Array) -> Array:
        return np.array([3.0 * x[0] ** 2 - 12.0 * x[0] + 11.0, 0.0, 1.0])

    con = _ineq(
        lambda x: np.array([x[2] ** 2 - x[0] ** 2 - x[1] ** 2, x[0] ** 2 + x[1] ** 2 + x[2] ** 2 - 4.0]),
        lambda x: np.array([[-2.0 * x[0], -2.0 * x[1], 2.0 * x[2]], [2.0 * x[0], 2.0 * x[1], 2.0 * x[2]]]),
    )
    bounds = [(0.0, None), (0.0, None), (0.0, 5.0)]
    return _make(
        "HS33",
        fun,
        jac,
        [0.0, 0.0, 3.0],
        bounds,
        [con],
        notes="The tabulated f* = -4 belongs to the KKT point (0, 0, 2), which is not a minimiser; "
        "the published minimiser (0, sqrt(2), sqrt(2)) has f = sqrt(2) - 6 = -4.5858 < f*, "
        "so xstar is left unset.",
    )


def _hs34() -> TestProblem:
    """HS34: maximise x1 under two exponential inequalities on a box, n=3, m=2."""

    def fun(x: Array) -> float:
        return float(-x[0])

    def jac(x: Array) -> Array:
        return np.array([-1.0, 0.0, 0.0])

    con = _ineq(
        lambda x: np.array([x[1] - np.exp(x[0]), x[2] - np.exp(x[1])]),
        lambda x: np.array([[-np.exp(x[0]), 1.0, 0.0], [0.0, -np.exp(x[1]), 1.0]]),
    )
    bounds = [(0.0, 100.0), (0.0, 100.0), (0.0, 10.0)]
    ln10 = np.log(10.0)
    return _make("HS34", fun, jac, [0.0, 1.05, 2.9], bounds, [con], xstar=[np.log(ln10), ln10, 10.0])


def _hs35_fun(x: Array) -> float:
    """Objective shared by HS35, HS35I and HS35MOD."""
    return float(
        9.0
        - 8.0 * x[0]
        - 6.0 * x[1]
        - 4.0 * x[2]
        + 2.0 * x[0] ** 2
        + 2.0 * x[1] ** 2
        + x[2] ** 2
        + 2.0 * x[0] * x[1]
        + 2.0 * x[0] * x[2]
    )


def _hs35_jac(x: Array) -> Array:
    """Gradient of :func:`_hs35_fun`."""
    return np.array(
        [
            -8.0 + 4.0 * x[0] + 2.0 * x[1] + 2.0 * x[2],
            -6.0 + 4.0 * x[1] + 2.0 * x[0],
            -4.0 + 2.0 * x[2] + 2.0 * x[0],
        ]
    )


def _hs35_con() -> LinearConstraint:
    """The single linear inequality x1 + x2 + 2 x3 <= 3 of the HS35 family."""
    return _lin_le([[1.0, 1.0, 2.0]], [3.0])


def _hs35() -> TestProblem:
    """HS35: Beale's convex QP with one linear inequality and x >= 0, n=3, m=1."""
    bounds = [(0.0, None)] * 3
    xstar = [4.0 / 3.0, 7.0 / 9.0, 4.0 / 9.0]
    return _make("HS35", _hs35_fun, _hs35_jac, [0.5] * 3, bounds, [_hs35_con()], xstar=xstar)


def _hs35i() -> TestProblem:
    """HS35I: HS35 with the CUTEst upper bounds x <= 5, n=3, m=1."""
    bounds = [(0.0, 5.0)] * 3
    xstar = [4.0 / 3.0, 7.0 / 9.0, 4.0 / 9.0]
    return _make("HS35I", _hs35_fun, _hs35_jac, [0.5] * 3, bounds, [_hs35_con()], xstar=xstar)


def _hs35mod() -> TestProblem:
    """HS35MOD: HS35 with x2 fixed at 0.5 (CUTEst variant), n=3, m=1."""
    bounds = [(0.0, None), (0.5, 0.5), (0.0, None)]
    return _make("HS35MOD", _hs35_fun, _hs35_jac, [0.5] * 3, bounds, [_hs35_con()], xstar=[1.5, 0.5, 0.5])


def _neg_prod3(x: Array) -> float:
    """``-x1 x2 x3``, the objective of HS29, HS36, HS37 and HS56."""
    return float(-x[0] * x[1] * x[2])


def _neg_prod3_grad(x: Array) -> Array:
    """Gradient of :func:`_neg_prod3` (padded with zeros beyond the third variable)."""
    g = np.zeros(np.size(x))
    g[:3] = -np.array([x[1] * x[2], x[0] * x[2], x[0] * x[1]])
    return g


def _hs36() -> TestProblem:
    """HS36: largest box under a linear budget with upper bounds, n=3, m=1."""
    bounds = [(0.0, 20.0), (0.0, 11.0), (0.0, 42.0)]
    con = _lin_le([[1.0, 2.0, 2.0]], [72.0])
    return _make("HS36", _neg_prod3, _neg_prod3_grad, [10.0] * 3, bounds, [con], xstar=[20.0, 11.0, 15.0])


def _hs37() -> TestProblem:
    """HS37: largest box with a two-sided linear budget, n=3, m=2."""
    bounds = [(0.0, 42.0)] * 3
    con = LinearConstraint(np.array([[1.0, 2.0, 2.0]]), 0.0, 72.0)
    return _make("HS37", _neg_prod3, _neg_prod3_grad, [10.0] * 3, bounds, [con], xstar=[24.0, 12.0, 12.0])


# ---------------------------------------------------------------------------------------------------------------
# n = 4
# ---------------------------------------------------------------------------------------------------------------


def _hs38() -> TestProblem:
    """HS38: Colville's (Wood's) function on a box, n=4, m=0."""

    def fun(x: Array) -> float:
        return float(
            100.0 * (x[1] - x[0] ** 2) ** 2
            + (1.0 - x[0]) ** 2
            + 90.0 * (x[3] - x[2] ** 2) ** 2
            + (1.0 - x[2]) ** 2
            + 10.1 * ((x[1] - 1.0) ** 2 + (x[3] - 1.0) ** 2)
            + 19.8 * (x[1] - 1.0) * (x[3] - 1.0)
        )

    def jac(x: Array) -> Array:
        r1 = x[1] - x[0] ** 2
        r2 = x[3] - x[2] ** 2
        return np.array(
            [
                -400.0 * x[0] * r1 - 2.0 * (1.0 - x[0]),
                200.0 * r1 + 20.2 * (x[1] - 1.0) + 19.8 * (x[3] - 1.0),
                -360.0 * x[2] * r2 - 2.0 * (1.0 - x[2]),
                180.0 * r2 + 20.2 * (x[3] - 1.0) + 19.8 * (x[1] - 1.0),
            ]
        )

    bounds = [(-10.0, 10.0)] * 4
    return _make("HS38", fun, jac, [-3.0, -1.0, -3.0, -1.0], bounds, xstar=[1.0] * 4)


def _hs39() -> TestProblem:
    """HS39: maximise x1 under two nonlinear equalities, n=4, m=2."""

    def fun(x: Array) -> float:
        return float(-x[0])

    def jac(x: Array) -> Array:
        return np.array([-1.0, 0.0, 0.0, 0.0])

    con = _eq(
        lambda x: np.array([x[1] - x[0] ** 3 - x[2] ** 2, x[0] ** 2 - x[1] - x[3] ** 2]),
        lambda x: np.array([[-3.0 * x[0] ** 2, 1.0, -2.0 * x[2], 0.0], [2.0 * x[0], -1.0, 0.0, -2.0 * x[3]]]),
    )
    return _make("HS39", fun, jac, [2.0] * 4, None, [con], xstar=[1.0, 1.0, 0.0, 0.0])


def _hs40() -> TestProblem:
    """HS40: product of the variables under three nonlinear equalities, n=4, m=3."""

    def fun(x: Array) -> float:
        return float(-np.prod(x))

    def jac(x: Array) -> Array:
        return -np.array([x[1] * x[2] * x[3], x[0] * x[2] * x[3], x[0] * x[1] * x[3], x[0] * x[1] * x[2]])

    con = _eq(
        lambda x: np.array([x[0] ** 3 + x[1] ** 2 - 1.0, x[0] ** 2 * x[3] - x[2], x[3] ** 2 - x[1]]),
        lambda x: np.array(
            [
                [3.0 * x[0] ** 2, 2.0 * x[1], 0.0, 0.0],
                [2.0 * x[0] * x[3], 0.0, -1.0, x[0] ** 2],
                [0.0, -1.0, 0.0, 2.0 * x[3]],
            ]
        ),
    )
    xstar = [2.0 ** (-1.0 / 3.0), 2.0**-0.5, 2.0 ** (-11.0 / 12.0), 2.0**-0.25]
    return _make("HS40", fun, jac, [0.8] * 4, None, [con], xstar=xstar)


def _hs41() -> TestProblem:
    """HS41: box design with one linear equality on a box, n=4, m=1."""

    def fun(x: Array) -> float:
        return float(2.0 - x[0] * x[1] * x[2])

    def jac(x: Array) -> Array:
        return np.array([-x[1] * x[2], -x[0] * x[2], -x[0] * x[1], 0.0])

    bounds = [(0.0, 1.0), (0.0, 1.0), (0.0, 1.0), (0.0, 2.0)]
    con = _lin_eq([[1.0, 2.0, 2.0, -1.0]], [0.0])
    return _make("HS41", fun, jac, [2.0] * 4, bounds, [con], xstar=[2.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0, 2.0])


def _hs42() -> TestProblem:
    """HS42: distance to (1, 2, 3, 4) with one linear and one circular equality, n=4, m=2."""
    c = np.arange(1.0, 5.0)

    def fun(x: Array) -> float:
        d = x - c
        return float(d @ d)

    def jac(x: Array) -> Array:
        return 2.0 * (x - c)

    con = _eq(
        lambda x: np.array([x[2] ** 2 + x[3] ** 2 - 2.0]),
        lambda x: np.array([[0.0, 0.0, 2.0 * x[2], 2.0 * x[3]]]),
    )
    lin = _lin_eq([[1.0, 0.0, 0.0, 0.0]], [2.0])
    s2 = np.sqrt(2.0)
    return _make("HS42", fun, jac, [1.0] * 4, None, [lin, con], xstar=[2.0, 2.0, 0.6 * s2, 0.8 * s2])


def _hs43() -> TestProblem:
    """HS43: Rosen–Suzuki problem, n=4, m=3."""

    def fun(x: Array) -> float:
        return float(
            x[0] ** 2 + x[1] ** 2 + 2.0 * x[2] ** 2 + x[3] ** 2 - 5.0 * x[0] - 5.0 * x[1] - 21.0 * x[2] + 7.0 * x[3]
        )

    def jac(x: Array) -> Array:
        return np.array([2.0 * x[0] - 5.0, 2.0 * x[1] - 5.0, 4.0 * x[2] - 21.0, 2.0 * x[3] + 7.0])

    def cfun(x: Array) -> Array:
        x1, x2, x3, x4 = x
        return np.array(
            [
                8.0 - x1**2 - x2**2 - x3**2 - x4**2 - x1 + x2 - x3 + x4,
                10.0 - x1**2 - 2.0 * x2**2 - x3**2 - 2.0 * x4**2 + x1 + x4,
                5.0 - 2.0 * x1**2 - x2**2 - x3**2 - 2.0 * x1 + x2 + x4,
            ]
        )

    def cjac(x: Array) -> Array:
        x1, x2, x3, x4 = x
        return np.array(
            [
                [-2.0 * x1 - 1.0, -2.0 * x2 + 1.0, -2.0 * x3 - 1.0, -2.0 * x4 + 1.0],
                [-2.0 * x1 + 1.0, -4.0 * x2, -2.0 * x3, -4.0 * x4 + 1.0],
                [-4.0 * x1 - 2.0, -2.0 * x2 + 1.0, -2.0 * x3, 1.0],
            ]
        )

    return _make("HS43", fun, jac, [0.0] * 4, None, [_ineq(cfun, cjac)], xstar=[0.0, 1.0, 2.0, -1.0])


def _hs44_parts() -> tuple[Callable[[Array], float], Callable[[Array], Array], LinearConstraint]:
    """Objective, gradient and linear constraints shared by HS44 and HS44NEW."""

    def fun(x: Array) -> float:
        x1, x2, x3, x4 = x
        return float(x1 - x2 - x3 - x1 * x3 + x1 * x4 + x2 * x3 - x2 * x4)

    def jac(x: Array) -> Array:
        x1, x2, x3, x4 = x
        return np.array([1.0 - x3 + x4, -1.0 + x3 - x4, -1.0 - x1 + x2, x1 - x2])

    A = [
        [1.0, 2.0, 0.0, 0.0],
        [4.0, 1.0, 0.0, 0.0],
        [3.0, 4.0, 0.0, 0.0],
        [0.0, 0.0, 2.0, 1.0],
        [0.0, 0.0, 1.0, 2.0],
        [0.0, 0.0, 1.0, 1.0],
    ]
    return fun, jac, _lin_le(A, [8.0, 12.0, 12.0, 8.0, 8.0, 5.0])


def _hs44() -> TestProblem:
    """HS44: indefinite bilinear QP with six linear inequalities and x >= 0, n=4, m=6."""
    fun, jac, con = _hs44_parts()
    return _make(
        "HS44",
        fun,
        jac,
        [0.0] * 4,
        [(0.0, None)] * 4,
        [con],
        xstar=[0.0, 3.0, 0.0, 4.0],
        notes="Nonconvex: (3, 0, 4, 0) is a local minimiser with f = -13.",
    )


def _hs44new() -> TestProblem:
    """HS44NEW: HS44 started from x0 = (1, 1, 1, 1) (CUTEst variant), n=4, m=6."""
    fun, jac, con = _hs44_parts()
    return _make(
        "HS44NEW",
        fun,
        jac,
        [1.0] * 4,
        [(0.0, None)] * 4,
        [con],
        xstar=[0.0, 3.0, 0.0, 4.0],
        notes="Nonconvex: (3, 0, 4, 0) is a local minimiser with f = -13.",
    )


# ---------------------------------------------------------------------------------------------------------------
# n = 5 to 7
# ---------------------------------------------------------------------------------------------------------------


def _hs45() -> TestProblem:
    """HS45: product of the variables on a box, n=5, m=0."""

    def fun(x: Array) -> float:
        return float(2.0 - np.prod(x) / 120.0)

    def jac(x: Array) -> Array:
        return -np.array([np.prod(np.delete(x, k)) for k in range(5)]) / 120.0

    bounds = [(0.0, float(k)) for k in range(1, 6)]
    return _make("HS45", fun, jac, [2.0] * 5, bounds, xstar=[1.0, 2.0, 3.0, 4.0, 5.0])


def _hs46() -> TestProblem:
    """HS46: high-order polynomial with two nonlinear equalities (singular at x*), n=5, m=2."""

    def fun(x: Array) -> float:
        return float((x[0] - x[1]) ** 2 + (x[2] - 1.0) ** 2 + (x[3] - 1.0) ** 4 + (x[4] - 1.0) ** 6)

    def jac(x: Array) -> Array:
        d = 2.0 * (x[0] - x[1])
        return np.array([d, -d, 2.0 * (x[2] - 1.0), 4.0 * (x[3] - 1.0) ** 3, 6.0 * (x[4] - 1.0) ** 5])

    def cfun(x: Array) -> Array:
        return np.array([x[0] ** 2 * x[3] + np.sin(x[3] - x[4]) - 1.0, x[1] + x[2] ** 4 * x[3] ** 2 - 2.0])

    def cjac(x: Array) -> Array:
        c = np.cos(x[3] - x[4])
        return np.array(
            [
                [2.0 * x[0] * x[3], 0.0, 0.0, x[0] ** 2 + c, -c],
                [0.0, 1.0, 4.0 * x[2] ** 3 * x[3] ** 2, 2.0 * x[2] ** 4 * x[3], 0.0],
            ]
        )

    x0 = [0.5 * np.sqrt(2.0), 1.75, 0.5, 2.0, 2.0]
    return _make("HS46", fun, jac, x0, None, [_eq(cfun, cjac)], xstar=[1.0] * 5)


def _hs47() -> TestProblem:
    """HS47: chained polynomial with three nonlinear equalities, n=5, m=3."""

    def fun(x: Array) -> float:
        return float((x[0] - x[1]) ** 2 + (x[1] - x[2]) ** 3 + (x[2] - x[3]) ** 4 + (x[3] - x[4]) ** 4)

    def jac(x: Array) -> Array:
        a = 2.0 * (x[0] - x[1])
        b = 3.0 * (x[1] - x[2]) ** 2
        c = 4.0 * (x[2] - x[3]) ** 3
        d = 4.0 * (x[3] - x[4]) ** 3
        return np.array([a, -a + b, -b + c, -c + d, -d])

    def cfun(x: Array) -> Array:
        return np.array([x[0] + x[1] ** 2 + x[2] ** 3 - 3.0, x[1] - x[2] ** 2 + x[3] - 1.0, x[0] * x[4] - 1.0])

    def cjac(x: Array) -> Array:
        return np.array(
            [
                [1.0, 2.0 * x[1], 3.0 * x[2] ** 2, 0.0, 0.0],
                [0.0, 1.0, -2.0 * x[2], 1.0, 0.0],
                [x[4], 0.0, 0.0, 0.0, x[0]],
            ]
        )

    s2 = np.sqrt(2.0)
    x0 = [2.0, s2, -1.0, 2.0 - s2, 0.5]
    return _make("HS47", fun, jac, x0, None, [_eq(cfun, cjac)], xstar=[1.0] * 5)


def _hs48() -> TestProblem:
    """HS48: convex quadratic with two linear equalities, n=5, m=2."""

    def fun(x: Array) -> float:
        return float((x[0] - 1.0) ** 2 + (x[1] - x[2]) ** 2 + (x[3] - x[4]) ** 2)

    def jac(x: Array) -> Array:
        a = 2.0 * (x[1] - x[2])
        b = 2.0 * (x[3] - x[4])
        return np.array([2.0 * (x[0] - 1.0), a, -a, b, -b])

    con = _lin_eq([[1.0, 1.0, 1.0, 1.0, 1.0], [0.0, 0.0, 1.0, -2.0, -2.0]], [5.0, -3.0])
    return _make("HS48", fun, jac, [3.0, 5.0, -3.0, 2.0, -2.0], None, [con], xstar=[1.0] * 5)


def _hs49() -> TestProblem:
    """HS49: high-order polynomial with two linear equalities, n=5, m=2."""

    def fun(x: Array) -> float:
        return float((x[0] - x[1]) ** 2 + (x[2] - 1.0) ** 2 + (x[3] - 1.0) ** 4 + (x[4] - 1.0) ** 6)

    def jac(x: Array) -> Array:
        d = 2.0 * (x[0] - x[1])
        return np.array([d, -d, 2.0 * (x[2] - 1.0), 4.0 * (x[3] - 1.0) ** 3, 6.0 * (x[4] - 1.0) ** 5])

    con = _lin_eq([[1.0, 1.0, 1.0, 4.0, 0.0], [0.0, 0.0, 1.0, 0.0, 5.0]], [7.0, 6.0])
    return _make("HS49", fun, jac, [10.0, 7.0, 2.0, -3.0, 0.8], None, [con], xstar=[1.0] * 5)


def _hs50() -> TestProblem:
    """HS50: chained polynomial with three linear equalities, n=5, m=3."""

    def fun(x: Array) -> float:
        return float((x[0] - x[1]) ** 2 + (x[1] - x[2]) ** 2 + (x[2] - x[3]) ** 4 + (x[3] - x[4]) ** 2)

    def jac(x: Array) -> Array:
        a = 2.0 * (x[0] - x[1])
        b = 2.0 * (x[1] - x[2])
        c = 4.0 * (x[2] - x[3]) ** 3
        d = 2.0 * (x[3] - x[4])
        return np.array([a, -a + b, -b + c, -c + d, -d])

    A = [[1.0, 2.0, 3.0, 0.0, 0.0], [0.0, 1.0, 2.0, 3.0, 0.0], [0.0, 0.0, 1.0, 2.0, 3.0]]
    con = _lin_eq(A, [6.0, 6.0, 6.0])
    return _make("HS50", fun, jac, [35.0, -31.0, 11.0, 5.0, -5.0], None, [con], xstar=[1.0] * 5)


_HS51_A = [[1.0, 3.0, 0.0, 0.0, 0.0], [0.0, 0.0, 1.0, 1.0, -2.0], [0.0, 1.0, 0.0, 0.0, -1.0]]
"""Constraint matrix shared by HS51, HS52 and HS53 (they differ in the right-hand side and bounds)."""


def _hs51_fun(x: Array) -> float:
    """Objective shared by HS51 and HS53."""
    return float((x[0] - x[1]) ** 2 + (x[1] + x[2] - 2.0) ** 2 + (x[3] - 1.0) ** 2 + (x[4] - 1.0) ** 2)


def _hs51_jac(x: Array) -> Array:
    """Gradient of :func:`_hs51_fun`."""
    a = 2.0 * (x[0] - x[1])
    b = 2.0 * (x[1] + x[2] - 2.0)
    return np.array([a, -a + b, b, 2.0 * (x[3] - 1.0), 2.0 * (x[4] - 1.0)])


def _hs51() -> TestProblem:
    """HS51: convex quadratic with three linear equalities, n=5, m=3."""
    con = _lin_eq(_HS51_A, [4.0, 0.0, 0.0])
    return _make("HS51", _hs51_fun, _hs51_jac, [2.5, 0.5, 2.0, -1.0, 0.5], None, [con], xstar=[1.0] * 5)


def _hs52() -> TestProblem:
    """HS52: HS51 with 4 x1 in place of x1 and homogeneous equalities, n=5, m=3."""

    def fun(x: Array) -> float:
        return float((4.0 * x[0] - x[1]) ** 2 + (x[1] + x[2] - 2.0) ** 2 + (x[3] - 1.0) ** 2 + (x[4] - 1.0) ** 2)

    def jac(x: Array) -> Array:
        a = 2.0 * (4.0 * x[0] - x[1])
        b = 2.0 * (x[1] + x[2] - 2.0)
        return np.array([4.0 * a, -a + b, b, 2.0 * (x[3] - 1.0), 2.0 * (x[4] - 1.0)])

    con = _lin_eq(_HS51_A, [0.0, 0.0, 0.0])
    xstar = np.array([-33.0, 11.0, 180.0, -158.0, 11.0]) / 349.0
    return _make("HS52", fun, jac, [2.0] * 5, None, [con], xstar=xstar)


def _hs53() -> TestProblem:
    """HS53: HS51's objective with HS52's homogeneous equalities on the box -10 <= x <= 10, n=5, m=3."""
    con = _lin_eq(_HS51_A, [0.0, 0.0, 0.0])
    xstar = np.array([-33.0, 11.0, 27.0, -5.0, 11.0]) / 43.0
    return _make("HS53", _hs51_fun, _hs51_jac, [2.0] * 5, [(-10.0, 10.0)] * 5, [con], xstar=xstar)


def _hs54() -> TestProblem:
    """HS54: negated Gaussian density with one linear equality on a box (Betts 11.7), n=6, m=1."""
    mu = np.array([1.0e4, 1.0, 2.0e6, 10.0, 1.0e-3, 1.0e8])
    sigma = np.array([8.0e3, 1.0, 7.0e6, 50.0, 5.0e-2, 5.0e8])
    rho = 0.2
    fac = 1.0 / (1.0 - rho**2)

    def quad(x: Array) -> tuple[float, Array]:
        y = (x - mu) / sigma
        q = fac * (y[0] ** 2 + y[1] ** 2 + 2.0 * rho * y[0] * y[1]) + y[2:] @ y[2:]
        dq = 2.0 * y
        dq[0] = 2.0 * fac * (y[0] + rho * y[1])
        dq[1] = 2.0 * fac * (y[1] + rho * y[0])
        return float(q), dq / sigma

    def fun(x: Array) -> float:
        return float(-np.exp(-0.5 * quad(x)[0]))

    def jac(x: Array) -> Array:
        q, dq = quad(x)
        return 0.5 * np.exp(-0.5 * q) * dq

    bounds = [(0.0, 2.0e4), (-10.0, 10.0), (0.0, 1.0e7), (0.0, 20.0), (-1.0, 1.0), (0.0, 2.0e8)]
    con = _lin_eq([[1.0, 4.0e3, 0.0, 0.0, 0.0, 0.0]], [1.76e4])
    x0 = [6.0e3, 1.5, 4.0e6, 2.0, 3.0e-3, 5.0e7]
    xstar = [91600.0 / 7.0, 79.0 / 70.0, 2.0e6, 10.0, 1.0e-3, 1.0e8]
    return _make(
        "HS54",
        fun,
        jac,
        x0,
        bounds,
        [con],
        xstar=xstar,
        notes="CUTEst's corrected statement (Betts 11.7). Badly scaled (variable scales 5e-2 to 5e8): unscaled "
        "SLSQP and trust-constr step x5 into the flat tail where f ~ 0 and stall; with x = diag(sigma) y "
        "both reach f* from x0.",
    )


def _hs55() -> TestProblem:
    """HS55: exponential objective with six linear equalities (one redundant) on a box, n=6, m=6."""

    def fun(x: Array) -> float:
        return float(x[0] + 2.0 * x[1] + 4.0 * x[4] + np.exp(x[0] * x[3]))

    def jac(x: Array) -> Array:
        e = np.exp(x[0] * x[3])
        return np.array([1.0 + x[3] * e, 2.0, 0.0, x[0] * e, 4.0, 0.0])

    A = [
        [1.0, 2.0, 0.0, 0.0, 5.0, 0.0],
        [1.0, 1.0, 1.0, 0.0, 0.0, 0.0],
        [0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
        [1.0, 0.0, 0.0, 1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0, 0.0, 0.0, 1.0],
    ]
    con = _lin_eq(A, [6.0, 3.0, 2.0, 1.0, 2.0, 2.0])
    bounds = [(0.0, 1.0), (0.0, None), (0.0, None), (0.0, 1.0), (0.0, None), (0.0, None)]
    x0 = [1.0, 2.0, 0.0, 0.0, 0.0, 2.0]
    xstar = [1.0, 5.0 / 3.0, 1.0 / 3.0, 0.0, 1.0 / 3.0, 5.0 / 3.0]
    return _make(
        "HS55",
        fun,
        jac,
        x0,
        bounds,
        [con],
        xstar=xstar,
        notes="The equalities have rank 5 (one is redundant). f* = 20/3 is the local minimum at x1 = 1 next to "
        "x0; the global minimum is 19/3 at (0, 4/3, 5/3, 1, 2/3, 1/3).",
    )


def _hs56() -> TestProblem:
    """HS56: largest box with trigonometric equalities, n=7, m=4."""

    def cfun(x: Array) -> Array:
        s = np.sin(x[3:]) ** 2
        return np.array(
            [
                x[0] - 4.2 * s[0],
                x[1] - 4.2 * s[1],
                x[2] - 4.2 * s[2],
                x[0] + 2.0 * x[1] + 2.0 * x[2] - 7.2 * s[3],
            ]
        )

    def cjac(x: Array) -> Array:
        d = np.sin(2.0 * x[3:])
        J = np.zeros((4, 7))
        J[0, 0] = J[1, 1] = J[2, 2] = 1.0
        J[3, :3] = [1.0, 2.0, 2.0]
        J[0, 3] = -4.2 * d[0]
        J[1, 4] = -4.2 * d[1]
        J[2, 5] = -4.2 * d[2]
        J[3, 6] = -7.2 * d[3]
        return J

    a = np.arcsin(np.sqrt(1.0 / 4.2))
    b = np.arcsin(np.sqrt(5.0 / 7.2))
    x0 = [1.0, 1.0, 1.0, a, a, a, b]
    s47, s27 = np.arcsin(np.sqrt(4.0 / 7.0)), np.arcsin(np.sqrt(2.0 / 7.0))
    xstar = [2.4, 1.2, 1.2, s47, s27, s27, 0.5 * np.pi]
    return _make("HS56", _neg_prod3, _neg_prod3_grad, x0, None, [_eq(cfun, cjac)], xstar=xstar)


BUILDERS: dict[str, Callable[[], TestProblem]] = {
    "HS1": _hs1,
    "HS2": _hs2,
    "HS3": _hs3,
    "HS3MOD": _hs3mod,
    "HS4": _hs4,
    "HS5": _hs5,
    "HS6": _hs6,
    "HS7": _hs7,
    "HS8": _hs8,
    "HS9": _hs9,
    "HS10": _hs10,
    "HS11": _hs11,
    "HS12": _hs12,
    "HS13": _hs13,
    "HS14": _hs14,
    "HS15": _hs15,
    "HS16": _hs16,
    "HS17": _hs17,
    "HS18": _hs18,
    "HS19": _hs19,
    "HS20": _hs20,
    "HS21": _hs21,
    "HS21MOD": _hs21mod,
    "HS22": _hs22,
    "HS23": _hs23,
    "HS24": _hs24,
    "HS25": _hs25,
    "HS26": _hs26,
    "HS27": _hs27,
    "HS28": _hs28,
    "HS29": _hs29,
    "HS30": _hs30,
    "HS31": _hs31,
    "HS32": _hs32,
    "HS33": _hs33,
    "HS34": _hs34,
    "HS35": _hs35,
    "HS35I": _hs35i,
    "HS35MOD": _hs35mod,
    "HS36": _hs36,
    "HS37": _hs37,
    "HS38": _hs38,
    "HS39": _hs39,
    "HS40": _hs40,
    "HS41": _hs41,
    "HS42": _hs42,
    "HS43": _hs43,
    "HS44": _hs44,
    "HS44NEW": _hs44new,
    "HS45": _hs45,
    "HS46": _hs46,
    "HS47": _hs47,
    "HS48": _hs48,
    "HS49": _hs49,
    "HS50": _hs50,
    "HS51": _hs51,
    "HS52": _hs52,
    "HS53": _hs53,
    "HS54": _hs54,
    "HS55": _hs55,
    "HS56": _hs56,
}
"""Builders of HS1–HS56 and their CUTEst variants, keyed by name, in collection order."""
