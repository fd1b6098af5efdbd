"""Hock–Schittkowski problems 57 to 119 and 268, with analytic derivatives.

Each problem has a small builder returning a fresh :class:`~sqp.problems.problem.TestProblem`; ``BUILDERS`` maps
the collection names to them in collection order.

Notes
-----
Definitions follow W. Hock and K. Schittkowski, *Test Examples for Nonlinear Programming Codes*, LNEMS 187,
Springer 1981, and K. Schittkowski, *More Test Examples for Nonlinear Programming Codes*, LNEMS 282, 1987 (HS268),
as transcribed in the CUTEst SIF files; the CUTEst variants HS76I, HS99EXP, HS100LNP and HS100MOD follow their SIF
definitions. Where CUTEst corrected the book (HS59, HS70) its version is used, since ``fstar`` comes from it.

Conventions: nonlinear constraints are SLSQP dicts (``"ineq"`` meaning ``fun(x) >= 0``), linear ones are
``scipy.optimize.LinearConstraint`` objects and two-sided nonlinear constraints are split into two inequalities.
``xstar`` is the published minimiser when it reproduces ``fstar`` and is feasible to about 1e-4; a few were
polished to more digits (said in ``notes``), and it is ``None`` where no reliable one is known.

HS67 and HS85 are defined by procedures (a fixed-point iteration and a long chain of intermediate quantities);
their derivatives are propagated exactly alongside the values by a tiny forward-mode helper, ``_Dual``.

All 63 problems of the range that the optima table lists are defined; none is left out. Departures from the
printed sources, each explained in the problem's ``notes``: HS87 uses b = 1.48477 (the value its published x*
and f* need), HS99EXP fixes Q(8) and S(8) (the SIF leaves its terminal conditions vacuous), HS85 keeps the
book's objective coefficient where the SIF differs, and HS109 divides two constraints by 2.25e6.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from functools import cache

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import LinearConstraint, brentq
from scipy.special import ndtr

from sqp.problems.problem import TestProblem
from sqp.problems.problem import eq as _eq
from sqp.problems.problem import hs_problem as _make
from sqp.problems.problem import ineq as _ineq

Array = NDArray[np.float64]
Fun = Callable[[Array], float]
Jac = Callable[[Array], Array]

SQRT2 = np.sqrt(2.0)


# --------------------------------------------------------------------------------------------------------------
# Shared helpers
# --------------------------------------------------------------------------------------------------------------




def _linear(a: Sequence, lb: float | Sequence[float], ub: float | Sequence[float]) -> LinearConstraint:
    """Linear constraints ``lb <= A x <= ub`` (``np.inf`` for a missing side)."""
    return LinearConstraint(np.atleast_2d(np.asarray(a, dtype=float)), lb, ub)


def _same_bounds(n: int, lo: float | None, hi: float | None) -> list[tuple[float | None, float | None]]:
    """The same bounds on all ``n`` variables."""
    return [(lo, hi)] * n


def _bounds(lower: Sequence[float | None], upper: Sequence[float | None]) -> list[tuple[float | None, float | None]]:
    """Bounds pairs from a list of lower and a list of upper bounds."""
    return list(zip(lower, upper, strict=True))


def _prod_grad(x: Array) -> Array:
    """Gradient of ``prod(x)``: entry i is the product of all other entries (exact when some entry is 0)."""
    return np.array([np.prod(np.delete(x, i)) for i in range(x.size)])


def _both_sides(value: Array, jac: Array, lo: Array, hi: Array) -> tuple[Array, Array]:
    """Split ``lo <= value <= hi`` into the inequalities ``value - lo >= 0`` and ``hi - value >= 0``."""
    return np.concatenate([value - lo, hi - value]), np.vstack([jac, -jac])


def _quad_parts(n: int, const: float, linear: dict[int, float], pairs: Sequence[tuple[int, int, float]]):
    """``(H, g, c)`` of ``c + sum g_i x_i + sum coef x_i x_j`` (1-based ``(i, j, coef)``) as ``x'Hx/2 + g'x + c``."""
    h = np.zeros((n, n))
    g = np.zeros(n)
    for i, v in linear.items():
        g[i - 1] += v
    for i, j, c in pairs:
        h[i - 1, j - 1] += c
        h[j - 1, i - 1] += c
    return h, g, float(const)


def _quadratic(n: int, const: float, linear: dict[int, float], pairs: Sequence[tuple[int, int, float]]):
    """Objective ``(fun, jac)`` of a quadratic given by constant, linear terms and product terms."""
    h, g, c = _quad_parts(n, const, linear, pairs)

    def fun(x: Array) -> float:
        return float(0.5 * x @ h @ x + g @ x + c)

    def jac(x: Array) -> Array:
        return h @ x + g

    return fun, jac


def _quadratic_constraints(kind: str, n: int, rows: Sequence[tuple]) -> dict:
    """One SLSQP constraint stacking quadratic rows ``(const, linear, pairs)`` (see ``_quad_parts``)."""
    parts = [_quad_parts(n, *row) for row in rows]
    h = np.array([p[0] for p in parts])
    g = np.array([p[1] for p in parts])
    c = np.array([p[2] for p in parts])

    def fun(x: Array) -> Array:
        return 0.5 * np.einsum("kij,i,j->k", h, x, x) + g @ x + c

    def jac(x: Array) -> Array:
        return h @ x + g

    return {"type": kind, "fun": fun, "jac": jac}


def _sq(i: int, j: int, coef: float = -1.0) -> list[tuple[int, int, float]]:
    """Product terms of ``coef * (x_i - x_j)**2``."""
    return [(i, i, coef), (j, j, coef), (i, j, -2.0 * coef)]


def _expo(n: int, powers: dict[int, float]) -> Array:
    """Exponent vector of a monomial, from 1-based ``{index: power}``."""
    e = np.zeros(n)
    for i, p in powers.items():
        e[i - 1] = p
    return e


def _signomial(const: float, terms: Sequence[tuple[float, Array]]) -> tuple[Fun, Jac]:
    """``const + sum_k c_k prod_i x_i**e_ki`` and its gradient, for ``x > 0`` (terms are ``(c_k, e_k)``).

    Evaluated with ``|x|`` so that a solver stepping outside the (positive) bounds gets finite values.
    """
    coef = np.array([t[0] for t in terms], dtype=float)
    expo = np.array([t[1] for t in terms], dtype=float)

    def values(x: Array) -> Array:
        return coef * np.exp(expo @ np.log(np.abs(x)))

    def fun(x: Array) -> float:
        return float(const + values(x).sum())

    def jac(x: Array) -> Array:
        return (values(x) @ expo) / x

    return fun, jac


def _stack(kind: str, parts: Sequence[tuple[Fun, Jac]]) -> dict:
    """One SLSQP constraint made of scalar ``(fun, jac)`` pairs."""

    def fun(x: Array) -> Array:
        return np.array([p[0](x) for p in parts])

    def jac(x: Array) -> Array:
        return np.array([p[1](x) for p in parts])

    return {"type": kind, "fun": fun, "jac": jac}


def _trig_terms(x: Array, terms: Sequence[tuple]) -> tuple[float, Array]:
    """Sum of ``coef * x_i * x_j * (a sin z + b cos z)``, ``z = x_k - x_l + shift``, with its gradient.

    Terms are ``(coef, i, j, a, b, k, l, shift)`` with 1-based indices; ``k`` or ``l`` may be ``None``.
    """
    value = 0.0
    grad = np.zeros_like(x)
    for coef, i, j, a, b, k, l, shift in terms:
        z = shift + (x[k - 1] if k else 0.0) - (x[l - 1] if l else 0.0)
        s, c = np.sin(z), np.cos(z)
        t = a * s + b * c
        dt = a * c - b * s
        xi, xj = x[i - 1], x[j - 1]
        value += coef * xi * xj * t
        grad[i - 1] += coef * xj * t
        grad[j - 1] += coef * xi * t
        if k:
            grad[k - 1] += coef * xi * xj * dt
        if l:
            grad[l - 1] -= coef * xi * xj * dt
    return value, grad


class _Dual:
    """A value carried with its gradient (forward-mode differentiation) for the procedurally defined problems."""

    __slots__ = ("v", "g")

    def __init__(self, v: float, g: Array) -> None:
        self.v = float(v)
        self.g = g

    @staticmethod
    def variables(x: Array) -> list[_Dual]:
        """The independent variables ``x_i`` with unit gradients."""
        eye = np.eye(x.size)
        return [_Dual(xi, eye[i]) for i, xi in enumerate(x)]

    def _lift(self, other: _Dual | float) -> _Dual:
        return other if isinstance(other, _Dual) else _Dual(other, np.zeros_like(self.g))

    def __add__(self, other: _Dual | float) -> _Dual:
        o = self._lift(other)
        return _Dual(self.v + o.v, self.g + o.g)

    __radd__ = __add__

    def __sub__(self, other: _Dual | float) -> _Dual:
        o = self._lift(other)
        return _Dual(self.v - o.v, self.g - o.g)

    def __rsub__(self, other: float) -> _Dual:
        return self._lift(other) - self

    def __neg__(self) -> _Dual:
        return _Dual(-self.v, -self.g)

    def __mul__(self, other: _Dual | float) -> _Dual:
        o = self._lift(other)
        return _Dual(self.v * o.v, self.g * o.v + o.g * self.v)

    __rmul__ = __mul__

    def __truediv__(self, other: _Dual | float) -> _Dual:
        o = self._lift(other)
        return _Dual(self.v / o.v, (self.g * o.v - o.g * self.v) / o.v**2)

    def __rtruediv__(self, other: float) -> _Dual:
        return self._lift(other) / self

    def __pow__(self, p: float) -> _Dual:
        return _Dual(self.v**p, p * self.v ** (p - 1) * self.g)


def _duals_value(d: _Dual | Sequence[_Dual]) -> float | Array:
    """Values of a dual number or a list of them."""
    return d.v if isinstance(d, _Dual) else np.array([e.v for e in d])


def _duals_grad(d: _Dual | Sequence[_Dual]) -> Array:
    """Gradient of a dual number, or Jacobian of a list of them."""
    return d.g if isinstance(d, _Dual) else np.array([e.g for e in d])


# --------------------------------------------------------------------------------------------------------------
# HS57 - HS66
# --------------------------------------------------------------------------------------------------------------

_HS57_A = np.array(
    [8, 8, 10, 10, 10, 10, 12, 12, 12, 12, 14, 14, 14, 16, 16, 16, 18, 18, 20, 20, 20, 22, 22, 22]
    + [24, 24, 24, 26, 26, 26, 28, 28, 30, 30, 30, 32, 32, 34, 36, 36, 38, 38, 40, 42],
    dtype=float,
)
_HS57_B = np.array(
    [0.49, 0.49, 0.48, 0.47, 0.48, 0.47, 0.46, 0.46, 0.45, 0.43, 0.45, 0.43, 0.43, 0.44, 0.43, 0.43]
    + [0.46, 0.45, 0.42, 0.42, 0.43, 0.41, 0.41, 0.40, 0.42, 0.40, 0.40, 0.41, 0.40, 0.41, 0.41, 0.40]
    + [0.40, 0.40, 0.38, 0.41, 0.40, 0.40, 0.41, 0.38, 0.40, 0.40, 0.39, 0.39]
)


def hs57() -> TestProblem:
    """HS57: exponential least-squares fit of 44 data points with one nonlinear inequality."""
    a, b = _HS57_A - 8.0, _HS57_B

    def parts(x: Array) -> tuple[Array, Array]:
        e = np.exp(-x[1] * a)
        return b - x[0] - (0.49 - x[0]) * e, e

    def fun(x: Array) -> float:
        r, _ = parts(x)
        return float(r @ r)

    def jac(x: Array) -> Array:
        r, e = parts(x)
        return 2.0 * np.array([r @ (e - 1.0), r @ ((0.49 - x[0]) * a * e)])

    con = _ineq(
        lambda x: np.array([0.49 * x[1] - x[0] * x[1] - 0.09]),
        lambda x: np.array([[-x[1], 0.49 - x[0]]]),
    )
    return _make("HS57", fun, jac, [0.42, 5.0], [(0.4, None), (-4.0, None)], [con], [0.419952675, 1.284845629])


# (coefficient, power of x1, power of x2) of the polynomial part of HS59 (CUTEst's corrected objective)
_HS59_TERMS = np.array(
    [
        (3.8112, 1, 0), (6.8306, 0, 1), (0.0020567, 3, 0), (-1.0345e-5, 4, 0), (-0.030234, 1, 1),
        (1.28134e-3, 2, 1), (2.266e-7, 4, 1), (-0.25645, 0, 2), (0.0034604, 0, 3), (-1.3514e-5, 0, 4),
        (5.2375e-6, 2, 2), (6.3e-8, 3, 2), (-7.0e-10, 3, 3), (-3.405e-4, 1, 2), (1.6638e-6, 1, 3),
        (-3.5256e-5, 3, 1), (-0.12694, 2, 0),
    ]
)  # fmt: skip


def hs59() -> TestProblem:
    """HS59: bivariate polynomial with rational and exponential terms, three nonlinear inequalities."""
    c, p, q = _HS59_TERMS.T

    def fun(x: Array) -> float:
        poly = c @ (x[0] ** p * x[1] ** q)
        return float(-75.196 + poly + 28.106 / (x[1] + 1.0) + 2.8673 * np.exp(0.0005 * x[0] * x[1]))

    def jac(x: Array) -> Array:
        e = 2.8673 * 0.0005 * np.exp(0.0005 * x[0] * x[1])
        d1 = c @ (p * x[0] ** np.maximum(p - 1, 0) * x[1] ** q) + e * x[1]
        d2 = c @ (q * x[0] ** p * x[1] ** np.maximum(q - 1, 0)) + e * x[0] - 28.106 / (x[1] + 1.0) ** 2
        return np.array([d1, d2])

    con = _ineq(
        lambda x: np.array([x[0] * x[1] - 700.0, x[1] - 0.008 * x[0] ** 2, (x[1] - 50.0) ** 2 - 5.0 * x[0] + 275.0]),
        lambda x: np.array([[x[1], x[0]], [-0.016 * x[0], 1.0], [-5.0, 2.0 * (x[1] - 50.0)]]),
    )
    return _make(
        "HS59", fun, jac, [90.0, 10.0], [(0.0, 75.0), (0.0, 65.0)], [con], [13.55010424, 51.66018129],
        notes="CUTEst's corrected objective (extra -0.12694 x1^2 term). From x0 solvers tend to stop at the local "
        "minimum f = -6.7495 near (46.4, 52.2).",
    )  # fmt: skip


def hs60() -> TestProblem:
    """HS60: smooth objective, one nonlinear equality, box bounds."""

    def fun(x: Array) -> float:
        return float((x[0] - 1) ** 2 + (x[0] - x[1]) ** 2 + (x[1] - x[2]) ** 4)

    def jac(x: Array) -> Array:
        a, b = 2 * (x[0] - x[1]), 4 * (x[1] - x[2]) ** 3
        return np.array([2 * (x[0] - 1) + a, -a + b, -b])

    con = _eq(
        lambda x: np.array([x[0] * (1 + x[1] ** 2) + x[2] ** 4 - 4 - 3 * SQRT2]),
        lambda x: np.array([[1 + x[1] ** 2, 2 * x[0] * x[1], 4 * x[2] ** 3]]),
    )
    return _make(
        "HS60", fun, jac, [2.0, 2.0, 2.0], _same_bounds(3, -10.0, 10.0), [con],
        [1.104859024, 1.196674194, 1.535262257],
    )  # fmt: skip


def hs61() -> TestProblem:
    """HS61: quadratic objective, two quadratic equalities, no bounds."""
    fun, jac = _quadratic(3, 0.0, {1: -33.0, 2: 16.0, 3: -24.0}, [(1, 1, 4.0), (2, 2, 2.0), (3, 3, 2.0)])
    con = _eq(
        lambda x: np.array([3 * x[0] - 2 * x[1] ** 2 - 7, 4 * x[0] - x[2] ** 2 - 11]),
        lambda x: np.array([[3.0, -4 * x[1], 0.0], [4.0, 0.0, -2 * x[2]]]),
    )
    return _make("HS61", fun, jac, [0.0, 0.0, 0.0], None, [con], [5.326770157, -2.118998639, 3.210464239])


def hs62() -> TestProblem:
    """HS62: logarithmic objective, one linear equality, box bounds."""
    w = np.array([255.0, 280.0, 290.0])
    num = np.array([[1.0, 1.0, 1.0], [0.0, 1.0, 1.0], [0.0, 0.0, 1.0]])
    den = np.array([[0.09, 1.0, 1.0], [0.0, 0.07, 1.0], [0.0, 0.0, 0.13]])

    def fun(x: Array) -> float:
        return float(-32.174 * w @ (np.log(num @ x + 0.03) - np.log(den @ x + 0.03)))

    def jac(x: Array) -> Array:
        return -32.174 * ((w / (num @ x + 0.03)) @ num - (w / (den @ x + 0.03)) @ den)

    return _make(
        "HS62", fun, jac, [0.7, 0.2, 0.1], _same_bounds(3, 0.0, 1.0), [_linear([1, 1, 1], 1.0, 1.0)],
        [0.6178126908, 0.328202223, 0.05398508606],
    )  # fmt: skip


def hs63() -> TestProblem:
    """HS63: quadratic objective, one linear and one quadratic equality, x >= 0."""
    fun, jac = _quadratic(3, 1000.0, {}, [(1, 1, -1.0), (2, 2, -2.0), (3, 3, -1.0), (1, 2, -1.0), (1, 3, -1.0)])
    con = _eq(lambda x: np.array([x @ x - 25.0]), lambda x: np.atleast_2d(2 * x))
    return _make(
        "HS63", fun, jac, [2.0, 2.0, 2.0], _same_bounds(3, 0.0, None), [_linear([8, 14, 7], 56.0, 56.0), con],
        [3.512118414, 0.2169881741, 3.552174034],
    )  # fmt: skip


def hs64() -> TestProblem:
    """HS64: sum of linear and reciprocal terms, one nonlinear inequality."""
    a, b = np.array([5.0, 20.0, 10.0]), np.array([50000.0, 72000.0, 144000.0])
    c = np.array([4.0, 32.0, 120.0])
    con = _ineq(lambda x: np.array([1.0 - c @ (1 / x)]), lambda x: np.atleast_2d(c / x**2))
    return _make(
        "HS64", lambda x: float(a @ x + b @ (1 / x)), lambda x: a - b / x**2, [1.0, 1.0, 1.0],
        _same_bounds(3, 1e-5, None), [con], [108.7347175, 85.12613942, 204.3247078],
    )  # fmt: skip


def hs65() -> TestProblem:
    """HS65: quadratic objective inside a ball, box bounds."""

    def fun(x: Array) -> float:
        return float((x[0] - x[1]) ** 2 + (x[0] + x[1] - 10) ** 2 / 9 + (x[2] - 5) ** 2)

    def jac(x: Array) -> Array:
        a, b = 2 * (x[0] - x[1]), 2 * (x[0] + x[1] - 10) / 9
        return np.array([a + b, -a + b, 2 * (x[2] - 5)])

    con = _ineq(lambda x: np.array([48.0 - x @ x]), lambda x: np.atleast_2d(-2 * x))
    return _make(
        "HS65", fun, jac, [-5.0, 5.0, 0.0], _bounds([-4.5, -4.5, -5.0], [4.5, 4.5, 5.0]), [con],
        [3.650461821, 3.65046168, 4.6204170507],
    )  # fmt: skip


def hs66() -> TestProblem:
    """HS66: linear objective, two exponential inequalities, box bounds."""
    con = _ineq(
        lambda x: np.array([x[1] - np.exp(x[0]), x[2] - np.exp(x[1])]),
        lambda x: np.array([[-np.exp(x[0]), 1.0, 0.0], [0.0, -np.exp(x[1]), 1.0]]),
    )
    return _make(
        "HS66", lambda x: float(0.2 * x[2] - 0.8 * x[0]), lambda x: np.array([-0.8, 0.0, 0.2]), [0.0, 1.05, 2.9],
        _bounds([0.0, 0.0, 0.0], [100.0, 100.0, 10.0]), [con], [0.1841264879, 1.202167873, 3.327322322],
    )  # fmt: skip


# --------------------------------------------------------------------------------------------------------------
# HS67 - HS79
# --------------------------------------------------------------------------------------------------------------


def _hs67_states(x: Array) -> list[_Dual]:
    """HS67's implicit quantities y2..y8 with gradients, by the book's two fixed-point iterations.

    As in the book (and CUTEst's SIF), each iteration stops as soon as the update changes its unknown by at most
    1e-3, keeping the previous iterate; gradients are propagated through the same steps.
    """
    x1, x2, x3 = _Dual.variables(np.asarray(x, dtype=float))
    y2 = 1.6 * x1
    for _ in range(1000):
        y3 = 1.22 * y2 - x1
        y6 = (x2 + y3) / x1
        new = 0.01 * x1 * (112.0 + 13.167 * y6 - 0.6667 * y6 * y6)
        if abs(new.v - y2.v) <= 0.001:
            break
        y2 = new
    y4 = _Dual(93.0, np.zeros(3))
    for _ in range(1000):
        y5 = 86.35 + 1.098 * y6 - 0.038 * y6 * y6 + 0.325 * (y4 - 89.0)
        y8 = 3.0 * y5 - 133.0
        y7 = 35.82 - 0.222 * y8
        new = 98000.0 * x3 / (y2 * y7 + 1000.0 * x3)
        if abs(new.v - y4.v) <= 0.001:
            break
        y4 = new
    return [y2, y3, y4, y5, y6, y7, y8]


def hs67() -> TestProblem:
    """HS67: Colville's alkylation model, states defined by two inner fixed-point iterations, 14 inequalities."""
    lo = np.array([0.0, 0.0, 85.0, 90.0, 3.0, 0.01, 145.0])
    hi = np.array([5000.0, 2000.0, 93.0, 95.0, 12.0, 4.0, 162.0])

    def objective(x: Array) -> _Dual:
        x1, x2, x3 = _Dual.variables(np.asarray(x, dtype=float))
        y = _hs67_states(x)
        return -(0.063 * y[0] * y[3] - 5.04 * x1 - 3.36 * y[1] - 0.035 * x2 - 10.0 * x3)

    def states(x: Array) -> tuple[Array, Array]:
        y = _hs67_states(x)
        return _both_sides(_duals_value(y), _duals_grad(y), lo, hi)

    con = _ineq(lambda x: states(x)[0], lambda x: states(x)[1])
    return _make(
        "HS67", lambda x: float(objective(x).v), lambda x: objective(x).g, [1745.0, 12000.0, 110.0],
        _bounds([1e-5, 1e-5, 1e-5], [2000.0, 16000.0, 120.0]), [con], None,
        notes="The inner iterations stop at the book's tolerance 1e-3, so f and the constraints are only piecewise "
        "smooth (jumps of order 1e-3 where the iteration count changes); the listed f* = -1162.119 relies on "
        "this (fully converged iterations give -1162.027 at the same point).",
    )  # fmt: skip


def _inspection(name: str, a: float, b: float, n: float, xstar: Sequence[float], notes: str = "") -> TestProblem:
    """HS68/HS69: cost-optimal inspection plan with normal-distribution equality constraints."""
    s = np.sqrt(n)  # d = 1

    def parts(x: Array) -> tuple[float, float, float]:
        em1 = np.expm1(x[0])
        return em1, b * em1 - x[2], em1 + x[3]

    def fun(x: Array) -> float:
        em1, num, den = parts(x)
        return float((a * n - num * x[3] / den) / x[0])

    def jac(x: Array) -> Array:
        em1, num, den = parts(x)
        p = num * x[3] / den
        dp1 = x[3] * np.exp(x[0]) * (b * den - num) / den**2
        return np.array([-dp1 / x[0] - (a * n - p) / x[0] ** 2, 0.0, x[3] / (den * x[0]), -num * em1 / (den**2 * x[0])])

    def cfun(x: Array) -> Array:
        return np.array([x[2] - 2 * ndtr(-x[1]), x[3] - ndtr(-x[1] + s) - ndtr(-x[1] - s)])

    def cjac(x: Array) -> Array:
        pdf = np.exp(-0.5 * np.array([x[1], s - x[1], -s - x[1]]) ** 2) / np.sqrt(2 * np.pi)
        return np.array([[0.0, 2 * pdf[0], 1.0, 0.0], [0.0, pdf[1] + pdf[2], 0.0, 1.0]])

    return _make(
        name, fun, jac, [1.0, 1.0, 1.0, 1.0], _bounds([1e-4, 0.0, 0.0, 0.0], [100.0, 100.0, 2.0, 2.0]),
        [_eq(cfun, cjac)], xstar, notes,
    )  # fmt: skip


def hs68() -> TestProblem:
    """HS68: cost-optimal inspection plan (a = 1e-4, b = 1, n = 24)."""
    return _inspection(
        "HS68", 1e-4, 1.0, 24.0, [0.06785874, 3.6461717, 0.00026617, 0.8948622],
        notes="The book prints x3* = 0.0026617; 0.00026617 = 2 Phi(-x2*) is meant.",
    )  # fmt: skip


def hs69() -> TestProblem:
    """HS69: cost-optimal inspection plan (a = 0.1, b = 1000, n = 4)."""
    return _inspection("HS69", 0.1, 1000.0, 4.0, [0.02937141, 1.1902534, 0.23394676, 0.7916678])


_HS70_C = np.array([0.1] + [float(i) for i in range(1, 19)])
_HS70_Y = np.array(
    [0.00189, 0.1038, 0.268, 0.506, 0.577, 0.604, 0.725, 0.898, 0.947, 0.845, 0.702, 0.528, 0.385, 0.257]
    + [0.159, 0.0869, 0.0453, 0.01509, 0.00189]
)


def hs70() -> TestProblem:
    """HS70: water-flow routing fit of a two-component gamma-type model to 19 points (CUTEst's corrected form)."""
    c = _HS70_C / 7.658
    logc = np.log(c)

    def component(p: float, ratio: Array | float) -> tuple[Array, Array, Array]:
        """``mix * q`` with ``q = (12p/(12p+1)) r**p sqrt(p/6.2832) c**(p-1) exp(p (1 - c r))``, and d(log q)."""
        logq = (
            -np.log1p(1 / (12 * p)) + p * np.log(ratio) + 0.5 * np.log(p / 6.2832) + (p - 1) * logc
            + p * (1 - c * ratio)
        )  # fmt: skip
        q = np.exp(logq)
        dlogq_dp = 1 / (12 * p * p + p) + np.log(ratio) + 0.5 / p + logc + 1 - c * ratio
        dlogq_dr = p / ratio - p * c
        return q, dlogq_dp, dlogq_dr

    def parts(x: Array):
        b = x[2] + x[3] * (1 - x[2])
        q1, d1p, d1r = component(x[1], b)
        q2, d2p, d2r = component(x[0], b / x[3])
        r = x[2] * q1 + (1 - x[2]) * q2 - _HS70_Y
        jr = np.empty((c.size, 4))
        jr[:, 0] = (1 - x[2]) * q2 * d2p
        jr[:, 1] = x[2] * q1 * d1p
        jr[:, 2] = q1 + x[2] * q1 * d1r * (1 - x[3]) - q2 + (1 - x[2]) * q2 * d2r * (1 / x[3] - 1)
        jr[:, 3] = x[2] * q1 * d1r * (1 - x[2]) + (1 - x[2]) * q2 * d2r * (-x[2] / x[3] ** 2)
        return r, jr

    def fun(x: Array) -> float:
        r, _ = parts(x)
        return float(r @ r)

    def jac(x: Array) -> Array:
        r, jr = parts(x)
        return 2 * r @ jr

    con = _ineq(
        lambda x: np.array([x[2] + x[3] - x[2] * x[3]]),
        lambda x: np.array([[0.0, 0.0, 1 - x[3], 1 - x[2]]]),
    )
    return _make(
        "HS70", fun, jac, [2.0, 4.0, 0.04, 2.0], _bounds([1e-5] * 4, [100.0, 100.0, 1.0, 100.0]), [con],
        [12.27695, 4.631788, 0.3128625, 2.029290],
    )  # fmt: skip


def hs71() -> TestProblem:
    """HS71: the classic 4-variable problem with a product inequality and a sphere equality."""

    def fun(x: Array) -> float:
        return float(x[0] * x[3] * (x[0] + x[1] + x[2]) + x[2])

    def jac(x: Array) -> Array:
        s = x[0] + x[1] + x[2]
        return np.array([x[3] * (s + x[0]), x[0] * x[3], x[0] * x[3] + 1, x[0] * s])

    cons = [
        _ineq(lambda x: np.array([np.prod(x) - 25.0]), lambda x: np.atleast_2d(_prod_grad(x))),
        _eq(lambda x: np.array([x @ x - 40.0]), lambda x: np.atleast_2d(2 * x)),
    ]
    return _make(
        "HS71", fun, jac, [1.0, 5.0, 5.0, 1.0], _same_bounds(4, 1.0, 5.0), cons,
        [1.0, 4.742999643, 3.821149939, 1.379408294],
    )  # fmt: skip


def hs72() -> TestProblem:
    """HS72: linear objective, two inequalities in reciprocals of the variables."""
    a = np.array([[4.0, 2.25, 1.0, 0.25], [0.16, 0.36, 0.64, 0.64]])
    rhs = np.array([0.0401, 0.010085])
    con = _ineq(lambda x: rhs - a @ (1 / x), lambda x: a / x**2)
    return _make(
        "HS72", lambda x: float(1 + x.sum()), lambda x: np.ones(4), [1.0, 1.0, 1.0, 1.0],
        _bounds([0.001] * 4, [4e5, 3e5, 2e5, 1e5]), [con], [193.4071, 179.5475, 185.0186, 168.7062],
    )  # fmt: skip


def hs73() -> TestProblem:
    """HS73: cattle-feed problem, linear objective with a chance constraint (square root)."""
    c = np.array([24.55, 26.75, 39.0, 40.5])
    a = np.array([12.0, 11.9, 41.8, 52.1])
    d = np.array([0.28, 0.19, 20.5, 0.62])

    def cfun(x: Array) -> Array:
        return np.array([a @ x - 21.0 - 1.645 * np.sqrt(d @ x**2)])

    def cjac(x: Array) -> Array:
        return np.atleast_2d(a - 1.645 * d * x / np.sqrt(d @ x**2))

    cons = [_linear([2.3, 5.6, 11.1, 1.3], 5.0, np.inf), _ineq(cfun, cjac), _linear([1, 1, 1, 1], 1.0, 1.0)]
    return _make(
        "HS73", lambda x: float(c @ x), lambda x: c, [1.0, 1.0, 1.0, 1.0], _same_bounds(4, 0.0, None), cons,
        [0.6355216, 0.0, 0.3127019, 0.05177655],
    )  # fmt: skip


def _power_dispatch(name: str, a: float, xstar: Sequence[float]) -> TestProblem:
    """HS74/HS75: power-dispatch problem with three trigonometric equalities."""

    def fun(x: Array) -> float:
        return float(3 * x[0] + 1e-6 * x[0] ** 3 + 2 * x[1] + (2e-6 / 3) * x[1] ** 3)

    def jac(x: Array) -> Array:
        return np.array([3 + 3e-6 * x[0] ** 2, 2 + 2e-6 * x[1] ** 2, 0.0, 0.0])

    def cfun(x: Array) -> Array:
        s = np.sin
        return np.array([
            1000 * (s(-x[2] - 0.25) + s(-x[3] - 0.25)) + 894.8 - x[0],
            1000 * (s(x[2] - 0.25) + s(x[2] - x[3] - 0.25)) + 894.8 - x[1],
            1000 * (s(x[3] - 0.25) + s(x[3] - x[2] - 0.25)) + 1294.8,
        ])  # fmt: skip

    def cjac(x: Array) -> Array:
        c = 1000 * np.cos(np.array([-x[2] - 0.25, -x[3] - 0.25, x[2] - 0.25, x[2] - x[3] - 0.25, x[3] - 0.25]))
        c34 = 1000 * np.cos(x[3] - x[2] - 0.25)
        return np.array([
            [-1.0, 0.0, -c[0], -c[1]],
            [0.0, -1.0, c[2] + c[3], -c[3]],
            [0.0, 0.0, -c34, c[4] + c34],
        ])  # fmt: skip

    return _make(
        name, fun, jac, [0.0, 0.0, 0.0, 0.0], _bounds([0.0, 0.0, -a, -a], [1200.0, 1200.0, a, a]),
        [_linear([0, 0, -1, 1], -a, a), _eq(cfun, cjac)], xstar,
    )  # fmt: skip


def hs74() -> TestProblem:
    """HS74: power dispatch with |x4 - x3| <= 0.55."""
    return _power_dispatch("HS74", 0.55, [679.9453, 1026.067, 0.1188764, -0.3962336])


def hs75() -> TestProblem:
    """HS75: power dispatch with |x4 - x3| <= 0.48."""
    return _power_dispatch("HS75", 0.48, [776.1592, 925.1949, 0.05110879, -0.4288911])


def _hs76(name: str, upper: float | None) -> TestProblem:
    """HS76 and its CUTEst variant HS76I: convex QP with three linear inequalities."""
    fun, jac = _quadratic(
        4, 0.0, {1: -1.0, 2: -3.0, 3: 1.0, 4: -1.0},
        [(1, 1, 1.0), (2, 2, 0.5), (3, 3, 1.0), (4, 4, 0.5), (1, 3, -1.0), (3, 4, 1.0)],
    )  # fmt: skip
    cons = [_linear([[1, 2, 1, 1], [3, 1, 2, -1], [0, 1, 4, 0]], [-np.inf, -np.inf, 1.5], [5.0, 4.0, np.inf])]
    return _make(
        name, fun, jac, [0.5, 0.5, 0.5, 0.5], _same_bounds(4, 0.0, upper), cons,
        [3 / 11, 23 / 11, 0.0, 6 / 11],
        notes="" if upper is None else "CUTEst's HS76I: HS76 with upper bounds 5 (an integer test problem there).",
    )  # fmt: skip


def hs76() -> TestProblem:
    """HS76: convex QP with three linear inequalities, x >= 0."""
    return _hs76("HS76", None)


def hs76i() -> TestProblem:
    """HS76I: HS76 with the upper bounds x <= 5 of CUTEst's variant."""
    return _hs76("HS76I", 5.0)


def hs77() -> TestProblem:
    """HS77: smooth objective, two nonlinear equalities."""

    def fun(x: Array) -> float:
        return float((x[0] - 1) ** 2 + (x[0] - x[1]) ** 2 + (x[2] - 1) ** 2 + (x[3] - 1) ** 4 + (x[4] - 1) ** 6)

    def jac(x: Array) -> Array:
        a = 2 * (x[0] - x[1])
        return np.array([2 * (x[0] - 1) + a, -a, 2 * (x[2] - 1), 4 * (x[3] - 1) ** 3, 6 * (x[4] - 1) ** 5])

    def cfun(x: Array) -> Array:
        return np.array([
            x[0] ** 2 * x[3] + np.sin(x[3] - x[4]) - 2 * SQRT2,
            x[1] + x[2] ** 4 * x[3] ** 2 - 8 - SQRT2,
        ])  # fmt: skip

    def cjac(x: Array) -> Array:
        c = np.cos(x[3] - x[4])
        return np.array([
            [2 * x[0] * x[3], 0.0, 0.0, x[0] ** 2 + c, -c],
            [0.0, 1.0, 4 * x[2] ** 3 * x[3] ** 2, 2 * x[2] ** 4 * x[3], 0.0],
        ])  # fmt: skip

    return _make(
        "HS77", fun, jac, [2.0] * 5, None, [_eq(cfun, cjac)], [1.166172, 1.182111, 1.380257, 1.506036, 0.6109203]
    )


def _hs78_constraints() -> dict:
    """The three equalities shared by HS78, HS80 and HS81."""

    def cfun(x: Array) -> Array:
        return np.array([x @ x - 10, x[1] * x[2] - 5 * x[3] * x[4], x[0] ** 3 + x[1] ** 3 + 1])

    def cjac(x: Array) -> Array:
        return np.array([
            2 * x,
            [0.0, x[2], x[1], -5 * x[4], -5 * x[3]],
            [3 * x[0] ** 2, 3 * x[1] ** 2, 0.0, 0.0, 0.0],
        ])  # fmt: skip

    return _eq(cfun, cjac)


def hs78() -> TestProblem:
    """HS78: product of the variables subject to three equalities."""
    return _make(
        "HS78", lambda x: float(np.prod(x)), _prod_grad, [-2.0, 1.5, 2.0, -1.0, -1.0], None, [_hs78_constraints()],
        [-1.717142, 1.595708, 1.827248, -0.7636429, -0.7636435],
    )  # fmt: skip


def hs79() -> TestProblem:
    """HS79: smooth objective, three nonlinear equalities."""

    def fun(x: Array) -> float:
        d = np.diff(x)
        return float((x[0] - 1) ** 2 + d[0] ** 2 + d[1] ** 2 + d[2] ** 4 + d[3] ** 4)

    def jac(x: Array) -> Array:
        d = np.diff(x)
        t = np.array([2 * d[0], 2 * d[1], 4 * d[2] ** 3, 4 * d[3] ** 3])  # derivatives of the difference terms
        g = np.zeros(5)
        g[0] = 2 * (x[0] - 1)
        g[1:] += t
        g[:-1] -= t
        return g

    def cfun(x: Array) -> Array:
        return np.array([
            x[0] + x[1] ** 2 + x[2] ** 3 - 2 - 3 * SQRT2,
            x[1] - x[2] ** 2 + x[3] + 2 - 2 * SQRT2,
            x[0] * x[4] - 2,
        ])  # fmt: skip

    def cjac(x: Array) -> Array:
        return np.array([
            [1.0, 2 * x[1], 3 * x[2] ** 2, 0.0, 0.0],
            [0.0, 1.0, -2 * x[2], 1.0, 0.0],
            [x[4], 0.0, 0.0, 0.0, x[0]],
        ])  # fmt: skip

    return _make(
        "HS79", fun, jac, [2.0] * 5, None, [_eq(cfun, cjac)], [1.191127, 1.362603, 1.472818, 1.635017, 1.679081]
    )


# --------------------------------------------------------------------------------------------------------------
# HS80 - HS98
# --------------------------------------------------------------------------------------------------------------

_HS80_BOUNDS = _bounds([-2.3, -2.3, -3.2, -3.2, -3.2], [2.3, 2.3, 3.2, 3.2, 3.2])
_HS80_XSTAR = [-1.717143, 1.595709, 1.827247, -0.7636413, -0.7636450]


def hs80() -> TestProblem:
    """HS80: exponential of the product of the variables, three equalities, box bounds."""
    return _make(
        "HS80", lambda x: float(np.exp(np.prod(x))), lambda x: np.exp(np.prod(x)) * _prod_grad(x),
        [-2.0, 2.0, 2.0, -1.0, -1.0], _HS80_BOUNDS, [_hs78_constraints()], _HS80_XSTAR,
    )  # fmt: skip


def hs81() -> TestProblem:
    """HS81: HS80 with an extra squared term in the objective."""

    def fun(x: Array) -> float:
        return float(np.exp(np.prod(x)) - 0.5 * (x[0] ** 3 + x[1] ** 3 + 1) ** 2)

    def jac(x: Array) -> Array:
        g = np.exp(np.prod(x)) * _prod_grad(x)
        g[:2] -= (x[0] ** 3 + x[1] ** 3 + 1) * 3 * x[:2] ** 2
        return g

    return _make(
        "HS81", fun, jac, [-2.0, 2.0, 2.0, -1.0, -1.0], _HS80_BOUNDS, [_hs78_constraints()], _HS80_XSTAR
    )


def hs83() -> TestProblem:
    """HS83: Colville's quadratic problem with three two-sided quadratic constraints (six inequalities)."""

    def fun(x: Array) -> float:
        return float(5.3578547 * x[2] ** 2 + 0.8356891 * x[0] * x[4] + 37.293239 * x[0] - 40792.141)

    def jac(x: Array) -> Array:
        return np.array([0.8356891 * x[4] + 37.293239, 0.0, 10.7157094 * x[2], 0.0, 0.8356891 * x[0]])

    lo, hi = np.array([0.0, 90.0, 20.0]), np.array([92.0, 110.0, 25.0])

    def parts(x: Array) -> tuple[Array, Array]:
        x1, x2, x3, x4, x5 = x
        g = np.array([
            85.334407 + 0.0056858 * x2 * x5 + 0.0006262 * x1 * x4 - 0.0022053 * x3 * x5,
            80.51249 + 0.0071317 * x2 * x5 + 0.0029955 * x1 * x2 + 0.0021813 * x3**2,
            9.300961 + 0.0047026 * x3 * x5 + 0.0012547 * x1 * x3 + 0.0019085 * x3 * x4,
        ])  # fmt: skip
        j = np.array([
            [0.0006262 * x4, 0.0056858 * x5, -0.0022053 * x5, 0.0006262 * x1, 0.0056858 * x2 - 0.0022053 * x3],
            [0.0029955 * x2, 0.0071317 * x5 + 0.0029955 * x1, 0.0043626 * x3, 0.0, 0.0071317 * x2],
            [0.0012547 * x3, 0.0, 0.0047026 * x5 + 0.0012547 * x1 + 0.0019085 * x4, 0.0019085 * x3, 0.0047026 * x3],
        ])  # fmt: skip
        return _both_sides(g, j, lo, hi)

    return _make(
        "HS83", fun, jac, [78.0, 33.0, 27.0, 27.0, 27.0], _bounds([78.0, 33.0, 27.0, 27.0, 27.0], [102.0] + [45.0] * 4),
        [_ineq(lambda x: parts(x)[0], lambda x: parts(x)[1])], [78.0, 33.0, 29.99526, 45.0, 36.77581],
    )  # fmt: skip


def hs84() -> TestProblem:
    """HS84: bilinear objective and three two-sided bilinear constraints (six inequalities)."""
    a2 = -8720288.849
    w = np.array([150512.5253, -156.6950325, 476470.3222, 729482.8271])
    c0 = np.array([-145421.402, -155011.1084, -326669.5104])
    c = np.array([
        [2931.1506, -40.427932, 5106.192, 15711.36],
        [4360.53352, 12.9492344, 10236.884, 13176.786],
        [7390.68412, -27.8986976, 16643.076, 30988.146],
    ])  # fmt: skip
    hi = np.array([294000.0, 294000.0, 277200.0])

    def fun(x: Array) -> float:
        return float(24345.0 - a2 * x[0] - x[0] * (w @ x[1:]))

    def jac(x: Array) -> Array:
        return np.concatenate([[-a2 - w @ x[1:]], -x[0] * w])

    def parts(x: Array) -> tuple[Array, Array]:
        g = x[0] * (c0 + c @ x[1:])
        j = np.column_stack([c0 + c @ x[1:], x[0] * c])
        return _both_sides(g, j, np.zeros(3), hi)

    return _make(
        "HS84", fun, jac, [2.52, 2.0, 37.5, 9.25, 6.8],
        _bounds([0.0, 1.2, 20.0, 9.0, 6.5], [1000.0, 2.4, 60.0, 9.3, 7.0]),
        [_ineq(lambda x: parts(x)[0], lambda x: parts(x)[1])], [4.53743097, 2.4, 60.0, 9.3, 7.0],
    )  # fmt: skip


# Colville's data shared by HS86 and its dual HS117
_COLVILLE_E = np.array([-15.0, -27.0, -36.0, -18.0, -12.0])
_COLVILLE_C = np.array([
    [30.0, -20.0, -10.0, 32.0, -10.0],
    [-20.0, 39.0, -6.0, -31.0, 32.0],
    [-10.0, -6.0, 10.0, -6.0, -10.0],
    [32.0, -31.0, -6.0, 39.0, -20.0],
    [-10.0, 32.0, -10.0, -20.0, 30.0],
])  # fmt: skip
_COLVILLE_D = np.array([4.0, 8.0, 10.0, 6.0, 2.0])
_COLVILLE_A = np.array([
    [-16.0, 2.0, 0.0, 1.0, 0.0],
    [0.0, -2.0, 0.0, 4.0, 2.0],
    [-3.5, 0.0, 2.0, 0.0, 0.0],
    [0.0, -2.0, 0.0, -4.0, -1.0],
    [0.0, -9.0, -2.0, 1.0, -2.8],
    [2.0, 0.0, -4.0, 0.0, 0.0],
    [-1.0, -1.0, -1.0, -1.0, -1.0],
    [-1.0, -2.0, -3.0, -2.0, -1.0],
    [1.0, 2.0, 3.0, 4.0, 5.0],
    [1.0, 1.0, 1.0, 1.0, 1.0],
])  # fmt: skip
_COLVILLE_B = np.array([-40.0, -2.0, -0.25, -4.0, -4.0, -1.0, -40.0, -60.0, 5.0, 1.0])


def hs86() -> TestProblem:
    """HS86: Colville's cubic problem with ten linear inequalities, x >= 0."""
    e, c, d = _COLVILLE_E, _COLVILLE_C, _COLVILLE_D
    return _make(
        "HS86", lambda x: float(e @ x + x @ c @ x + d @ x**3), lambda x: e + 2 * c @ x + 3 * d * x**2,
        [0.0, 0.0, 0.0, 0.0, 1.0], _same_bounds(5, 0.0, None), [_linear(_COLVILLE_A, _COLVILLE_B, np.inf)],
        [0.3, 0.33346761, 0.4, 0.42831010, 0.22396487],
    )  # fmt: skip


def _hs93_terms(x: Array, a0: float, a5: float, b0: float, b6: float) -> tuple[float, Array]:
    """``x1 x4 S (a0 + a5 x5^2) + x2 x3 T (b0 + b6 x6^2)``, S = x1+x2+x3, T = x1+1.57x2+x4, with gradient."""
    s, t = x[0] + x[1] + x[2], x[0] + 1.57 * x[1] + x[3]
    p, q = x[0] * x[3], x[1] * x[2]
    al, be = a0 + a5 * x[4] ** 2, b0 + b6 * x[5] ** 2
    value = p * s * al + q * t * be
    grad = np.array([
        al * (x[3] * s + p) + be * q,
        al * p + be * (x[2] * t + 1.57 * q),
        al * p + be * x[1] * t,
        al * x[0] * s + be * q,
        2 * a5 * x[4] * p * s,
        2 * b6 * x[5] * q * t,
    ])  # fmt: skip
    return float(value), grad


def hs93() -> TestProblem:
    """HS93: transformer design, posynomial-like objective and two inequalities."""

    def cfun(x: Array) -> Array:
        return np.array([0.001 * np.prod(x) - 2.07, 1 - _hs93_terms(x, 0.0, 0.00062, 0.0, 0.00058)[0]])

    def cjac(x: Array) -> Array:
        return np.array([0.001 * _prod_grad(x), -_hs93_terms(x, 0.0, 0.00062, 0.0, 0.00058)[1]])

    return _make(
        "HS93", lambda x: _hs93_terms(x, 0.0204, 0.0607, 0.0187, 0.0437)[0],
        lambda x: _hs93_terms(x, 0.0204, 0.0607, 0.0187, 0.0437)[1],
        [5.54, 4.4, 12.02, 11.82, 0.702, 0.852], _same_bounds(6, 0.0, None), [_ineq(cfun, cjac)],
        [5.332666, 4.656744, 10.43299, 12.08230, 0.7526074, 0.87865084],
    )  # fmt: skip


def _hs95(name: str, b: Sequence[float], notes: str = "") -> TestProblem:
    """HS95-HS98: linear objective with four bilinear inequalities; only the right-hand sides differ."""
    cost = np.array([4.3, 31.8, 63.3, 15.8, 68.5, 4.7])
    rows = [
        (-b[0], {1: 17.1, 2: 38.2, 3: 204.2, 4: 212.3, 5: 623.4, 6: 1495.5},
         [(1, 3, -169.0), (3, 5, -3580.0), (4, 5, -3810.0), (4, 6, -18500.0), (5, 6, -24300.0)]),
        (-b[1], {1: 17.9, 2: 36.8, 3: 113.9, 4: 169.7, 5: 337.8, 6: 1385.2},
         [(1, 3, -139.0), (4, 5, -2450.0), (4, 6, -16600.0), (5, 6, -17200.0)]),
        (-b[2], {2: -273.0, 4: -70.0, 5: -819.0}, [(4, 5, 26000.0)]),
        (-b[3], {1: 159.9, 2: -311.0, 4: 587.0, 5: 391.0, 6: 2198.0}, [(1, 6, -14000.0)]),
    ]  # fmt: skip
    return _make(
        name, lambda x: float(cost @ x), lambda x: cost, np.zeros(6),
        _bounds([0.0] * 6, [0.31, 0.046, 0.068, 0.042, 0.028, 0.0134]), [_quadratic_constraints("ineq", 6, rows)],
        notes=notes,
    )  # fmt: skip


def hs95() -> TestProblem:
    """HS95: bilinear inequalities, right-hand side (4.97, -1.88, -29.08, -78.02)."""
    return _hs95(
        "HS95", [4.97, -1.88, -29.08, -78.02],
        "Degenerate at x0 = 0: SLSQP stops with violation 2e-5 and trust-constr at f = 0.0166; "
        "f* is reached from other starts (x* = (0, 0, 0, 0, 0, 0.00332)).",
    )  # fmt: skip


def hs96() -> TestProblem:
    """HS96: bilinear inequalities, right-hand side (4.97, -1.88, -69.08, -118.02)."""
    return _hs95("HS96", [4.97, -1.88, -69.08, -118.02])


def hs97() -> TestProblem:
    """HS97: bilinear inequalities, right-hand side (32.97, 25.12, -29.08, -78.02)."""
    return _hs95("HS97", [32.97, 25.12, -29.08, -78.02])


def hs98() -> TestProblem:
    """HS98: bilinear inequalities, right-hand side (32.97, 25.12, -124.08, -173.02)."""
    return _hs95("HS98", [32.97, 25.12, -124.08, -173.02])


# --------------------------------------------------------------------------------------------------------------
# HS85, HS87, HS88 - HS92 (procedural, nonsmooth and heat-conduction problems)
# --------------------------------------------------------------------------------------------------------------

_HS85_LO = np.array(
    [17.505, 11.275, 214.228, 7.458, 0.961, 1.612, 0.146, 107.99, 922.693, 926.832, 18.766, 1072.163, 8961.448]
    + [0.063, 71084.33, 2802713.0]
)
_HS85_HI = np.array(
    [1053.6667, 35.03, 665.585, 584.463, 265.916, 7.046, 0.222, 273.366, 1286.105, 1444.046, 537.141, 3247.039]
    + [26844.086, 0.386, 140000.0, 12146108.0]
)


def _hs85_model(x: Array) -> tuple[_Dual, list[_Dual]]:
    """HS85's wood-pulp plant model: objective and the 37 nonlinear inequalities (>= 0), as dual numbers."""
    x1, x2, x3, x4, x5 = _Dual.variables(np.asarray(x, dtype=float))
    y1 = x2 + x3 + 41.6
    c1 = 0.024 * x4 - 4.62
    y2 = 12.5 / c1 + 12.0
    c2 = 0.0003535 * x1 * x1 + 0.5311 * x1 + 0.08705 * y2 * x1
    c3 = 0.052 * x1 + 78.0 + 0.002377 * y2 * x1
    y3 = c2 / c3
    y4 = 19.0 * y3
    c4 = 0.04782 * (x1 - y3) + 0.1956 * (x1 - y3) * (x1 - y3) / x2 + 0.6376 * y4 + 1.594 * y3
    c5 = 100.0 * x2
    c6 = x1 - y3 - y4
    c7 = 0.95 - c4 / c5
    y5 = c6 * c7
    y6 = x1 - y5 - y4 - y3
    c8 = 0.995 * (y5 + y4)
    y7 = c8 / y1
    y8 = c8 / 3798.0
    c9 = y7 - 0.0663 * y7 / y8 - 0.3153
    y9 = 96.82 / c9 + 0.321 * y1
    y10 = 1.29 * y5 + 1.258 * y4 + 2.29 * y3 + 1.71 * y6
    y11 = 1.71 * x1 - 0.452 * y4 + 0.58 * y3
    c10 = 12.3 / 752.3
    c11 = 1.75 * y2 * 0.995 * x1
    c12 = 0.995 * y10 + 1998.0
    y12 = c10 * x1 + c11 / c12
    y13 = c12 - 1.75 * y2
    y14 = 3623.0 + 64.4 * x2 + 58.4 * x3 + 146312.0 / (y9 + x5)
    c13 = 0.995 * y10 + 60.8 * x2 + 48.0 * x4 - 0.1121 * y14 - 5095.0
    y15 = y13 / c13
    y16 = 148000.0 - 331000.0 * y15 + 40.0 * y13 - 61.0 * y15 * y13
    c14 = 2324.0 * y10 - 28740000.0 * y2
    y17 = 14130000.0 - 1328.0 * y10 - 531.0 * y11 + c14 / c12
    c15 = y13 / y15 - y13 / 0.52
    c16 = 1.104 - 0.72 * y15
    c17 = y9 + x5
    f = (
        -5.843e-7 * y17 + 1.17e-4 * y14 + 0.1365 + 2.358e-5 * y13 + 1.502e-6 * y16 + 0.0321 * y12
        + 0.004324 * y5 + 1e-4 * c15 / c16 + 37.48 * y2 / c12
    )  # fmt: skip
    ys = [y2, y3, y4, y5, y6, y7, y8, y9, y10, y11, y12, y13, y14, y15, y16, y17]
    cons = [y1 - 213.1, 405.23 - y1]
    cons += [y - lo for y, lo in zip(ys, _HS85_LO, strict=True)]
    cons += [hi - y for y, hi in zip(ys, _HS85_HI, strict=True)]
    cons += [y4 - (0.28 / 0.72) * y5, 21.0 - 3496.0 * y2 / c12, 62212.0 / c17 - 110.6 - y1]
    return f, cons


def hs85() -> TestProblem:
    """HS85: Himmelblau's wood-pulp plant, 17 intermediate quantities bounded above and below (38 inequalities)."""
    con = _ineq(lambda x: _duals_value(_hs85_model(x)[1]), lambda x: _duals_grad(_hs85_model(x)[1]))
    return _make(
        "HS85", lambda x: float(_hs85_model(x)[0].v), lambda x: _hs85_model(x)[0].g, [900.0, 80.0, 115.0, 267.0, 27.0],
        _bounds([704.4148, 68.6, 0.0, 193.0, 25.0], [906.3855, 288.88, 134.75, 287.0966, 84.1988]),
        [_linear([0, 1.5, -1, 0, 0], 0.0, np.inf), con],
        [705.1803, 68.60005, 102.9001, 282.3249, 37.58411],
        notes="The book's objective (coefficient 0.004324 of y5); its f* -1.905155 is slightly below the listed one.",
    )  # fmt: skip


def hs87() -> TestProblem:
    """HS87: electrical network with a piecewise-linear (discontinuous) cost, four trigonometric equalities."""
    a, b, c = 131.078, 1.48477, 0.90798
    d, e = np.cos(1.47588), np.sin(1.47588)

    def slopes(x: Array) -> tuple[float, float]:
        s1 = 30.0 if x[0] < 300.0 else 31.0
        s2 = 28.0 if x[1] < 100.0 else (29.0 if x[1] < 200.0 else 30.0)
        return s1, s2

    def fun(x: Array) -> float:
        s1, s2 = slopes(x)
        return float(s1 * x[0] + s2 * x[1])

    def jac(x: Array) -> Array:
        return np.array([*slopes(x), 0.0, 0.0, 0.0, 0.0])

    def cfun(x: Array) -> Array:
        p = x[2] * x[3] / a
        return np.array([
            300.0 - x[0] - p * np.cos(b - x[5]) + c * d * x[2] ** 2 / a,
            -x[1] - p * np.cos(b + x[5]) + c * d * x[3] ** 2 / a,
            -x[4] - p * np.sin(b + x[5]) + c * e * x[3] ** 2 / a,
            200.0 - p * np.sin(b - x[5]) + c * e * x[2] ** 2 / a,
        ])  # fmt: skip

    def cjac(x: Array) -> Array:
        x3, x4 = x[2] / a, x[3] / a
        cm, sm, cp, sp = np.cos(b - x[5]), np.sin(b - x[5]), np.cos(b + x[5]), np.sin(b + x[5])
        return np.array([
            [-1.0, 0.0, -x4 * cm + 2 * c * d * x3, -x3 * cm, 0.0, -x[2] * x4 * sm],
            [0.0, -1.0, -x4 * cp, -x3 * cp + 2 * c * d * x4, 0.0, x[2] * x4 * sp],
            [0.0, 0.0, -x4 * sp, -x3 * sp + 2 * c * e * x4, -1.0, -x[2] * x4 * cp],
            [0.0, 0.0, -x4 * sm + 2 * c * e * x3, -x3 * sm, 0.0, x[2] * x4 * cm],
        ])  # fmt: skip

    return _make(
        "HS87", fun, jac, [390.0, 1000.0, 419.5, 340.5, 198.175, 0.5],
        _bounds([0.0, 0.0, 340.0, 340.0, -1000.0, 0.0], [400.0, 1000.0, 420.0, 420.0, 1000.0, 0.5236]),
        [_eq(cfun, cjac)], [107.8119, 196.3186, 373.8307, 420.0, 21.30713, 0.153292],
        notes="Nonsmooth: the cost is piecewise linear and jumps at x1 = 300, x2 = 100 and 200. b = 1.48477 "
        "(Colville, Himmelblau): the book and CUTEst print 1.48577, but the book's x* and f* satisfy the "
        "constraints only with 1.48477.",
    )  # fmt: skip


@cache
def _heat_modes() -> tuple[Array, Array, Array]:
    """The 30 roots of mu tan(mu) = 1 and the coefficients ``p, q`` of ``h = 2/15 + sum p rho^2 - q rho``."""
    def char(m: float) -> float:
        return m * np.sin(m) - np.cos(m)

    mu = np.array([brentq(char, j * np.pi + 1e-9, j * np.pi + np.pi / 2) for j in range(30)])
    amp = 2 * np.sin(mu) / (mu + np.sin(mu) * np.cos(mu))
    return mu, mu**3 * amp * np.sin(mu), 2 * amp * (np.sin(mu) / mu - np.cos(mu))


def _heat(name: str, n: int, xstar: Sequence[float] | None, notes: str = "") -> TestProblem:
    """HS88-HS92: time-optimal heat conduction, ``sum x^2`` subject to one transcendental inequality."""
    mu, p, q = _heat_modes()
    m2 = mu[:, None] ** 2
    sign = np.array([1.0] + [2.0 * (-1) ** k for k in range(1, n)])  # weights of exp(-mu^2 r_k), k = 1..n

    def h_and_grad(x: Array) -> tuple[float, Array]:
        r = np.cumsum((x**2)[::-1])[::-1]  # r_k = sum_{i >= k} x_i^2
        w = sign * np.exp(-m2 * r)
        rho = -(w.sum(axis=1) + (-1) ** n) / mu**2
        drho = 2 * x * np.cumsum(w, axis=1)
        return float(2 / 15 + p @ rho**2 - q @ rho), (2 * p * rho - q) @ drho

    con = _ineq(
        lambda x: np.array([1e-4 - h_and_grad(x)[0]]),
        lambda x: np.atleast_2d(-h_and_grad(x)[1]),
    )
    x0 = [0.5 * (-1) ** i for i in range(n)]
    if n % 2 == 0:
        notes = (notes + " " if notes else "") + (
            "With n even the constraint gradient vanishes at x = 0 (h = 2/15 there), where SLSQP from x0 gets stuck."
        )
    return _make(name, lambda x: float(x @ x), lambda x: 2 * x, x0, None, [con], xstar, notes)


def hs88() -> TestProblem:
    """HS88: heat conduction with two switching times."""
    return _heat("HS88", 2, [1.074319, -0.4566137])


def hs89() -> TestProblem:
    """HS89: heat conduction with three switching times."""
    return _heat("HS89", 3, None)


def hs90() -> TestProblem:
    """HS90: heat conduction with four switching times."""
    return _heat("HS90", 4, None)


def hs91() -> TestProblem:
    """HS91: heat conduction with five switching times."""
    return _heat("HS91", 5, None)


def hs92() -> TestProblem:
    """HS92: heat conduction with six switching times."""
    return _heat("HS92", 6, None, "trust-constr from x0 stops at a non-optimal point (f = 1.547).")


# --------------------------------------------------------------------------------------------------------------
# HS99 - HS109
# --------------------------------------------------------------------------------------------------------------

_HS99_A = np.array([50.0, 50.0, 75.0, 75.0, 75.0, 100.0, 100.0])
_HS99_T = np.array([0.0, 25.0, 50.0, 100.0, 150.0, 200.0, 290.0, 380.0])
_HS99_B = 32.0
# the book's x* polished to 10 digits (its 7 printed digits leave the terminal conditions violated by 0.08)
_HS99_XSTAR = [0.542467816, 0.5290214244, 0.5084491554, 0.4802688509, 0.4512363498, 0.4091830824, 0.3527878918]


def hs99() -> TestProblem:
    """HS99: rocket-flight trajectory, seven angles, terminal conditions on height and speed."""
    a, dt = _HS99_A, np.diff(_HS99_T)
    wq = dt * (0.5 * dt + _HS99_T[-1] - _HS99_T[1:])  # weight of (a_k sin x_k - b) in q8

    def cfun(x: Array) -> Array:
        u = a * np.sin(x) - _HS99_B
        return np.array([wq @ u - 1e5, dt @ u - 1000.0])

    def cjac(x: Array) -> Array:
        return np.array([wq * a * np.cos(x), dt * a * np.cos(x)])

    def fun(x: Array) -> float:
        return float(-((a * dt) @ np.cos(x)) ** 2)

    def jac(x: Array) -> Array:
        return 2 * ((a * dt) @ np.cos(x)) * a * dt * np.sin(x)

    return _make(
        "HS99", fun, jac, [0.5] * 7, _same_bounds(7, 0.0, 1.58), [_eq(cfun, cjac)], _HS99_XSTAR,
        notes="x* is the book's, polished to 10 digits so that the terminal conditions hold to 1e-4.",
    )  # fmt: skip


def hs99exp() -> TestProblem:
    """HS99EXP: HS99 with the recursions for r, q and s as 21 equality constraints (31 variables)."""
    a, dt, b = _HS99_A, np.diff(_HS99_T), _HS99_B
    # variable order of the SIF file: (X(i), R(i), Q(i), S(i)) for i = 1..7, then R(8), Q(8), S(8)
    ix = np.arange(7) * 4
    ir, iq, i_s = np.append(ix + 1, 28), np.append(ix + 2, 29), np.append(ix + 3, 30)

    def cfun(x: Array) -> Array:
        xs, r, q, s = x[ix], x[ir], x[iq], x[i_s]
        res_r = r[:-1] - r[1:] + a * dt * np.cos(xs)
        res_q = q[:-1] - q[1:] + dt * s[:-1] + 0.5 * dt**2 * (a * np.sin(xs) - b)
        res_s = s[:-1] - s[1:] + dt * (a * np.sin(xs) - b)
        return np.column_stack([res_r, res_q, res_s]).ravel()

    def cjac(x: Array) -> Array:
        j = np.zeros((21, 31))
        for k in range(7):
            row = 3 * k
            j[row, [ir[k], ir[k + 1], ix[k]]] = [1.0, -1.0, -a[k] * dt[k] * np.sin(x[ix[k]])]
            j[row + 1, [iq[k], iq[k + 1], i_s[k], ix[k]]] = [
                1.0, -1.0, dt[k], 0.5 * dt[k] ** 2 * a[k] * np.cos(x[ix[k]])
            ]  # fmt: skip
            j[row + 2, [i_s[k], i_s[k + 1], ix[k]]] = [1.0, -1.0, dt[k] * a[k] * np.cos(x[ix[k]])]
        return j

    def jac(x: Array) -> Array:
        g = np.zeros(31)
        g[28] = -2 * x[28]
        return g

    bounds: list[tuple[float | None, float | None]] = [(None, None)] * 31
    for k in ix:
        bounds[k] = (0.0, 1.58)
    for k in (1, 2, 3):  # R(1) = Q(1) = S(1) = 0
        bounds[k] = (0.0, 0.0)
    bounds[29], bounds[30] = (1e5, 1e5), (1000.0, 1000.0)
    x0 = np.zeros(31)
    x0[ix] = 0.5
    return _make(
        "HS99EXP", lambda x: float(-x[28] ** 2), jac, x0, bounds, [_eq(cfun, cjac)], _hs99exp_xstar(),
        notes="The SIF puts the terminal values 1e5 and 1000 into the constants of Q(8)DEF and S(8)DEF but leaves "
        "Q(8), S(8) free, which makes the terminal conditions vacuous (optimum -1.008e9 at x = 0); here Q(8) "
        "and S(8) are instead fixed to 1e5 and 1000 by their bounds, giving the expanded HS99 with the listed f*. "
        "Badly scaled (q up to 1e5): from x0 SLSQP ends with violation 1.5e-3, trust-constr with 2.5e-3. "
        "x* is HS99's with its trajectory appended.",
    )  # fmt: skip


def _hs99exp_xstar() -> Array:
    """HS99's minimiser with the trajectory quantities r, q, s appended in HS99EXP's variable order."""
    a, dt, b = _HS99_A, np.diff(_HS99_T), _HS99_B
    xs = np.array(_HS99_XSTAR)
    u = a * np.sin(xs) - b
    r = np.concatenate([[0.0], np.cumsum(a * dt * np.cos(xs))])
    s = np.concatenate([[0.0], np.cumsum(dt * u)])
    q = np.zeros(8)
    for k in range(7):
        q[k + 1] = q[k] + dt[k] * s[k] + 0.5 * dt[k] ** 2 * u[k]
    out = np.zeros(31)
    out[0:28:4], out[1:28:4], out[2:28:4], out[3:28:4] = xs, r[:7], q[:7], s[:7]
    out[28:] = r[7], q[7], s[7]
    return out




def _hs100_objective(x: Array) -> float:
    """HS100's objective."""
    return float(
        (x[0] - 10) ** 2 + 5 * (x[1] - 12) ** 2 + x[2] ** 4 + 3 * (x[3] - 11) ** 2 + 10 * x[4] ** 6 + 7 * x[5] ** 2
        + x[6] ** 4 - 4 * x[5] * x[6] - 10 * x[5] - 8 * x[6]
    )  # fmt: skip


def _hs100_gradient(x: Array) -> Array:
    """Gradient of HS100's objective."""
    return np.array([
        2 * (x[0] - 10), 10 * (x[1] - 12), 4 * x[2] ** 3, 6 * (x[3] - 11), 60 * x[4] ** 5,
        14 * x[5] - 4 * x[6] - 10, 4 * x[6] ** 3 - 4 * x[5] - 8,
    ])  # fmt: skip


def _hs100_constraints(x: Array, c4_linear: Sequence[float]) -> tuple[Array, Array]:
    """HS100's four constraint functions and Jacobian; ``c4_linear`` are c4's coefficients of x4, x5, x6, x7."""
    x1, x2, x3, x4, x5, x6, x7 = x
    l4, l5, l6, l7 = c4_linear
    c = np.array([
        127 - 2 * x1**2 - 3 * x2**4 - x3 - 4 * x4**2 - 5 * x5,
        282 - 7 * x1 - 3 * x2 - 10 * x3**2 - x4 + x5,
        196 - 23 * x1 - x2**2 - 6 * x6**2 + 8 * x7,
        -4 * x1**2 - x2**2 + 3 * x1 * x2 - 2 * x3**2 + l4 * x4 + l5 * x5 + l6 * x6 + l7 * x7,
    ])  # fmt: skip
    j = np.array([
        [-4 * x1, -12 * x2**3, -1.0, -8 * x4, -5.0, 0.0, 0.0],
        [-7.0, -3.0, -20 * x3, -1.0, 1.0, 0.0, 0.0],
        [-23.0, -2 * x2, 0.0, 0.0, 0.0, -12 * x6, 8.0],
        [-8 * x1 + 3 * x2, -2 * x2 + 3 * x1, -4 * x3, l4, l5, l6, l7],
    ])  # fmt: skip
    return c, j


_HS100_X0 = [1.0, 2.0, 0.0, 4.0, 0.0, 1.0, 1.0]
_HS100_XSTAR = [2.330499, 1.951372, -0.4775414, 4.365726, -0.6244870, 1.038131, 1.594227]
_HS100_C4 = (0.0, 0.0, -5.0, 11.0)


def hs100() -> TestProblem:
    """HS100: polynomial objective with four polynomial inequalities."""
    con = _ineq(lambda x: _hs100_constraints(x, _HS100_C4)[0], lambda x: _hs100_constraints(x, _HS100_C4)[1])
    return _make("HS100", _hs100_objective, _hs100_gradient, _HS100_X0, None, [con], _HS100_XSTAR)


def hs100lnp() -> TestProblem:
    """HS100LNP: HS100 with its two active inequalities as equalities and the inactive ones dropped."""
    con = _eq(
        lambda x: _hs100_constraints(x, _HS100_C4)[0][[0, 3]],
        lambda x: _hs100_constraints(x, _HS100_C4)[1][[0, 3]],
    )
    return _make("HS100LNP", _hs100_objective, _hs100_gradient, _HS100_X0, None, [con], _HS100_XSTAR)


def hs100mod() -> TestProblem:
    """HS100MOD: Toint's modification of HS100 (extra linear terms 587 x4 + 391 x5 + 2193 x6 in c4)."""
    c4 = (587.0, 391.0, 2193.0, 11.0)
    con = _ineq(lambda x: _hs100_constraints(x, c4)[0], lambda x: _hs100_constraints(x, c4)[1])
    return _make("HS100MOD", _hs100_objective, _hs100_gradient, _HS100_X0, None, [con], None)


def _hs101(name: str, a: float, xstar: Sequence[float], notes: str = "") -> TestProblem:
    """HS101-HS103: signomial objective, four signomial inequalities and 100 <= f <= 3000."""
    e = _expo
    obj = [
        (10.0, e(7, {1: 1, 2: -1, 4: 2, 6: -3, 7: a})),
        (15.0, e(7, {1: -1, 2: -2, 3: 1, 4: 1, 5: -1, 7: -0.5})),
        (20.0, e(7, {1: -2, 2: 1, 4: -1, 5: -2, 6: 1})),
        (25.0, e(7, {1: 2, 2: 2, 3: -1, 5: 0.5, 6: -2, 7: 1})),
    ]
    rows = [
        [(0.5, {1: 0.5, 3: -1, 6: -2, 7: 1}), (0.7, {1: 3, 2: 1, 3: -2, 6: 1, 7: 0.5}),
         (0.2, {2: -1, 3: 1, 4: -0.5, 6: 2 / 3, 7: 0.25})],
        [(1.3, {1: -0.5, 2: 1, 3: -1, 5: -1, 6: 1}), (0.8, {3: 1, 4: -1, 5: -1, 6: 2}),
         (3.1, {1: -1, 2: 0.5, 4: -2, 5: -1, 6: 1 / 3})],
        [(2.0, {1: 1, 3: -1.5, 5: 1, 6: -1, 7: 1 / 3}), (0.1, {2: 1, 3: -0.5, 5: 1, 6: -1, 7: -0.5}),
         (1.0, {1: -1, 2: 1, 3: 0.5, 5: 1}), (0.65, {2: -2, 3: 1, 5: 1, 6: -1, 7: 1})],
        [(0.2, {1: -2, 2: 1, 4: -1, 5: 0.5, 7: 1 / 3}), (0.3, {1: 0.5, 2: 2, 3: 1, 4: 1 / 3, 5: -2 / 3, 7: 0.25}),
         (0.4, {1: -3, 2: -2, 3: 1, 5: 1, 7: 0.75}), (0.5, {3: -2, 4: 1, 7: 0.5})],
    ]  # fmt: skip
    parts = [_signomial(1.0, [(-c, e(7, p)) for c, p in row]) for row in rows]
    parts += [_signomial(-100.0, obj), _signomial(3000.0, [(-c, p) for c, p in obj])]
    fun, jac = _signomial(0.0, obj)
    return _make(
        name, fun, jac, [6.0] * 7, _bounds([0.1] * 6 + [0.01], [10.0] * 7), [_stack("ineq", parts)], xstar, notes
    )


def hs101() -> TestProblem:
    """HS101: signomial problem with exponent a = -0.25."""
    return _hs101("HS101", -0.25, [2.856159, 0.6108230, 2.150813, 4.712874, 0.9994875, 1.347508, 0.03165277])


def hs102() -> TestProblem:
    """HS102: signomial problem with exponent a = 0.125."""
    xstar = [3.896253191, 0.8093587601, 2.664385994, 4.300912875, 0.8535549352, 1.095287445, 0.0273104597]
    return _hs101("HS102", 0.125, xstar, "x* computed here (trust-constr, 10 digits).")


def hs103() -> TestProblem:
    """HS103: signomial problem with exponent a = 0.5."""
    xstar = [4.394104511, 0.8544687388, 2.843230314, 3.399978668, 0.722926133, 0.8704063818, 0.0246388263]
    return _hs101("HS103", 0.5, xstar, "x* computed here (trust-constr, 10 digits).")


def hs104() -> TestProblem:
    """HS104: reactor design, signomial objective and inequalities, 0.1 <= f <= 4.2."""
    e = _expo
    obj = [
        (0.4, e(8, {1: 0.67, 7: -0.67})), (0.4, e(8, {2: 0.67, 8: -0.67})), (-1.0, e(8, {1: 1})), (-1.0, e(8, {2: 1}))
    ]  # fmt: skip
    parts = [
        _signomial(1.0, [(-0.0588, e(8, {5: 1, 7: 1})), (-0.1, e(8, {1: 1}))]),
        _signomial(1.0, [(-0.0588, e(8, {6: 1, 8: 1})), (-0.1, e(8, {1: 1})), (-0.1, e(8, {2: 1}))]),
        _signomial(
            1.0, [(-4.0, e(8, {3: 1, 5: -1})), (-2.0, e(8, {3: -0.71, 5: -1})), (-0.0588, e(8, {3: -1.3, 7: 1}))]
        ),
        _signomial(
            1.0, [(-4.0, e(8, {4: 1, 6: -1})), (-2.0, e(8, {4: -0.71, 6: -1})), (-0.0588, e(8, {4: -1.3, 8: 1}))]
        ),
        _signomial(10.0 - 0.1, obj),
        _signomial(4.2 - 10.0, [(-c, p) for c, p in obj]),
    ]
    fun, jac = _signomial(10.0, obj)
    return _make(
        "HS104", fun, jac, [6.0, 3.0, 0.4, 0.2, 6.0, 6.0, 1.0, 0.5], _same_bounds(8, 0.1, 10.0),
        [_stack("ineq", parts)], [6.465114, 2.232709, 0.6673975, 0.5957564, 5.932676, 5.527235, 1.013322, 0.4006682],
    )  # fmt: skip


# HS105 data: distinct observed values and how often each occurs (235 observations)
_HS105_Y = np.array(
    [95, 105, 110, 115, 120, 125, 130, 135, 140, 145, 150, 155, 160, 165, 170, 175, 180, 185, 190, 195, 200]
    + [205, 210, 215, 220, 230, 235, 240, 245, 250],
    dtype=float,
)
_HS105_COUNT = np.array(
    [1, 1, 4, 4, 15, 15, 15, 13, 21, 12, 17, 4, 20, 8, 17, 8, 6, 6, 7, 4, 3, 3, 8, 1, 6, 5, 1, 7, 1, 2], dtype=float
)


def hs105() -> TestProblem:
    """HS105: maximum-likelihood fit of a mixture of three normal distributions to 235 observations."""
    y, w = _HS105_Y, _HS105_COUNT

    def parts(x: Array) -> tuple[Array, Array]:
        weights = np.array([x[0], x[1], 1.0 - x[0] - x[1]])
        means, sds = x[2:5], x[5:8]
        z = (y[:, None] - means) / sds
        dens = np.exp(-0.5 * z**2) / sds  # (points, components), without the mixture weights
        terms = weights * dens
        s = terms.sum(axis=1)
        ds = np.zeros((y.size, 8))
        ds[:, 0] = dens[:, 0] - dens[:, 2]
        ds[:, 1] = dens[:, 1] - dens[:, 2]
        ds[:, 2:5] = terms * z / sds
        ds[:, 5:8] = terms * (z**2 - 1) / sds
        return s, ds

    def fun(x: Array) -> float:
        s, _ = parts(x)
        return float(-w @ np.log(s / np.sqrt(2 * np.pi)))

    def jac(x: Array) -> Array:
        s, ds = parts(x)
        return -(w / s) @ ds

    return _make(
        "HS105", fun, jac, [0.1, 0.2, 100.0, 125.0, 175.0, 11.2, 13.2, 15.8],
        _bounds([0.001, 0.001, 100.0, 130.0, 170.0, 5.0, 5.0, 5.0], [0.499, 0.499, 180.0, 210.0, 240.0] + [25.0] * 3),
        [_linear([1, 1, 0, 0, 0, 0, 0, 0], -np.inf, 1.0)],
        None,
        notes="The published x0 has x4 = 125 below its lower bound 130. The listed f* = 1138.416 (book, CUTEst) is "
        "not the minimum: the book's own x* gives 1136.67 and SLSQP reaches about 1136.31, so x* is omitted.",
    )  # fmt: skip


def hs106() -> TestProblem:
    """HS106: heat-exchanger design, linear objective, three linear and three bilinear inequalities."""
    lin = _linear(
        [[0, 0, 0, 0.0025, 0, 0.0025, 0, 0], [0, 0, 0, -0.0025, 0.0025, 0, 0.0025, 0], [0, 0, 0, 0, -0.01, 0, 0, 0.01]],
        -np.inf, 1.0,
    )  # fmt: skip
    rows = [
        (83333.333, {1: -100.0, 4: -833.33252}, [(1, 6, 1.0)]),
        (0.0, {4: 1250.0, 5: -1250.0}, [(2, 7, 1.0), (2, 4, -1.0)]),
        (-1250000.0, {5: 2500.0}, [(3, 8, 1.0), (3, 5, -1.0)]),
    ]
    c = np.array([1.0, 1.0, 1.0, 0, 0, 0, 0, 0])
    return _make(
        "HS106", lambda x: float(c @ x), lambda x: c, [5000.0, 5000.0, 5000.0, 200.0, 350.0, 150.0, 225.0, 425.0],
        _bounds([100.0, 1000.0, 1000.0] + [10.0] * 5, [10000.0] * 3 + [1000.0] * 5),
        [lin, _quadratic_constraints("ineq", 8, rows)],
        [579.3167, 1359.943, 5110.071, 182.0174, 295.5985, 217.9799, 286.4162, 395.5979],
        notes="Badly scaled; SLSQP reaches 7049.248, below the listed f* (the book's x* gives 7049.33).",
    )  # fmt: skip


def _polytrig_constraints(kind: str, n: int, rows: Sequence[tuple]) -> dict:
    """Stacked rows ``(const, linear, pairs, trig_terms)``: a quadratic (``_quad_parts``) plus ``_trig_terms``."""
    quads = [_quad_parts(n, const, linear, pairs) for const, linear, pairs, _ in rows]

    def both(x: Array) -> tuple[Array, Array]:
        values, grads = [], []
        for (h, g, c), row in zip(quads, rows, strict=True):
            tv, tg = _trig_terms(x, row[3])
            values.append(0.5 * x @ h @ x + g @ x + c + tv)
            grads.append(h @ x + g + tg)
        return np.array(values), np.array(grads)

    return {"type": kind, "fun": lambda x: both(x)[0], "jac": lambda x: both(x)[1]}


def hs107() -> TestProblem:
    """HS107: static power scheduling, cubic cost and six trigonometric power-flow equalities."""
    c = 48.4 / 50.176 * np.sin(0.25)
    d = 48.4 / 50.176 * np.cos(0.25)
    rows = [
        (0.4, {1: -1.0}, [(5, 5, 2 * c)], [(-1, 5, 6, d, c, 8, None, 0.0), (-1, 5, 7, d, c, 9, None, 0.0)]),
        (0.4, {2: -1.0}, [(6, 6, 2 * c)], [(1, 5, 6, d, -c, 8, None, 0.0), (1, 6, 7, d, -c, 8, 9, 0.0)]),
        (0.8, {}, [(7, 7, 2 * c)], [(1, 5, 7, d, -c, 9, None, 0.0), (-1, 6, 7, d, c, 8, 9, 0.0)]),
        (0.2, {3: -1.0}, [(5, 5, 2 * d)], [(1, 5, 6, c, -d, 8, None, 0.0), (1, 5, 7, c, -d, 9, None, 0.0)]),
        (0.2, {4: -1.0}, [(6, 6, 2 * d)], [(-1, 5, 6, c, d, 8, None, 0.0), (-1, 6, 7, c, d, 8, 9, 0.0)]),
        (-0.337, {}, [(7, 7, 2 * d)], [(-1, 5, 7, c, d, 9, None, 0.0), (1, 6, 7, c, -d, 8, 9, 0.0)]),
    ]

    def fun(x: Array) -> float:
        return float(3000 * x[0] + 1000 * x[0] ** 3 + 2000 * x[1] + 666.667 * x[1] ** 3)

    def jac(x: Array) -> Array:
        return np.array([3000 + 3000 * x[0] ** 2, 2000 + 2000.001 * x[1] ** 2, 0, 0, 0, 0, 0, 0, 0])

    lo = [0.0, 0.0, None, None, 0.90909, 0.90909, 0.90909, None, None]
    hi = [None, None, None, None, 1.0909, 1.0909, 1.0909, None, None]
    return _make(
        "HS107", fun, jac, [0.8, 0.8, 0.2, 0.2, 1.0454, 1.0454, 1.0454, 0.0, 0.0], _bounds(lo, hi),
        [_polytrig_constraints("eq", 9, rows)],
        [0.6670095, 1.022388, 0.2282879, 0.1848217, 1.090900, 1.090900, 1.069036, 0.1066126, -0.3387867],
        notes="The published start lacks x7; 1.0454 as for x5, x6 (as in CUTEst).",
    )  # fmt: skip


def hs108() -> TestProblem:
    """HS108: largest hexagon of diameter one, bilinear objective and 13 quadratic inequalities."""
    fun, jac = _quadratic(9, 0.0, {}, [(1, 4, -0.5), (2, 3, 0.5), (3, 9, -0.5), (5, 9, 0.5), (5, 8, -0.5), (6, 7, 0.5)])
    rows = [
        (1.0, {}, [(3, 3, -1.0), (4, 4, -1.0)]),
        (1.0, {}, [(9, 9, -1.0)]),
        (1.0, {}, [(5, 5, -1.0), (6, 6, -1.0)]),
        (1.0, {}, [(1, 1, -1.0), *_sq(2, 9)]),
        (1.0, {}, [*_sq(1, 5), *_sq(2, 6)]),
        (1.0, {}, [*_sq(1, 7), *_sq(2, 8)]),
        (1.0, {}, [*_sq(3, 5), *_sq(4, 6)]),
        (1.0, {}, [*_sq(3, 7), *_sq(4, 8)]),
        (1.0, {}, [(7, 7, -1.0), *_sq(8, 9)]),
        (0.0, {}, [(1, 4, 1.0), (2, 3, -1.0)]),
        (0.0, {}, [(3, 9, 1.0)]),
        (0.0, {}, [(5, 9, -1.0)]),
        (0.0, {}, [(5, 8, 1.0), (6, 7, -1.0)]),
    ]
    return _make(
        "HS108", fun, jac, [1.0] * 9, [(None, None)] * 8 + [(0.0, None)], [_quadratic_constraints("ineq", 9, rows)],
        [0.8841292, 0.4672425, 0.03742076, 0.9992996, 0.8841292, 0.4672424, 0.03742076, 0.9992996, 0.0],
    )  # fmt: skip


def hs109() -> TestProblem:
    """HS109: power scheduling with cubic cost, two quadratic inequalities and six trigonometric equalities."""
    a, b, c = 50.176, np.sin(0.25), np.cos(0.25)
    q = -2 * c + 0.0007533 * a
    rows = [
        (400 * a, {1: -a}, [(5, 5, 2 * b)], [(1, 5, 6, 1, 0, None, 3, -0.25), (1, 5, 7, 1, 0, None, 4, -0.25)]),
        (400 * a, {2: -a}, [(6, 6, 2 * b)], [(1, 5, 6, 1, 0, 3, None, -0.25), (1, 6, 7, 1, 0, 3, 4, -0.25)]),
        (881.779 * a, {}, [(7, 7, 2 * b)], [(1, 5, 7, 1, 0, 4, None, -0.25), (1, 6, 7, 1, 0, 4, 3, -0.25)]),
        (-200 * a, {8: a}, [(5, 5, q)], [(1, 5, 6, 0, 1, None, 3, -0.25), (1, 5, 7, 0, 1, None, 4, -0.25)]),
        (-200 * a, {9: a}, [(6, 6, q)], [(1, 5, 6, 0, 1, 3, None, -0.25), (1, 6, 7, 0, 1, 3, 4, -0.25)]),
        (-22.938 * a, {}, [(7, 7, q)], [(1, 5, 7, 0, 1, 4, None, -0.25), (1, 6, 7, 0, 1, 4, 3, -0.25)]),
    ]
    # x1^2 + x8^2 <= 2.25e6 and x2^2 + x9^2 <= 2.25e6, divided by 2.25e6 (keeps finite differences accurate)
    r = 1 / 2.25e6
    ineq = [(1.0, {}, [(1, 1, -r), (8, 8, -r)]), (1.0, {}, [(2, 2, -r), (9, 9, -r)])]

    def fun(x: Array) -> float:
        return float(3 * x[0] + 1e-6 * x[0] ** 3 + 2 * x[1] + 0.522074e-6 * x[1] ** 3)

    def jac(x: Array) -> Array:
        return np.array([3 + 3e-6 * x[0] ** 2, 2 + 1.566222e-6 * x[1] ** 2, 0, 0, 0, 0, 0, 0, 0])

    lo = [0.0, 0.0, -0.55, -0.55, 196.0, 196.0, 196.0, -400.0, -400.0]
    hi = [None, None, 0.55, 0.55, 252.0, 252.0, 252.0, 800.0, 800.0]
    return _make(
        "HS109", fun, jac, np.zeros(9), _bounds(lo, hi),
        [_linear([0, 0, -1, 1, 0, 0, 0, 0, 0], -0.55, 0.55), _quadratic_constraints("ineq", 9, ineq),
         _polytrig_constraints("eq", 9, rows)],
        [675.0253393, 1134.021090, 0.1334850509, -0.3711902627, 252.0, 252.0, 201.4658577, 426.6190057, 368.4881991],
        notes="x* polished to 10 digits (the book's rounded x* violates the equalities by 1.7). The two "
        "quadratic inequalities x1^2 + x8^2 <= 2.25e6, x2^2 + x9^2 <= 2.25e6 are divided by 2.25e6.",
    )  # fmt: skip


# --------------------------------------------------------------------------------------------------------------
# HS111 - HS119, HS268
# --------------------------------------------------------------------------------------------------------------

_EQUILIBRIUM_C = np.array([-6.089, -17.164, -34.054, -5.914, -24.721, -14.986, -24.1, -10.708, -26.662, -22.179])
_EQUILIBRIUM_A = np.array([
    [1, 2, 2, 0, 0, 1, 0, 0, 0, 1],
    [0, 0, 0, 1, 2, 1, 1, 0, 0, 0],
    [0, 0, 1, 0, 0, 0, 1, 1, 2, 1],
], dtype=float)  # fmt: skip
_EQUILIBRIUM_B = np.array([2.0, 1.0, 1.0])
_EQUILIBRIUM_NOTE = (
    "The listed f* = -47.707579 (CUTEst) lies above the true minimum -47.761091 (book), which solvers reach; the "
    "book's x* is therefore too far from the listed f* to serve as xstar."
)


def hs111() -> TestProblem:
    """HS111: chemical equilibrium in log-variables, three exponential equalities."""
    c, a = _EQUILIBRIUM_C, _EQUILIBRIUM_A

    def fun(x: Array) -> float:
        w = np.exp(x)
        return float(w @ (c + x - np.log(w.sum())))

    def jac(x: Array) -> Array:
        w = np.exp(x)
        return w * (c + x - np.log(w.sum()))

    con = _eq(lambda x: a @ np.exp(x) - _EQUILIBRIUM_B, lambda x: a * np.exp(x))
    return _make("HS111", fun, jac, [-2.3] * 10, _same_bounds(10, -100.0, 100.0), [con], None, _EQUILIBRIUM_NOTE)


def hs112() -> TestProblem:
    """HS112: chemical equilibrium (entropy-like objective), three linear equalities."""
    c = _EQUILIBRIUM_C

    def fun(x: Array) -> float:
        return float(x @ (c + np.log(x / x.sum())))

    def jac(x: Array) -> Array:
        return c + np.log(x / x.sum())

    return _make(
        "HS112", fun, jac, [0.1] * 10, _same_bounds(10, 1e-6, None),
        [_linear(_EQUILIBRIUM_A, _EQUILIBRIUM_B, _EQUILIBRIUM_B)], None, _EQUILIBRIUM_NOTE,
    )  # fmt: skip


def hs113() -> TestProblem:
    """HS113: Wong's quadratic problem with three linear and five quadratic inequalities."""
    w = np.array([1.0, 4.0, 1.0, 2.0, 5.0, 7.0, 2.0, 1.0])
    t = np.array([10.0, 5.0, 3.0, 1.0, 0.0, 11.0, 10.0, 7.0])

    def fun(x: Array) -> float:
        return float(x[0] ** 2 + x[1] ** 2 + x[0] * x[1] - 14 * x[0] - 16 * x[1] + w @ (x[2:] - t) ** 2 + 45)

    def jac(x: Array) -> Array:
        return np.concatenate([[2 * x[0] + x[1] - 14, 2 * x[1] + x[0] - 16], 2 * w * (x[2:] - t)])

    lin = _linear(
        [[-4, -5, 0, 0, 0, 0, 3, -9, 0, 0], [-10, 8, 0, 0, 0, 0, 17, -2, 0, 0], [8, -2, 0, 0, 0, 0, 0, 0, -5, 2]],
        [-105.0, 0.0, -12.0], np.inf,
    )  # fmt: skip
    rows = [  # expanded forms of -3(x1-2)^2 - 4(x2-3)^2 - 2x3^2 + 7x4 + 120 etc.
        (72.0, {1: 12.0, 2: 24.0, 4: 7.0}, [(1, 1, -3.0), (2, 2, -4.0), (3, 3, -2.0)]),
        (4.0, {2: -8.0, 3: 12.0, 4: 2.0}, [(1, 1, -5.0), (3, 3, -1.0)]),
        (-34.0, {1: 8.0, 2: 16.0, 6: 1.0}, [(1, 1, -0.5), (2, 2, -2.0), (5, 5, -3.0)]),
        (-8.0, {2: 8.0, 5: -14.0, 6: 6.0}, [(1, 1, -1.0), (2, 2, -2.0), (1, 2, 2.0)]),
        (-768.0, {1: 3.0, 2: -6.0, 9: 192.0, 10: 7.0}, [(9, 9, -12.0)]),
    ]
    return _make(
        "HS113", fun, jac, [2.0, 3.0, 5.0, 5.0, 1.0, 2.0, 7.0, 3.0, 6.0, 10.0], None,
        [lin, _quadratic_constraints("ineq", 10, rows)],
        [2.171996, 2.363683, 8.773926, 5.095984, 0.9906548, 1.430574, 1.321644, 9.828726, 8.280092, 8.375927],
    )  # fmt: skip


def hs114() -> TestProblem:
    """HS114: alkylation process, four linear and four nonlinear inequalities, three equalities."""
    a, b = 0.99, 0.9
    cost = np.array([5.04, 0.035, 10.0, 0.0, 3.36, 0, 0, 0, 0, 0])

    def fun(x: Array) -> float:
        return float(cost @ x - 0.063 * x[3] * x[6])

    def jac(x: Array) -> Array:
        g = cost.copy()
        g[3] -= 0.063 * x[6]
        g[6] -= 0.063 * x[3]
        return g

    lin = _linear(
        [[0, 0, 0, 0, 0, 0, 0, 0, -b, -0.222], [0, 0, 0, 0, 0, 0, 3, 0, 0, -a],
         [0, 0, 0, 0, 0, 0, 0, 0, 1 / b, 0.222], [0, 0, 0, 0, 0, 0, -3, 0, 0, 1 / a]],
        [-35.82, 133.0, 35.82, -133.0], np.inf,
    )  # fmt: skip

    def ifun(x: Array) -> Array:
        u = 1.12 * x[0] + 0.13167 * x[0] * x[7] - 0.00667 * x[0] * x[7] ** 2
        v = 1.098 * x[7] - 0.038 * x[7] ** 2 + 0.325 * x[5] + 57.425
        return np.array([u - a * x[3], v - a * x[6], x[3] / a - u, x[6] / a - v])

    def ijac(x: Array) -> Array:
        du = np.zeros(10)
        du[0] = 1.12 + 0.13167 * x[7] - 0.00667 * x[7] ** 2
        du[7] = 0.13167 * x[0] - 0.01334 * x[0] * x[7]
        dv = np.zeros(10)
        dv[7], dv[5] = 1.098 - 0.076 * x[7], 0.325
        e4, e7 = np.eye(10)[3], np.eye(10)[6]
        return np.array([du - a * e4, dv - a * e7, e4 / a - du, e7 / a - dv])

    def efun(x: Array) -> Array:
        return np.array([98000 * x[2] / (x[3] * x[8] + 1000 * x[2]) - x[5], (x[1] + x[4]) / x[0] - x[7]])

    def ejac(x: Array) -> Array:
        den = x[3] * x[8] + 1000 * x[2]
        j = np.zeros((2, 10))
        k = 98000 / den**2
        j[0, [2, 3, 5, 8]] = [k * x[3] * x[8], -k * x[2] * x[8], -1.0, -k * x[2] * x[3]]
        j[1, [0, 1, 4, 7]] = [-(x[1] + x[4]) / x[0] ** 2, 1 / x[0], 1 / x[0], -1.0]
        return j

    lo = [1e-5, 1e-5, 1e-5, 1e-5, 1e-5, 85.0, 90.0, 3.0, 1.2, 145.0]
    hi = [2000.0, 16000.0, 120.0, 5000.0, 2000.0, 93.0, 95.0, 12.0, 4.0, 162.0]
    return _make(
        "HS114", fun, jac, [1745.0, 12000.0, 110.0, 3048.0, 1974.0, 89.2, 92.8, 8.0, 3.6, 145.0], _bounds(lo, hi),
        [lin, _ineq(ifun, ijac), _linear([-1, 0, 0, 1.22, -1, 0, 0, 0, 0, 0], 0.0, 0.0), _eq(efun, ejac)],
        [1698.096, 15818.73, 54.10228, 3031.226, 2000.0, 90.11548, 95.0, 10.49324, 1.561636, 153.5353],
    )  # fmt: skip


def hs116() -> TestProblem:
    """HS116: three-stage membrane separation, linear objective, five linear and ten quadratic inequalities."""
    lin = _linear(
        [[0, -1, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0], [-1, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0],
         [0, 0, 0, 0, 0, 0, -0.002, 0.002, 0, 0, 0, 0, 0], [0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1]],
        [0.0, 0.0, -1.0, 50.0], [np.inf, np.inf, np.inf, 250.0],
    )  # fmt: skip
    rows = [
        (0.0, {13: 1.0, 10: -1.262626}, [(3, 10, 1.231059)]),
        (0.0, {5: 1.0, 2: -0.03475}, [(2, 5, -0.975), (2, 2, 0.00975)]),
        (0.0, {6: 1.0, 3: -0.03475}, [(3, 6, -0.975), (3, 3, 0.00975)]),
        (0.0, {}, [(5, 7, 1.0), (1, 8, -1.0), (4, 7, -1.0), (4, 8, 1.0)]),
        (1.0, {5: -1.0, 6: -1.0}, [(2, 9, -0.002), (5, 8, -0.002), (1, 8, 0.002), (6, 9, 0.002)]),
        (0.0, {2: -500.0, 6: 500.0}, [(2, 9, 1.0), (3, 10, -1.0), (6, 9, -1.0), (2, 10, 1.0)]),
        (-0.9, {2: 1.0}, [(2, 10, -0.002), (3, 10, 0.002)]),
        (0.0, {4: 1.0, 1: -0.03475}, [(1, 4, -0.975), (1, 1, 0.00975)]),
        (0.0, {11: 1.0, 8: -1.262626}, [(1, 8, 1.231059)]),
        (0.0, {12: 1.0, 9: -1.262626}, [(2, 9, 1.231059)]),
    ]
    c = np.zeros(13)
    c[10:] = 1.0
    lo = [0.1, 0.1, 0.1, 1e-4, 0.1, 0.1, 0.1, 0.1, 500.0, 0.1, 1.0, 1e-4, 1e-4]
    hi = [1.0, 1.0, 1.0, 0.1, 0.9, 0.9, 1000.0, 1000.0, 1000.0, 500.0, 150.0, 150.0, 150.0]
    return _make(
        "HS116", lambda x: float(c @ x), lambda x: c,
        [0.5, 0.8, 0.9, 0.1, 0.14, 0.5, 489.0, 80.0, 650.0, 450.0, 150.0, 150.0, 150.0], _bounds(lo, hi),
        [lin, _quadratic_constraints("ineq", 13, rows)],
        [0.8037703, 0.8999860, 0.9709724, 0.09999952, 0.1908154, 0.4605717, 574.0803, 74.08043, 500.0162, 0.1,
         20.23413, 77.34755, 0.00673039],
        notes="Solvers reach 97.5875, slightly below the listed f*.",
    )  # fmt: skip


def hs117() -> TestProblem:
    """HS117: dual of Colville's problem HS86, cubic objective and five quadratic inequalities, x >= 0."""
    a, b, c, d, e = _COLVILLE_A, _COLVILLE_B, _COLVILLE_C, _COLVILLE_D, _COLVILLE_E

    def fun(x: Array) -> float:
        z = x[10:]
        return float(-b @ x[:10] + z @ c @ z + 2 * d @ z**3)

    def jac(x: Array) -> Array:
        z = x[10:]
        return np.concatenate([-b, 2 * c @ z + 6 * d * z**2])

    con = _ineq(
        lambda x: 2 * c @ x[10:] + 3 * d * x[10:] ** 2 + e - a.T @ x[:10],
        lambda x: np.hstack([-a.T, 2 * c + np.diag(6 * d * x[10:])]),
    )
    x0 = np.full(15, 0.001)
    x0[6] = 60.0
    return _make(
        "HS117", fun, jac, x0, _same_bounds(15, 0.0, None), [con],
        [0.0, 0.0, 5.174037, 0.0, 3.061109, 11.83951, 0.0, 0.0, 0.1038968, 0.0, 0.3, 0.3334676, 0.4, 0.4283101,
         0.2239649],
    )  # fmt: skip


def hs118() -> TestProblem:
    """HS118: quadratic production-planning problem with 17 linear constraints."""
    lin = {}
    pairs = []
    for k in range(5):
        for off, (cl, cq) in enumerate([(2.3, 1e-4), (1.7, 1e-4), (2.2, 1.5e-4)]):
            lin[3 * k + off + 1] = cl
            pairs.append((3 * k + off + 1, 3 * k + off + 1, cq))
    fun, jac = _quadratic(15, 0.0, lin, pairs)
    rows, lb, ub = [], [], []
    for k in range(1, 5):  # ramping limits between consecutive periods
        for off, up in [(0, 6.0), (2, 6.0), (1, 7.0)]:
            row = np.zeros(15)
            row[3 * k + off], row[3 * k + off - 3] = 1.0, -1.0
            rows.append(row)
            lb.append(-7.0)
            ub.append(up)
    for k, demand in enumerate([60.0, 50.0, 70.0, 85.0, 100.0]):
        row = np.zeros(15)
        row[3 * k : 3 * k + 3] = 1.0
        rows.append(row)
        lb.append(demand)
        ub.append(np.inf)
    lo = [8.0, 43.0, 3.0] + [0.0] * 12
    hi = [21.0, 57.0, 16.0] + [90.0, 120.0, 60.0] * 4
    return _make(
        "HS118", fun, jac, [20.0, 55.0, 15.0] + [20.0, 60.0, 20.0] * 4, _bounds(lo, hi), [_linear(rows, lb, ub)],
        [8.0, 49.0, 3.0, 1.0, 56.0, 0.0, 1.0, 63.0, 6.0, 3.0, 70.0, 12.0, 5.0, 77.0, 18.0],
    )  # fmt: skip


_HS119_PAIRS = [
    (1, 4), (1, 7), (1, 8), (1, 16), (2, 3), (2, 7), (2, 10), (3, 7), (3, 9), (3, 10), (3, 14), (4, 7), (4, 11),
    (4, 15), (5, 6), (5, 10), (5, 12), (5, 16), (6, 8), (6, 15), (7, 11), (7, 13), (8, 10), (8, 15), (9, 12),
    (9, 16), (10, 14), (11, 13), (12, 14), (13, 14),
]  # fmt: skip
_HS119_B = np.array([
    [0.22, 0.20, 0.19, 0.25, 0.15, 0.11, 0.12, 0.13, 1.0, 0, 0, 0, 0, 0, 0, 0],
    [-1.46, 0, -1.30, 1.82, -1.15, 0, 0.80, 0, 0, 1.0, 0, 0, 0, 0, 0, 0],
    [1.29, -0.89, 0, 0, -1.16, -0.96, 0, -0.49, 0, 0, 1.0, 0, 0, 0, 0, 0],
    [-1.10, -1.06, 0.95, -0.54, 0, -1.78, -0.41, 0, 0, 0, 0, 1.0, 0, 0, 0, 0],
    [0, 0, 0, -1.43, 1.51, 0.59, -0.33, -0.43, 0, 0, 0, 0, 1.0, 0, 0, 0],
    [0, -1.72, -0.33, 0, 1.62, 1.24, 0.21, -0.26, 0, 0, 0, 0, 0, 1.0, 0, 0],
    [1.12, 0, 0, 0.31, 0, 0, 1.12, 0, -0.36, 0, 0, 0, 0, 0, 1.0, 0],
    [0, 0.45, 0.26, -1.10, 0.58, 0, -1.03, 0.10, 0, 0, 0, 0, 0, 0, 0, 1.0],
])  # fmt: skip
_HS119_C = np.array([2.5, 1.1, -3.1, -3.5, 1.3, 2.1, 2.3, -1.5])


def hs119() -> TestProblem:
    """HS119: Colville's problem 7, quartic objective with eight linear equalities and box bounds."""
    a = np.eye(16)
    for i, j in _HS119_PAIRS:
        a[i - 1, j - 1] = 1.0
    sym = a + a.T

    def fun(x: Array) -> float:
        u = x**2 + x + 1
        return float(u @ a @ u)

    def jac(x: Array) -> Array:
        return (sym @ (x**2 + x + 1)) * (2 * x + 1)

    return _make(
        "HS119", fun, jac, [10.0] * 16, _same_bounds(16, 0.0, 5.0), [_linear(_HS119_B, _HS119_C, _HS119_C)],
        [0.03984734773, 0.7919831565, 0.2028703347, 0.8443579137, 1.269906449, 0.9347387126, 1.68196197,
         0.155300866, 1.567870335, 0.0, 0.0, 0.0, 0.6602040608, 0.0, 0.6742559314, 0.0],
        notes="x* is the book's polished to 10 digits.",
    )  # fmt: skip


def hs268() -> TestProblem:
    """HS268: least-squares-type quadratic with five linear inequalities (Schittkowski 1987)."""
    d = np.array([
        [10197.0, -12454.0, -1013.0, 1948.0, 329.0],
        [-12454.0, 20909.0, -1733.0, -4914.0, -186.0],
        [-1013.0, -1733.0, 1755.0, 1089.0, -174.0],
        [1948.0, -4914.0, 1089.0, 1515.0, -22.0],
        [329.0, -186.0, -174.0, -22.0, 27.0],
    ])  # fmt: skip
    b = np.array([-9170.0, 17099.0, -2271.0, -4336.0, -43.0])
    lin = _linear(
        [[-1, -1, -1, -1, -1], [10, 10, -3, 5, 4], [-8, 1, -2, -5, 3], [8, -1, 2, 5, -3], [-4, -2, 3, -5, 1]],
        [-5.0, 20.0, -40.0, 11.0, -30.0], np.inf,
    )  # fmt: skip
    return _make(
        "HS268", lambda x: float(x @ d @ x - 2 * b @ x + 14463.0), lambda x: 2 * d @ x - 2 * b, [1.0] * 5, None,
        [lin], [1.0, 2.0, -1.0, 3.0, -4.0],
    )  # fmt: skip


BUILDERS: dict[str, Callable[[], TestProblem]] = {
    "HS57": hs57, "HS59": hs59, "HS60": hs60, "HS61": hs61, "HS62": hs62, "HS63": hs63, "HS64": hs64,
    "HS65": hs65, "HS66": hs66, "HS67": hs67, "HS68": hs68, "HS69": hs69, "HS70": hs70, "HS71": hs71,
    "HS72": hs72, "HS73": hs73, "HS74": hs74, "HS75": hs75, "HS76": hs76, "HS76I": hs76i, "HS77": hs77,
    "HS78": hs78, "HS79": hs79, "HS80": hs80, "HS81": hs81, "HS83": hs83, "HS84": hs84, "HS85": hs85,
    "HS86": hs86, "HS87": hs87, "HS88": hs88, "HS89": hs89, "HS90": hs90, "HS91": hs91, "HS92": hs92,
    "HS93": hs93, "HS95": hs95, "HS96": hs96, "HS97": hs97, "HS98": hs98, "HS99": hs99, "HS99EXP": hs99exp,
    "HS100": hs100, "HS100LNP": hs100lnp, "HS100MOD": hs100mod, "HS101": hs101, "HS102": hs102,
    "HS103": hs103, "HS104": hs104, "HS105": hs105, "HS106": hs106, "HS107": hs107, "HS108": hs108,
    "HS109": hs109, "HS111": hs111, "HS112": hs112, "HS113": hs113, "HS114": hs114, "HS116": hs116,
    "HS117": hs117, "HS118": hs118, "HS119": hs119, "HS268": hs268,
}  # fmt: skip
