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
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from functools import cache

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import LinearConstraint, brentq
from scipy.special import ndtr

from sqp.problems.problem import TestProblem, hs_optima

Array = NDArray[np.float64]
Fun = Callable[[Array], float]
Jac = Callable[[Array], Array]

SQRT2 = np.sqrt(2.0)


# --------------------------------------------------------------------------------------------------------------
# Shared helpers
# --------------------------------------------------------------------------------------------------------------


def _make(
    name: str,
    fun: Fun,
    jac: Jac,
    x0: Sequence[float],
    bounds: Sequence[tuple[float | None, float | None]] | None = None,
    constraints: Sequence[object] = (),
    xstar: Sequence[float] | None = None,
    notes: str = "",
) -> TestProblem:
    """Assemble a problem record, looking its f* up in the optima table."""
    return TestProblem(
        name=name,
        fun=fun,
        jac=jac,
        x0=np.asarray(x0, dtype=float),
        bounds=None if bounds is None else list(bounds),
        constraints=tuple(constraints),
        fstar=hs_optima()[name],
        xstar=None if xstar is None else np.asarray(xstar, dtype=float),
        notes=notes,
    )


def _ineq(fun: Callable[[Array], Array], jac: Callable[[Array], Array]) -> dict:
    """An SLSQP inequality ``fun(x) >= 0``."""
    return {"type": "ineq", "fun": fun, "jac": jac}


def _eq(fun: Callable[[Array], Array], jac: Callable[[Array], Array]) -> dict:
    """An SLSQP equality ``fun(x) == 0``."""
    return {"type": "eq", "fun": fun, "jac": jac}


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
    """``const + sum_k c_k prod_i x_i**e_ki`` and its gradient, for ``x > 0`` (terms are ``(c_k, e_k)``)."""
    coef = np.array([t[0] for t in terms], dtype=float)
    expo = np.array([t[1] for t in terms], dtype=float)

    def values(x: Array) -> Array:
        return coef * np.exp(expo @ np.log(x))

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
        "HS59", fun, jac, [90.0, 10.0], [(0.0, 75.0), (0.0, 65.0)], [con], None,
        notes="CUTEst's corrected objective (extra -0.12694 x1^2 term); the book's x* does not apply.",
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
    fun, jac = _quadratic(3, 1000.0, {}, [(1, 1, -1.0), (2, 2, -2.0), (3, 3, -1.0), (1, 2, -0.5), (1, 3, -0.5)])
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
    """HS67's implicit quantities y2..y8 (two fixed-point iterations, run to full precision) with gradients."""
    x1, x2, x3 = _Dual.variables(np.asarray(x, dtype=float))
    y2 = 1.6 * x1
    for _ in range(500):
        y6 = (x2 + 1.22 * y2 - x1) / x1
        new = 0.01 * x1 * (112.0 + 13.167 * y6 - 0.6667 * y6 * y6)
        converged = abs(new.v - y2.v) <= 1e-13 * max(1.0, abs(y2.v))
        y2 = new
        if converged:
            break
    y3 = 1.22 * y2 - x1
    y6 = (x2 + y3) / x1
    y4 = _Dual(93.0, np.zeros(3))
    for _ in range(2000):
        y5 = 86.35 + 1.098 * y6 - 0.038 * y6 * y6 + 0.325 * (y4 - 89.0)
        y7 = 35.82 - 0.222 * (3.0 * y5 - 133.0)
        new = 98000.0 * x3 / (y2 * y7 + 1000.0 * x3)
        converged = abs(new.v - y4.v) <= 1e-13 * max(1.0, abs(y4.v))
        y4 = new
        if converged:
            break
    y5 = 86.35 + 1.098 * y6 - 0.038 * y6 * y6 + 0.325 * (y4 - 89.0)
    y8 = 3.0 * y5 - 133.0
    y7 = 35.82 - 0.222 * y8
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
        notes="Inner iterations run to machine precision instead of the book's 1e-3 tolerance, so the problem is "
        "smooth; this gives f* = -1162.119 (CUTEst) rather than the book's -1162.0365.",
    )  # fmt: skip


def _inspection(name: str, a: float, b: float, n: float, xstar: Sequence[float]) -> TestProblem:
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
        [_eq(cfun, cjac)], xstar,
    )  # fmt: skip


def hs68() -> TestProblem:
    """HS68: cost-optimal inspection plan (a = 1e-4, b = 1, n = 24)."""
    return _inspection("HS68", 1e-4, 1.0, 24.0, [0.06785874, 3.6461717, 0.0026617, 0.8948622])


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
        s = 1000 * np.sin
        return np.array([
            s(-x[2] - 0.25) + s(-x[3] - 0.25) + 894.8 - x[0],
            s(x[2] - 0.25) + s(x[2] - x[3] - 0.25) + 894.8 - x[1],
            s(x[3] - 0.25) + s(x[3] - x[2] - 0.25) + 1294.8,
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
        "HS84", fun, jac, [2.52, 2.0, 37.5, 9.25, 6.8], _bounds([0.0, 1.2, 20.0, 9.0, 6.5], [1000.0, 2.4, 60.0, 9.3, 7.0]),
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


def _hs95(name: str, b: Sequence[float]) -> TestProblem:
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
    )  # fmt: skip


def hs95() -> TestProblem:
    """HS95: bilinear inequalities, right-hand side (4.97, -1.88, -29.08, -78.02)."""
    return _hs95("HS95", [4.97, -1.88, -29.08, -78.02])


def hs96() -> TestProblem:
    """HS96: bilinear inequalities, right-hand side (4.97, -1.88, -69.08, -118.02)."""
    return _hs95("HS96", [4.97, -1.88, -69.08, -118.02])


def hs97() -> TestProblem:
    """HS97: bilinear inequalities, right-hand side (32.97, 25.12, -29.08, -78.02)."""
    return _hs95("HS97", [32.97, 25.12, -29.08, -78.02])


def hs98() -> TestProblem:
    """HS98: bilinear inequalities, right-hand side (32.97, 25.12, -124.08, -173.02)."""
    return _hs95("HS98", [32.97, 25.12, -124.08, -173.02])
