"""Dense arrays and scipy.sparse matrices are interchangeable in every callable and matrix the engine takes.

Each case swaps the format of one input (the objective Hessian ``hess``, ``hess0``, a constraint's ``jac`` or
``hess(x, v)``, ``LinearConstraint.A``) and must give the same solve as the reference format, to 1e-10: sparse on a
small problem (the engine works densely there), dense on one with more than :data:`sqp.DENSE_LIMIT` variables (the
engine works sparsely there).
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.optimize import LinearConstraint, NonlinearConstraint

import sqp

SWAPPABLE = ("hess", "hess0", "jac", "constraint_hess", "A")


def _chain(n: int, swap: str | None, sparse_reference: bool, exact: bool = True) -> dict[str, Any]:
    """A chain-like program: a tridiagonal quadratic, parabola equalities on pairs of variables (sparse rows), one
    dense-row inequality ``sum w x^2 <= r`` and two-sided difference rows ``|x_i - x_{i+1}| <= 0.01``.

    Every matrix is given in the reference format (sparse when ``sparse_reference``), except ``swap``."""
    H = sp.diags([-np.ones(n - 1), 3.0 * np.ones(n), -np.ones(n - 1)], [-1, 0, 1], format="csc")
    b = np.linspace(-1.0, 1.0, n)
    m = max(2, n // 8)
    i0 = 2 * np.arange(m)
    w = np.linspace(0.5, 1.5, n)
    k = max(2, n // 4)
    A = sp.csr_matrix((np.tile([1.0, -1.0], k), (np.repeat(np.arange(k), 2),
                                                 np.column_stack([np.arange(k), np.arange(k) + 1]).ravel() + n // 2)),
                      shape=(k, n))

    def fmt(name: str, M: Any) -> Any:
        sparse = sparse_reference != (swap == name)
        return sp.csr_matrix(M) if sparse else (M.toarray() if sp.issparse(M) else np.asarray(M))

    def parabola_jac(x: Any) -> Any:
        rows = np.repeat(np.arange(m), 2)
        cols = np.column_stack([i0, i0 + 1]).ravel()
        vals = np.column_stack([np.ones(m), -x[i0 + 1]]).ravel()
        return fmt("jac", sp.csr_matrix((vals, (rows, cols)), shape=(m, n)))

    def parabola_hess(x: Any, v: Any) -> Any:
        d = np.zeros(n)
        d[i0 + 1] = -v
        return fmt("constraint_hess", sp.diags(d))

    parabola = {"type": "eq", "fun": lambda x: x[i0] - 0.5 * x[i0 + 1] ** 2 - 0.1, "jac": parabola_jac}
    ball = NonlinearConstraint(lambda x: np.array([w @ (x * x)]), -np.inf, 0.15 * n,
                               jac=lambda x: 2 * (w * x)[None, :],  # a dense row, dense in both references
                               hess=lambda x, v: fmt("constraint_hess", sp.diags(2 * v[0] * w)))
    if exact:
        parabola["hess"] = parabola_hess
    else:
        ball = NonlinearConstraint(ball.fun, ball.lb, ball.ub, jac=ball.jac)
    kw: dict[str, Any] = {
        "fun": lambda x: 0.5 * x @ (H @ x) - b @ x, "x0": np.full(n, 0.5), "jac": lambda x: H @ x - b,
        "constraints": [parabola, ball, LinearConstraint(fmt("A", A), -0.01, 0.01)],
        "bounds": [(-2.0, 2.0)] * n, "max_iter": 60,
    }
    if exact:
        kw["hess"] = lambda x: fmt("hess", H)
    kw["hess0"] = fmt("hess0", H + 0.1 * sp.identity(n))
    return kw


def _same(a: sqp.Result, b: sqp.Result) -> None:
    assert (a.status, a.nit) == (b.status, b.nit)
    np.testing.assert_allclose(a.x, b.x, rtol=0, atol=1e-10)
    for la, lb in zip(a.constraint_multipliers, b.constraint_multipliers, strict=True):
        np.testing.assert_allclose(la, lb, rtol=0, atol=1e-10 * max(1.0, float(np.max(np.abs(lb)))))


@pytest.mark.parametrize("exact", [True, False], ids=["exact", "bfgs"])
@pytest.mark.parametrize("swap", SWAPPABLE)
def test_sparse_input_on_a_small_problem(swap: str, exact: bool) -> None:
    if swap in ("hess", "constraint_hess") and not exact:
        pytest.skip("no Hessian callables without hess")
    ref = sqp.minimize(**_chain(24, None, sparse_reference=False, exact=exact))
    assert ref.success, ref.message
    _same(sqp.minimize(**_chain(24, swap, sparse_reference=False, exact=exact)), ref)


@pytest.mark.parametrize("swap", SWAPPABLE)
def test_dense_input_on_a_large_problem(swap: str) -> None:
    n = sqp.DENSE_LIMIT + 20
    ref = sqp.minimize(**_chain(n, None, sparse_reference=True))
    assert ref.success, ref.message
    _same(sqp.minimize(**_chain(n, swap, sparse_reference=True)), ref)


def test_dense_hess0_on_a_large_bfgs_problem() -> None:
    n = sqp.DENSE_LIMIT + 20
    ref = sqp.minimize(**_chain(n, None, sparse_reference=True, exact=False))
    assert ref.success, ref.message
    _same(sqp.minimize(**_chain(n, "hess0", sparse_reference=True, exact=False)), ref)
