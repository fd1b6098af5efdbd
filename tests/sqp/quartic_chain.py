"""A smooth test objective shared by the active-set tests: ``1/2 |x - target|^2 + 1/4 sum (x_{i+1} - x_i)^4``, a
chain whose Hessian is tridiagonal (given dense or sparse by the caller), and that chain kept in a box by sparse
rows."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import scipy.sparse as sp


def quartic_chain(target: np.ndarray) -> tuple[Callable, Callable, Callable]:
    """``(fun, jac, tridiagonal)``: the objective, its gradient, and the Hessian's ``(main, off)`` diagonals."""

    def fun(x):
        return 0.5 * float(np.sum((x - target) ** 2)) + 0.25 * float(np.sum(np.diff(x) ** 4))

    def jac(x):
        g = x - target
        dx3 = np.diff(x) ** 3
        g[:-1] -= dx3
        g[1:] += dx3
        return g

    def tridiagonal(x):
        w = 3.0 * np.diff(x) ** 2
        main = np.ones(x.size)
        main[:-1] += w
        main[1:] += w
        return main, -w

    return fun, jac, tridiagonal


def chain_in_a_box(target: np.ndarray) -> tuple[Callable, Callable, Callable, dict]:
    """``(fun, jac, hess, rows)``: the quartic chain pulled towards ``target`` with every component kept in
    ``x_i² ≤ 0.5`` (one sparse row each), exact sparse Hessians."""
    fun, jac, tridiagonal = quartic_chain(target)

    def hess(x):
        main, off = tridiagonal(x)
        return sp.diags([main, off, off], [0, 1, -1], format="csc")

    rows = {"type": "ineq", "fun": lambda x: 0.5 - x ** 2, "jac": lambda x: sp.diags(-2.0 * x, format="csr"),
            "hess": lambda x, v: sp.diags(-2.0 * v, format="csc")}
    return fun, jac, hess, rows
