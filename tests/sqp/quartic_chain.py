"""A smooth test objective shared by the active-set tests: ``1/2 |x - target|^2 + 1/4 sum (x_{i+1} - x_i)^4``, a
chain whose Hessian is tridiagonal (given dense or sparse by the caller)."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np


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
