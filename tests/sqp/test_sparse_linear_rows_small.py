"""Below DENSE_LIMIT variables a sparse LinearConstraint is held dense: the same iterations, bit for bit, as the
dense one (a sparse A had sent every equality QP to a backend instead of the direct KKT solve)."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.optimize import LinearConstraint

import sqp
from sqp.build import build_problem


def _problem(n: int = 40):
    rng = np.random.default_rng(7)
    target = rng.standard_normal(n)

    def fun(x):
        return float(np.sum((x - target) ** 2) + 0.1 * np.sum(np.cos(x)))

    def jac(x):
        return 2.0 * (x - target) - 0.1 * np.sin(x)

    def hess(x):
        return np.diag(2.0 - 0.1 * np.cos(x))

    A = np.zeros((2, n))
    A[0, :] = 1.0
    A[1, ::2] = 1.0
    circle = {"type": "eq", "fun": lambda x: np.array([x[:3] @ x[:3] - 1.0]), "jac": lambda x: np.concatenate(
        [2.0 * x[:3], np.zeros(n - 3)])[None, :], "hess": lambda x, v: np.diag(np.r_[2.0 * v[0] * np.ones(3),
                                                                                   np.zeros(n - 3)])}
    return fun, jac, hess, A, circle, np.zeros(n) + 0.1


def test_sparse_A_is_held_dense_below_the_dense_limit():
    fun, jac, hess, A, circle, x0 = _problem()
    problem = build_problem(fun, x0, jac, None, [LinearConstraint(sp.csr_matrix(A), 1.0, 1.0), circle])
    assert isinstance(problem.A, np.ndarray)
    np.testing.assert_array_equal(problem.A, A)


def test_sparse_and_dense_A_give_the_same_iterations():
    fun, jac, hess, A, circle, x0 = _problem()
    runs = [sqp.minimize(fun, x0, jac=jac, hess=hess, constraints=[LinearConstraint(M, 1.0, 1.0), circle])
            for M in (A, sp.csr_matrix(A))]
    assert all(r.success for r in runs)
    assert runs[0].nit == runs[1].nit
    np.testing.assert_array_equal(runs[0].x, runs[1].x)
